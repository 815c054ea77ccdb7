"""Search by time, object, cone, filter, image type, exposure time, proposal, task and level, with
LCO-style paging; parameters out of range get a 400 naming them."""

from __future__ import annotations

from typing import Any

import pytest

from nightcrew.testing.archive import fits_frame

from .conftest import Client

# name, DATE-OBS, OBJECT, FILTER, IMAGETYP, EXPTIME, RA, DEC, PROPOSAL, TASK-NAM
FRAMES = [
    ("m13-v.fits", "2026-11-24T20:00:00", "M 13", "V", "object", 30.0, 250.42, 36.46, "P1", "m13-survey"),
    ("m13-r.fits", "2026-11-24T20:05:00", "M 13", "R", "object", 60.0, 250.42, 36.46, "P1", "m13-survey"),
    ("m57-v.fits", "2026-11-24T22:00:00", "M 57", "V", "object", 120.0, 283.40, 33.03, "P2", "m57-deep"),
    ("near-pole.fits", "2026-11-25T01:00:00", "NCP", "V", "object", 10.0, 10.0, 89.9, "P2", "polar"),
    ("bias-1.fits", "2026-11-24T18:00:00", None, None, "bias", 0.0, None, None, None, None),
    ("flat-v.fits", "2026-11-24T17:00:00", None, "V", "skyflat", 5.0, None, None, None, None),
]


@pytest.fixture
async def filled(client: Client) -> Client:
    for seed, (name, date, obj, filt, kind, exptime, ra, dec, proposal, task) in enumerate(FRAMES):
        cards: dict[str, Any] = {
            "OBJECT": obj,
            "FILTER": filt,
            "RA": ra,
            "DEC": dec,
            "PROPOSAL": proposal,
            "TASK_NAM": task,
        }
        data = fits_frame(
            date_obs=date,
            imagetyp=kind,
            exptime=exptime,
            seed=seed,
            **{k: v for k, v in cards.items() if v is not None},
        )
        status, body = await client.upload(data, name)
        assert status == 201, body
    return client


async def names(client: Client, **params: object) -> list[str]:
    status, body = await client.get("/frames/", **params)
    assert status == 200, body
    assert body["count"] == len(body["results"])
    return sorted(frame["basename"] for frame in body["results"])


async def test_each_search_parameter_narrows_the_result(filled: Client) -> None:
    assert len(await names(filled)) == len(FRAMES)
    assert await names(filled, start="2026-11-24T19:00", end="2026-11-24T21:00") == [
        "m13-r.fits",
        "m13-v.fits",
    ]
    assert await names(filled, OBJECT="M 57") == ["m57-v.fits"]
    assert await names(filled, FILTER="V", IMAGETYP="OBJECT") == [
        "m13-v.fits",
        "m57-v.fits",
        "near-pole.fits",
    ]
    assert await names(filled, OBSTYPE="bias") == ["bias-1.fits"]
    assert await names(filled, EXPTIME_MIN=30, EXPTIME_MAX=60) == ["m13-r.fits", "m13-v.fits"]
    assert await names(filled, PROPID="P2") == ["m57-v.fits", "near-pole.fits"]
    assert await names(filled, TASK="m13-survey") == ["m13-r.fits", "m13-v.fits"]
    assert await names(filled, RLEVEL=0) == sorted(f[0] for f in FRAMES)
    assert await names(filled, RLEVEL=91) == []
    assert await names(filled, basename="flat-v.fits") == ["flat-v.fits"]


async def test_a_cone_finds_frames_within_its_radius_also_across_ra_zero_and_the_pole(filled: Client) -> None:
    assert await names(filled, ra=250.0, dec=36.5, radius=0.5) == ["m13-r.fits", "m13-v.fits"]
    assert await names(filled, ra=250.0, dec=36.5, radius=0.2) == []  # 0.34 deg away
    assert await names(filled, ra=190.0, dec=89.95, radius=0.2) == ["near-pole.fits"]  # 180 deg of RA apart
    assert await names(filled, ra=250.0, dec=36.5, radius=0.5, start="2026-11-24T20:02", FILTER="R") == [
        "m13-r.fits"
    ]


async def test_pages_follow_the_lco_count_next_previous_shape(filled: Client) -> None:
    status, first = await filled.get("/frames/", limit=4, ordering="DATE_OBS")
    assert status == 200 and first["count"] == 6 and first["previous"] is None
    assert [f["basename"] for f in first["results"]] == [
        "flat-v.fits",
        "bias-1.fits",
        "m13-v.fits",
        "m13-r.fits",
    ]
    async with filled.http.get(first["next"]) as response:
        second = await response.json()
    assert [f["basename"] for f in second["results"]] == ["m57-v.fits", "near-pole.fits"]
    assert second["next"] is None and "offset=0" in second["previous"]


BAD_PARAMETERS = [
    ({"dec": "91", "ra": "1", "radius": "1"}, "dec must be within -90..90, got '91'"),
    ({"ra": "360", "dec": "0", "radius": "1"}, "ra < 360"),
    ({"ra": "10"}, "a cone search needs all of ra, dec and radius"),
    ({"radius": "-1", "ra": "1", "dec": "1"}, "radius must be within 0..180"),
    ({"limit": "0"}, "limit must be within 1..1000, got '0'"),
    ({"limit": "many"}, "limit must be an integer, got 'many'"),
    ({"start": "2026-11-25", "end": "2026-11-24"}, "start (2026-11-25) must be before end (2026-11-24)"),
    ({"start": "last night"}, "start must be an ISO date"),
    ({"RLEVEL": "300"}, "RLEVEL must be within 0..255"),
    ({"EXPTIME_MIN": "nan"}, "EXPTIME_MIN must be within"),
    ({"colour": "red"}, "unknown search parameter 'colour'"),
    ({"ordering": "size"}, "ordering must be one of"),
]


async def test_search_parameters_out_of_range_are_a_400_naming_them(client: Client) -> None:
    for params, message in BAD_PARAMETERS:
        status, body = await client.get("/frames/", **params)
        assert (status, body["error"]) == (400, "Bad Request"), params
        assert message in body["detail"], (params, body)
