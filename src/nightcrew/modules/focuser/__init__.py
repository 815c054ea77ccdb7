"""Focusers: the base class for their drivers."""

from nightcrew.modules.focuser.base import BaseFocuser

__all__ = ["BaseFocuser"]
