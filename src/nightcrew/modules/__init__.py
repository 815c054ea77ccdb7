"""Modules: the processes-to-be of an observatory, one per device or task."""

from nightcrew.modules.module import Module

__all__ = ["Module"]
