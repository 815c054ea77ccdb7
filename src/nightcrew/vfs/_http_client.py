"""What the roots on HTTP servers (the file cache, the image archive) share: a checked address
and timeout, one aiohttp session made on first use and closed with the root, and network errors
turned into :class:`VfsError` naming the server."""

from __future__ import annotations

import io
from typing import Any, ClassVar

from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs._errors import VfsError
from nightcrew.vfs._root import FileRoot

__all__ = ["HttpClientRoot"]


class HttpClientRoot(FileRoot):
    """A root whose files an HTTP server keeps.

    Args:
        url: The server's address, ``http://`` or ``https://``.
        token: Its bearer token, if it has one.
        timeout: Wall seconds one request may take.
    """

    #: The server as errors name it, e.g. "the file cache".
    server_name: ClassVar[str]

    def __init__(self, url: str, *, token: str | None, timeout: float) -> None:
        kind = type(self).__name__
        if not isinstance(url, str) or not url.startswith(("http://", "https://")):
            raise InvalidArgumentError(f"{kind} url must start with http:// or https://, got {url!r}")
        if not timeout > 0:
            raise InvalidArgumentError(f"{kind} timeout must be > 0 seconds, got {timeout}")
        self.url = url.rstrip("/")
        self._token = token
        self._timeout = float(timeout)
        self._session: Any = None  # aiohttp.ClientSession, made on first use (in the running loop)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.url!r})"

    async def _send(
        self,
        method: str,
        url: str,
        path: str,
        *,
        data: bytes | io.BytesIO | None = None,
        params: dict[str, str] | None = None,
        authorised: bool = True,
    ) -> tuple[int, bytes]:
        """Send one request (with the token if ``authorised``); return its status and body."""
        import aiohttp

        if self._session is None:
            self._session = aiohttp.ClientSession(timeout=aiohttp.ClientTimeout(total=self._timeout))
        headers = {"Authorization": f"Bearer {self._token}"} if self._token and authorised else {}
        try:
            async with self._session.request(
                method, url, data=data, params=params, headers=headers
            ) as response:
                return response.status, await response.read()
        except (aiohttp.ClientError, TimeoutError) as exc:
            why = str(exc) or type(exc).__name__
            raise VfsError(f"cannot reach {self.server_name} at {self.url}: {why}", path=path) from exc

    async def close(self) -> None:
        session, self._session = self._session, None
        if session is not None:
            await session.close()
