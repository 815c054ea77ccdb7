"""The archive's HTTP server (aiohttp): upload, search, details, related frames, files, frontend.

Routes (documented in docs/archive.md; they follow the LCO science archive's ``/frames/``)::

    GET  /frames/                      search: count, next, previous, results
    POST /frames/upload/?filename=F    a FITS file as the body; Authorization: Bearer TOKEN
    GET  /frames/{id}/                 one frame
    GET  /frames/{id}/headers/         its whole header (a raw frame: with the WCS of its reduced frame)
    GET  /frames/{id}/related/         raw ↔ reduced, masters used / frames calibrated
    GET  /frames/{id}/download/        the FITS file
    GET  /frames/{id}/thumbnail/       a PNG (?size=16..1024, 256 by default)
    GET|POST /frames/zip/              frame_ids=1,2,3 → one zip
    GET  /health                       {"status": "ok", "frames": N}
    GET  /                             the web frontend (static files, no build step)

Every refusal is raised as :class:`Rejected` and becomes ``{"error", "detail"}`` JSON in
:func:`_replies`, the one place that makes error replies.
"""

from __future__ import annotations

import asyncio
import hashlib
import hmac
import logging
import tempfile
from collections.abc import Awaitable, Callable
from http import HTTPStatus
from pathlib import Path
from typing import Any

from aiohttp import web

from nightcrew.services.archive._config import ArchiveConfig
from nightcrew.services.archive._db import Database, Row, open_database
from nightcrew.services.archive._errors import Rejected
from nightcrew.services.archive._files import blocking_thumbnail, blocking_zip
from nightcrew.services.archive._fits import FrameFacts, check_basename, gunzip_upload, inspect_fits
from nightcrew.services.archive._index import FrameIndex, StoredFile
from nightcrew.services.archive._search import parse_search
from nightcrew.services.archive._store import FrameStore, storage_path

__all__ = ["ArchiveServer"]

log = logging.getLogger(__name__)

STATIC = Path(__file__).parent / "static"
_CHUNK = 1 << 20
Handler = Callable[[web.Request], Awaitable[web.StreamResponse]]


