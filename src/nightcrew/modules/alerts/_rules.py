"""Rules that turn a notice into a rapid-response request group, or say why not.

:class:`AlertRules` is what an observatory configures (notice types and roles it takes, its field of
view, how soon the target must be observable, the priority and the exposure plan); it is validated
when built, so a bad key fails at start-up. :func:`request_for` applies them to one notice: pure,
with the site and the time passed in.
"""

from __future__ import annotations

from datetime import datetime, timedelta
from typing import Any, Self

from pydantic import BaseModel, ConfigDict, Field, model_validator

from nightcrew.modules.alerts._notice import Notice
from nightcrew.robotic.tasks import InstrumentConfig, RequestGroup, estimate_duration, parse_request_group
from nightcrew.robotic.tasks.visibility import observable_stretches
from nightcrew.site import Site

__all__ = ["AlertRules", "Rejected", "request_for"]


class Rejected(Exception):
    """The notice is fine but asks for nothing here (wrong role or type, too large, not observable)."""


class AlertRules(BaseModel):
    """Which notices become requests, and what is observed for them.

    Args:
        notice_types: Types taken (GCN ``Packet_Type`` numbers as text, or streams); empty: any.
        roles: Roles taken (``observation``; ``test`` only to try the chain out).
        field_of_view: The camera's field of view in degrees (its smaller side).
        max_error_fraction: Largest error radius taken, as a fraction of ``field_of_view`` (0.5:
            the error circle fits in the field).
        observable_within: Hours: the target must be observable now or within this time.
        window: Hours from the notice during which the request may run.
        priority: The request's priority (it pre-empts running tasks of lower priority).
        proposal: The proposal the requests belong to.
        telescope_class: The telescope class of the requests' location.
        max_airmass: The requests' airmass limit.
        exposures: The exposure plan: instrument configurations as in a request file.
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    notice_types: tuple[str, ...] = ()
    roles: tuple[str, ...] = ("observation",)
    field_of_view: float = Field(gt=0.0, le=180.0)
    max_error_fraction: float = Field(default=0.5, gt=0.0)
    observable_within: float = Field(default=2.0, ge=0.0, le=48.0)
    window: float = Field(default=6.0, gt=0.0, le=72.0)
    priority: float = Field(default=100.0, gt=0.0, le=1_000_000.0)
    proposal: str = Field(default="alerts", min_length=1)
    telescope_class: str = Field(default="0m4", min_length=1)
    max_airmass: float = Field(default=2.0, ge=1.0)
    exposures: tuple[InstrumentConfig, ...] = Field(
        default=(InstrumentConfig(exposure_time=60.0, exposure_count=5),), min_length=1
    )

    @model_validator(mode="after")
    def _check(self) -> Self:
        if self.window < self.observable_within:
            raise ValueError(
                f"window ({self.window:g} h) must be at least observable_within "
                f"({self.observable_within:g} h)"
            )
        return self


def request_for(
    notice: Notice, rules: AlertRules, site: Site, now: datetime, note: str | None = None
) -> RequestGroup:
    """The rapid-response request group for ``notice``, received at ``now``; ``note`` is its
    request's ``observation_note`` (default: the notice's IVORN).

    Raises:
        Rejected: Its role or type is not taken, its error circle is larger than the rules allow,
            or its target is not observable within ``observable_within`` hours.
    """
    if notice.role not in rules.roles:
        raise Rejected(f"role {notice.role!r} is not one of {', '.join(rules.roles)}")
    if rules.notice_types and notice.notice_type not in rules.notice_types:
        raise Rejected(f"notice type {notice.notice_type!r} is not one of {', '.join(rules.notice_types)}")
    if notice.ra is None or notice.dec is None or notice.error_radius is None:
        raise Rejected("no position")
    largest = rules.max_error_fraction * rules.field_of_view
    if notice.error_radius > largest:
        raise Rejected(
            f"error radius {notice.error_radius:g}° is larger than {largest:g}° (of the field of view)"
        )
    end = now + timedelta(hours=rules.window)
    group = parse_request_group(_group_data(notice, rules, now, end, note or f"from VOEvent {notice.ivorn}"))
    request = group.requests[0]
    needed = estimate_duration(request).total_s
    latest = now + timedelta(hours=rules.observable_within)
    starts = [
        start
        for start, end in observable_stretches(request, site, now, now + timedelta(hours=rules.window))
        if (end - start).total_seconds() >= needed and start <= latest
    ]
    if not starts:
        raise Rejected(
            f"not observable within {rules.observable_within:g} h (airmass {rules.max_airmass:g}, Sun)"
        )
    return group


def _group_data(
    notice: Notice, rules: AlertRules, start: datetime, end: datetime, note: str
) -> dict[str, Any]:
    name = (notice.ivorn.split("#", 1)[-1].strip() or notice.ivorn)[:100]
    return {
        "name": name,
        "proposal": rules.proposal,
        "observation_type": "RAPID_RESPONSE",
        "priority": rules.priority,
        "requests": [
            {
                "location": {"telescope_class": rules.telescope_class},
                "windows": [{"start": start.isoformat(), "end": end.isoformat()}],
                "observation_note": note,
                "configurations": [
                    {
                        "type": "EXPOSE",
                        "target": {"name": name[:50] or "alert", "ra": notice.ra, "dec": notice.dec},
                        "constraints": {"max_airmass": rules.max_airmass},
                        "instrument_configs": [c.model_dump(mode="json") for c in rules.exposures],
                    }
                ],
            }
        ],
    }
