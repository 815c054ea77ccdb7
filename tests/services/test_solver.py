"""The plate-solving service (``nightcrew solver``, a real astrometry.net engine with the Debian
Tycho-2 indexes) solves rendered frames to the truth and answers bad requests with one clear error."""

from __future__ import annotations

import json
import urllib.error
import urllib.request
from typing import Any

import pytest
from astropy.wcs import WCS  # type: ignore[import-untyped]

from nightcrew.images import Image
from nightcrew.images.astrometry import AstrometryError, RemoteAstrometry, RemoteSolver, SolveHints
from nightcrew.services.solver import SolveRequestError, parse_request
from nightcrew.testing.solver import RenderedField, rendered_field, sky_distance_arcsec


@pytest.fixture(scope="module")
def field() -> RenderedField:
    return rendered_field(100.0, 30.0, rotation_deg=10.0)


def centre_error_arcsec(cards: Any, field: RenderedField) -> float:
    rows, cols = field.shape
    ra, dec = WCS(cards).all_pix2world([(cols - 1) / 2.0], [(rows - 1) / 2.0], 0)
    return sky_distance_arcsec(float(ra[0]), float(dec[0]), field.true_ra_deg, field.true_dec_deg)


def post(url: str, body: bytes) -> tuple[int, dict[str, Any]]:
    request = urllib.request.Request(f"{url}/solve", data=body, headers={"Content-Type": "application/json"})
    try:
        with urllib.request.urlopen(request, timeout=60) as response:
            return response.status, json.loads(response.read())
    except urllib.error.HTTPError as exc:
        return exc.code, json.loads(exc.read())


@pytest.mark.parametrize(
    "hints",
    [SolveHints(100.08, 29.95, 1.0, 1.16, 0.1), SolveHints()],
    ids=["position-and-scale", "blind"],
)
async def test_solves_a_rendered_frame_to_the_truth(
    solver_url: str, field: RenderedField, hints: SolveHints
) -> None:
    client = RemoteSolver(solver_url)
    cards = await client.solve_stars(field.x, field.y, field.flux, shape=field.shape, hints=hints)
    assert cards["CTYPE1"].startswith("RA---TAN")
    assert centre_error_arcsec(cards, field) < 1.0


async def test_the_remote_astrometry_processor_writes_the_wcs(solver_url: str, field: RenderedField) -> None:
    from astropy.table import Table  # type: ignore[import-untyped]

    catalog = Table({"x": field.x, "y": field.y, "flux": field.flux})
    image = Image(field.data, header={"RA": 100.1, "DEC": 30.05, "PIXSCALE": 1.16}, catalog=catalog)
    solved = await RemoteAstrometry(solver=RemoteSolver(solver_url))(image)
    ra, dec = solved.pixel_to_sky([(field.shape[1] - 1) / 2.0], [(field.shape[0] - 1) / 2.0])
    assert sky_distance_arcsec(float(ra[0]), float(dec[0]), 100.0, 30.0) < 1.0


def request_body(field: RenderedField, **changes: Any) -> dict[str, Any]:
    body: dict[str, Any] = {
        "version": 1,
        "width": field.shape[1],
        "height": field.shape[0],
        "stars": {"x": field.x[:50].tolist(), "y": field.y[:50].tolist(), "flux": field.flux[:50].tolist()},
        "hints": {"ra": 100.0, "dec": 30.0, "radius": 1.0, "pixel_scale": 1.16},
    }
    body.update(changes)
    return body


def test_bad_requests_get_one_clear_http_error(solver_url: str, field: RenderedField) -> None:
    status, reply = post(solver_url, b'{"version": 1, "width": ')
    assert status == 400 and "not valid JSON" in reply["error"]
    few = {"x": [1.0, 2.0, 3.0], "y": [1.0, 2.0, 3.0], "flux": [3.0, 2.0, 1.0]}
    status, reply = post(solver_url, json.dumps(request_body(field, stars=few)).encode())
    assert status == 400 and reply["error"] == "stars: too few stars to solve: 3 (need at least 8)"
    # At 0.01"/px a 2k frame is 20" across: far smaller than any quad of the Tycho-2 indexes.
    tiny = request_body(field, hints={"pixel_scale": 0.01})
    status, reply = post(solver_url, json.dumps(tiny).encode())
    assert status == 400 and reply["error"].startswith('hints.pixel_scale: at 0.01"/px a 2048x2048 frame')
    status, reply = post(
        solver_url, json.dumps(request_body(field, hints={"ra": 10.0, "dec": 95.0})).encode()
    )
    assert status == 400 and reply["error"] == "hints.dec: must be within [-90, 90], got 95.0"


async def test_the_client_reports_the_services_error(solver_url: str, field: RenderedField) -> None:
    with pytest.raises(AstrometryError, match=r"HTTP 400: hints.pixel_scale: at 0.01"):
        await RemoteSolver(solver_url).solve_stars(
            field.x, field.y, field.flux, shape=field.shape, hints=SolveHints(pixel_scale_arcsec=0.01)
        )


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"width": 0}, r"^width: must be within 1\.\.100000, got 0$"),
        ({"version": 2}, r"^version: this service speaks version 1, got 2$"),
        (
            {"stars": {"x": [5000.0] * 8, "y": [1.0] * 8, "flux": [1.0] * 8}},
            r"^stars\.x\[0\]: 5000.0 is outside",
        ),
        ({"hints": {"ra": 10.0}}, r"^hints: give both ra and dec, or neither$"),
        ({"hints": {"pixel_scale": 1.0, "scale_tolerance": 1.5}}, r"^hints\.scale_tolerance: must be within"),
        ({"hints": {"fov": 1.0}}, r"^hints: unknown field\(s\) fov$"),
    ],
)
def test_parse_request_names_the_bad_field(
    field: RenderedField, change: dict[str, Any], message: str
) -> None:
    with pytest.raises(SolveRequestError, match=message):
        parse_request(request_body(field, **change))


def test_stars_of_no_sky_get_no_solution_within_the_time_limit(solver_url: str, field: RenderedField) -> None:
    import numpy as np

    rng = np.random.default_rng(7)
    stars = {
        "x": rng.uniform(0, 2047, 60).tolist(),
        "y": rng.uniform(0, 2047, 60).tolist(),
        "flux": [1.0] * 60,
    }
    status, reply = post(solver_url, json.dumps(request_body(field, stars=stars)).encode())
    assert status == 200 and reply["solved"] is False
    assert reply["message"].startswith(
        ("no match for 60 stars within 1 deg", "no solution within the time limit")
    )
    # The service is still there for the next request.
    status, reply = post(solver_url, json.dumps(request_body(field)).encode())
    assert status == 200 and reply["solved"] is True
