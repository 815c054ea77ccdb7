"""Benchmark: the image archive's ingest rate and search latency, on SQLite and on PostgreSQL.

Run: ``.venv/bin/python bench/archive.py [--frames 1000] [--rows 100000] [--queries 200]``.

* **Ingest**: ``--frames`` small FITS frames (64x64, 11 kB) uploaded over HTTP to a running
  archive, four at a time, each checked, stored (fsync, rename) and indexed. Baseline in the same
  run: the same frames only written to disk the same way (no HTTP, no check, no index).
* **Search**: ``--rows`` header rows inserted straight through the archive's database layer
  (``insert_frame``, the same statements an upload runs; not 100,000 FITS uploads), then
  ``--queries`` cone (5°) + 30-day + filter searches at seeded random places, timed through HTTP
  (``GET /frames/``: count and first page) and in the database engine (SQLite: the call in this
  process; PostgreSQL: the server's EXPLAIN ANALYZE execution time). Baseline in the same run: the
  same query as a full scan (SQLite ``NOT INDEXED``; PostgreSQL with index scans disabled).
  Target: p95 ≤ 100 ms through HTTP.

PostgreSQL is a private cluster (nightcrew.testing.postgres) with fsync on, as in a deployment.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import math
import shutil
import tempfile
import time
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import aiohttp
import numpy as np

from nightcrew.services.archive._db import Database
from nightcrew.services.archive._fits import FrameFacts, inspect_fits
from nightcrew.services.archive._index import StoredFile, insert_frame
from nightcrew.services.archive._search import parse_search
from nightcrew.services.archive._store import FrameStore
from nightcrew.testing.archive import RunningArchive, fits_frame, running_archive
from nightcrew.testing.postgres import PostgresCluster

FILTERS = ["U", "B", "V", "R", "I", "clear"]
EPOCH = datetime(2026, 1, 1, tzinfo=UTC)


def percentile(values: list[float], q: float) -> float:
    return float(np.percentile(values, q))


async def ingest(archive: RunningArchive, frames: list[bytes]) -> float:
    """Frames per second uploaded over HTTP, four requests at a time."""
    queue = list(enumerate(frames))
    headers = {"Authorization": f"Bearer {archive.token}"}

    async def worker(http: aiohttp.ClientSession) -> None:
        while queue:
            index, data = queue.pop()
            url = f"{archive.url}/frames/upload/?filename=f{index:05d}.fits"
            async with http.post(url, data=data, headers=headers) as response:
                assert response.status == 201, await response.text()

    started = time.perf_counter()
    async with aiohttp.ClientSession() as http:
        await asyncio.gather(*(worker(http) for _ in range(4)))
    return len(frames) / (time.perf_counter() - started)


def disk_only(directory: Path, frames: list[bytes]) -> float:
    store = FrameStore(directory)
    started = time.perf_counter()
    for index, data in enumerate(frames):
        store.blocking_write(f"20260101/cam/f{index:05d}.fits", data)
    return len(frames) / (time.perf_counter() - started)


def synthetic_facts(rng: np.random.Generator, template: FrameFacts, rows: int) -> list[FrameFacts]:
    """Header rows spread over a year and the whole sky, six filters."""
    seconds = rng.uniform(0, 365 * 86400, rows)
    ras = rng.uniform(0, 360, rows)
    decs = np.degrees(np.arcsin(rng.uniform(-1, 1, rows)))
    filters = rng.integers(0, len(FILTERS), rows)
    facts = []
    for i in range(rows):
        moment = EPOCH + timedelta(seconds=float(seconds[i]))
        facts.append(
            FrameFacts(
                date_obs=moment,
                day_obs=moment.strftime("%Y%m%d"),
                instrument="sbig6303",
                imagetyp="object",
                exptime=30.0,
                object=f"field-{i % 5000}",
                filter=FILTERS[filters[i]],
                proposal=f"P{i % 7}",
                task=f"task-{i % 300}",
                rlevel=0,
                ra=float(ras[i]),
                dec=float(decs[i]),
                cards=template.cards,
            )
        )
    return facts


async def fill(database: Database, facts: list[FrameFacts]) -> float:
    """Insert the rows in transactions of 1000; return rows per second."""
    started = time.perf_counter()
    for start in range(0, len(facts), 1000):
        async with database.transaction() as tx:
            for i, fact in enumerate(facts[start : start + 1000], start):
                await insert_frame(
                    tx, fact, StoredFile(f"row{i:06d}.fits", f"x/row{i:06d}.fits", f"{i:064x}", 11520)
                )
    return len(facts) / (time.perf_counter() - started)


def query_params(rng: np.random.Generator) -> dict[str, str]:
    start = EPOCH + timedelta(days=float(rng.uniform(0, 335)))
    return {
        "ra": f"{rng.uniform(0, 360):.4f}",
        "dec": f"{math.degrees(math.asin(rng.uniform(-0.95, 0.95))):.4f}",
        "radius": "5",
        "start": start.isoformat(),
        "end": (start + timedelta(days=30)).isoformat(),
        "FILTER": FILTERS[int(rng.integers(0, len(FILTERS)))],
    }


async def search_times(archive: RunningArchive, queries: list[dict[str, str]]) -> tuple[list[float], int]:
    times, found = [], 0
    async with aiohttp.ClientSession() as http:
        for params in queries:
            started = time.perf_counter()
            async with http.get(f"{archive.url}/frames/", params=params) as response:
                body = await response.json()
            times.append((time.perf_counter() - started) * 1e3)
            found += body["count"]
    return times, found


async def database_times(
    database: Database, queries: list[dict[str, str]], *, full_scan: bool
) -> list[float]:
    """Milliseconds the database engine spends on each query's count.

    SQLite runs in this process: the wall time of the call. PostgreSQL: the server's own
    ``Execution Time`` (EXPLAIN ANALYZE), so the index's effect is not hidden by round trips on a
    busy machine. The full scan: SQLite ``NOT INDEXED``, PostgreSQL with index scans disabled.
    """
    times = []
    for params in queries:
        query = parse_search(params)
        sql = f"SELECT COUNT(*) AS n FROM frames{query.where()}"
        if database.dialect == "sqlite":
            if full_scan:
                sql = sql.replace("FROM frames", "FROM frames NOT INDEXED")
            started = time.perf_counter()
            await database.fetch(sql, query.params)
            times.append((time.perf_counter() - started) * 1e3)
            continue
        async with database.transaction() as tx:
            if full_scan:
                await tx.fetch("SET LOCAL enable_indexscan = off")
                await tx.fetch("SET LOCAL enable_bitmapscan = off")
            plan = await tx.fetch(f"EXPLAIN (ANALYZE, FORMAT JSON) {sql}", query.params)
        times.append(float(json.loads(next(iter(plan[0].values())))[0]["Execution Time"]))
    return times


async def run(kind: str, dsn: str | None, args: argparse.Namespace, rows: list[dict[str, Any]]) -> None:
    directory = Path(tempfile.mkdtemp(prefix=f"bench-archive-{kind}-"))
    try:
        frames = [
            fits_frame(seed=i, shape=(64, 64), date_obs=f"2026-01-01T00:00:{i % 60:02d}")
            for i in range(args.frames)
        ]
        async with running_archive(directory, database=dsn) as archive:
            rate = await ingest(archive, frames)
            baseline = await asyncio.to_thread(disk_only, directory / "disk-only", frames)
            database = archive.server.database
            facts = synthetic_facts(
                np.random.default_rng(1), inspect_fits(frames[0], max_pixels=64 * 64), args.rows
            )
            fill_rate = await fill(database, facts)
            await database.fetch("ANALYZE")  # planner statistics, as after any bulk load
            queries = [query_params(np.random.default_rng(100 + i)) for i in range(args.queries)]
            http_ms, found = await search_times(archive, queries)
            indexed_ms = await database_times(database, queries, full_scan=False)
            scan_ms = await database_times(database, queries[: max(5, args.queries // 10)], full_scan=True)
            rows.append(
                {
                    "database": kind,
                    "ingest": rate,
                    "disk": baseline,
                    "fill": fill_rate,
                    "http_p50": percentile(http_ms, 50),
                    "http_p95": percentile(http_ms, 95),
                    "db_p95": percentile(indexed_ms, 95),
                    "scan_p95": percentile(scan_ms, 95),
                    "found": found / len(queries),
                    "total": await archive.server.index.count(),
                }
            )
    finally:
        shutil.rmtree(directory, ignore_errors=True)


async def main(args: argparse.Namespace) -> None:
    rows: list[dict[str, Any]] = []
    await run("SQLite", None, args, rows)
    cluster = PostgresCluster(durable=True)
    try:
        await asyncio.to_thread(cluster.start)
        await run("PostgreSQL", await cluster.create_database("bench"), args, rows)
    finally:
        await asyncio.to_thread(cluster.remove)
    print(
        f"ingest: {args.frames} FITS frames of 11 kB over HTTP, 4 at a time; "
        "baseline = the same files only written (fsync, rename)"
    )
    print(
        f"search: cone 5 deg + 30 days + filter over {args.rows} + {args.frames} frames, "
        f"{args.queries} queries"
    )
    print(
        f"{'database':<11} {'ingest/s':>9} {'disk-only/s':>12} {'ratio':>6} {'rows/s':>8} "
        f"{'HTTP p50 ms':>12} {'HTTP p95 ms':>12} {'engine p95':>10} {'scan p95':>9} "
        f"{'scan/index':>11} {'hits':>5}"
    )
    for row in rows:
        print(
            f"{row['database']:<11} {row['ingest']:>9.0f} {row['disk']:>12.0f} "
            f"{row['ingest'] / row['disk']:>6.2f} "
            f"{row['fill']:>8.0f} {row['http_p50']:>12.1f} {row['http_p95']:>12.1f} {row['db_p95']:>10.1f} "
            f"{row['scan_p95']:>9.1f} {row['scan_p95'] / row['db_p95']:>10.0f}x {row['found']:>5.1f}"
        )
        met = "met" if row["http_p95"] <= 100 else "MISSED"
        print(f"  {row['database']}: {row['total']} frames indexed; target HTTP p95 <= 100 ms -> {met}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=1000, help="frames uploaded for the ingest rate")
    parser.add_argument("--rows", type=int, default=100_000, help="header rows for the search")
    parser.add_argument("--queries", type=int, default=200, help="searches timed")
    asyncio.run(main(parser.parse_args()))
