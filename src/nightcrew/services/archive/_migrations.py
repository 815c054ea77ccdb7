"""The archive's schema, as numbered migrations written once for SQLite and PostgreSQL.

Each migration is a list of statements with three placeholders for what the dialects spell
differently: ``{id}`` (an auto-numbered primary key), ``{real}`` (a double) and ``{big}`` (a 64-bit
integer). ``archive_schema`` records the versions applied; :func:`pending` lists the rest. Add a
migration by appending to :data:`MIGRATIONS`; never edit one that has shipped.
"""

from __future__ import annotations

__all__ = ["MIGRATIONS", "SCHEMA_TABLE", "render"]

SCHEMA_TABLE = (
    "CREATE TABLE IF NOT EXISTS archive_schema (version INTEGER PRIMARY KEY, applied TEXT NOT NULL)"
)

_TYPES = {
    "sqlite": {"id": "INTEGER PRIMARY KEY AUTOINCREMENT", "real": "REAL", "big": "INTEGER"},
    "postgresql": {"id": "BIGSERIAL PRIMARY KEY", "real": "DOUBLE PRECISION", "big": "BIGINT"},
}

#: Version → statements. Frames are searched by the indexed columns; the header and the links to
#: the frames a frame was made from live in tables of their own, so a search reads narrow rows.
MIGRATIONS: dict[int, list[str]] = {
    1: [
        """CREATE TABLE frames (
            id {id},
            basename TEXT NOT NULL UNIQUE,
            path TEXT NOT NULL,
            checksum TEXT NOT NULL UNIQUE,
            size {big} NOT NULL,
            obs_time {real} NOT NULL,
            date_obs TEXT NOT NULL,
            day_obs TEXT NOT NULL,
            instrument TEXT NOT NULL,
            imagetyp TEXT NOT NULL,
            exptime {real} NOT NULL,
            object TEXT,
            filter TEXT,
            proposal TEXT,
            task TEXT,
            rlevel INTEGER NOT NULL,
            ra {real},
            dec {real},
            cx {real},
            cy {real},
            cz {real},
            uploaded TEXT NOT NULL
        )""",
        "CREATE TABLE frame_headers (frame_id {big} PRIMARY KEY REFERENCES frames(id), cards TEXT NOT NULL)",
        """CREATE TABLE frame_links (
            frame_id {big} NOT NULL REFERENCES frames(id),
            role TEXT NOT NULL,
            basename TEXT,
            date_obs TEXT
        )""",
        "CREATE INDEX frames_obs_time ON frames (obs_time)",
        "CREATE INDEX frames_filter_time ON frames (filter, obs_time)",
        "CREATE INDEX frames_object_time ON frames (object, obs_time)",
        "CREATE INDEX frames_imagetyp_time ON frames (imagetyp, obs_time)",
        "CREATE INDEX frames_instrument_time ON frames (instrument, obs_time)",
        "CREATE INDEX frames_rlevel_time ON frames (rlevel, obs_time)",
        "CREATE INDEX frames_dec ON frames (dec)",
        "CREATE INDEX frames_proposal ON frames (proposal)",
        "CREATE INDEX frames_task ON frames (task)",
        "CREATE INDEX frames_date_obs ON frames (date_obs)",
        "CREATE INDEX frame_links_frame ON frame_links (frame_id)",
        "CREATE INDEX frame_links_basename ON frame_links (basename)",
        "CREATE INDEX frame_links_date_obs ON frame_links (date_obs)",
    ],
}


def render(statement: str, dialect: str) -> str:
    """The statement with the dialect's spelling of the placeholders."""
    return statement.format(**_TYPES[dialect])
