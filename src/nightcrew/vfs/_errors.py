"""Errors of the virtual file system.

All derive from :class:`nightcrew.errors.NightcrewError`, so they keep their class across RPC::

    NightcrewError
    └── VfsError                 a file operation failed (permission, is a directory, closed root ...)
        ├── VfsPathError         a path is malformed or leaves its root (``..``, symlink, NUL ...)
        │   └── UnknownRootError the first path component names no configured root
        ├── VfsFileNotFoundError the file or directory does not exist
        └── VfsFormatError       the content cannot be read or written as FITS / YAML / CSV

The message names the VFS path (``/cache/a.fits: no such file or directory``), so it still says
where the problem is after travelling over the comm, which carries only class name and message.
"""

from __future__ import annotations

from nightcrew.errors import NightcrewError

__all__ = ["UnknownRootError", "VfsError", "VfsFileNotFoundError", "VfsFormatError", "VfsPathError"]


class VfsError(NightcrewError):
    """A virtual file system operation failed.

    Args:
        message: What went wrong, without the path.
        path: The path concerned, prefixed to the message when given.
        module: Name of the module where the error was raised, if it came over the comm.
    """

    def __init__(self, message: str = "", *, path: str | None = None, module: str | None = None) -> None:
        super().__init__(f"{path}: {message}" if path is not None else message, module=module)
        self.reason = message
        self.path = path

    def with_path(self, path: str) -> VfsError:
        """Return an error of the same class about ``path`` (a root's relative path → a VFS path)."""
        return type(self)(self.reason, path=path, module=self.module)


class VfsPathError(VfsError):
    """A path is malformed or would leave its root."""


class UnknownRootError(VfsPathError):
    """A path starts with a root name that is not configured."""


class VfsFileNotFoundError(VfsError):
    """A file or directory does not exist."""


class VfsFormatError(VfsError):
    """Content cannot be parsed or serialised in the requested format."""
