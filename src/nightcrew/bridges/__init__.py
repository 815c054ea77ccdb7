"""Bridges to other protocols: the layer between nightcrew modules and foreign devices or clients."""
