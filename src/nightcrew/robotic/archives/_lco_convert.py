"""Between the LCO portal's JSON and the task model (pure functions, no I/O).

The portal's request groups become :class:`RequestGroup` values through the same validation as a
file (so a bad one names its field); its ids stay with them: the request id is the task id, and
the configuration ids are needed to create observations. Our schedule and progress become the
portal's observation and configuration-status documents.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Any

from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import ObservationType, Task, TaskProgress, parse_request_group, tasks_of_group

__all__ = ["PortalTasks", "configuration_status_updates", "observation_document", "tasks_from_portal"]

#: The portal's target fields we keep (sidereal targets only).
_TARGET_FIELDS = ("name", "ra", "dec", "proper_motion_ra", "proper_motion_dec", "epoch", "parallax")


@dataclass(frozen=True)
class PortalTasks:
    """The tasks of one portal request group, with each task's configuration ids."""

    tasks: list[Task]
    configuration_ids: dict[str, list[int]]


def tasks_from_portal(group: dict[str, Any], *, source: str) -> PortalTasks:
    """Validate one request group as the portal sends it; InvalidTaskError names the field."""
    requests = group.get("requests") or []
    data = {
        "name": group.get("name"),
        "proposal": group.get("proposal"),
        "observation_type": _observation_type(group.get("observation_type")),
        "ipp": min(2.0, max(0.5, float(group.get("ipp_value") or 1.0))),
        "requests": [_request(request) for request in requests],
    }
    model = parse_request_group(data, source=f"{source} request group {group.get('id')}")
    task_ids = [str(request["id"]) for request in requests]
    tasks = tasks_of_group(model, str(group.get("id")), task_ids)
    configuration_ids = {
        str(request["id"]): [int(c["id"]) for c in request.get("configurations", [])] for request in requests
    }
    return PortalTasks(tasks, configuration_ids)


def _observation_type(value: object) -> str:
    # DIRECT and REAL_TIME groups are never schedulable; anything unknown is treated as NORMAL.
    names = {t.value for t in ObservationType}
    return str(value) if value in names else ObservationType.NORMAL.value


def _request(request: dict[str, Any]) -> dict[str, Any]:
    location = {k: v for k, v in (request.get("location") or {}).items() if v not in (None, "")}
    return {
        "location": {
            k: location[k] for k in ("telescope_class", "site", "enclosure", "telescope") if k in location
        },
        "windows": [{"start": w.get("start"), "end": w.get("end")} for w in request.get("windows") or []],
        "configurations": [_configuration(c) for c in request.get("configurations") or []],
        "acceptability_threshold": request.get("acceptability_threshold", 90.0),
        "observation_note": request.get("observation_note") or "",
    }


def _configuration(configuration: dict[str, Any]) -> dict[str, Any]:
    target = configuration.get("target") or {}
    constraints = {
        k: v
        for k, v in (configuration.get("constraints") or {}).items()
        if k in ("max_airmass", "min_lunar_distance", "max_lunar_phase") and v is not None
    }
    acquisition = configuration.get("acquisition_config") or {}
    guiding = configuration.get("guiding_config") or {}
    result: dict[str, Any] = {
        "type": configuration.get("type"),
        "instrument_type": configuration.get("instrument_type") or "",
        "constraints": constraints,
        "acquisition_config": {
            "mode": _acquisition_mode(acquisition.get("mode")),
            "extra_params": acquisition.get("extra_params") or {},
        },
        "guiding_config": {
            "mode": "OFF" if guiding.get("mode", "OFF") == "OFF" else "ON",
            "optional": bool(guiding.get("optional", True)),
            "exposure_time": guiding.get("exposure_time"),
            "extra_params": guiding.get("extra_params") or {},
        },
        "instrument_configs": [_instrument_config(i) for i in configuration.get("instrument_configs") or []],
        "extra_params": configuration.get("extra_params") or {},
    }
    if target.get("ra") is not None:
        result["target"] = {k: target[k] for k in _TARGET_FIELDS if target.get(k) is not None}
    if configuration.get("repeat_duration") is not None:
        result["repeat_duration"] = configuration["repeat_duration"]
    return result


def _acquisition_mode(mode: object) -> str:
    # The portal's instrument-specific modes mean "acquire somehow": ON.
    if mode in (None, "", "OFF"):
        return "OFF"
    return str(mode) if mode in ("WCS", "BRIGHTEST") else "ON"


def _instrument_config(instrument_config: dict[str, Any]) -> dict[str, Any]:
    extra = dict(instrument_config.get("extra_params") or {})
    binning = extra.pop("bin_x", 1)
    extra.pop("bin_y", None)
    return {
        "exposure_time": instrument_config.get("exposure_time"),
        "exposure_count": instrument_config.get("exposure_count"),
        "optical_elements": {k: str(v) for k, v in (instrument_config.get("optical_elements") or {}).items()},
        "binning": binning,
        "extra_params": extra,
    }


def observation_document(
    entry: PlannedSlot,
    configuration_ids: list[int],
    *,
    site: str,
    enclosure: str,
    telescope: str,
    instrument_name: str,
    guide_camera_name: str | None,
) -> dict[str, Any]:
    """The portal's observation for one planned slot (``POST /api/observations/``)."""
    statuses = []
    for configuration_id in configuration_ids:
        status: dict[str, Any] = {"configuration": configuration_id, "instrument_name": instrument_name}
        if guide_camera_name:
            status["guide_camera_name"] = guide_camera_name
        statuses.append(status)
    return {
        "request": int(entry.task_id),
        "site": site,
        "enclosure": enclosure,
        "telescope": telescope,
        "start": entry.start.isoformat(),
        "end": entry.end.isoformat(),
        "configuration_statuses": statuses,
    }


def configuration_status_updates(
    task: Task,
    progress: TaskProgress,
    *,
    reason: str,
    start: datetime,
    end: datetime,
    before: TaskProgress | None = None,
) -> list[dict[str, Any]]:
    """One ``PATCH`` body per configuration: COMPLETED, FAILED (partly done) or NOT_ATTEMPTED.

    ``progress`` is the request's whole progress, ``before`` what it was when this observation
    started (a retry after an interruption): the state says whether the configuration is complete
    now, ``time_completed`` and FAILED vs NOT_ATTEMPTED count only what this observation took.
    """
    updates = []
    for index, configuration in enumerate(task.request.configurations):
        done = [
            progress.count(index, i) - (before.count(index, i) if before else 0)
            for i in range(len(configuration.instrument_configs))
        ]
        if progress.configuration_complete(task.request, index) and (
            configuration.instrument_configs or not reason
        ):
            state = "COMPLETED"
        elif any(done):
            state = "FAILED"
        else:
            state = "NOT_ATTEMPTED" if reason else "COMPLETED"
        seconds = sum(
            n * ic.exposure_time for n, ic in zip(done, configuration.instrument_configs, strict=True)
        )
        summary: dict[str, Any] = {
            "start": start.isoformat(),
            "end": end.isoformat(),
            "state": state,
            "reason": reason if state != "COMPLETED" else "",
            "time_completed": seconds,
            "events": {},
        }
        updates.append({"state": state, "summary": summary})
    return updates
