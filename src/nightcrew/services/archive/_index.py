"""The frame index: what the server stores and asks of the database.

Frames are rows of ``frames`` (the searchable values), ``frame_headers`` (the whole header, JSON)
and ``frame_links`` (the frames it was made from: raw frame and masters, by basename, or by the
master's DATE-OBS as ``nightcrew reduce`` writes it today). Related frames are found both ways:
the frames this one names, and the frames that name it. A raw frame's record shows the WCS of the
reduced frame made from it once one is archived (:meth:`FrameIndex.solved_wcs`), whichever came
first.
"""

from __future__ import annotations

import json
from datetime import UTC, datetime
from typing import Any

from nightcrew.images.astrometry import is_wcs_keyword
from nightcrew.services.archive._db import Database, Row
from nightcrew.services.archive._fits import FrameFacts, iso_date_obs
from nightcrew.services.archive._search import SearchQuery, unit_vector

__all__ = ["FrameIndex", "StoredFile"]

COLUMNS = (
    "id, basename, path, checksum, size, date_obs, day_obs, instrument, imagetyp, exptime, object, "
    "filter, proposal, task, rlevel, ra, dec"
)
#: The master kind a role names (IMAGETYP of masters is ``master_<kind>``, or the kind itself).
_MASTER_TYPES = {
    "bias": ("master_bias", "bias"),
    "dark": ("master_dark", "dark"),
    "flat": ("master_flat", "flat", "skyflat"),
}
_INVERSE = {"raw": "reduced", "bias": "calibrated", "dark": "calibrated", "flat": "calibrated"}


class StoredFile:
    """Where an accepted upload lies and what it is."""

    def __init__(self, basename: str, path: str, checksum: str, size: int) -> None:
        self.basename, self.path, self.checksum, self.size = basename, path, checksum, size


