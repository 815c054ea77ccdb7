"""ImageWatcher never loses a file: 1000 files, a destination failing at random, a restart midway."""

from __future__ import annotations

import hashlib
import os
import shutil
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from nightcrew.modules.image import ImageWatcher
from nightcrew.modules.image.watch_state import Backoff, PendingFile, WatchState
from nightcrew.testing import Observatory
from nightcrew.vfs import LocalFile, MemoryFile, VfsError, VirtualFileSystem

FILES = 1000


class FlakyRoot(MemoryFile):
    """A destination that fails like a bad network share: seeded errors and truncated writes."""

    def __init__(self, seed: int, fail: float = 0.15, corrupt: float = 0.05) -> None:
        super().__init__()
        self._rng = np.random.default_rng(seed)
        self._fail, self._corrupt = fail, corrupt
        self.failures = self.corruptions = 0

    async def write_bytes(self, path: str, data: bytes | bytearray | memoryview) -> None:
        draw = self._rng.random()
        if draw < self._fail:
            self.failures += 1
            raise VfsError("injected failure: share not responding", path=path)
        if draw < self._fail + self._corrupt:
            self.corruptions += 1
            data = bytes(data)[: len(data) // 2]  # silently short: only verification notices
        await super().write_bytes(path, data)


def make_files(directory: Path, count: int) -> dict[str, str]:
    """``count`` files of random content in two nights; relative path → sha256."""
    rng = np.random.default_rng(7)
    checksums = {}
    for index in range(count):
        name = f"night-{index % 2}/img-{index:04d}.fits"
        data = rng.integers(0, 256, size=int(rng.integers(256, 4096)), dtype=np.uint8).tobytes()
        (directory / name).parent.mkdir(parents=True, exist_ok=True)
        (directory / name).write_bytes(data)
        checksums[name] = hashlib.sha256(data).hexdigest()
    return checksums


@pytest.fixture
def memory_disk(tmp_path: Path) -> Iterator[Path]:
    """A directory in RAM where there is one (tmpfs: fsync is free), else the test's tmp_path.

    The watcher's logic is under test, not the disk: 2000 fsyncs on a busy disk take many seconds.
    """
    if not os.path.isdir("/dev/shm"):
        yield tmp_path
        return
    directory = Path(tempfile.mkdtemp(prefix="nightcrew-watcher-", dir="/dev/shm"))
    try:
        yield directory
    finally:
        shutil.rmtree(directory, ignore_errors=True)


async def test_thousand_files_with_a_failing_destination_and_a_restart(
    fast_observatory: Observatory, memory_disk: Path
) -> None:
    tmp_path = memory_disk
    obs = fast_observatory
    watch = tmp_path / "watch"
    watch.mkdir()
    checksums = make_files(watch, FILES)
    flaky = FlakyRoot(seed=3)
    vfs = VirtualFileSystem({"flaky": flaky, "archive": LocalFile(str(tmp_path / "archive"))})
    options = {
        "watch": str(watch),
        "destinations": ["/flaky/raw", "/archive"],
        "pattern": "**/*.fits",
        "interval": 2.0,
        "retry_delay": 1.0,
        "max_retry_delay": 8.0,
        "vfs": vfs,
    }
    verified: set[str] = set()

    def originals() -> set[str]:
        prefix = len(str(watch)) + 1
        return {
            f"{folder[prefix:]}/{name}"
            for folder, _, names in os.walk(watch)
            for name in names
            if name.endswith(".fits")
        }

    async def check_deleted_originals_have_verified_copies() -> None:
        for name in sorted(set(checksums) - verified - originals()):
            for target in (f"/flaky/raw/{name}", f"/archive/{name}"):
                assert await vfs.checksum(target) == checksums[name], (
                    f"{name} deleted before {target} was good"
                )
            verified.add(name)

    started = time.perf_counter()
    watcher = await obs.start(ImageWatcher, "watcher", **options)
    while watcher.moved < FILES // 3:
        await obs.clock.sleep(20.0)  # checking takes wall time too: not after every sweep
        await check_deleted_originals_have_verified_copies()
        assert time.perf_counter() - started < 40, f"only {watcher.moved} files moved"
    await watcher.close()  # a restart midway: the saved state carries on
    assert (watch / ".nightcrew-watcher.json").exists()
    watcher = await obs.start(ImageWatcher, "watcher-again", **options)
    while originals():
        await obs.clock.sleep(20.0)  # checking takes wall time too: not after every sweep
        await check_deleted_originals_have_verified_copies()
        assert time.perf_counter() - started < 40, f"{len(originals())} files left"
    await check_deleted_originals_have_verified_copies()
    assert verified == set(checksums)
    assert await vfs.find("/flaky/raw/**") == sorted(f"/flaky/raw/{n}" for n in checksums)
    assert await vfs.find("/archive/**/*.fits") == sorted(f"/archive/{n}" for n in checksums)
    assert watcher.pending == 0
    print(
        f"{FILES} files moved in {time.perf_counter() - started:.1f} s wall; "
        f"{flaky.failures} injected failures, {flaky.corruptions} corrupted writes caught"
    )
    assert flaky.failures > 50 and flaky.corruptions > 10


async def test_a_file_still_being_written_waits(fast_observatory: Observatory, tmp_path: Path) -> None:
    obs = fast_observatory
    watch = tmp_path / "watch"
    watch.mkdir()
    vfs = VirtualFileSystem({"archive": LocalFile(str(tmp_path / "archive"))})
    # Sweeps by hand: the loop sweeps once at the start, then waits for ever.
    watcher = await obs.start(
        ImageWatcher, "watcher", watch=str(watch), destinations=["/archive"], interval=1e6, vfs=vfs
    )
    await obs.clock.sleep(5.0)  # the loop's first sweep is over
    growing = watch / "growing.fits"
    for _ in range(3):  # grows between sweeps: never taken on
        with growing.open("ab") as stream:
            stream.write(b"x" * 100)
        await watcher.sweep()
        assert watcher.pending == 0 and growing.exists()
    await watcher.sweep()  # unchanged since the last sweep: taken on and moved
    assert not growing.exists()
    assert (tmp_path / "archive" / "growing.fits").read_bytes() == b"x" * 300


def test_state_round_trip_and_backoff() -> None:
    state = WatchState({"a.fits": PendingFile(10, "abc", {"/x", "/y"})})
    assert WatchState.from_json(state.to_json()) == state
    backoff = Backoff(1.0, 5.0)
    assert [backoff.failed(0.0) for _ in range(5)] == [1.0, 2.0, 4.0, 5.0, 5.0]
    assert not backoff.ready(4.9) and backoff.ready(5.0)
    backoff.succeeded()
    assert backoff.ready(0.0) and backoff.failed(0.0) == 1.0
