"""Fixtures of the archive tests: every test runs on SQLite and on PostgreSQL.

PostgreSQL is a private cluster (nightcrew.testing.postgres) started once per session; each test
gets a fresh database in it. Without PostgreSQL those cases skip, except under CI=true.
"""

from __future__ import annotations

import json
from collections.abc import AsyncIterator, Iterator
from pathlib import Path
from typing import Any

import aiohttp
import pytest

from nightcrew.testing.archive import RunningArchive, running_archive
from nightcrew.testing.postgres import PostgresCluster, postgres_missing


@pytest.fixture(scope="session")
def postgres_cluster() -> Iterator[PostgresCluster]:
    reason = postgres_missing()
    if reason is not None:
        pytest.skip(reason)
    cluster = PostgresCluster()
    try:
        cluster.start()
        yield cluster
    finally:
        cluster.remove()


@pytest.fixture(params=["sqlite", "postgresql"])
async def database(request: pytest.FixtureRequest) -> str | None:
    """None for SQLite in the test's directory, or the DSN of a fresh PostgreSQL database."""
    if request.param == "sqlite":
        return None
    cluster: PostgresCluster = request.getfixturevalue("postgres_cluster")
    return await cluster.create_database()


@pytest.fixture
async def archive(tmp_path: Path, database: str | None) -> AsyncIterator[RunningArchive]:
    async with running_archive(tmp_path, database=database) as running:
        yield running


class Client:
    """The archive's API over real HTTP: JSON in and out, uploads with or without the token."""

    def __init__(self, archive: RunningArchive) -> None:
        self.archive = archive
        self.http = aiohttp.ClientSession()

    async def upload(
        self, data: bytes, filename: str, *, token: str | None = ""
    ) -> tuple[int, dict[str, Any]]:
        headers = {} if token is None else {"Authorization": f"Bearer {token or self.archive.token}"}
        async with self.http.post(
            f"{self.archive.url}/frames/upload/", params={"filename": filename}, data=data, headers=headers
        ) as response:
            return response.status, json.loads(await response.read())

    async def get(self, path: str, **params: Any) -> tuple[int, Any]:
        async with self.http.get(
            self.archive.url + path, params={k: str(v) for k, v in params.items()}
        ) as response:
            return response.status, json.loads(await response.read())

    async def get_bytes(self, path: str, **params: Any) -> tuple[int, bytes, str]:
        async with self.http.get(self.archive.url + path, params=params) as response:
            return response.status, await response.read(), response.content_type

    async def close(self) -> None:
        await self.http.close()


@pytest.fixture
async def client(archive: RunningArchive) -> AsyncIterator[Client]:
    made = Client(archive)
    try:
        yield made
    finally:
        await made.close()
