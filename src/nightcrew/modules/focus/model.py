"""A focus model: predicts the best focus from temperatures and keeps the focuser there.

The model is a formula (see :mod:`nightcrew.focus.expression`) over temperature variables read from
other modules and free coefficients, e.g. ``a*T_mirror + b*T_tube + c*temp + d``. Every
FocusFoundEvent (a focus series' result) is stored with the temperatures of that moment; with
``refit`` the coefficients are fitted anew by weighted linear least squares over that history, so
the model follows the telescope as it ages. Only models linear in their coefficients (a sum of
terms each multiplied by at most one coefficient) can be refitted; others are refused at start-up.

Per-filter offsets (``filter_offsets``) are added to the prediction for the filter in the beam; a
measured focus has its filter's offset removed before fitting, so all filters teach one model.
The history lives in a VFS file (``history_file``) and survives restarts.
"""

from __future__ import annotations

import asyncio
import logging
import math
from typing import Any

from nightcrew.errors import ConfigError, ModuleError, NightcrewError
from nightcrew.events import FocusFoundEvent
from nightcrew.focus import (
    Expression,
    ExpressionError,
    FocusRecord,
    check_linear,
    fit_coefficients,
    records_from_plain,
    records_to_plain,
)
from nightcrew.focus.sources import TemperatureSource, sources_from_config
from nightcrew.interfaces import IFilters, IFocuser, IFocusModel, ModuleState
from nightcrew.interfaces.quantities import Period
from nightcrew.modules.module import Module
from nightcrew.robotic.temperature_source import read_temperature

__all__ = ["FocusModel"]

log = logging.getLogger(__name__)


