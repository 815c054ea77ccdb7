"""Client of a remote plate-solving service speaking a small JSON API over HTTP.

The API (version 1) — one endpoint, ``POST {url}/solve`` with ``Content-Type: application/json``::

    request  {"version": 1,
              "width": 2048, "height": 2048,                    # frame size in pixels
              "stars": {"x": [...], "y": [...], "flux": [...]},  # 0-based pixel centres
              "hints": {"ra": 100.0, "dec": 30.0, "radius": 1.0,        # degrees, each optional
                        "pixel_scale": 1.16, "scale_tolerance": 0.1}}   # arcsec/px

    200      {"solved": true,  "wcs": {"CTYPE1": "RA---TAN", "CRPIX1": 1024.5, ...}}
             {"solved": false, "message": "why not"}
    4xx/5xx  {"error": "what went wrong"}  (any body is tolerated)

``wcs`` holds FITS WCS cards (1-based ``CRPIX``, as in any FITS header). Stars are sent
brightest first, at most ``max_stars`` of them. The client uses only the standard library and runs
the blocking request in a worker thread.
"""

from __future__ import annotations

import asyncio
import json
import urllib.error
import urllib.request
from typing import Any

import numpy as np
import numpy.typing as npt
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.images.astrometry._errors import AstrometryError, NoSolutionError, SolverUnavailableError
from nightcrew.images.astrometry._solve_field import SolveHints

__all__ = ["API_VERSION", "RemoteSolver"]

API_VERSION = 1


class RemoteSolver:
    """Sends star lists to a solve service (see the module docstring for the API).

    Args:
        url: Base URL of the service, e.g. ``http://solver.example.org:8080``.
        timeout_s: Limit of one request, connection included.
        max_stars: Brightest stars sent.
    """

    def __init__(self, url: str, *, timeout_s: float = 60.0, max_stars: int = 200) -> None:
        if not url.startswith(("http://", "https://")):
            raise ValueError(f"url must start with http:// or https://, got {url!r}")
        if timeout_s <= 0:
            raise ValueError(f"timeout_s must be positive, got {timeout_s}")
        if max_stars < 4:
            raise ValueError(f"max_stars must be >= 4, got {max_stars}")
        self.url = url.rstrip("/")
        self.timeout_s = timeout_s
        self.max_stars = max_stars

    def request_body(
        self,
        x: npt.ArrayLike,
        y: npt.ArrayLike,
        flux: npt.ArrayLike,
        *,
        shape: tuple[int, int],
        hints: SolveHints,
    ) -> dict[str, Any]:
        """The JSON request for these stars: finite ones only, brightest first, at most ``max_stars``."""
        xs, ys, fs = (np.asarray(a, dtype=np.float64) for a in (x, y, flux))
        good = np.isfinite(xs) & np.isfinite(ys) & np.isfinite(fs)
        order = np.argsort(-fs[good], kind="stable")[: self.max_stars]
        hint_values = {
            "ra": hints.ra_deg,
            "dec": hints.dec_deg,
            "radius": hints.radius_deg if hints.ra_deg is not None else None,
            "pixel_scale": hints.pixel_scale_arcsec,
            "scale_tolerance": hints.scale_tolerance if hints.pixel_scale_arcsec is not None else None,
        }
        return {
            "version": API_VERSION,
            "width": int(shape[1]),
            "height": int(shape[0]),
            "stars": {
                "x": xs[good][order].tolist(),
                "y": ys[good][order].tolist(),
                "flux": fs[good][order].tolist(),
            },
            "hints": {key: value for key, value in hint_values.items() if value is not None},
        }

    async def solve_stars(
        self,
        x: npt.ArrayLike,
        y: npt.ArrayLike,
        flux: npt.ArrayLike,
        *,
        shape: tuple[int, int],
        hints: SolveHints,
    ) -> fits.Header:
        """The WCS of a star list as FITS cards.

        Raises:
            NoSolutionError: the service found no solution.
            SolverUnavailableError: the service cannot be reached.
            AstrometryError: it answered with an error or with something that is not the API.
        """
        body = self.request_body(x, y, flux, shape=shape, hints=hints)
        reply = await asyncio.to_thread(self._blocking_post, json.dumps(body).encode())
        return _parse_reply(reply)

    def _blocking_post(self, content: bytes) -> Any:
        request = urllib.request.Request(
            f"{self.url}/solve",
            data=content,
            headers={"Content-Type": "application/json", "Accept": "application/json"},
            method="POST",
        )
        try:
            with urllib.request.urlopen(request, timeout=self.timeout_s) as response:
                text = response.read().decode()
        except urllib.error.HTTPError as exc:
            raise AstrometryError(
                f"solve service at {self.url}: HTTP {exc.code}: {_error_text(exc)}"
            ) from exc
        except (urllib.error.URLError, TimeoutError, ConnectionError) as exc:
            raise SolverUnavailableError(f"solve service at {self.url} unreachable: {exc}") from exc
        try:
            return json.loads(text)
        except json.JSONDecodeError as exc:
            raise AstrometryError(f"solve service at {self.url} sent no JSON: {text[:200]!r}") from exc


def _error_text(exc: urllib.error.HTTPError) -> str:
    """The ``error`` of a JSON error body, else the start of the body, else the reason."""
    body = exc.read().decode(errors="replace")
    try:
        return str(json.loads(body)["error"])
    except (json.JSONDecodeError, KeyError, TypeError):
        return body[:200] or str(exc.reason)


def _parse_reply(reply: Any) -> fits.Header:
    if not isinstance(reply, dict) or not isinstance(reply.get("solved"), bool):
        raise AstrometryError(f"solve service reply lacks 'solved': {str(reply)[:200]}")
    if not reply["solved"]:
        raise NoSolutionError(f"solve service found no solution: {reply.get('message', 'no reason given')}")
    cards = reply.get("wcs")
    if not isinstance(cards, dict) or "CTYPE1" not in cards:
        raise AstrometryError(f"solve service reply has no WCS cards: {str(reply)[:200]}")
    header = fits.Header()
    for keyword, value in cards.items():
        if not isinstance(value, str | int | float) or isinstance(value, bool):
            raise AstrometryError(f"solve service sent an invalid WCS card {keyword}={value!r}")
        header[str(keyword)] = value
    return header
