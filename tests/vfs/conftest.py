"""Fixtures for the VFS tests: one VFS per root type, so contract tests run on every root."""

from __future__ import annotations

from collections.abc import AsyncIterator, Iterator
from pathlib import Path

import pytest

from nightcrew.vfs import FileRoot, LocalFile, MemoryFile, TempFile, VirtualFileSystem

ROOT_KINDS = ["local", "memory", "shared-memory", "temp"]


@pytest.fixture(autouse=True)
def _forget_shared_memory() -> Iterator[None]:
    """Shared MemoryFile stores live in the process: start and end every test without them."""
    MemoryFile.clear_shared()
    yield
    MemoryFile.clear_shared()


def make_root(kind: str, tmp_path: Path) -> FileRoot:
    """Build a fresh, empty root of the given kind."""
    if kind == "local":
        return LocalFile(str(tmp_path / "images"))
    if kind == "memory":
        return MemoryFile()
    if kind == "shared-memory":
        return MemoryFile("contract")
    if kind == "temp":
        return TempFile(prefix="nightcrew-test-")
    raise AssertionError(kind)


@pytest.fixture(params=ROOT_KINDS)
def root(request: pytest.FixtureRequest, tmp_path: Path) -> FileRoot:
    kind: str = request.param
    return make_root(kind, tmp_path)


@pytest.fixture
async def vfs(root: FileRoot) -> AsyncIterator[VirtualFileSystem]:
    """A VFS with the parametrised root mounted as ``/cache``."""
    async with VirtualFileSystem({"cache": root}) as filesystem:
        yield filesystem
