"""Roofs and domes: base classes for their drivers."""

from nightcrew.modules.roof.base import BaseRoof
from nightcrew.modules.roof.dome import BaseDome, azimuth_difference

__all__ = ["BaseDome", "BaseRoof", "azimuth_difference"]
