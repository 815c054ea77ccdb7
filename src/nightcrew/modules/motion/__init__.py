"""What all moving devices share: motion status and one motion at a time."""

from nightcrew.modules.motion.base import BaseMotion
from nightcrew.modules.motion.runner import MotionRunner

__all__ = ["BaseMotion", "MotionRunner"]
