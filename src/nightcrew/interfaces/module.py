"""Interfaces every module offers: identity, lifecycle state and run-time configuration."""

from __future__ import annotations

from abc import abstractmethod
from typing import Any

from nightcrew.interfaces.base import Interface
from nightcrew.interfaces.enums import ModuleState

__all__ = ["IConfig", "IModule"]


class IModule(Interface):
    """A module: the one interface every module offers."""

    @abstractmethod
    async def get_label(self) -> str:
        """Human-readable name of the module."""

    @abstractmethod
    async def get_version(self) -> str:
        """Software version of the module (nightcrew's version unless the module says otherwise)."""

    @abstractmethod
    async def get_state(self) -> ModuleState:
        """Current lifecycle state."""

    @abstractmethod
    async def get_error_string(self) -> str:
        """Why the module is in error state; empty if it is not."""

    @abstractmethod
    async def reset_error(self) -> bool:
        """Try to leave error state; True if the module is ready afterwards."""


class IConfig(Interface):
    """Configuration options that can be read or changed while the module runs."""

    @abstractmethod
    async def get_config_caps(self) -> dict[str, tuple[bool, bool, bool]]:
        """Option name → (has getter, has setter, has a list of allowed values)."""

    @abstractmethod
    async def get_config_value(self, name: str) -> Any:
        """Current value of option ``name`` (a name from :meth:`get_config_caps`)."""

    @abstractmethod
    async def set_config_value(self, name: str, value: Any) -> None:
        """Set option ``name`` to ``value``."""

    @abstractmethod
    async def get_config_value_options(self, name: str) -> list[str]:
        """Allowed values of option ``name``."""
