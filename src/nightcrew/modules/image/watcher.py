"""ImageWatcher: moves new files from a local directory to every destination, losing none.

Every ``interval`` clock seconds it lists the watched directory. A file whose size did not change
since the previous sweep is complete; it is read once, then copied to each destination (VFS
directories) and each copy is verified by size and checksum. Only when every destination holds a
verified copy, and the original still has the checksum that was copied, is the original deleted.
A destination that fails is left alone for a while (``retry_delay``, doubling up to
``max_retry_delay``) and the file waits; the other destinations go on. A destination that refuses
a file's content (an archive refusing a frame without its required keywords) is not down: that
file is not offered to it again until its size changes, an error says why, it stays in the
watched directory, and the files after it go on. Progress is saved in ``state_file`` after every
sweep (see :mod:`nightcrew.modules.image.watch_state`).
"""

from __future__ import annotations

import hashlib
import logging
import os
from typing import Any

from nightcrew.config import DataPath
from nightcrew.errors import ConfigError
from nightcrew.interfaces import ModuleState
from nightcrew.interfaces.quantities import Period
from nightcrew.modules.image.watch_state import Backoff, PendingFile, WatchState
from nightcrew.modules.module import Module
from nightcrew.vfs import LocalFile, VfsError, VfsFormatError

__all__ = ["ImageWatcher"]

log = logging.getLogger(__name__)

STATE_NAME = ".nightcrew-watcher.json"


def _hidden(path: str) -> bool:
    return any(part.startswith(".") for part in path.split("/"))


