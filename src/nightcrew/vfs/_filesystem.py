"""The virtual file system: one namespace of paths over several storage roots.

Modules exchange files by VFS path (``/cache/2024-11-02/img-0001.fits``), never by content over
the comm: each module's VFS maps the first path component to a root of its own, so the same path
can point at a shared disk, a memory store in tests, or (later) a remote server.
"""

from __future__ import annotations

import contextlib
import io
import logging
from collections.abc import AsyncIterator, Iterator, Mapping, Sequence
from types import MappingProxyType, TracebackType
from typing import IO, TYPE_CHECKING, Any, BinaryIO, Literal, Self, TextIO, overload

from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.vfs import _formats
from nightcrew.vfs._errors import UnknownRootError, VfsError, VfsPathError
from nightcrew.vfs._paths import join_vfs_path, split_vfs_path
from nightcrew.vfs._root import FileRoot

if TYPE_CHECKING:
    from astropy.io.fits import HDUList  # type: ignore[import-untyped]

__all__ = ["VirtualFileSystem"]

log = logging.getLogger(__name__)


@contextlib.contextmanager
def _naming(path: str) -> Iterator[None]:
    """Re-raise a root's error about a relative path as the same error about the VFS ``path``."""
    try:
        yield
    except VfsError as exc:
        raise exc.with_path(path) from exc


