"""What every long-running command does alike (kept in :mod:`nightcrew.night.running`, which the
simulated night uses too)."""

from nightcrew.night.running import quiet_module_logs, stop_on_signals

__all__ = ["quiet_module_logs", "stop_on_signals"]
