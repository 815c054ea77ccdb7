"""Utility modules: Trigger (event → method call), Kiosk (latest image over HTTP), AutonomousWarning."""

from nightcrew.modules.utils.autonomous import AutonomousWarning
from nightcrew.modules.utils.kiosk import Kiosk
from nightcrew.modules.utils.trigger import Trigger, TriggerRule

__all__ = ["AutonomousWarning", "Kiosk", "Trigger", "TriggerRule"]