class VirtualFileSystem:
    """Files under ``/<root>/<path>``, stored by the root named in the first component.

    Args:
        roots: Root name → built root, e.g. ``{"cache": LocalFile("/data/images")}``. In YAML::

            vfs:
              class: nightcrew.vfs.VirtualFileSystem
              roots:
                cache: {class: nightcrew.vfs.LocalFile, root: /data/images}

    Paths are checked before any root is touched: ``..`` may not climb out of its root, and NUL
    bytes, backslashes and control characters are refused (:class:`VfsPathError`); an unknown
    root raises :class:`UnknownRootError` naming the known ones. The constructor does no I/O;
    :meth:`close` (or ``async with``) releases the roots. Whoever builds a VFS closes it: a
    module closes the VFS it built from its configuration (or its empty default) when it closes;
    a VFS built in code and handed to modules is closed by that code, after the modules.
    """

    def __init__(self, roots: Mapping[str, FileRoot] | None = None) -> None:
        checked: dict[str, FileRoot] = {}
        for name, root in (roots or {}).items():
            if not isinstance(name, str) or not name or name in (".", "..") or "/" in name:
                raise ConfigError(f"invalid root name {name!r}: use a plain name like 'cache'", key="roots")
            try:
                split_vfs_path("/" + name)
            except VfsPathError as exc:
                raise ConfigError(f"invalid root name {name!r}: {exc.reason}", key="roots") from exc
            if not isinstance(root, FileRoot):
                raise ConfigError(
                    f"expected a FileRoot (LocalFile, MemoryFile, ...), got {type(root).__name__}",
                    key=f"roots.{name}",
                )
            checked[name] = root
        self._roots = checked
        self._closed = False

    @property
    def roots(self) -> Mapping[str, FileRoot]:
        """The roots by name (read-only)."""
        return MappingProxyType(self._roots)

    def __repr__(self) -> str:
        return f"VirtualFileSystem({self._roots!r})"

    # --- lifecycle -----------------------------------------------------------------------------

    async def close(self) -> None:
        """Close every root once (TempFile roots delete their files); safe to call twice.

        A root whose close fails is logged and the others are still closed: closing runs while a
        module shuts down, where one dead server must not keep the other connections open.
        """
        if self._closed:
            return
        self._closed = True
        closed: set[int] = set()
        for name, root in self._roots.items():
            if id(root) in closed:
                continue  # one root mounted under two names
            closed.add(id(root))
            try:
                await root.close()
            except Exception:
                log.exception("closing VFS root /%s (%r) failed", name, root)

    async def __aenter__(self) -> Self:
        return self

    async def __aexit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        await self.close()

    # --- paths ---------------------------------------------------------------------------------

    def resolve(self, path: str) -> tuple[FileRoot, str]:
        """Return the root serving ``path`` and the normalised path inside it (no I/O)."""
        name, relative = split_vfs_path(path)
        try:
            return self._roots[name], relative
        except KeyError:
            known = ", ".join(f"/{known}" for known in sorted(self._roots)) or "none"
            raise UnknownRootError(f"unknown root '/{name}' (known roots: {known})", path=path) from None

    # --- bytes ---------------------------------------------------------------------------------

    async def read_bytes(self, path: str) -> bytes:
        """Return the whole content of the file at ``path``."""
        root, relative = self.resolve(path)
        with _naming(path):
            return await root.read_bytes(relative)

    async def write_bytes(self, path: str, data: bytes | bytearray | memoryview) -> None:
        """Replace the file at ``path`` by ``data`` atomically (readers see old or new, never half)."""
        root, relative = self.resolve(path)
        with _naming(path):
            await root.write_bytes(relative, data)

    async def exists(self, path: str) -> bool:
        """Return whether a file or directory exists at ``path``."""
        root, relative = self.resolve(path)
        with _naming(path):
            return await root.exists(relative)

    async def listdir(self, path: str) -> list[str]:
        """Return the sorted names (not paths) in the directory at ``path``."""
        root, relative = self.resolve(path)
        with _naming(path):
            return await root.listdir(relative)

    async def remove(self, path: str) -> None:
        """Remove the file at ``path``."""
        root, relative = self.resolve(path)
        with _naming(path):
            await root.remove(relative)

    async def size(self, path: str) -> int:
        """Return the size of the file at ``path`` in bytes."""
        root, relative = self.resolve(path)
        with _naming(path):
            return await root.size(relative)

    async def checksum(self, path: str, algorithm: str = "sha256") -> str:
        """Return the hex digest of the file at ``path`` (any :mod:`hashlib` algorithm)."""
        root, relative = self.resolve(path)
        with _naming(path):
            return await root.checksum(relative, algorithm)

    async def find(self, pattern: str) -> list[str]:
        """Return the sorted VFS paths of files matching a glob ``pattern``.

        The root must be named literally: ``/cache/2024-*/*.fits``, ``/cache/**/*.fits``. ``*``,
        ``?`` and ``[...]`` match within one component, a ``**`` component any number of them.
        """
        name, relative = split_vfs_path(pattern)
        root, _ = self.resolve(join_vfs_path(name, ""))
        with _naming(pattern):
            found = await root.find(relative)
        return [join_vfs_path(name, path) for path in found]

    # --- streams -------------------------------------------------------------------------------

    @overload
    def open_file(
        self, path: str, mode: Literal["r", "w"] = "r", *, encoding: str = "utf-8"
    ) -> contextlib.AbstractAsyncContextManager[TextIO]: ...

    @overload
    def open_file(
        self, path: str, mode: Literal["rb", "wb"], *, encoding: str = "utf-8"
    ) -> contextlib.AbstractAsyncContextManager[BinaryIO]: ...

    def open_file(
        self, path: str, mode: str = "r", *, encoding: str = "utf-8"
    ) -> contextlib.AbstractAsyncContextManager[IO[Any]]:
        """Open ``path`` as a file object: ``async with vfs.open_file("/cache/log.txt", "w") as f``.

        The content is buffered in memory: reading fetches the whole file on entry, writing stores
        it atomically on a clean exit (nothing is written if the block raises). Modes: ``r``,
        ``rb``, ``w``, ``wb``. Named ``open_file`` so as not to clash with a lifecycle ``open()``.
        """
        if mode not in ("r", "rb", "w", "wb"):
            raise InvalidArgumentError(f"unsupported mode {mode!r}; use 'r', 'rb', 'w' or 'wb'")
        self.resolve(path)  # refuse a bad path now, not on entry
        return self._opened(path, mode, encoding)

    @contextlib.asynccontextmanager
    async def _opened(self, path: str, mode: str, encoding: str) -> AsyncIterator[IO[Any]]:
        binary = mode.endswith("b")
        if mode.startswith("r"):
            data = await self.read_bytes(path)
            yield io.BytesIO(data) if binary else io.StringIO(data.decode(encoding), newline="")
            return
        if binary:
            bytes_buffer = io.BytesIO()
            yield bytes_buffer
            await self.write_bytes(path, bytes_buffer.getvalue())
        else:
            text_buffer = io.StringIO(newline="")
            yield text_buffer
            await self.write_bytes(path, text_buffer.getvalue().encode(encoding))

    # --- formats -------------------------------------------------------------------------------

    async def read_fits(self, path: str) -> HDUList:
        """Return the FITS file at ``path`` as an astropy ``HDUList`` held in memory."""
        data = await self.read_bytes(path)
        with _naming(path):
            return _formats.decode_fits(data)

    async def write_fits(self, path: str, hdul: HDUList) -> None:
        """Write an astropy ``HDUList`` (or a single HDU) to ``path`` atomically."""
        with _naming(path):
            data = _formats.encode_fits(hdul)
        await self.write_bytes(path, data)

    async def read_yaml(self, path: str) -> Any:
        """Return the value of the YAML file at ``path`` (safe loader: plain types only)."""
        data = await self.read_bytes(path)
        with _naming(path):
            return _formats.decode_yaml(data)

    async def write_yaml(self, path: str, value: Any) -> None:
        """Write ``value`` (plain types only) to ``path`` as YAML, keys in their order."""
        with _naming(path):
            data = _formats.encode_yaml(value)
        await self.write_bytes(path, data)

    async def read_csv(self, path: str) -> list[dict[str, str]]:
        """Return the rows of the CSV file (with header line) at ``path`` as dicts of strings."""
        data = await self.read_bytes(path)
        with _naming(path):
            return _formats.decode_csv(data)

    async def write_csv(
        self, path: str, rows: Sequence[Mapping[str, object]], *, fieldnames: Sequence[str] | None = None
    ) -> None:
        """Write ``rows`` to ``path`` as CSV; columns are ``fieldnames`` or the rows' keys in order."""
        with _naming(path):
            data = _formats.encode_csv(rows, fieldnames)
        await self.write_bytes(path, data)