class FocusModel(Module, IFocusModel):
    """Predicts the best focus from temperatures; learns from FocusFoundEvents.

    Args:
        focuser: Module offering IFocuser, moved by :meth:`set_optimal_focus`.
        model: The formula in mm, e.g. ``a*T_mirror + b*temp + c``.
        coefficients: Value of every coefficient in the formula (starting values when refitted).
        temperatures: Variable → source, e.g. ``{T_mirror: {module: telescope, sensor: mirror},
            temp: {module: weather, weather_sensor: temperature}}`` (see :mod:`nightcrew.focus.sources`).
        refit: Refit all coefficients from the history when it has ``min_measurements`` entries.
        min_measurements: Fewest measurements to fit from; default: number of coefficients + 2.
        max_history: Most recent measurements kept (and fitted).
        history_file: VFS path (YAML) of the history; None keeps it in memory only.
        interval: Clock seconds between two automatic focus settings; None: only on request.
        filter_offsets: Filter name → mm added to the prediction (absent filters: 0).
        filter_wheel: Module offering IFilters, asked for the current filter (needed for offsets).
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        focuser: str | IFocuser,
        model: str,
        coefficients: dict[str, float],
        temperatures: dict[str, dict[str, str]],
        refit: bool = True,
        min_measurements: int | None = None,
        max_history: int = 500,
        history_file: str | None = None,
        interval: Period | None = 600.0,
        filter_offsets: dict[str, float] | None = None,
        filter_wheel: str | IFilters | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        try:
            self._model = Expression(model)
        except ExpressionError as exc:
            raise ConfigError(str(exc), key="model") from None
        self._sources: dict[str, TemperatureSource] = sources_from_config(temperatures, "temperatures")
        self._coefficients = {str(k): float(v) for k, v in coefficients.items()}
        _check_names(self._model, self._coefficients, self._sources)
        if refit:
            try:
                check_linear(self._model, list(self._coefficients))
            except ExpressionError as exc:
                raise ConfigError(str(exc), key="model") from None
        self._refit = refit
        self._min_measurements = len(self._coefficients) + 2 if min_measurements is None else min_measurements
        if self._min_measurements < len(self._coefficients) or self._min_measurements < 1:
            raise ConfigError(
                f"must be at least the number of coefficients ({len(self._coefficients)})",
                key="min_measurements",
            )
        if max_history < self._min_measurements:
            raise ConfigError(f"must be >= min_measurements ({self._min_measurements})", key="max_history")
        if interval is not None and not interval > 0:
            raise ConfigError(f"must be > 0 seconds or null, got {interval}", key="interval")
        self._filter_offsets = {str(k): float(v) for k, v in (filter_offsets or {}).items()}
        if self._filter_offsets and filter_wheel is None:
            raise ConfigError("filter offsets need a filter_wheel to know the filter", key="filter_wheel")
        self._focuser, self._filter_wheel = focuser, filter_wheel
        self._max_history, self._history_file, self._interval = max_history, history_file, interval
        self._history: list[FocusRecord] = []
        self._history_lock = asyncio.Lock()
        if interval is not None:
            self.add_background_task(self._apply_loop)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await self._load_history()
        await super().open()
        await self.comm.register_event(FocusFoundEvent, self.on_focus_found)

    # --- IFocusModel ---------------------------------------------------------------------------

    async def get_optimal_focus(self) -> float:
        temperatures = await self._read_temperatures()
        filter_name = await self._current_filter()
        focus = self._model.evaluate({**self._coefficients, **temperatures})
        return focus + self._filter_offsets.get(filter_name or "", 0.0)

    async def set_optimal_focus(self) -> None:
        focus = await self.get_optimal_focus()
        focuser = await self.proxy(self._focuser, IFocuser)
        log.info("%s: setting focus to %.4f mm", self.name, focus)
        await focuser.set_focus(focus)

    # --- learning ------------------------------------------------------------------------------

    async def on_focus_found(self, event: FocusFoundEvent, sender: str) -> None:
        """Store the measurement with the temperatures of now, then refit."""
        if not (math.isfinite(event.focus) and math.isfinite(event.error) and event.error >= 0):
            log.warning("%s: ignoring focus %r ± %r from %s", self.name, event.focus, event.error, sender)
            return
        try:
            temperatures = await self._read_temperatures()
        except NightcrewError as exc:
            log.warning("%s: focus %.4f from %s not stored: %s", self.name, event.focus, sender, exc)
            return
        record = FocusRecord(self.clock.now(), event.focus, event.error, event.filter_name, temperatures)
        async with self._history_lock:
            history = [*self._history, record][-self._max_history :]
            await self._save_history(history)
            # Stored first, then seen: whoever sees the new record also sees the refit.
            self._history = history
            self._fit(history)

    def _fit(self, history: list[FocusRecord]) -> None:
        if not self._refit:
            return
        usable = [r for r in history if set(self._sources) <= set(r.temperatures)]
        if len(usable) < self._min_measurements:
            log.info("%s: %d of %d measurements to fit from", self.name, len(usable), self._min_measurements)
            return
        try:
            fit = fit_coefficients(
                self._model,
                list(self._coefficients),
                [r.temperatures for r in usable],
                [r.focus - self._filter_offsets.get(r.filter_name or "", 0.0) for r in usable],
                [r.error for r in usable],
            )
        except (ExpressionError, ValueError) as exc:
            log.warning("%s: refit failed, keeping the coefficients: %s", self.name, exc)
            return
        self._coefficients = fit.coefficients
        values = ", ".join(f"{k}={v:.6g}±{fit.uncertainties[k]:.2g}" for k, v in fit.coefficients.items())
        log.info("%s: refitted from %d measurements: %s, rms %.4f mm", self.name, fit.count, values, fit.rms)

    @property
    def coefficients(self) -> dict[str, float]:
        """The coefficients in use (fitted or configured)."""
        return dict(self._coefficients)

    @property
    def history(self) -> list[FocusRecord]:
        return list(self._history)

    def _get_config_coefficients(self) -> dict[str, float]:
        return self.coefficients

    # --- background ----------------------------------------------------------------------------

    async def _apply_loop(self) -> None:
        assert self._interval is not None
        while True:
            try:
                await self.set_optimal_focus()
            except NightcrewError as exc:  # fail safe: leave the focuser where it is
                log.warning("%s: focus not set: %s", self.name, exc)
            await self.clock.sleep(self._interval)

    # --- reading -------------------------------------------------------------------------------

    async def _read_temperatures(self) -> dict[str, float]:
        names = list(self._sources)
        values = await asyncio.gather(*(self._read(name, self._sources[name]) for name in names))
        return dict(zip(names, values, strict=True))

    async def _read(self, variable: str, source: TemperatureSource) -> float:
        try:
            return await read_temperature(self, source)
        except ModuleError as exc:
            raise ModuleError(f"no value for {variable} ({exc})") from None

    async def _current_filter(self) -> str | None:
        if self._filter_wheel is None:
            return None
        return await (await self.proxy(self._filter_wheel, IFilters)).get_filter()

    # --- persistence ---------------------------------------------------------------------------

    async def _load_history(self) -> None:
        path = self._history_file
        if path is None or not await self.vfs.exists(path):
            return
        try:
            loaded = await self.vfs.read_yaml(path)
        except NightcrewError as exc:
            log.error("%s: cannot read focus history %s, starting afresh: %s", self.name, path, exc)
            return
        records, problems = records_from_plain(loaded)
        for problem in problems:
            log.warning("%s: %s: skipped %s", self.name, path, problem)
        self._history = records[-self._max_history :]
        log.info("%s: loaded %d focus measurements from %s", self.name, len(self._history), path)
        self._fit(self._history)

    async def _save_history(self, history: list[FocusRecord]) -> None:
        if self._history_file is None:
            return
        try:
            await self.vfs.write_yaml(self._history_file, records_to_plain(history))
        except NightcrewError as exc:
            log.error("%s: cannot write focus history %s: %s", self.name, self._history_file, exc)


def _check_names(
    model: Expression, coefficients: dict[str, float], sources: dict[str, TemperatureSource]
) -> None:
    """Every name in the model is a coefficient or a variable, and nothing is both or unused."""
    both = sorted(set(coefficients) & set(sources))
    if both:
        raise ConfigError(f"{', '.join(both)} cannot be both coefficient and temperature", key="coefficients")
    unknown = sorted(model.names - set(coefficients) - set(sources))
    if unknown:
        raise ConfigError(
            f"{', '.join(unknown)} in the model is neither in 'coefficients' nor in 'temperatures'",
            key="model",
        )
    for name, value in coefficients.items():
        if name not in model.names:
            raise ConfigError(
                f"coefficient {name!r} does not appear in the model", key=f"coefficients.{name}"
            )
        if not math.isfinite(value):
            raise ConfigError(f"must be finite, got {value}", key=f"coefficients.{name}")
