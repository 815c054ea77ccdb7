"""Telescope mounts: the base class every driver derives from, and coordinate helpers."""

from nightcrew.modules.telescope.base import BaseTelescope

__all__ = ["BaseTelescope"]
