"""Requests and request groups: what a user submits.

A :class:`RequestGroup` (name, proposal, observation type, priority, IPP) holds one or more
:class:`Request` values. A request is the unit the scheduler places: it must run in one go, on a
telescope matching its :class:`Location`, inside one of its :class:`Window` intervals, and does its
configurations in order. Each request becomes one task in an archive; a cadence request becomes
one per visit (:mod:`._cadence`).
"""

from __future__ import annotations

from collections.abc import Iterator
from datetime import datetime
from enum import StrEnum
from typing import Self

from pydantic import Field, field_validator, model_validator

from nightcrew.robotic.tasks._base import Number, TaskModel, UtcDatetime, raise_problems
from nightcrew.robotic.tasks._cadence import Cadence
from nightcrew.robotic.tasks._configuration import Configuration
from nightcrew.robotic.tasks._moving import epoch_problems

__all__ = ["Location", "ObservationType", "Request", "RequestGroup", "Window"]


class ObservationType(StrEnum):
    """How urgent a request group is (as in the LCO portal)."""

    NORMAL = "NORMAL"
    TIME_CRITICAL = "TIME_CRITICAL"
    RAPID_RESPONSE = "RAPID_RESPONSE"


class Location(TaskModel):
    """Which telescopes may do a request: a class (e.g. ``0m4``), optionally narrowed down."""

    telescope_class: str = Field(min_length=1)
    site: str | None = None
    enclosure: str | None = None
    telescope: str | None = None


class Window(TaskModel):
    """An interval in which a request may be done; times without a zone are UTC."""

    start: UtcDatetime
    end: UtcDatetime

    @model_validator(mode="after")
    def _check_order(self) -> Self:
        if self.end <= self.start:
            raise_problems([("end", f"must be after start ({self.start.isoformat()})")])
        return self


class Request(TaskModel):
    """Configurations done in one go on one telescope, inside one of the windows.

    Args:
        location: Where it may run.
        windows: When it may run (at least one, unless a cadence gives them).
        configurations: What to do, in order (at least one).
        acceptability_threshold: Per cent of the exposure time that must be done for the request
            to count as completed, 0..100.
        observation_note: Free text for the observer.
        cadence: Repeat the request (instead of ``windows``); the group expands it into one
            request per visit, each with its one window and this cadence (see :mod:`._cadence`).
    """

    location: Location
    windows: tuple[Window, ...] = ()
    configurations: tuple[Configuration, ...] = Field(min_length=1)
    acceptability_threshold: Number = Field(default=90.0, ge=0.0, le=100.0)
    observation_note: str = ""
    cadence: Cadence | None = None

    @model_validator(mode="after")
    def _check_windows(self) -> Self:
        raise_problems(self._window_problems())
        return self

    def _window_problems(self) -> Iterator[tuple[str, str]]:
        if self.cadence is None:
            if not self.windows:
                yield "windows", "at least one window is needed (or a cadence)"
            return
        if len(self.windows) > 1:  # one: a visit of an expanded cadence
            yield "cadence", "a cadence request gives no windows of its own (its cadence makes them)"
        exposures = self.exposure_seconds
        if exposures > self.cadence.period * 3600.0:
            yield (
                "cadence.period",
                (f"{self.cadence.period:g} h is shorter than the request's {exposures:,.0f} s of exposures"),
            )
        elif exposures > self.cadence.jitter * 3600.0:
            yield (
                "cadence.jitter",
                (
                    f"a window of {self.cadence.jitter:g} h cannot hold the request's "
                    f"{exposures:,.0f} s of exposures"
                ),
            )

    @property
    def exposure_seconds(self) -> float:
        """Shutter time of the whole request (a REPEAT_EXPOSE configuration: its repeat duration)."""
        return sum(
            c.repeat_duration
            if c.repeat_duration is not None
            else sum(i.exposure_time * i.exposure_count for i in c.instrument_configs)
            for c in self.configurations
        )

    def visits(self) -> tuple[Request, ...]:
        """The request itself, or for a cadence not yet expanded one request per visit."""
        if self.cadence is None or self.windows:
            return (self,)
        return tuple(
            self.model_copy(update={"windows": (Window(start=start, end=end),)})
            for start, end in self.cadence.windows()
        )

    @model_validator(mode="after")
    def _check_elements_epochs(self) -> Self:
        targets = [(f"configurations[{i}].target", c.target) for i, c in enumerate(self.configurations)]
        raise_problems(epoch_problems(targets, self.first_start, self.last_end))
        return self

    @property
    def first_start(self) -> datetime:
        """Start of the earliest window."""
        return min(window.start for window in self.windows)

    @property
    def last_end(self) -> datetime:
        """End of the latest window: after it the request can no longer be done."""
        return max(window.end for window in self.windows)


class RequestGroup(TaskModel):
    """Requests submitted together.

    Args:
        name: For people, 1..100 characters.
        proposal: The proposal (programme) it belongs to.
        observation_type: How urgent it is.
        priority: Weight for the scheduler (larger goes first), > 0 and <= 1,000,000.
        ipp: Intra-proposal priority, 0.5..2.0: scales ``priority`` within the proposal.
        requests: At least one.
    """

    name: str = Field(min_length=1, max_length=100)
    proposal: str = Field(min_length=1)
    observation_type: ObservationType = ObservationType.NORMAL
    priority: Number = Field(default=1.0, gt=0.0, le=1_000_000.0)
    ipp: Number = Field(default=1.0, ge=0.5, le=2.0)
    requests: tuple[Request, ...] = Field(min_length=1)

    @field_validator("requests", mode="after")
    @classmethod
    def _expand_cadences(cls, requests: tuple[Request, ...]) -> tuple[Request, ...]:
        # Expanded when built, so no request without windows reaches an archive or the scheduler.
        return tuple(visit for request in requests for visit in request.visits())

    @model_validator(mode="after")
    def _check_names_fit(self) -> Self:
        raise_problems(self._blank_problems())
        return self

    def _blank_problems(self) -> Iterator[tuple[str, str]]:
        # min_length accepts "  "; a name of spaces cannot be told apart in a table.
        if not self.name.strip():
            yield "name", "must not be blank"
        if not self.proposal.strip():
            yield "proposal", "must not be blank"
