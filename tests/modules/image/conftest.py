"""The faster observatory of the weather tests, shared here."""

from tests.modules.weather.conftest import fast_observatory

__all__ = ["fast_observatory"]