class FrameIndex:
    """Frames in the database."""

    def __init__(self, database: Database) -> None:
        self.database = database

    async def existing(self, checksum: str, basename: str) -> Row | None:
        """A stored frame with this content or this name, if any."""
        return await self.database.fetch_one(
            f"SELECT {COLUMNS} FROM frames WHERE checksum = ? OR basename = ? ORDER BY id LIMIT 1",
            [checksum, basename],
        )

    async def insert(self, facts: FrameFacts, stored: StoredFile) -> Row:
        """Index a frame (one transaction); return its row, read inside that transaction so that a
        committed frame is answered without asking the database again."""
        async with self.database.transaction() as tx:
            frame_id = await insert_frame(tx, facts, stored)
            row = await tx.fetch_one(f"SELECT {COLUMNS} FROM frames WHERE id = ?", [frame_id])
        assert row is not None
        return row

    async def frame(self, frame_id: int) -> Row | None:
        return await self.database.fetch_one(f"SELECT {COLUMNS} FROM frames WHERE id = ?", [frame_id])

    async def frames(self, frame_ids: list[int]) -> list[Row]:
        marks = ", ".join("?" for _ in frame_ids)
        return await self.database.fetch(
            f"SELECT {COLUMNS} FROM frames WHERE id IN ({marks}) ORDER BY id", frame_ids
        )

    async def cards(self, frame_id: int) -> list[list[Any]]:
        row = await self.database.fetch_one("SELECT cards FROM frame_headers WHERE frame_id = ?", [frame_id])
        return [] if row is None else list(json.loads(row["cards"]))

    async def solved_wcs(self, frame: Row) -> list[list[Any]]:
        """For a raw frame without a WCS: the WCS cards of the newest reduced frame made from it
        that has one (its plate solution; reduction keeps the pixel grid), else none."""
        if frame["rlevel"] != 0 or any(is_wcs_keyword(card[0]) for card in await self.cards(frame["id"])):
            return []
        reduced = await self.database.fetch(
            "SELECT f.id, f.basename FROM frame_links l JOIN frames f ON f.id = l.frame_id "
            "WHERE l.role = 'raw' AND l.basename = ? ORDER BY f.id DESC",
            [frame["basename"]],
        )
        for row in reduced:
            wcs = [card for card in await self.cards(row["id"]) if is_wcs_keyword(card[0])]
            if any(card[0] == "CTYPE1" for card in wcs):
                return [
                    [key, value, f"{comment} (solved in {row['basename']})".strip()]
                    for key, value, comment in wcs
                ]
        return []

    async def search(self, query: SearchQuery) -> tuple[int, list[Row]]:
        """The number of matching frames, and the page of them the query asks for."""
        where = query.where()
        counted = await self.database.fetch_one(f"SELECT COUNT(*) AS n FROM frames{where}", query.params)
        rows = await self.database.fetch(
            f"SELECT {COLUMNS} FROM frames{where} ORDER BY {query.order} LIMIT ? OFFSET ?",
            [*query.params, query.limit, query.offset],
        )
        return (0 if counted is None else int(counted["n"])), rows

    async def count(self) -> int:
        row = await self.database.fetch_one("SELECT COUNT(*) AS n FROM frames")
        return 0 if row is None else int(row["n"])

    async def related(self, frame: Row) -> list[tuple[str, Row]]:
        """(relation, frame) pairs: what this frame was made from, and what was made from it."""
        found: list[tuple[str, Row]] = []
        for link in await self.database.fetch(
            "SELECT role, basename, date_obs FROM frame_links WHERE frame_id = ?", [frame["id"]]
        ):
            if link["basename"]:
                rows = await self.database.fetch(
                    f"SELECT {COLUMNS} FROM frames WHERE basename = ?", [link["basename"]]
                )
            else:
                rows = await self._masters_at(link["role"], link["date_obs"], frame["instrument"])
            found += [(link["role"], row) for row in rows]
        naming = await self.database.fetch(
            f"SELECT l.role AS relation, {', '.join('f.' + c.strip() for c in COLUMNS.split(','))} "
            "FROM frame_links l JOIN frames f ON f.id = l.frame_id "
            "WHERE l.basename = ? OR (l.basename IS NULL AND l.date_obs = ? AND f.instrument = ?) "
            "ORDER BY f.id",
            [frame["basename"], frame["date_obs"], frame["instrument"]],
        )
        for row in naming:
            relation = row.pop("relation")
            if row["basename"] != frame["basename"] and (
                relation == "raw" or frame["imagetyp"] in _MASTER_TYPES.get(relation, ())
            ):
                found.append((_INVERSE[relation], row))
        return found

    async def _masters_at(self, role: str, date_obs: str, instrument: str) -> list[Row]:
        kinds = _MASTER_TYPES.get(role, ())
        marks = ", ".join("?" for _ in kinds)
        return await self.database.fetch(
            f"SELECT {COLUMNS} FROM frames WHERE date_obs = ? AND instrument = ? AND imagetyp IN ({marks})",
            [date_obs, instrument, *kinds],
        )


async def insert_frame(tx: Database, facts: FrameFacts, stored: StoredFile) -> int:
    """Insert one frame's rows through ``tx`` (a transaction); return the frame's id."""
    x, y, z = (
        unit_vector(facts.ra, facts.dec)
        if facts.ra is not None and facts.dec is not None
        else (None, None, None)
    )
    row = await tx.fetch_one(
        "INSERT INTO frames (basename, path, checksum, size, obs_time, date_obs, day_obs, instrument, "
        "imagetyp, exptime, object, filter, proposal, task, rlevel, ra, dec, cx, cy, cz, uploaded) "
        "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) RETURNING id",
        [
            stored.basename,
            stored.path,
            stored.checksum,
            stored.size,
            facts.date_obs.timestamp(),
            iso_date_obs(facts.date_obs),
            facts.day_obs,
            facts.instrument,
            facts.imagetyp,
            facts.exptime,
            facts.object,
            facts.filter,
            facts.proposal,
            facts.task,
            facts.rlevel,
            facts.ra,
            facts.dec,
            x,
            y,
            z,
            datetime.now(UTC).isoformat(timespec="seconds"),
        ],
    )
    assert row is not None
    frame_id = int(row["id"])
    await tx.fetch(
        "INSERT INTO frame_headers (frame_id, cards) VALUES (?, ?)", [frame_id, json.dumps(facts.cards)]
    )
    for link in facts.links:
        await tx.fetch(
            "INSERT INTO frame_links (frame_id, role, basename, date_obs) VALUES (?, ?, ?, ?)",
            [frame_id, link.role, link.basename, link.date_obs],
        )
    return frame_id
