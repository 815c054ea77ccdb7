"""VFS file names from a pattern of FITS keywords, e.g. ``/cache/{DATE-OBS}-{IMAGETYP}-{FILTER}.fits``.

Placeholders name header keywords and may carry a format spec (``{FOCUS:.2f}``). Each value is
sanitised to one safe path component (letters, digits and ``._+-``; anything else becomes ``-``),
so a header value can never add directories or climb out of the root. A keyword missing from the
header becomes ``none``. The pattern itself is checked when the object using it (camera, image
writer, CreateFilename) is built.
"""

from __future__ import annotations

import re
import string
from collections.abc import Mapping

from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.interfaces import FitsValue

__all__ = ["check_filename_pattern", "format_filename", "sanitise_component"]

_UNSAFE = re.compile(r"[^A-Za-z0-9._+-]+")
_KEYWORD = re.compile(r"^[A-Z0-9_-]{1,8}$")
MISSING = "none"


def check_filename_pattern(pattern: str, key: str = "filename_pattern") -> None:
    """Raise ConfigError if ``pattern`` is not an absolute VFS path with valid placeholders."""
    if not pattern.startswith("/") or pattern.endswith("/"):
        raise ConfigError(
            f"must be an absolute VFS file path like /cache/{{DATE-OBS}}.fits, got {pattern!r}", key=key
        )
    try:
        fields = [field for _, field, _, _ in string.Formatter().parse(pattern) if field is not None]
    except ValueError as exc:
        raise ConfigError(f"invalid pattern {pattern!r}: {exc}", key=key) from exc
    for field in fields:
        if not _KEYWORD.match(field):
            raise ConfigError(
                f"placeholder {{{field}}} in {pattern!r} is not a FITS keyword (upper case, at most 8 chars)",
                key=key,
            )


def sanitise_component(text: str) -> str:
    """``text`` as one harmless path component."""
    cleaned = _UNSAFE.sub("-", text).strip("-.")  # no hidden files, no ".."
    if cleaned in ("", ".", ".."):
        return "_"
    return cleaned


def format_filename(pattern: str, header: Mapping[str, FitsValue]) -> str:
    """The file name for an image with ``header`` (keyword → value)."""
    parts: list[str] = []
    for literal, field, spec, conversion in string.Formatter().parse(pattern):
        parts.append(literal)
        if field is None:
            continue
        value = header.get(field)
        if value is None:
            parts.append(MISSING)
            continue
        try:
            text = format(str(value) if conversion else value, spec or "")
        except ValueError as exc:
            raise InvalidArgumentError(f"cannot format {field}={value!r} with '{spec}': {exc}") from exc
        parts.append(sanitise_component(text))
    return "".join(parts)
