"""Modules driving ASCOM Alpaca devices, one per device type, on nightcrew's device bases."""

from nightcrew.modules.alpaca.device import AlpacaModule
from nightcrew.modules.alpaca.server import AlpacaServer

__all__ = ["AlpacaModule", "AlpacaServer"]
