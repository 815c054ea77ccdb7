"""Reading notices and the rules that turn them into rapid-response requests (pure)."""

from __future__ import annotations

from datetime import UTC, datetime

import pytest

from nightcrew.modules.alerts import AlertRules, NoticeError, Rejected, parse_notice, request_for
from nightcrew.robotic.tasks import ObservationType, Target
from nightcrew.site import Site

from .voevents import STREAM, notice

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
EVENING = datetime(2024, 1, 15, 20, 0, tzinfo=UTC)  # the Pleiades are high, the Sun far down
RULES = AlertRules(field_of_view=0.5, notice_types=("61",), priority=80.0)


def test_a_grb_position_notice_is_read() -> None:
    read = parse_notice(notice("pos1", error=0.05))
    assert (read.ivorn, read.role, read.notice_type, read.trigger) == (
        f"{STREAM}#pos1",
        "observation",
        "61",
        "1001",
    )
    assert (read.ra, read.dec, read.error_radius) == (56.75, 24.12, 0.05)
    assert read.time == datetime(2024, 1, 15, 20, 0, tzinfo=UTC) and not read.retraction


def test_a_retraction_needs_no_position_and_cites_its_event() -> None:
    read = parse_notice(notice("retr", ra=None, retraction=True, cites=(("retraction", f"{STREAM}#pos1"),)))
    assert read.retraction and read.cited == (f"{STREAM}#pos1",) and read.ra is None


@pytest.mark.parametrize(
    ("payload", "message"),
    [
        (b"<VOEvent><oops", "not well-formed XML"),
        (b"<html/>", "not a VOEvent"),
        (notice("bad", dec=120.0), r"#bad: coordinates out of range \(ra 56\.75, dec 120\)"),
        (notice("nowhere", ra=None), r"#nowhere: no position"),
    ],
)
def test_a_malformed_notice_is_one_clear_error(payload: bytes, message: str) -> None:
    with pytest.raises(NoticeError, match=message):
        parse_notice(payload)


def test_a_notice_becomes_a_rapid_response_request_at_its_position() -> None:
    group = request_for(parse_notice(notice("pos1")), RULES, SITE, EVENING)
    assert group.observation_type is ObservationType.RAPID_RESPONSE and group.priority == 80.0
    (request,) = group.requests
    target = request.configurations[0].target
    assert isinstance(target, Target) and (target.ra, target.dec) == (56.75, 24.12)
    assert request.windows[0].start == EVENING


@pytest.mark.parametrize(
    ("payload", "reason"),
    [
        (notice("t", role="test"), "role 'test' is not one of observation"),
        (notice("x", packet_type=62), "notice type '62' is not one of 61"),
        (notice("wide", error=2.0), "error radius 2° is larger than 0.25°"),
        (notice("south", ra=83.0, dec=-80.0), "not observable within 2 h"),
    ],
)
def test_the_rules_say_why_a_notice_is_not_observed(payload: bytes, reason: str) -> None:
    with pytest.raises(Rejected, match=reason):
        request_for(parse_notice(payload), RULES, SITE, EVENING)


def test_bad_rules_name_the_field() -> None:
    with pytest.raises(ValueError, match="field_of_view"):
        AlertRules.model_validate({"field_of_view": -1})
    with pytest.raises(ValueError, match="exposures"):
        AlertRules.model_validate({"field_of_view": 0.5, "exposures": [{"exposure_time": "long"}]})
