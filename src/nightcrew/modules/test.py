"""Small modules for trying nightcrew out and for tests."""

from __future__ import annotations

import logging
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.interfaces.quantities import Period
from nightcrew.modules.module import Module

__all__ = ["StandAlone"]

log = logging.getLogger(__name__)


class StandAlone(Module):
    """Logs a message at a fixed interval — the "hello world" of the paper.

    Args:
        message: What to log.
        interval: Seconds between two messages (clock seconds), 0.01 s to a day.
    """

    def __init__(self, message: str = "Hello world", interval: Period = 10.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not interval > 0:
            raise ConfigError(f"interval must be > 0 seconds, got {interval}", key="interval")
        self._message = message
        self._interval = float(interval)
        self.add_background_task(self._message_loop)

    async def _message_loop(self) -> None:
        while True:
            log.info(self._message)
            await self.clock.sleep(self._interval)

    def _get_config_message(self) -> str:
        return self._message

    def _set_config_message(self, message: str) -> None:
        self._message = message

    def _get_config_interval(self) -> float:
        return self._interval

    def _set_config_interval(self, interval: Period) -> None:
        # Its bounds are its hint's: set_config_value checks them before this runs.
        self._interval = float(interval)