class ArchiveServer:
    """The archive: a database, a frame directory and an HTTP server.

    Args:
        config: Where to listen and store (:class:`ArchiveConfig`).

    The constructor does no I/O; :meth:`start` connects the database (applying migrations),
    listens, and returns the URL; :meth:`close` stops both and is safe to call twice.
    """

    def __init__(self, config: ArchiveConfig) -> None:
        self.config = config
        self.database: Database = open_database(config.database, busy_timeout=config.sqlite_busy_timeout)
        self.index = FrameIndex(self.database)
        self.store = FrameStore(config.storage)
        self._commit_lock = asyncio.Lock()  # duplicate check, file and row of one upload at a time
        self._runner: web.AppRunner | None = None
        self.url = ""

    def __repr__(self) -> str:
        return f"ArchiveServer({self.url or 'not started'})"

    async def start(self) -> str:
        """Connect, migrate, listen; return the base URL (``http://127.0.0.1:PORT``)."""
        self.config.storage.mkdir(parents=True, exist_ok=True)
        for left in await asyncio.to_thread(self.store.blocking_remove_temporaries):
            log.warning("removed %s, left by an upload cut off by a crash", left)
        await self.database.open()
        app = web.Application(middlewares=[_replies], client_max_size=self.config.max_upload_bytes + _CHUNK)
        self._routes(app)
        self._runner = web.AppRunner(app, access_log=None)
        await self._runner.setup()
        site = web.TCPSite(self._runner, self.config.host, self.config.port)
        await site.start()
        port = self._runner.addresses[0][1]
        host = f"[{self.config.host}]" if ":" in self.config.host else self.config.host
        self.url = f"http://{host}:{port}"
        log.info(
            "archive at %s (%s database, frames in %s)", self.url, self.database.dialect, self.config.storage
        )
        return self.url

    async def close(self) -> None:
        runner, self._runner = self._runner, None
        if runner is not None:
            await runner.cleanup()
        await self.database.close()

    def _routes(self, app: web.Application) -> None:
        app.router.add_get("/", self._frontend)
        app.router.add_static("/static/", STATIC)
        app.router.add_get("/health", self._health)
        app.router.add_get("/frames/", self._search)
        app.router.add_post("/frames/upload/", self._upload)
        app.router.add_route("*", "/frames/zip/", self._zip)
        app.router.add_get(r"/frames/{id:\d+}/", self._frame)
        app.router.add_get(r"/frames/{id:\d+}/headers/", self._headers)
        app.router.add_get(r"/frames/{id:\d+}/related/", self._related)
        app.router.add_get(r"/frames/{id:\d+}/download/", self._download)
        app.router.add_get(r"/frames/{id:\d+}/thumbnail/", self._thumbnail)

    # --- reading ---------------------------------------------------------------------------------

    async def _frontend(self, request: web.Request) -> web.StreamResponse:
        return web.FileResponse(STATIC / "index.html")

    async def _health(self, request: web.Request) -> web.StreamResponse:
        return web.json_response({"status": "ok", "frames": await self.index.count()})

    async def _search(self, request: web.Request) -> web.StreamResponse:
        query = parse_search(request.query)
        count, rows = await self.index.search(query)
        base = _base(request)
        url = request.url

        def page(offset: int) -> str:
            return str(url.with_query({**url.query, "offset": str(offset)}).with_scheme(url.scheme))

        following = query.offset + query.limit
        return web.json_response(
            {
                "count": count,
                "next": page(following) if following < count else None,
                "previous": page(max(0, query.offset - query.limit)) if query.offset > 0 else None,
                "results": [frame_json(row, base) for row in rows],
            }
        )

    async def _frame_row(self, request: web.Request) -> Row:
        frame_id = int(request.match_info["id"])
        # Ids are 64-bit in both databases: a longer number names no frame (not a database error).
        row = await self.index.frame(frame_id) if frame_id < 2**63 else None
        if row is None:
            raise Rejected(404, f"no frame with id {frame_id}")
        return row

    async def _frame(self, request: web.Request) -> web.StreamResponse:
        return web.json_response(frame_json(await self._frame_row(request), _base(request)))

    async def _headers(self, request: web.Request) -> web.StreamResponse:
        row = await self._frame_row(request)
        cards = await self.index.cards(row["id"]) + await self.index.solved_wcs(row)
        data = {key: value for key, value, _ in cards if key and key not in ("COMMENT", "HISTORY")}
        return web.json_response({"data": data, "cards": cards})

    async def _related(self, request: web.Request) -> web.StreamResponse:
        row = await self._frame_row(request)
        base = _base(request)
        return web.json_response(
            [
                {**frame_json(other, base), "relation": relation}
                for relation, other in await self.index.related(row)
            ]
        )

    async def _download(self, request: web.Request) -> web.StreamResponse:
        row = await self._frame_row(request)
        headers = {
            "Content-Disposition": f'attachment; filename="{row["basename"]}"',
            "Content-Type": "application/fits",
        }
        return web.FileResponse(self.store.absolute(row["path"]), headers=headers)

    async def _thumbnail(self, request: web.Request) -> web.StreamResponse:
        row = await self._frame_row(request)
        size = _integer(request.query.get("size", "256"), "size", 16, 1024)
        cache = self.config.storage / ".thumbnails" / f"{row['id']}-{size}.png"
        try:
            png = await asyncio.to_thread(
                blocking_thumbnail,
                self.store.absolute(row["path"]),
                cache,
                size,
                self.config.max_frame_pixels,
            )
        except ValueError as exc:
            raise Rejected(422, str(exc)) from exc
        return web.Response(body=png, content_type="image/png", headers={"Cache-Control": "max-age=86400"})

    async def _zip(self, request: web.Request) -> web.StreamResponse:
        if request.method not in ("GET", "POST"):
            raise Rejected(405, "use GET or POST with frame_ids")
        given = request.query.get("frame_ids", "")
        if request.method == "POST":
            if request.content_type == "application/json":
                body: Any = await request.json()
                given = ",".join(str(i) for i in body.get("frame_ids", [])) if isinstance(body, dict) else ""
            else:
                form = await request.post()
                given = ",".join(str(value) for value in form.getall("frame_ids", []))
        ids = [_integer(part, "frame_ids", 1, 2**62) for part in given.replace(" ", "").split(",") if part]
        if not ids:
            raise Rejected(400, "frame_ids must list at least one frame id (frame_ids=1,2,3)")
        if len(set(ids)) > self.config.max_zip_frames:
            raise Rejected(400, f"at most {self.config.max_zip_frames} frames per zip, got {len(set(ids))}")
        rows = await self.index.frames(sorted(set(ids)))
        missing = sorted(set(ids) - {row["id"] for row in rows})
        if missing:
            raise Rejected(404, f"no frames with ids {', '.join(map(str, missing))}")
        return await self._send_zip(request, rows)

    async def _send_zip(self, request: web.Request, rows: list[Row]) -> web.StreamResponse:
        with tempfile.TemporaryDirectory(prefix="archive-zip-") as directory:
            target = Path(directory) / "frames.zip"
            files = [
                (self.store.absolute(row["path"]), f"{row['day_obs']}/{row['basename']}") for row in rows
            ]
            await asyncio.to_thread(blocking_zip, files, target)
            response = web.StreamResponse(
                headers={
                    "Content-Type": "application/zip",
                    "Content-Disposition": 'attachment; filename="frames.zip"',
                }
            )
            response.content_length = target.stat().st_size
            await response.prepare(request)
            source = await asyncio.to_thread(open, target, "rb")
            try:
                while chunk := await asyncio.to_thread(source.read, _CHUNK):
                    await response.write(chunk)
            finally:
                source.close()
            await response.write_eof()
            return response

    # --- upload ----------------------------------------------------------------------------------

    async def _upload(self, request: web.Request) -> web.StreamResponse:
        self._authorize(request)
        basename = check_basename(request.query.get("filename", ""))
        data = await self._body(request)
        checksum = await asyncio.to_thread(lambda: hashlib.sha256(data).hexdigest())
        facts = await asyncio.to_thread(self._inspect, basename, data)
        async with self._commit_lock:
            existing = await self.index.existing(checksum, basename)
            if existing is not None:
                raise _conflict(existing, checksum, _base(request))
            relative = storage_path(facts.day_obs, facts.instrument, basename)
            try:
                await asyncio.to_thread(self.store.blocking_write, relative, data)
            except FileExistsError as exc:
                raise Rejected(409, f"{relative} is on disk but not in the index: remove it by hand") from exc
            except OSError as exc:
                raise Rejected(507, f"cannot store {basename}: {exc.strerror}") from exc
            try:
                row = await self.index.insert(facts, StoredFile(basename, relative, checksum, len(data)))
            except BaseException:
                await asyncio.shield(asyncio.to_thread(self.store.blocking_discard, relative))
                raise
        log.info("stored frame %d: %s (%d bytes)", row["id"], relative, len(data))
        return web.json_response({**frame_json(row, _base(request)), "duplicate": False}, status=201)

    def _inspect(self, basename: str, data: bytes) -> FrameFacts:
        """Blocking: what to index of an upload (unpacked first when it is a ``.gz``)."""
        fits_bytes = gunzip_upload(basename, data, self.config.max_upload_bytes)
        return inspect_fits(fits_bytes, self.config.max_frame_pixels)

    def _authorize(self, request: web.Request) -> None:
        given = request.headers.get("Authorization", "")
        scheme, _, token = given.partition(" ")
        if scheme.lower() != "bearer" or not hmac.compare_digest(
            token.strip().encode(), self.config.token.encode()
        ):
            why = "no bearer token" if not given else "a wrong bearer token"
            raise Rejected(401, f"uploads need the archive's token (Authorization: Bearer ...); got {why}")

    async def _body(self, request: web.Request) -> bytes:
        cap = self.config.max_upload_bytes
        if request.content_length is not None and request.content_length > cap:
            raise Rejected(413, f"upload of {request.content_length} bytes exceeds the limit of {cap} bytes")
        data = bytearray()
        async for chunk in request.content.iter_chunked(_CHUNK):
            data += chunk
            if len(data) > cap:
                raise Rejected(413, f"upload exceeds the limit of {cap} bytes")
        if not data:
            raise Rejected(400, "empty upload: send the FITS file as the request body")
        return bytes(data)


