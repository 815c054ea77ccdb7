"""Who closes a VFS: a module closes the one it built (from its YAML description), after its tasks
and children, once; one handed to it ready-made stays open for its maker; a root failing to close
does not keep the others open."""

from __future__ import annotations

import logging
import uuid
from pathlib import Path

import pytest

from nightcrew.config import build_object, load_config
from nightcrew.errors import ConfigError
from nightcrew.modules import Module
from nightcrew.object import Object
from nightcrew.testing import Observatory, wait_for
from nightcrew.testing.processes import descendants
from nightcrew.testing.sshd import SshServer
from nightcrew.vfs import FileRoot, MemoryFile, TempFile, VirtualFileSystem
from tests.vfs.remote_servers import sshd_fixture  # noqa: F401 - the session's server


def module_file(tmp_path: Path, name: str, roots: str) -> Path:
    """A module's YAML file with a VFS of the given ``roots`` lines (indented by 4)."""
    path = tmp_path / f"{name}.yaml"
    path.write_text(
        f"class: nightcrew.modules.Module\nname: {name}\n"
        f"vfs:\n  class: nightcrew.vfs.VirtualFileSystem\n  roots:\n{roots}"
    )
    return path


def built(path: Path) -> Module:
    module = build_object(load_config(path), Module)
    assert isinstance(module, Module)
    return module


async def test_a_module_built_from_yaml_with_an_ssh_root_leaves_no_session_open(
    sshd: SshServer, tmp_path: Path
) -> None:
    directory = sshd.files / uuid.uuid4().hex[:12]
    roots = (
        f"    remote:\n      class: nightcrew.vfs.SSHFile\n      host: {sshd.host}\n"
        f"      port: {sshd.port}\n      username: {sshd.username}\n      root: {directory}\n"
        f"      client_keys: [{sshd.client_key}]\n      known_hosts: {sshd.known_hosts}\n"
    )
    module = built(module_file(tmp_path, "writer", roots))
    assert sshd.pid is not None
    before = set(descendants(sshd.pid))
    await module.open()
    await module.vfs.write_bytes("/remote/a.fits", b"frame")
    sessions = set(descendants(sshd.pid)) - before  # sshd forks a process for each connection
    assert sessions, "the write opened no SSH session"
    assert (directory / "a.fits").read_bytes() == b"frame"

    await module.close()
    await wait_for(
        lambda: not sessions & set(descendants(sshd.pid or 0)),
        30.0,
        message="sshd's session processes still running after the module closed",
    )
    await module.close()  # safe twice


async def test_a_module_closes_the_vfs_it_built_once_and_after_its_children(tmp_path: Path) -> None:
    closed: list[str] = []

    class Child(Object):
        async def close(self) -> None:
            if self._is_open:
                # The shared VFS still works while a child closes.
                closed.append(f"child sees {await self.vfs.listdir('/cache')}")
            await super().close()

    module = built(module_file(tmp_path, "owner", "    cache: {class: nightcrew.vfs.MemoryFile}\n"))
    child = module.add_child(Child())
    assert child.vfs is module.vfs
    root = module.vfs.roots["cache"]
    assert isinstance(root, MemoryFile)
    await module.open()
    await module.vfs.write_bytes("/cache/a.fits", b"x")
    await module.close()
    assert closed == ["child sees ['a.fits']"]
    assert await root.list_files() == []  # a private MemoryFile is emptied by its close
    await root.write_bytes("b.fits", b"y")
    await module.close()  # safe twice: the VFS is not closed again
    assert await root.list_files() == ["b.fits"]


async def test_a_module_never_opened_still_closes_the_vfs_it_built(tmp_path: Path) -> None:
    module = built(module_file(tmp_path, "idle", "    scratch: {class: nightcrew.vfs.TempFile}\n"))
    await module.vfs.write_bytes("/scratch/a.txt", b"x")  # used without opening the module
    root = module.vfs.roots["scratch"]
    assert isinstance(root, TempFile) and root.directory is not None
    directory = root.directory
    await module.close()
    assert not directory.exists()


async def test_a_vfs_handed_over_ready_made_stays_open_for_its_maker() -> None:
    vfs = VirtualFileSystem({"cache": MemoryFile()})
    first = Module(name="first", vfs=vfs)
    second = build_object({"class": "nightcrew.modules.Module", "name": "second", "vfs": vfs}, Module)
    assert second.vfs is vfs
    for module in (first, second):
        await module.open()
    await vfs.write_bytes("/cache/a.fits", b"x")
    await first.close()
    await second.close()
    assert await vfs.read_bytes("/cache/a.fits") == b"x"  # nobody but its maker closes it
    await vfs.close()
    assert await vfs.exists("/cache/a.fits") is False


async def test_the_observatory_closes_its_default_vfs_but_not_a_given_one() -> None:
    async with Observatory() as obs:
        await obs.start(Module, "m")
        await obs.vfs.write_bytes("/cache/a.fits", b"x")
    assert await obs.vfs.find("/cache/**") == []  # its private MemoryFile was emptied by close

    given = VirtualFileSystem({"cache": MemoryFile()})
    async with Observatory(vfs=given) as obs:
        await obs.start(Module, "m")
        await given.write_bytes("/cache/a.fits", b"x")
    assert await given.find("/cache/**") == ["/cache/a.fits"]
    await given.close()


def test_a_bad_root_in_the_yaml_is_named_with_file_line_and_key(tmp_path: Path) -> None:
    path = module_file(tmp_path, "bad", '    cache: {class: nightcrew.vfs.TempFile, prefix: "a/b"}\n')
    with pytest.raises(ConfigError, match="TempFile prefix must be a plain name") as info:
        built(path)
    assert (info.value.file, info.value.line, info.value.key) == (str(path), 6, "vfs.roots.cache")


class _FailingRoot(MemoryFile):
    """A root whose connection cannot be closed cleanly (a dead server)."""

    async def close(self) -> None:
        raise OSError("connection reset by peer")


async def test_close_goes_on_past_a_root_that_fails_and_closes_each_root_once(
    caplog: pytest.LogCaptureFixture,
) -> None:
    temp, memory = TempFile(), MemoryFile()
    closes: list[str] = []

    class Counted(MemoryFile):
        async def close(self) -> None:
            closes.append("counted")

    counted: FileRoot = Counted()
    vfs = VirtualFileSystem({"a": _FailingRoot(), "b": temp, "c": memory, "d": counted, "e": counted})
    await vfs.write_bytes("/b/x", b"1")
    await vfs.write_bytes("/c/x", b"1")
    directory = temp.directory
    assert directory is not None and directory.exists()
    with caplog.at_level(logging.ERROR, logger="nightcrew.vfs._filesystem"):
        await vfs.close()
    assert not directory.exists()
    assert await memory.list_files() == []
    assert closes == ["counted"]  # mounted twice, closed once
    assert [r.getMessage() for r in caplog.records] == ["closing VFS root /a (MemoryFile()) failed"]
    await vfs.close()
    assert closes == ["counted"]
