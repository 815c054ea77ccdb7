"""Weather stations (the measuring devices): the base class for their drivers."""

from nightcrew.modules.weatherstation.base import BaseWeatherStation

__all__ = ["BaseWeatherStation"]
