"""The supervisor tests' Prosody and supervised directory, for the watchdog tests."""

from tests.supervisor.conftest import prosody, supervised

__all__ = ["prosody", "supervised"]
