"""Modules driving ASCOM Alpaca devices, one per device type, on nightcrew's device bases."""

from nightcrew.modules.alpaca.device import AlpacaModule

__all__ = ["AlpacaModule"]
