"""Focus modules: the temperature focus model (and, later, focus series)."""

from nightcrew.modules.focus.model import FocusModel

__all__ = ["FocusModel"]
