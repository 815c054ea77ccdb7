"""Focus modules: the temperature focus model (and, later, focus series)."""

from nightcrew.modules.focus.model import FocusModel
from nightcrew.modules.focus.series import AutoFocusSeries

__all__ = ["AutoFocusSeries", "FocusModel"]
