"""Parsing and checking VFS paths; turning glob patterns into regular expressions.

A VFS path looks like ``/cache/2024/img.fits``: the first component names a root, the rest is a
path inside that root. Paths are checked here, as text, before any root sees them; a root that
touches a real disk checks again after resolving symlinks (see ``LocalFile``).
"""

from __future__ import annotations

import re

from nightcrew.vfs._errors import VfsPathError

__all__ = ["glob_regex", "join_vfs_path", "normalise_relative", "split_vfs_path", "static_prefix"]

_GLOB_CHARS = frozenset("*?[")


def _check_characters(path: object) -> str:
    """Return ``path`` if it is a string without characters that have no place in a path."""
    if not isinstance(path, str):
        raise VfsPathError(f"a path must be a string, got {type(path).__name__}")
    if "\x00" in path:
        raise VfsPathError("NUL byte in path", path=repr(path))
    if "\\" in path:
        # A backslash is a separator on Windows and an escape in globs: refuse it rather than guess.
        raise VfsPathError("backslash in path (use '/')", path=path)
    if any(ord(char) < 0x20 or ord(char) == 0x7F for char in path):
        raise VfsPathError("control character in path", path=repr(path))
    return path


def normalise_relative(path: str) -> str:
    """Normalise a path inside a root to ``a/b/c`` form; ``""`` stands for the root itself.

    Empty and ``.`` components are dropped and ``..`` removes the previous component. A ``..``
    that would climb above the root raises :class:`VfsPathError`. A leading ``/`` is not an escape:
    the path stays inside the root.
    """
    _check_characters(path)
    parts: list[str] = []
    for part in path.split("/"):
        if part in ("", "."):
            continue
        if part == "..":
            if not parts:
                raise VfsPathError("'..' leaves the root", path=path)
            parts.pop()
        else:
            parts.append(part)
    return "/".join(parts)


def split_vfs_path(path: str) -> tuple[str, str]:
    """Split a VFS path into ``(root_name, path_inside_root)``.

    ``/cache/a/../b.fits`` gives ``("cache", "b.fits")``; ``/cache`` gives ``("cache", "")``.
    Raises :class:`VfsPathError` for an empty or relative path, a path without a root name, or one
    whose ``..`` climbs out of its root (even if it would climb back in).
    """
    _check_characters(path)
    if not path:
        raise VfsPathError("empty path")
    if not path.startswith("/"):
        raise VfsPathError("a VFS path must start with '/<root>/'", path=path)
    head, _, rest = path.lstrip("/").partition("/")
    while head == ".":  # "/./cache/x" is "/cache/x"
        head, _, rest = rest.lstrip("/").partition("/")
    if not head:
        raise VfsPathError("no root named in path", path=path)
    if head == "..":
        raise VfsPathError("'..' leaves the file system", path=path)
    try:
        return head, normalise_relative(rest)
    except VfsPathError as exc:
        raise VfsPathError(f"'..' leaves the root '/{head}'", path=path) from exc


def join_vfs_path(root_name: str, relative: str) -> str:
    """Inverse of :func:`split_vfs_path` for a normalised relative path."""
    return f"/{root_name}/{relative}" if relative else f"/{root_name}"


def static_prefix(pattern: str) -> str:
    """Return the leading directories of a normalised pattern that contain no glob characters.

    ``2024/11/*.fits`` gives ``2024/11``, so a root need only walk that directory.
    """
    parts = pattern.split("/")[:-1]
    static: list[str] = []
    for part in parts:
        if _GLOB_CHARS & set(part):
            break
        static.append(part)
    return "/".join(static)


def _component_regex(component: str) -> str:
    """Translate one glob component: ``*`` and ``?`` stop at ``/``; ``[...]`` is a character set."""
    out: list[str] = []
    i = 0
    while i < len(component):
        char = component[i]
        if char == "*":
            out.append("[^/]*")
        elif char == "?":
            out.append("[^/]")
        elif char == "[" and (end := component.find("]", i + 2)) != -1:
            body = component[i + 1 : end]
            negate = body.startswith("!")
            body = re.escape(body[1:] if negate else body).replace(r"\-", "-")
            out.append(f"[{'^' if negate else ''}{body}]")
            i = end
        else:
            out.append(re.escape(char))
        i += 1
    return "".join(out)


def glob_regex(pattern: str) -> re.Pattern[str]:
    """Compile a normalised glob pattern (relative to a root) into a regex for whole paths.

    ``*`` matches within one component, ``**`` as a whole component matches any number of
    components (also none), so ``**/*.fits`` finds FITS files at every depth.
    """
    parts = pattern.split("/")
    regex: list[str] = []
    for index, part in enumerate(parts):
        last = index == len(parts) - 1
        if part == "**":
            regex.append(".*" if last else "(?:[^/]+/)*")
        else:
            regex.append(_component_regex(part) + ("" if last else "/"))
    return re.compile("".join(regex))
