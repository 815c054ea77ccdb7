"""The archive's database: one small async interface over SQLite (stdlib) and PostgreSQL (asyncpg).

Chosen: asyncpg for PostgreSQL (asyncio-native, the fastest maintained driver); the stdlib's
sqlite3 for SQLite, on one connection used from worker threads one call at a time (SQLite
serialises writers anyway). SQL is written once with ``?`` placeholders; the PostgreSQL side
numbers them (``$1``...). Every failure to reach the database, a lock held too long included,
becomes :class:`DatabaseUnavailable` (HTTP 503); a broken uniqueness rule becomes a 409.
"""

from __future__ import annotations

import asyncio
import contextlib
import re
import sqlite3
from abc import ABC, abstractmethod
from collections.abc import AsyncIterator, Sequence
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import asyncpg  # type: ignore[import-untyped]

from nightcrew.services.archive._errors import DatabaseUnavailable, Rejected
from nightcrew.services.archive._migrations import MIGRATIONS, SCHEMA_TABLE, render

__all__ = ["Database", "Row", "open_database"]

Row = dict[str, Any]
_PLACEHOLDER = re.compile(r"\?")


class Database(ABC):
    """A connection (or pool) to the archive's database."""

    dialect: str

    @abstractmethod
    async def open(self) -> None:
        """Connect and apply pending migrations."""

    @abstractmethod
    async def close(self) -> None:
        """Disconnect; safe to call twice."""

    @abstractmethod
    async def fetch(self, sql: str, params: Sequence[Any] = ()) -> list[Row]:
        """Rows of a query."""

    @abstractmethod
    def transaction(self) -> contextlib.AbstractAsyncContextManager[Database]:
        """A transaction: statements run through the yielded object, committed at the end."""

    async def fetch_one(self, sql: str, params: Sequence[Any] = ()) -> Row | None:
        rows = await self.fetch(sql, params)
        return rows[0] if rows else None

    async def migrate(self) -> list[int]:
        """Apply the migrations not applied yet, each in its own transaction; return their versions."""
        applied_now = []
        for version in sorted(MIGRATIONS):
            async with self.transaction() as tx:
                await self._lock_schema(tx)
                await tx.fetch(SCHEMA_TABLE)
                if await tx.fetch("SELECT version FROM archive_schema WHERE version = ?", [version]):
                    continue
                for statement in MIGRATIONS[version]:
                    await tx.fetch(render(statement, self.dialect))
                now = datetime.now(UTC).isoformat(timespec="seconds")
                await tx.fetch("INSERT INTO archive_schema (version, applied) VALUES (?, ?)", [version, now])
                applied_now.append(version)
        return applied_now

    async def _lock_schema(self, tx: Database) -> None:
        """Keep two servers starting at once from migrating together (SQLite: BEGIN IMMEDIATE does)."""
        return


def open_database(url: str, *, busy_timeout: float = 5.0) -> Database:
    """A Database for ``sqlite:///PATH`` or a ``postgresql://`` DSN (not connected yet)."""
    if url.startswith("sqlite:///"):
        return SqliteDatabase(Path(url.removeprefix("sqlite:///")), busy_timeout=busy_timeout)
    return PostgresDatabase(url)


class SqliteDatabase(Database):
    """One SQLite file in WAL mode; a lock held elsewhere for ``busy_timeout`` seconds gives 503."""

    dialect = "sqlite"

    def __init__(self, path: Path, *, busy_timeout: float = 5.0) -> None:
        self.path = path
        self._busy_timeout = busy_timeout
        self._connection: sqlite3.Connection | None = None
        self._lock = asyncio.Lock()

    async def open(self) -> None:
        def connect() -> sqlite3.Connection:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            connection = sqlite3.connect(
                self.path, timeout=self._busy_timeout, isolation_level=None, check_same_thread=False
            )
            connection.row_factory = sqlite3.Row
            connection.execute("PRAGMA journal_mode=WAL")
            connection.execute("PRAGMA foreign_keys=ON")
            return connection

        self._connection = await _sqlite_call(connect)
        await self.migrate()

    async def close(self) -> None:
        connection, self._connection = self._connection, None
        if connection is not None:
            async with self._lock:
                await asyncio.to_thread(connection.close)

    def _run(self, sql: str, params: Sequence[Any]) -> list[Row]:
        if self._connection is None:
            raise DatabaseUnavailable("not connected")
        cursor = self._connection.execute(sql, list(params))
        return [dict(row) for row in cursor.fetchall()]

    async def fetch(self, sql: str, params: Sequence[Any] = ()) -> list[Row]:
        async with self._lock:
            result: list[Row] = await _sqlite_call(self._run, sql, params)
            return result

    @contextlib.asynccontextmanager
    async def transaction(self) -> AsyncIterator[Database]:
        async with self._lock:
            await _sqlite_call(self._run, "BEGIN IMMEDIATE", ())
            try:
                yield _SqliteTransaction(self)
                await _sqlite_call(self._run, "COMMIT", ())
            except BaseException:
                with contextlib.suppress(sqlite3.Error, DatabaseUnavailable):
                    await asyncio.to_thread(self._run, "ROLLBACK", ())
                raise


