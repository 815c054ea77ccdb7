"""The virtual file system: modules share files by path, wherever the files are stored.

A path's first component names a root (``/cache/img.fits`` → root ``cache``); each root is a
:class:`FileRoot`: :class:`LocalFile` (a directory on disk), :class:`MemoryFile` (in-process,
shareable by name), :class:`TempFile` (a temporary directory removed on close), :class:`HttpFile`
(an HTTP file cache, see :mod:`nightcrew.modules.image.http_cache`), :class:`SSHFile` (a
directory on an SSH server, over SFTP), :class:`SMBFile` (a directory on an SMB share),
:class:`ArchiveFile` (the image archive, ``nightcrew archive``: writing uploads a frame). Errors are
described in :mod:`nightcrew.vfs._errors` and derive from :class:`nightcrew.errors.NightcrewError`.
"""

from nightcrew.vfs._archive import ArchiveFile
from nightcrew.vfs._errors import (
    UnknownRootError,
    VfsError,
    VfsFileNotFoundError,
    VfsFormatError,
    VfsPathError,
)
from nightcrew.vfs._filesystem import VirtualFileSystem
from nightcrew.vfs._http import HttpFile
from nightcrew.vfs._local import LocalFile
from nightcrew.vfs._memory import MemoryFile
from nightcrew.vfs._root import FileRoot
from nightcrew.vfs._smb import SMBFile
from nightcrew.vfs._ssh import SSHFile
from nightcrew.vfs._temp import TempFile

__all__ = [
    "ArchiveFile",
    "FileRoot",
    "HttpFile",
    "LocalFile",
    "MemoryFile",
    "SMBFile",
    "SSHFile",
    "TempFile",
    "UnknownRootError",
    "VfsError",
    "VfsFileNotFoundError",
    "VfsFormatError",
    "VfsPathError",
    "VirtualFileSystem",
]
