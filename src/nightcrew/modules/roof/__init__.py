"""Roofs and domes: base classes for their drivers."""

from nightcrew.modules.roof.base import BaseRoof
from nightcrew.modules.roof.dome import BaseDome, azimuth_difference
from nightcrew.modules.roof.geometry import DomeGeometry, slit_azimuth

__all__ = ["BaseDome", "BaseRoof", "DomeGeometry", "azimuth_difference", "slit_azimuth"]
