"""The database going away in the middle of an upload: a 503 naming it, and nothing half-stored —
the file written before the commit is removed again, and the index holds no row."""

from __future__ import annotations

import asyncio
import sqlite3
from collections.abc import Iterator
from pathlib import Path

import asyncpg  # type: ignore[import-untyped]
import pytest

from nightcrew.testing.archive import fits_frame, running_archive
from nightcrew.testing.postgres import PostgresCluster, postgres_missing

from .conftest import Client
from .test_upload import stored_files

PATIENCE = 30.0


async def test_sqlite_locked_during_the_commit_gives_503_and_no_file(tmp_path: Path) -> None:
    async with running_archive(tmp_path, sqlite_busy_timeout=0.2) as archive:
        client = Client(archive)
        # Another writer holds the database: reads go on (WAL), the upload's commit cannot.
        other = sqlite3.connect(tmp_path / "archive.db", isolation_level=None)
        try:
            other.execute("BEGIN IMMEDIATE")
            status, body = await client.upload(fits_frame(), "a.fits")
            assert status == 503 and body["error"] == "Service Unavailable"
            assert (
                "database is unavailable (SQLite: database is locked); nothing was stored" in body["detail"]
            )
            assert stored_files(archive) == []
            other.execute("ROLLBACK")
            assert (await client.upload(fits_frame(), "a.fits"))[0] == 201
            assert stored_files(archive) == ["20261124/sbig6303/a.fits"]
        finally:
            other.close()
            await client.close()


@pytest.fixture
def own_cluster() -> Iterator[PostgresCluster]:
    """A cluster of this test's own, because the test stops it."""
    reason = postgres_missing()
    if reason is not None:
        pytest.skip(reason)
    cluster = PostgresCluster()
    try:
        cluster.start()
        yield cluster
    finally:
        cluster.remove()


async def test_postgres_stopping_mid_upload_gives_503_and_no_file(
    tmp_path: Path, own_cluster: PostgresCluster
) -> None:
    dsn = await own_cluster.create_database()
    async with running_archive(tmp_path, database=dsn) as archive:
        client = Client(archive)
        watcher = await asyncpg.connect(dsn)
        try:
            # The upload's transaction sleeps inside its header insert until the server stops: it
            # cannot commit first (a lock held by another session would be released by the stop).
            await watcher.execute(SLEEPING_HEADER_INSERT)
            upload = asyncio.create_task(client.upload(fits_frame(), "a.fits"))
            async with asyncio.timeout(PATIENCE):
                while not await watcher.fetchval(  # noqa: ASYNC110 - polling another process's state
                    "SELECT count(*) FROM pg_stat_activity WHERE wait_event = 'PgSleep'"
                ):
                    await asyncio.sleep(0.02)
            assert (archive.storage / "20261124/sbig6303/a.fits").exists()  # the file waits for its row
            await asyncio.to_thread(own_cluster.stop)
            status, body = await upload
            assert status == 503 and "the archive's database is unavailable (PostgreSQL:" in body["detail"]
            assert stored_files(archive) == []
            await asyncio.to_thread(own_cluster.start)
            again = await asyncpg.connect(dsn)
            try:
                await again.execute("DROP TRIGGER sleep_on_insert ON frame_headers")
            finally:
                await again.close()
            async with asyncio.timeout(PATIENCE):  # the pool replaces its dead connections
                while (await client.upload(fits_frame(), "a.fits"))[0] == 503:  # noqa: ASYNC110 - retrying
                    await asyncio.sleep(0.05)
            status, body = await client.get("/frames/")
            assert status == 200 and [f["basename"] for f in body["results"]] == ["a.fits"]
            assert stored_files(archive) == ["20261124/sbig6303/a.fits"]
        finally:
            watcher.terminate()
            await client.close()


SLEEPING_HEADER_INSERT = """
CREATE FUNCTION sleep_on_insert() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN PERFORM pg_sleep(3600); RETURN NEW; END $$;
CREATE TRIGGER sleep_on_insert BEFORE INSERT ON frame_headers FOR EACH ROW EXECUTE FUNCTION sleep_on_insert();
"""
