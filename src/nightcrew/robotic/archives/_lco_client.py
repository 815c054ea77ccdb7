"""A small client of the LCO observation portal's HTTP API (only the endpoints the archive uses).

Authentication is the portal's token header (``Authorization: Token <token>``). List endpoints
may be paginated (``{"count", "next", "previous", "results"}``); :meth:`LcoPortalClient.get_all`
follows ``next`` until the end. Network and HTTP errors become :class:`PortalError`.
"""

from __future__ import annotations

from datetime import datetime
from typing import Any

import aiohttp

from nightcrew.robotic.tasks import TaskError

__all__ = ["LcoPortalClient", "PortalError"]

#: Pages followed at most, so a portal that links a page to itself cannot keep us forever.
_MAX_PAGES = 1000


class PortalError(TaskError):
    """The portal could not be reached or answered with an error (``status``: HTTP status or 0)."""

    def __init__(self, message: str, *, status: int = 0) -> None:
        super().__init__(message)
        self.status = status


class LcoPortalClient:
    """Calls the portal at ``url`` (e.g. ``https://observe.lco.global``) with ``token``.

    Use ``async with client:``; the constructor does no I/O.
    """

    def __init__(self, url: str, token: str, *, timeout: float = 30.0) -> None:
        self.url = url.rstrip("/")
        self._token = token
        self._timeout = timeout
        self._session: aiohttp.ClientSession | None = None

    async def __aenter__(self) -> LcoPortalClient:
        await self.open()
        return self

    async def __aexit__(self, *exc_info: object) -> None:
        await self.close()

    async def open(self) -> None:
        if self._session is None:
            self._session = aiohttp.ClientSession(
                headers={"Authorization": f"Token {self._token}"},
                timeout=aiohttp.ClientTimeout(total=self._timeout),
            )

    async def close(self) -> None:
        session, self._session = self._session, None
        if session is not None:
            await session.close()

    async def request(
        self, method: str, path_or_url: str, *, params: dict[str, Any] | None = None, body: Any = None
    ) -> Any:
        """One call; the decoded JSON answer."""
        if self._session is None:
            raise PortalError("the portal client is not open")
        url = path_or_url if path_or_url.startswith("http") else self.url + path_or_url
        try:
            async with self._session.request(method, url, params=params, json=body) as response:
                text = await response.text()
                if response.status >= 400:
                    hint = " (check the API token)" if response.status in (401, 403) else ""
                    raise PortalError(
                        f"{method} {url}: HTTP {response.status}{hint}: {text[:300]}", status=response.status
                    )
                return await response.json(content_type=None) if text else None
        except aiohttp.ClientError as exc:
            raise PortalError(f"{method} {url}: {exc}") from exc
        except TimeoutError as exc:
            raise PortalError(f"{method} {url}: no answer within {self._timeout} s") from exc

    async def get_all(self, path: str, params: dict[str, Any] | None = None) -> list[Any]:
        """Every item of a list endpoint, following ``next`` links of paginated answers."""
        answer = await self.request("GET", path, params=params)
        items: list[Any] = []
        for _ in range(_MAX_PAGES):
            if not isinstance(answer, dict) or "results" not in answer:
                return items + list(answer or [])
            items.extend(answer["results"])
            if not answer.get("next"):
                return items
            answer = await self.request("GET", answer["next"])
        raise PortalError(f"GET {path}: more than {_MAX_PAGES} pages")

    async def schedulable_request_groups(
        self, start: datetime, end: datetime, telescope_classes: tuple[str, ...] = ()
    ) -> list[dict[str, Any]]:
        """``GET /api/requestgroups/schedulable_requests/``: groups with a window in [start, end]."""
        params: dict[str, Any] = {"start": start.isoformat(), "end": end.isoformat()}
        if telescope_classes:
            params["telescope_class"] = list(telescope_classes)
        return await self.get_all("/api/requestgroups/schedulable_requests/", _flat(params))

    async def last_changed(self) -> str:
        """``GET /api/last_changed/``: when request groups last changed (ISO text)."""
        answer = await self.request("GET", "/api/last_changed/")
        return str(answer["last_change_time"])

    async def submit_observations(self, observations: list[dict[str, Any]]) -> dict[str, Any]:
        """``POST /api/observations/`` with a list: ``{"num_created": n, "errors": {...}}``."""
        answer: dict[str, Any] = await self.request("POST", "/api/observations/", body=observations)
        return answer

    async def cancel_observations(self, selection: dict[str, Any]) -> int:
        """``POST /api/observations/cancel/``: how many observations were canceled."""
        answer = await self.request("POST", "/api/observations/cancel/", body=selection)
        return int(answer.get("canceled", 0))

    async def observations(self, params: dict[str, Any]) -> list[dict[str, Any]]:
        """``GET /api/observations/`` with filters (site, telescope, request_num, state, ...)."""
        return await self.get_all("/api/observations/", params)

    async def update_configuration_status(self, status_id: int, update: dict[str, Any]) -> None:
        """``PATCH /api/configurationstatus/<id>/``: state and summary of one configuration."""
        await self.request("PATCH", f"/api/configurationstatus/{status_id}/", body=update)


def _flat(params: dict[str, Any]) -> Any:
    # aiohttp repeats a key for a list only when given as pairs.
    pairs: list[tuple[str, str]] = []
    for key, value in params.items():
        for item in value if isinstance(value, list) else [value]:
            pairs.append((key, str(item)))
    return pairs
