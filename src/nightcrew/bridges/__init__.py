"""Bridges to other device protocols (INDI, Alpaca): clients and servers, no nightcrew modules."""