class ImageWatcher(Module):
    """Moves files from a local directory to one or more VFS destinations.

    Args:
        watch: Local directory to watch (files in subdirectories too; hidden ones are skipped).
        destinations: VFS directories to copy to, e.g. ``[/archive/raw, /backup/raw]``; a file
            ``a/b.fits`` goes to ``/archive/raw/a/b.fits``.
        pattern: Glob of the files to move, relative to ``watch`` (``**/*.fits``); all by default.
        interval: Clock seconds between two sweeps.
        retry_delay: Clock seconds before trying a failed destination again (doubles each time).
        max_retry_delay: The longest wait between tries.
        state_file: Local file for the progress; ``<watch>/.nightcrew-watcher.json`` by default.
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        watch: str,
        destinations: list[str],
        pattern: str = "**",
        interval: Period = 5.0,
        retry_delay: float = 10.0,
        max_retry_delay: float = 600.0,
        state_file: DataPath | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not watch:
            raise ConfigError("name the directory to watch", key="watch")
        if not destinations:
            raise ConfigError("name at least one destination", key="destinations")
        for index, destination in enumerate(destinations):
            if not destination.startswith("/"):
                raise ConfigError(
                    f"must be a VFS directory like /archive, got {destination!r}",
                    key=f"destinations[{index}]",
                )
        if len(set(destinations)) != len(destinations):
            raise ConfigError("a destination is listed twice", key="destinations")
        if not interval > 0:
            raise ConfigError(f"must be > 0 seconds, got {interval}", key="interval")
        if not 0 < retry_delay <= max_retry_delay:
            raise ConfigError("need 0 < retry_delay <= max_retry_delay", key="retry_delay")
        self._source = LocalFile(watch, mkdir=False)
        self._destinations = [d.rstrip("/") for d in destinations]
        self._pattern = pattern.strip("/") or "**"
        self._interval = float(interval)
        state_path = os.path.abspath(state_file or os.path.join(watch, STATE_NAME))
        self._state_root = LocalFile(os.path.dirname(state_path))  # atomic writes for the state
        self._state_name = os.path.basename(state_path)
        self._backoffs = {d: Backoff(retry_delay, max_retry_delay) for d in self._destinations}
        self._progress = WatchState()
        self._sizes: dict[str, int] = {}  # file → size at the last sweep, before it is taken on
        self.moved = 0  # originals deleted after verified copies, since opening
        self.add_background_task(self._sweep_loop)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        try:
            self._progress = WatchState.from_json(await self._state_root.read_bytes(self._state_name))
            log.info("%s: resuming %d files from the saved state", self.name, len(self._progress.files))
        except VfsError:
            self._progress = WatchState()  # first start
        except ValueError as exc:
            log.warning("%s: ignoring unreadable state (%s); copies may be repeated", self.name, exc)
        await super().open()

    async def close(self) -> None:
        was_open = self._is_open
        await super().close()
        if was_open:
            await self._save_state()

    @property
    def pending(self) -> int:
        """Files taken on but not yet moved."""
        return len(self._progress.files)

    # --- sweeping ------------------------------------------------------------------------------

    async def _sweep_loop(self) -> None:
        while True:
            try:
                await self.sweep()
            finally:
                await self._save_state()
            await self.clock.sleep(self._interval)

    async def sweep(self) -> None:
        """Take on complete files, copy what is due and delete originals whose copies are verified."""
        present = [p for p in await self._source.find(self._pattern) if not _hidden(p)]
        await self._take_on(present)
        for name in set(self._progress.files) - set(present):
            log.warning("%s: %s vanished before it was moved", self.name, name)
            del self._progress.files[name]
        for name in sorted(self._progress.files):
            await self._deliver(name, self._progress.files[name])

    async def _take_on(self, present: list[str]) -> None:
        sizes = {}
        for name in present:
            if name in self._progress.files:
                continue
            try:
                sizes[name] = await self._source.size(name)
            except VfsError:
                continue  # gone meanwhile
            if self._sizes.get(name) == sizes[name]:  # unchanged for a sweep: the writer is done
                self._progress.files[name] = PendingFile(sizes[name])
                del sizes[name]
        self._sizes = sizes

    async def _deliver(self, name: str, pending: PendingFile) -> None:
        data: bytes | None = None
        if pending.refused and await self._source.size(name) != pending.size:
            pending.refused = {}  # rewritten: offer it again
        for destination in self._destinations:
            backoff = self._backoffs[destination]
            if destination in pending.verified or destination in pending.refused:
                continue
            if not backoff.ready(self.clock.time()):
                continue
            if data is None:
                data = await self._source.read_bytes(name)
                checksum = hashlib.sha256(data).hexdigest()
                if checksum != pending.checksum:  # first read, or rewritten: copies start afresh
                    pending.size, pending.checksum = len(data), checksum
                    pending.verified, pending.refused = set(), {}
            target = f"{destination}/{name}"
            try:
                await self.vfs.write_bytes(target, data)
                if await self.vfs.size(target) != len(data) or await self.vfs.checksum(target) != checksum:
                    raise VfsError("copy differs from the original", path=target)
            except VfsFormatError as exc:  # the content, not the destination: trying again cannot help
                pending.refused[destination] = exc.reason
                log.error("%s: %s refused %s, which stays here: %s", self.name, destination, name, exc)
                continue
            except Exception as exc:  # any failure of a destination: the file waits, nothing is lost
                delay = backoff.failed(self.clock.time())
                log.warning("%s: %s; retrying %s in %.0f s", self.name, exc, destination, delay)
                continue
            backoff.succeeded()
            pending.verified.add(destination)
        if pending.verified.issuperset(self._destinations):
            await self._remove_original(name, pending)

    async def _remove_original(self, name: str, pending: PendingFile) -> None:
        # The original must still be what was copied: a file rewritten meanwhile starts over.
        if await self._source.checksum(name) != pending.checksum:
            pending.verified = set()
            return
        await self._source.remove(name)
        del self._progress.files[name]
        self.moved += 1

    async def _save_state(self) -> None:
        try:
            await self._state_root.write_bytes(self._state_name, self._progress.to_json())
        except VfsError as exc:
            log.error("%s: cannot save the state: %s", self.name, exc)
