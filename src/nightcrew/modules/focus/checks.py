"""``nightcrew check`` across files: a temperature source must name a module of the observatory.

A mastermind's ``focus_temperature`` (and its imaging scripts') and a focus model's
``temperatures`` name a module and a sensor; a module name that no file provides would leave the
refocus (or the model) without a temperature all night, so ``check`` refuses it, and a module of
the wrong kind (a ``sensor`` on a module without ITemperatures, a ``weather_sensor`` on one without
IWeather) too. Files among which no module gives temperatures at all are a part of an observatory
(like ``examples/automation``), not a whole one: a name they do not hold is not held against them.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from nightcrew.config._classes import ClassResolutionError, import_class
from nightcrew.errors import ConfigError
from nightcrew.focus.sources import TemperatureSource, source_from_config
from nightcrew.interfaces import ITemperatures, IWeather
from nightcrew.modules.focus.model import FocusModel
from nightcrew.modules.observatory_files import module_configs

__all__ = ["temperature_source_problems"]


def temperature_source_problems(files: Iterable[Path]) -> list[str]:
    """For the module files of one observatory: a line per temperature source naming a module
    that no file among ``files`` provides, or one that cannot give that kind of reading."""
    modules = module_configs(files)
    whole = any(_offers(config, (ITemperatures, IWeather)) for _, config in modules.values())
    problems = []
    for path, config in modules.values():
        for key, source in _sources(config):
            problem = _problem(source, modules, whole=whole)
            if problem is not None:
                problems.append(f"{path}: key '{key}': {problem}")
    return problems


def _sources(config: Mapping[str, Any]) -> list[tuple[str, TemperatureSource]]:
    entries: list[tuple[str, object]] = []
    if isinstance(config.get("focus_temperature"), Mapping):
        entries.append(("focus_temperature", config["focus_temperature"]))
    temperatures = config.get("temperatures")
    if isinstance(temperatures, Mapping) and _is_focus_model(config):
        entries += [(f"temperatures.{name}", entry) for name, entry in temperatures.items()]
    runner = config.get("runner")
    scripts = runner.get("scripts") if isinstance(runner, Mapping) else None
    if isinstance(scripts, Mapping):  # a mastermind's scripts (an imaging script's refocus trigger)
        for name, script in scripts.items():
            if isinstance(script, Mapping) and isinstance(script.get("focus_temperature"), Mapping):
                entries.append((f"runner.scripts.{name}.focus_temperature", script["focus_temperature"]))
    sources = []
    for key, entry in entries:
        try:
            sources.append((key, source_from_config(entry, key)))
        except ConfigError:
            continue  # reported by the file's own check
    return sources


def _is_focus_model(config: Mapping[str, Any]) -> bool:
    try:
        cls = import_class(str(config["class"]))
    except (ConfigError, ClassResolutionError):
        return False
    return isinstance(cls, type) and issubclass(cls, FocusModel)


def _offers(config: Mapping[str, Any], interfaces: tuple[type, ...]) -> bool:
    try:
        cls = import_class(str(config["class"]))
    except (ConfigError, ClassResolutionError):
        return False
    return isinstance(cls, type) and issubclass(cls, interfaces)


def _problem(
    source: TemperatureSource, modules: Mapping[str, tuple[Path, dict[str, Any]]], *, whole: bool
) -> str | None:
    if source.module not in modules:
        if not whole:
            return None
        known = ", ".join(sorted(modules)) or "none"
        return f"no module '{source.module}' here provides temperatures (modules: {known})"
    path, config = modules[source.module]
    try:
        cls = import_class(str(config["class"]))
    except (ConfigError, ClassResolutionError):
        return None  # the module file's own check names it
    weather = source.weather_sensor is not None
    needed, what = (IWeather, "weather_sensor") if weather else (ITemperatures, "sensor")
    if isinstance(cls, type) and not issubclass(cls, needed):
        return f"module '{source.module}' ({path}) has no {needed.__name__}, so no '{what}' to read"
    return None
