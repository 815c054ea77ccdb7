"""Twilight flat-field modules: the flat-fielder, its pointing and a scheduler of combinations."""

from nightcrew.modules.flatfield.flatfield import FlatField
from nightcrew.modules.flatfield.pointing import FlatFieldPointing
from nightcrew.modules.flatfield.scheduler import FlatFieldScheduler

__all__ = ["FlatField", "FlatFieldPointing", "FlatFieldScheduler"]
