"""The task model: request groups, requests, configurations, and tasks with their states.

A user submits a :class:`RequestGroup` (LCO-portal style)::

    RequestGroup  name, proposal, observation_type, priority, ipp
    └── Request   location, windows or cadence, acceptability_threshold  (one task each;
        │         a cadence: one per visit)
        └── Configuration  type, target, constraints, acquisition_config, guiding_config, dither_config,
            │              repeat_duration, extra_params
            └── InstrumentConfig  exposure_time, exposure_count, optical_elements, binning

:func:`parse_request_group` / :func:`load_request_group_file` validate plain data; a bad group
raises :class:`InvalidTaskError` whose problems name each field by its path
(``requests[0].configurations[1].instrument_configs[0].exposure_time: must be > 0``).
:func:`estimate_duration` adds exposures, read-outs and an :class:`OverheadModel`. Archives hand out
:class:`Task` values (one request plus its group's data and a :class:`TaskStatus`), whose state
changes go through :meth:`TaskStatus.transition` (see :data:`ALLOWED_TRANSITIONS`).

The models are pydantic v2 classes: they validate when built (so no half-valid task exists), give
the failing field's path for free, and (de)serialise to the JSON the archives store and the LCO
portal speaks.
"""

from __future__ import annotations

from nightcrew.robotic.tasks._cadence import MAX_CADENCE_VISITS, Cadence, cadence_visit
from nightcrew.robotic.tasks._configuration import (
    AcquisitionConfig,
    AcquisitionMode,
    AnyTarget,
    Configuration,
    ConfigurationType,
    Constraints,
    DitherConfig,
    DitherPattern,
    GuidingConfig,
    GuidingMode,
    InstrumentConfig,
    Target,
)
from nightcrew.robotic.tasks._duration import (
    DEFAULT_OVERHEADS,
    DurationEstimate,
    OverheadModel,
    configuration_duration,
    estimate_duration,
)
from nightcrew.robotic.tasks._errors import (
    InvalidTaskError,
    InvalidTransitionError,
    TaskError,
    TaskNotFoundError,
    TaskProblem,
)
from nightcrew.robotic.tasks._moving import (
    MajorBodyTarget,
    MovingTarget,
    MpcElementsTarget,
    OrbitalElementsScheme,
    OrbitalElementsTarget,
    SatelliteTarget,
    target_radec,
)
from nightcrew.robotic.tasks._request import Location, ObservationType, Request, RequestGroup, Window
from nightcrew.robotic.tasks._state import (
    ALLOWED_TRANSITIONS,
    FINAL_STATES,
    SCHEDULABLE_STATES,
    CutShortFrame,
    TaskProgress,
    TaskState,
    TaskStatus,
)
from nightcrew.robotic.tasks._task import Task, cadence_progress, cadence_summaries, tasks_of_group
from nightcrew.robotic.tasks._validation import (
    filled_defaults,
    load_request_group_file,
    parse_request_group,
    request_group_schema,
)

__all__ = [
    "ALLOWED_TRANSITIONS",
    "DEFAULT_OVERHEADS",
    "FINAL_STATES",
    "MAX_CADENCE_VISITS",
    "SCHEDULABLE_STATES",
    "AcquisitionConfig",
    "AcquisitionMode",
    "AnyTarget",
    "Cadence",
    "Configuration",
    "ConfigurationType",
    "Constraints",
    "CutShortFrame",
    "DitherConfig",
    "DitherPattern",
    "DurationEstimate",
    "GuidingConfig",
    "GuidingMode",
    "InstrumentConfig",
    "InvalidTaskError",
    "InvalidTransitionError",
    "Location",
    "MajorBodyTarget",
    "MovingTarget",
    "MpcElementsTarget",
    "ObservationType",
    "OrbitalElementsScheme",
    "OrbitalElementsTarget",
    "OverheadModel",
    "Request",
    "RequestGroup",
    "SatelliteTarget",
    "Target",
    "Task",
    "TaskError",
    "TaskNotFoundError",
    "TaskProblem",
    "TaskProgress",
    "TaskState",
    "TaskStatus",
    "Window",
    "cadence_progress",
    "cadence_summaries",
    "cadence_visit",
    "configuration_duration",
    "estimate_duration",
    "filled_defaults",
    "load_request_group_file",
    "parse_request_group",
    "request_group_schema",
    "target_radec",
    "tasks_of_group",
]
