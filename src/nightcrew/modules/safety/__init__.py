"""Safety: the watchdog that closes and parks when the modules keeping the observatory safe go silent."""

from nightcrew.modules.safety.heartbeats import HeartbeatMonitor
from nightcrew.modules.safety.watchdog import SafetyWatchdog

__all__ = ["HeartbeatMonitor", "SafetyWatchdog"]