def _conflict(existing: Row, checksum: str, base: str) -> Rejected:
    frame = frame_json(existing, base)
    if existing["checksum"] == checksum:
        return Rejected(
            409,
            f"duplicate of frame {existing['id']} ({existing['basename']}, same sha256)",
            extra={"duplicate": True, "frame": frame},
        )
    return Rejected(
        409,
        f"a different frame is stored as {existing['basename']} (id {existing['id']}); rename the file",
        extra={"duplicate": False, "frame": frame},
    )


def frame_json(row: Row, base: str) -> dict[str, Any]:
    """One frame as the API shows it (LCO's field names where they exist)."""
    frame = f"{base}/frames/{row['id']}"
    return {
        "id": row["id"],
        "basename": row["basename"],
        "filename": row["basename"],
        "path": row["path"],
        "url": f"{frame}/download/",
        "thumbnail_url": f"{frame}/thumbnail/",
        "headers_url": f"{frame}/headers/",
        "related_url": f"{frame}/related/",
        "DATE_OBS": row["date_obs"],
        "DAY_OBS": row["day_obs"],
        "INSTRUME": row["instrument"],
        "OBSTYPE": row["imagetyp"],
        "IMAGETYP": row["imagetyp"],
        "EXPTIME": row["exptime"],
        "OBJECT": row["object"],
        "FILTER": row["filter"],
        "PROPID": row["proposal"],
        "TASK": row["task"],
        "RLEVEL": row["rlevel"],
        "RA": row["ra"],
        "DEC": row["dec"],
        "size": row["size"],
        "sha256": row["checksum"],
    }


def _base(request: web.Request) -> str:
    return f"{request.scheme}://{request.host}"


def _integer(text: str, name: str, low: int, high: int) -> int:
    try:
        value = int(text)
    except ValueError:
        raise Rejected(400, f"{name} must be an integer, got {text!r}") from None
    if not low <= value <= high:
        raise Rejected(400, f"{name} must be within {low}..{high}, got {value}")
    return value


@web.middleware
async def _replies(request: web.Request, handler: Handler) -> web.StreamResponse:
    """The one place refusals become replies: JSON with the status phrase and one message."""
    try:
        return await handler(request)
    except Rejected as exc:
        if exc.status >= 500:
            log.warning("%s %s: %s", request.method, request.path, exc.message)
        headers = {"WWW-Authenticate": 'Bearer realm="archive"'} if exc.status == 401 else None
        body = {"error": HTTPStatus(exc.status).phrase, "detail": exc.message, **exc.extra}
        return web.json_response(body, status=exc.status, headers=headers)
