"""The remote-solver client against a small local HTTP server implementing the JSON API.

No remote solve service can run here, so the server in this test stands in for one: a stdlib
``ThreadingHTTPServer`` on 127.0.0.1 that implements the documented API (``POST /solve``) with the
local :class:`~nightcrew.images.astrometry.CatalogMatcher`. It checks the requests it receives, so
the test covers the client's encoding, transport and decoding, not the solving itself.
"""

from __future__ import annotations

import json
import math
import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

import numpy as np
import pytest
from astropy.table import Table  # type: ignore[import-untyped]
from astropy.wcs import WCS  # type: ignore[import-untyped]

from nightcrew.images import Image
from nightcrew.images.astrometry import (
    API_VERSION,
    AstrometryError,
    CatalogAstrometry,
    CatalogMatcher,
    FirstSolution,
    NoSolutionError,
    RemoteAstrometry,
    RemoteSolver,
    SolverUnavailableError,
)
from nightcrew.sim.catalog import StarCatalog
from nightcrew.sim.projection import Pointing, sky_to_pixel, wcs_header
from nightcrew.sim.render import CameraModel, Exposure, Optics, field_radius_deg, frame_geometry
from nightcrew.testing.solver import simulated_sky_indexes

POINTING = Pointing(60.0, 45.0, 0.0)
GEOMETRY = frame_geometry(CameraModel(), Optics(), Exposure(10.0))
CATALOG = StarCatalog()


class _SolveHandler(BaseHTTPRequestHandler):
    requests: list[dict[str, Any]] = []

    def do_POST(self) -> None:
        body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
        self.requests.append(body)
        if self.path != "/solve" or body.get("version") != API_VERSION:
            self._reply(400, {"error": f"unknown request {self.path} version {body.get('version')}"})
            return
        hints, stars = body["hints"], body["stars"]
        if "ra" not in hints:
            self._reply(200, {"solved": False, "message": "this service needs a position hint"})
            return
        shape = (body["height"], body["width"])
        matcher = CatalogMatcher()
        reference = CATALOG.query(
            hints["ra"], hints["dec"], matcher.catalog_radius_deg(shape, hints["pixel_scale"])
        )
        try:
            match = matcher.solve(
                stars["x"], stars["y"], stars["flux"], shape=shape,
                catalog_ra=reference["ra"], catalog_dec=reference["dec"], catalog_mag=reference["mag"],
                ra_deg=hints["ra"], dec_deg=hints["dec"], pixel_scale_arcsec=hints["pixel_scale"],
            )  # fmt: skip
        except NoSolutionError as exc:
            self._reply(200, {"solved": False, "message": str(exc)})
            return
        self._reply(200, {"solved": True, "wcs": match.wcs.header_cards()})

    def _reply(self, status: int, body: dict[str, Any]) -> None:
        content = json.dumps(body).encode()
        self.send_response(status)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(content)))
        self.end_headers()
        self.wfile.write(content)

    def log_message(self, format: str, *args: Any) -> None:
        pass  # keep the test output quiet


@pytest.fixture
def service() -> Iterator[str]:
    _SolveHandler.requests = []
    server = ThreadingHTTPServer(("127.0.0.1", 0), _SolveHandler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()
        thread.join()


def star_image(*, with_position: bool = True) -> Image:
    """True star positions of the frame (centroid noise 0.1 px) as a catalog, header 5' off."""
    stars = CATALOG.query(POINTING.ra_deg, POINTING.dec_deg, field_radius_deg(GEOMETRY), mag_limit=15.0)
    x, y = sky_to_pixel(stars["ra"], stars["dec"], POINTING, GEOMETRY)
    on = (x > 0) & (x < GEOMETRY.shape[1] - 1) & (y > 0) & (y < GEOMETRY.shape[0] - 1)
    rng = np.random.default_rng(2)
    catalog = {
        "x": x[on] + rng.normal(0, 0.1, on.sum()),
        "y": y[on] + rng.normal(0, 0.1, on.sum()),
        "flux": 10 ** (-0.4 * stars["mag"][on].astype(float)),
    }
    header = (
        {"RA": POINTING.ra_deg + 5 / 60 / math.cos(math.radians(POINTING.dec_deg))} if with_position else {}
    )
    if with_position:
        header["DEC"] = POINTING.dec_deg
    return Image(np.zeros(GEOMETRY.shape, np.uint16), header=header, catalog=Table(catalog))


def error_arcsec(image: Image) -> float:
    true, solved = WCS(wcs_header(POINTING, GEOMETRY)), image.wcs
    assert solved is not None
    grid = np.array([[0.0, 0.0], [2047.0, 2047.0], [0.0, 2047.0], [1000.0, 500.0]])
    t, s = true.all_pix2world(grid, 0), solved.all_pix2world(grid, 0)
    d_ra = (s[:, 0] - t[:, 0]) * math.cos(math.radians(POINTING.dec_deg))
    return float(np.max(3600 * np.hypot(d_ra, s[:, 1] - t[:, 1])))


async def test_remote_solver_round_trip(service: str) -> None:
    scale = GEOMETRY.pixel_scale_arcsec
    solved = await RemoteAstrometry(solver=RemoteSolver(service, max_stars=150), pixel_scale_arcsec=scale)(
        star_image()
    )
    assert error_arcsec(solved) < 1.0
    assert solved.metadata["astrometry"].solver == "remote"
    (request,) = _SolveHandler.requests
    assert request["width"] == 2048 and request["height"] == 2048
    assert len(request["stars"]["x"]) == 150
    assert request["stars"]["flux"] == sorted(request["stars"]["flux"], reverse=True)
    assert request["hints"]["pixel_scale"] == pytest.approx(scale)
    assert request["hints"]["scale_tolerance"] == 0.1


async def test_remote_no_solution_is_reported(service: str) -> None:
    with pytest.raises(NoSolutionError, match="needs a position hint"):
        await RemoteAstrometry(solver=RemoteSolver(service), pixel_scale_arcsec=1.16)(
            star_image(with_position=False)
        )


async def test_remote_http_error_carries_the_service_message(service: str) -> None:
    with pytest.raises(AstrometryError, match="HTTP 400: unknown request /v2/solve"):
        await RemoteAstrometry(solver=RemoteSolver(f"{service}/v2"), pixel_scale_arcsec=1.16)(star_image())


async def test_unreachable_service_falls_back_to_the_next_solver(service: str) -> None:
    dead = service.rsplit(":", 1)[0] + ":9"  # the discard port: nothing listens on loopback
    remote = RemoteAstrometry(solver=RemoteSolver(dead, timeout_s=5.0), pixel_scale_arcsec=1.16)
    with pytest.raises(SolverUnavailableError, match="unreachable"):
        await remote(star_image())
    index_dir = simulated_sky_indexes([(POINTING.ra_deg, POINTING.dec_deg)], width_arcmin=40.0)
    matcher = CatalogAstrometry(index_dir=str(index_dir), pixel_scale_arcsec=GEOMETRY.pixel_scale_arcsec)
    chained = FirstSolution([remote, matcher])
    solved = await chained(star_image())
    assert solved.metadata["astrometry"].solver == "catalog"
    assert error_arcsec(solved) < 1.0