class _SqliteTransaction(Database):
    """Statements inside a SqliteDatabase transaction (its lock is held by the transaction)."""

    dialect = "sqlite"

    def __init__(self, database: SqliteDatabase) -> None:
        self._database = database

    async def open(self) -> None:
        return

    async def close(self) -> None:
        return

    async def fetch(self, sql: str, params: Sequence[Any] = ()) -> list[Row]:
        result: list[Row] = await _sqlite_call(self._database._run, sql, params)
        return result

    def transaction(self) -> contextlib.AbstractAsyncContextManager[Database]:
        raise NotImplementedError("transactions do not nest")


async def _sqlite_call(function: Any, *args: Any) -> Any:
    try:
        return await asyncio.to_thread(function, *args)
    except sqlite3.IntegrityError as exc:
        raise Rejected(409, f"conflicts with a stored frame ({exc})") from exc
    except sqlite3.Error as exc:
        raise DatabaseUnavailable(f"SQLite: {exc}") from exc


class PostgresDatabase(Database):
    """A small asyncpg pool; a lost server gives 503 (the pool reconnects on the next request)."""

    dialect = "postgresql"

    def __init__(self, dsn: str) -> None:
        self._dsn = dsn
        self._pool: Any = None

    def __repr__(self) -> str:
        return "PostgresDatabase(<dsn hidden>)"  # a DSN may hold a password

    async def open(self) -> None:
        try:
            self._pool = await asyncpg.create_pool(
                self._dsn, min_size=1, max_size=4, timeout=10, command_timeout=30
            )
        except (OSError, asyncpg.PostgresError, asyncpg.InterfaceError) as exc:
            raise DatabaseUnavailable(f"PostgreSQL: {exc}") from exc
        await self.migrate()

    async def close(self) -> None:
        pool, self._pool = self._pool, None
        if pool is not None:
            await pool.close()

    async def fetch(self, sql: str, params: Sequence[Any] = ()) -> list[Row]:
        async with self._errors():
            if self._pool is None:
                raise DatabaseUnavailable("not connected")
            rows = await self._pool.fetch(_numbered(sql), *params)
        return [dict(row) for row in rows]

    @contextlib.asynccontextmanager
    async def transaction(self) -> AsyncIterator[Database]:
        async with self._errors():
            if self._pool is None:
                raise DatabaseUnavailable("not connected")
            async with self._pool.acquire() as connection, connection.transaction():
                yield _PostgresConnection(connection)

    async def _lock_schema(self, tx: Database) -> None:
        await tx.fetch("SELECT pg_advisory_xact_lock(4242019)")

    @staticmethod
    @contextlib.asynccontextmanager
    async def _errors() -> AsyncIterator[None]:
        try:
            yield
        except asyncpg.IntegrityConstraintViolationError as exc:
            raise Rejected(409, f"conflicts with a stored frame ({exc})") from exc
        except (OSError, asyncpg.PostgresError, asyncpg.InterfaceError, asyncpg.InternalClientError) as exc:
            # InternalClientError: a connection the server is closing under a running statement
            raise DatabaseUnavailable(f"PostgreSQL: {exc}") from exc


class _PostgresConnection(Database):
    """One connection inside a transaction (what PostgresDatabase.transaction yields)."""

    dialect = "postgresql"

    def __init__(self, connection: Any) -> None:
        self._connection = connection

    async def open(self) -> None:
        return

    async def close(self) -> None:
        return

    async def fetch(self, sql: str, params: Sequence[Any] = ()) -> list[Row]:
        async with PostgresDatabase._errors():
            rows = await self._connection.fetch(_numbered(sql), *params)
        return [dict(row) for row in rows]

    def transaction(self) -> contextlib.AbstractAsyncContextManager[Database]:
        raise NotImplementedError("transactions do not nest")


def _numbered(sql: str) -> str:
    counter = iter(range(1, 10_000))
    return _PLACEHOLDER.sub(lambda _: f"${next(counter)}", sql)
