"""Encoding and decoding of FITS, YAML and CSV content, as pure functions of bytes.

The VFS helpers serialise completely before writing, so a value that fails to serialise never
touches the stored file. astropy is imported inside the FITS functions: a module that never
touches FITS does not pay for importing it.
"""

from __future__ import annotations

import csv
import io
import warnings
from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import yaml

from nightcrew.config import parse_yaml
from nightcrew.errors import ConfigError
from nightcrew.vfs._errors import VfsFormatError

if TYPE_CHECKING:
    from astropy.io.fits import HDUList  # type: ignore[import-untyped]

__all__ = ["decode_csv", "decode_fits", "decode_yaml", "encode_csv", "encode_fits", "encode_yaml"]


def _astropy_fits() -> Any:
    """Import astropy.io.fits on first use (astropy is untyped: values are ``Any``)."""
    from astropy.io import fits  # type: ignore[import-untyped]

    return fits


def decode_fits(data: bytes) -> HDUList:
    """Return the HDUs in ``data`` with their data loaded into writable arrays.

    A file astropy complains about while reading (truncated, e.g. still being copied; a damaged
    header) raises VfsFormatError instead of giving partial data with a warning.
    """
    fits = _astropy_fits()
    from astropy.utils.exceptions import AstropyUserWarning  # type: ignore[import-untyped]

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", AstropyUserWarning)
            hdul = fits.open(io.BytesIO(data), lazy_load_hdus=False, memmap=False)
            for hdu in hdul:
                _ = hdu.data  # load now: the buffer is closed below
            hdul.close()
    except (OSError, ValueError, TypeError, AstropyUserWarning, fits.VerifyError) as exc:
        raise VfsFormatError(f"not a valid FITS file: {exc}") from exc
    return hdul


def encode_fits(hdul: HDUList) -> bytes:
    """Return ``hdul`` serialised as a FITS file; invalid headers raise VfsFormatError."""
    fits = _astropy_fits()
    buffer = io.BytesIO()
    try:
        hdul.writeto(buffer, output_verify="exception")
    except (OSError, ValueError, TypeError, fits.VerifyError) as exc:
        raise VfsFormatError(f"cannot write FITS: {exc}") from exc
    return buffer.getvalue()


def decode_yaml(data: bytes) -> Any:
    """Return the value of a UTF-8 YAML document (plain types only: safe loader)."""
    try:
        return parse_yaml(data.decode("utf-8"), "YAML document")
    except UnicodeDecodeError as exc:
        raise VfsFormatError(f"not valid YAML: {exc}") from exc
    except ConfigError as exc:
        raise VfsFormatError(f"not valid YAML: {exc}") from None


def encode_yaml(value: Any) -> bytes:
    """Return ``value`` as UTF-8 YAML, keys in their given order (plain types only)."""
    try:
        text = yaml.safe_dump(value, sort_keys=False, allow_unicode=True)
    except yaml.YAMLError as exc:
        raise VfsFormatError(f"cannot write YAML: {exc}") from exc
    return text.encode("utf-8")


def decode_csv(data: bytes) -> list[dict[str, str]]:
    """Return the rows of a UTF-8 CSV file with a header line, as dicts of strings."""
    try:
        text = data.decode("utf-8-sig")  # tolerate the byte order mark spreadsheets write
        return list(csv.DictReader(io.StringIO(text, newline=""), strict=True))
    except (UnicodeDecodeError, csv.Error) as exc:
        raise VfsFormatError(f"not valid CSV: {exc}") from exc


def _field_names(rows: Iterable[Mapping[str, object]]) -> list[str]:
    """Return the keys of all rows, in order of first appearance."""
    return list(dict.fromkeys(key for row in rows for key in row))


def encode_csv(rows: Sequence[Mapping[str, object]], fieldnames: Sequence[str] | None = None) -> bytes:
    """Return ``rows`` as UTF-8 CSV with a header line and ``\\n`` line ends.

    Columns are ``fieldnames``, or all keys of the rows in order of first appearance. A key
    missing in a row is written empty; a key not among ``fieldnames`` raises VfsFormatError.
    Values are written with ``str()`` (``None`` as empty), so they read back as strings.
    """
    columns = list(fieldnames) if fieldnames is not None else _field_names(rows)
    buffer = io.StringIO(newline="")
    writer = csv.DictWriter(buffer, fieldnames=columns, lineterminator="\n", extrasaction="raise")
    try:
        writer.writeheader()
        writer.writerows(rows)
    except (ValueError, csv.Error) as exc:
        raise VfsFormatError(f"cannot write CSV: {exc}") from exc
    return buffer.getvalue().encode("utf-8")
