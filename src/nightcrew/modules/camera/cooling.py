"""The cooling schedule of a camera: cool down at dusk, hold, warm up at dawn.

Every ``interval`` clock seconds it reads the camera's cooling (ICooling: set point, power, the
chip's temperature), asks the Sun when it next sets below ``ready_sun_altitude`` and rises above
``warm_sun_altitude``, and commands what :func:`nightcrew.robotic.cooling.cooling_command`
decides: a ramp of at most ``ramp_rate`` °C per minute, done ``lead_time`` seconds before the
first dusk frame; the set point held all night; a ramp back to the chip's warm temperature at
dawn, then the cooler off (after ``warm_up_time_limit`` seconds at the latest, with a warning).
It starts the night where it is: started after dusk, it cools at once.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from nightcrew.astro import sun_crossing
from nightcrew.config._classes import ClassResolutionError, import_class
from nightcrew.errors import ConfigError, NotSupportedError
from nightcrew.interfaces import CoolingStatus, ICooling
from nightcrew.modules.camera.base import BaseCamera
from nightcrew.modules.module import Module
from nightcrew.modules.observatory_files import module_configs
from nightcrew.robotic.cooling import CoolerCommand, CoolingPhase, CoolingPlan, cooling_command

__all__ = ["CoolingSchedule", "cooling_reach_problems"]

log = logging.getLogger(__name__)

#: °C assumed for a chip that has not told its temperature yet (the warm-up's end).
_UNKNOWN_WARM = 20.0


class CoolingSchedule(Module):
    """Cools a camera for the night and warms it up in the morning (see the module docstring).

    Args:
        camera: Module offering ICooling.
        setpoint: The night's detector temperature, °C.
        ramp_rate: Largest change of the set point, °C per minute (cool-down and warm-up).
        ready_sun_altitude: At the set point before the Sun sets below this, degrees (the dusk
            flats: the mastermind's ``twilight_max_sun_altitude``).
        warm_sun_altitude: Warm up once the Sun rises above this, degrees.
        lead_time: Clock seconds at the set point before ``ready_sun_altitude``.
        warm_up_time_limit: Clock seconds after which a warm-up ends with the cooler off.
        interval: Clock seconds between two looks at the camera.
        **kwargs: Module options (``site`` is required).
    """

    def __init__(
        self,
        *,
        camera: str | ICooling = "camera",
        setpoint: float = -10.0,
        ramp_rate: float = 3.0,
        ready_sun_altitude: float = -3.0,
        warm_sun_altitude: float = -3.0,
        lead_time: float = 600.0,
        warm_up_time_limit: float = 1800.0,
        interval: float = 30.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        try:
            self._plan = CoolingPlan(
                setpoint=float(setpoint),
                ramp_rate=float(ramp_rate),
                ready_sun_altitude=float(ready_sun_altitude),
                warm_sun_altitude=float(warm_sun_altitude),
                lead_time=float(lead_time),
                warm_up_time_limit=float(warm_up_time_limit),
            )
        except ValueError as exc:
            raise ConfigError(str(exc), key=str(exc).split()[0]) from exc
        if not (math.isfinite(interval) and interval > 0):
            raise ConfigError(f"must be > 0 seconds, got {interval}", key="interval")
        if self.site is None:
            raise ConfigError("the cooling schedule follows the Sun: give the site", key="site")
        self._camera = camera
        self._interval = float(interval)
        self._last: CoolerCommand | None = None
        self._last_time = 0.0
        self._warming_since: float | None = None
        self._warm_temperature: float | None = None
        self.add_background_task(self._cooling_loop)

    @property
    def plan(self) -> CoolingPlan:
        return self._plan

    async def _cooling_loop(self) -> None:
        camera = await self.proxy(self._camera, ICooling)
        while True:
            try:
                await self.step(await camera.get_cooling(), camera)
            except NotSupportedError as exc:  # nothing to schedule: say so once, not every interval
                log.warning("%s: the camera cannot cool (%s): no cooling schedule", self.name, exc)
                return
            await self.clock.sleep(self._interval)

    async def step(self, status: CoolingStatus, camera: ICooling) -> CoolerCommand:
        """One look: decide from ``status`` and command the camera if anything changed."""
        now = self.clock.time()
        if self._last is None and status.enabled:  # someone else cools: ramp on from there
            self._last, self._last_time = CoolerCommand(CoolingPhase.COOLING, True, status.setpoint), now
        temperature = status.temperature
        if temperature is None:  # a camera that does not say: trust it follows the set point
            temperature = status.setpoint if status.enabled else (self._warm_temperature or _UNKNOWN_WARM)
        if not status.enabled:
            self._warm_temperature = temperature
        site, plan = self.site, self._plan
        assert site is not None  # checked when built
        try:
            ready_at = sun_crossing(site, now, plan.ready_sun_altitude, rising=False)
            warm_at = sun_crossing(site, now, plan.warm_sun_altitude, rising=True)
        except ValueError:  # polar day or night: no dusk to cool for
            ready_at = warm_at = math.inf
        command = cooling_command(
            plan,
            now=now,
            ready_at=ready_at,
            warm_at=warm_at,
            temperature=temperature,
            warm_temperature=self._warm_temperature or _UNKNOWN_WARM,
            last=self._last,
            last_time=self._last_time,
            warming_since=self._warming_since,
        )
        self._report(command, temperature, now)
        if command != self._last or command.enabled != status.enabled:
            await camera.set_cooling(command.enabled, self._commanded_setpoint(command))
        self._last, self._last_time = command, now
        return command

    def _commanded_setpoint(self, command: CoolerCommand) -> float:
        """The set point sent: on a cool-down, where the ramp will be at the next look. The chip
        then lags its set point all through the ramp (the same steps, one look earlier), so a script
        waiting for the set point waits from the ramp's first look on, not only once it has begun."""
        if command.phase is not CoolingPhase.COOLING:
            return command.setpoint
        ahead = command.setpoint - self._plan.ramp_rate * self._interval / 60.0
        return max(self._plan.setpoint, ahead)

    def _report(self, command: CoolerCommand, temperature: float, now: float) -> None:
        """Log each change of phase; keep when the warm-up began."""
        before = self._last.phase if self._last is not None else None
        if command.phase is before:
            return
        plan = self._plan
        if command.phase is CoolingPhase.COOLING:
            log.info(
                "%s: cooling down from %.1f °C to %g °C at %g °C/min",
                self.name,
                temperature,
                plan.setpoint,
                plan.ramp_rate,
            )
        elif command.phase is CoolingPhase.HOLDING:
            log.info("%s: holding %g °C (chip at %.1f °C)", self.name, plan.setpoint, temperature)
        elif command.phase is CoolingPhase.WARMING:
            self._warming_since = now
            log.info(
                "%s: warming up to %.1f °C at %g °C/min",
                self.name,
                self._warm_temperature or _UNKNOWN_WARM,
                plan.ramp_rate,
            )
        elif before is CoolingPhase.WARMING:
            if self._warming_since is not None and now - self._warming_since >= plan.warm_up_time_limit:
                log.warning(
                    "%s: warm-up not done after %g s (chip at %.1f °C): cooler off",
                    self.name,
                    plan.warm_up_time_limit,
                    temperature,
                )
            else:
                log.info("%s: warm at %.1f °C: cooler off", self.name, temperature)
            self._warming_since = None


def cooling_reach_problems(files: Iterable[Path]) -> list[str]:
    """For the module files of one observatory: a line per cooling schedule whose set point is
    below what its camera (a module file among ``files``, by name) says it can reach."""
    modules = module_configs(files)
    problems = []
    for path, config in modules.values():
        try:
            if not issubclass(import_class(str(config["class"])), CoolingSchedule):
                continue
            camera_path, camera = modules[str(config.get("camera", "camera"))]
            camera_class = import_class(str(camera["class"]))
        except (ConfigError, KeyError, ClassResolutionError):
            continue  # no such camera here, or a class the file's own check names
        if not issubclass(camera_class, BaseCamera):
            continue
        try:
            coldest = camera_class.coldest_setpoint(camera)
        except (TypeError, ValueError, ArithmeticError):
            continue  # a malformed cooler the camera file's own check names
        setpoint = config.get("setpoint", -10.0)
        if coldest is not None and isinstance(setpoint, int | float) and setpoint < coldest:
            problems.append(
                f"{path}: key 'setpoint': {setpoint:g} °C is below the {coldest:g} °C the camera of "
                f"{camera_path} can reach (its cooler: ambient - max_delta)"
            )
    return problems
