"""The robotic layer: autonomous operation and running scripts on request."""

from __future__ import annotations

from abc import abstractmethod

from nightcrew.interfaces.base import Interface
from nightcrew.timeout import timeout

__all__ = ["IAutonomous", "IScriptRunner"]


class IAutonomous(Interface):
    """A module that may act on its own (mastermind, scheduler); others yield to it."""

    @abstractmethod
    async def is_autonomous(self) -> bool:
        """Whether the module is currently acting on its own."""


class IScriptRunner(Interface):
    """Runs observing scripts given as text."""

    @timeout(3600)
    @abstractmethod
    async def run_script(self, script: str) -> None:
        """Run ``script`` (the YAML configuration of a script) and return when it ends."""
