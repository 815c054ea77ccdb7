"""The :class:`Image`: pixels with their FITS header, bad-pixel mask, uncertainty, sources and metadata.

Conventions:

- Pixel coordinates are 0-based with integer values at pixel centres, ``x`` along columns (the
  last numpy axis) and ``y`` along rows — the numpy and :mod:`nightcrew.sim` convention. FITS
  (1-based) only appears inside the header's WCS keywords.
- ``mask`` is True where a pixel is *bad* (to be ignored), like ``numpy.ma``, SEP and photutils.
- Arrays held by an image are read-only views. An image never changes its pixels in place: a
  processor returns a new image (:meth:`Image.replace`), which shares the arrays it does not
  replace. That makes :meth:`Image.copy` cheap (no pixel copy) and safe. Take
  ``image.data.astype(...)`` or ``np.array(image.data)`` for a writable copy.
- ``metadata`` holds results of processors as typed values (e.g. offsets, a measured FWHM). It
  lives in memory only: FITS files carry the header, pixels, mask, uncertainty and catalog.

FITS layout written by :meth:`Image.to_bytes` and read by :meth:`Image.from_bytes`: the primary HDU
holds data and header, then optional extensions ``MASK`` (uint8, 1 = bad), ``UNCERT`` (1-sigma, same
unit as the data) and ``CAT`` (the source catalog as a binary table). When reading, the data come
from the first HDU that has image data, so files with an empty primary HDU work too.
"""

from __future__ import annotations

import asyncio
import io
import math
import warnings
from collections.abc import Mapping
from typing import Any, Self

import numpy as np
import numpy.typing as npt
from astropy.io import fits  # type: ignore[import-untyped]
from astropy.table import Table  # type: ignore[import-untyped]
from astropy.utils.exceptions import AstropyUserWarning  # type: ignore[import-untyped]
from astropy.wcs import WCS, FITSFixedWarning  # type: ignore[import-untyped]

from nightcrew.images.errors import ImageDataError, ImageFormatError, MissingWcsError
from nightcrew.vfs import VirtualFileSystem

__all__ = ["Image"]

FloatArray = npt.NDArray[np.float64]

MASK_EXTENSION = "MASK"
UNCERTAINTY_EXTENSION = "UNCERT"
CATALOG_EXTENSION = "CAT"
_ARCSEC_PER_RAD = 206264.806
#: Keywords astropy writes from the array itself; stale copies from a file must not travel along.
_STRUCTURAL = ("SIMPLE", "BITPIX", "EXTEND", "BZERO", "BSCALE", "XTENSION", "PCOUNT", "GCOUNT", "EXTNAME")

_UNSET: Any = object()


class Image:
    """A 2-D frame with everything known about it.

    Parameters
    ----------
    data
        Pixel values, 2-D, integer or floating point (ADU or electrons). Not copied: the image
        keeps a read-only view.
    header
        FITS header (astropy ``Header``, or a mapping of keyword to value). Copied.
    mask
        True where a pixel is bad; same shape as ``data``.
    uncertainty
        1-sigma uncertainty of each pixel, same unit and shape as ``data``.
    catalog
        Sources found on the image (astropy ``Table``; columns ``x``, ``y`` in 0-based pixels).
    metadata
        Results of processors (name → typed value); in memory only.

    Raises
    ------
    ImageDataError
        ``data`` is not a non-empty 2-D numeric array, or ``mask``/``uncertainty`` have another shape.
    """

    __slots__ = ("_data", "_mask", "_uncertainty", "catalog", "header", "metadata")

    def __init__(
        self,
        data: npt.ArrayLike,
        *,
        header: fits.Header | Mapping[str, Any] | None = None,
        mask: npt.ArrayLike | None = None,
        uncertainty: npt.ArrayLike | None = None,
        catalog: Table | None = None,
        metadata: Mapping[str, Any] | None = None,
    ) -> None:
        self._data = _read_only(_checked_data(data))
        shape = self._data.shape
        self._mask = None if mask is None else _read_only(_checked_layer(mask, shape, "mask", np.bool_))
        self._uncertainty = (
            None
            if uncertainty is None
            else _read_only(_checked_layer(uncertainty, shape, "uncertainty", np.float64))
        )
        self.header: fits.Header = _header_copy(header)
        self.catalog: Table | None = catalog
        self.metadata: dict[str, Any] = dict(metadata or {})

    # --- arrays -------------------------------------------------------------------------------

    @property
    def data(self) -> npt.NDArray[Any]:
        """Pixel values (read-only view), rows by columns."""
        return self._data

    @property
    def mask(self) -> npt.NDArray[np.bool_] | None:
        """True where a pixel is bad (read-only view), or None if all pixels are good."""
        return self._mask

    @property
    def uncertainty(self) -> npt.NDArray[np.floating[Any]] | None:
        """1-sigma uncertainty per pixel (read-only view), or None if unknown."""
        return self._uncertainty

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, columns)."""
        rows, cols = self._data.shape
        return int(rows), int(cols)

    def __repr__(self) -> str:
        rows, cols = self.shape
        layers = [name for name in ("mask", "uncertainty", "catalog") if getattr(self, name) is not None]
        extra = f" with {', '.join(layers)}" if layers else ""
        return f"<Image {cols}x{rows} {self._data.dtype}{extra}>"

    # --- copies -------------------------------------------------------------------------------

    def replace(
        self,
        *,
        data: npt.ArrayLike = _UNSET,
        header: fits.Header | Mapping[str, Any] = _UNSET,
        mask: npt.ArrayLike | None = _UNSET,
        uncertainty: npt.ArrayLike | None = _UNSET,
        catalog: Table | None = _UNSET,
        metadata: Mapping[str, Any] = _UNSET,
    ) -> Image:
        """A new image with the given parts replaced.

        Arrays not replaced are shared (they are read-only); the header, catalog and metadata
        dict are copied, so changing them on the new image leaves this one alone. Replacing
        ``data`` with another shape needs ``mask``/``uncertainty`` replaced (or set to None) too.
        """
        return Image(
            self._data if data is _UNSET else data,
            header=self.header if header is _UNSET else header,
            mask=self._mask if mask is _UNSET else mask,
            uncertainty=self._uncertainty if uncertainty is _UNSET else uncertainty,
            catalog=(self.catalog.copy() if self.catalog is not None else None)
            if catalog is _UNSET
            else catalog,
            metadata=self.metadata if metadata is _UNSET else metadata,
        )

    def copy(self) -> Image:
        """A copy sharing the read-only pixel arrays, with its own header, catalog and metadata."""
        return self.replace()

    # --- world coordinates ----------------------------------------------------------------------

    @property
    def wcs(self) -> WCS | None:
        """The celestial WCS of the header, or None if the header has none.

        Built from the header on each access (about 2 ms): keep the result when using it often.
        """
        if "CTYPE1" not in self.header or "CTYPE2" not in self.header:
            return None
        with warnings.catch_warnings():
            # astropy reports header repairs (e.g. MJD-OBS derived from DATE-OBS); they are harmless.
            warnings.simplefilter("ignore", FITSFixedWarning)
            try:
                wcs = WCS(self.header, naxis=2)
            except (ValueError, KeyError, MemoryError) as exc:
                raise ImageFormatError(f"invalid WCS in header: {exc}") from exc
        return wcs if wcs.has_celestial else None

    @property
    def pixel_scale(self) -> float | None:
        """Pixel scale in arcsec/px, or None if unknown.

        From the WCS (square root of the pixel area) if present, else the header's ``PIXSCALE`` or
        ``SECPIX``, else ``XPIXSZ`` (µm, including binning) and ``FOCALLEN`` (mm).
        """
        wcs = self.wcs
        if wcs is not None:
            from astropy.wcs.utils import proj_plane_pixel_area  # type: ignore[import-untyped]

            return math.sqrt(float(proj_plane_pixel_area(wcs))) * 3600.0
        for keyword in ("PIXSCALE", "SECPIX"):
            value = _positive(self.header.get(keyword))
            if value is not None:
                return value
        size_um, focal_mm = _positive(self.header.get("XPIXSZ")), _positive(self.header.get("FOCALLEN"))
        if size_um is not None and focal_mm is not None:
            return _ARCSEC_PER_RAD * size_um * 1e-3 / focal_mm
        return None

    def pixel_to_sky(self, x: npt.ArrayLike, y: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Sky positions (RA, Dec in degrees, frame of the WCS) of 0-based pixel positions.

        Raises
        ------
        MissingWcsError
            The header has no celestial WCS.
        """
        wcs = self._required_wcs()
        ra, dec = wcs.all_pix2world(np.asarray(x, np.float64), np.asarray(y, np.float64), 0)
        return np.asarray(ra, np.float64), np.asarray(dec, np.float64)

    def sky_to_pixel(self, ra_deg: npt.ArrayLike, dec_deg: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
        """0-based pixel positions of sky positions (RA, Dec in degrees).

        Raises
        ------
        MissingWcsError
            The header has no celestial WCS.
        """
        wcs = self._required_wcs()
        x, y = wcs.all_world2pix(np.asarray(ra_deg, np.float64), np.asarray(dec_deg, np.float64), 0)
        return np.asarray(x, np.float64), np.asarray(y, np.float64)

    def _required_wcs(self) -> WCS:
        wcs = self.wcs
        if wcs is None:
            raise MissingWcsError("the image header has no celestial WCS")
        return wcs

    # --- FITS ---------------------------------------------------------------------------------

    def to_hdul(self) -> fits.HDUList:
        """The image as an astropy ``HDUList`` (primary, then MASK, UNCERT, CAT if present)."""
        hdus = [fits.PrimaryHDU(np.asarray(self._data), header=_without_structural(self.header))]
        if self._mask is not None:
            hdus.append(fits.ImageHDU(self._mask.astype(np.uint8), name=MASK_EXTENSION))
        if self._uncertainty is not None:
            hdus.append(fits.ImageHDU(np.asarray(self._uncertainty), name=UNCERTAINTY_EXTENSION))
        if self.catalog is not None:
            table = fits.table_to_hdu(self.catalog)
            table.name = CATALOG_EXTENSION
            hdus.append(table)
        return fits.HDUList(hdus)

    @classmethod
    def from_hdul(cls, hdul: fits.HDUList) -> Self:
        """The image in an astropy ``HDUList`` laid out as :meth:`to_hdul` writes it.

        Raises
        ------
        ImageFormatError
            No HDU holds 2-D image data.
        """
        names = {hdu.name.upper(): hdu for hdu in hdul}
        science = next(
            (
                hdu
                for hdu in hdul
                if hdu.is_image
                and hdu.data is not None
                and hdu.name.upper() not in (MASK_EXTENSION, UNCERTAINTY_EXTENSION)
            ),
            None,
        )
        if science is None:
            raise ImageFormatError("the FITS file holds no image data")
        mask = names.get(MASK_EXTENSION)
        uncertainty = names.get(UNCERTAINTY_EXTENSION)
        catalog = names.get(CATALOG_EXTENSION)
        try:
            return cls(
                _native(science.data),
                header=_without_structural(science.header),
                mask=None if mask is None else np.asarray(mask.data) != 0,
                uncertainty=None if uncertainty is None else _native(uncertainty.data),
                catalog=None if catalog is None else Table.read(catalog, format="fits"),
            )
        except ImageDataError as exc:
            raise ImageFormatError(f"unusable FITS image: {exc}") from exc

    def to_bytes(self) -> bytes:
        """The image as FITS file content.

        Raises
        ------
        ImageFormatError
            A header card or catalog column cannot be written to FITS.
        """
        buffer = io.BytesIO()
        try:
            self.to_hdul().writeto(buffer, output_verify="exception")
        except (OSError, ValueError, TypeError, fits.VerifyError) as exc:
            raise ImageFormatError(f"cannot write FITS: {exc}") from exc
        return buffer.getvalue()

    @classmethod
    def from_bytes(cls, content: bytes) -> Self:
        """The image in FITS file content (see the module docstring for the layout).

        Raises
        ------
        ImageFormatError
            ``content`` is not a readable FITS file with image data (astropy's warnings about a
            damaged or truncated file count as errors).
        """
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error", AstropyUserWarning)
                with fits.open(io.BytesIO(content), memmap=False, lazy_load_hdus=False) as hdul:
                    return cls.from_hdul(hdul)
        except (OSError, ValueError, TypeError, AstropyUserWarning, fits.VerifyError) as exc:
            raise ImageFormatError(f"not a valid FITS image: {exc}") from exc

    @classmethod
    async def from_vfs(cls, vfs: VirtualFileSystem, path: str) -> Self:
        """Read the image at ``path``; decoding runs in a worker thread.

        Raises
        ------
        ImageFormatError
            The file is not a FITS image (the message names ``path``).
        VfsError
            The file cannot be read.
        """
        content = await vfs.read_bytes(path)
        try:
            return await asyncio.to_thread(cls.from_bytes, content)
        except ImageFormatError as exc:
            raise ImageFormatError(f"{path}: {exc.message}") from exc

    async def to_vfs(self, vfs: VirtualFileSystem, path: str) -> None:
        """Write the image to ``path`` as FITS; encoding runs in a worker thread."""
        content = await asyncio.to_thread(self.to_bytes)
        await vfs.write_bytes(path, content)


def _checked_data(data: npt.ArrayLike) -> npt.NDArray[Any]:
    array = np.asarray(data)
    if array.dtype.kind not in "iuf":
        raise ImageDataError(f"image data must be integer or floating point, got dtype {array.dtype}")
    if array.ndim != 2:
        raise ImageDataError(f"image data must be 2-D, got shape {array.shape}")
    if array.size == 0:
        raise ImageDataError(f"image data is empty (shape {array.shape})")
    return array


def _checked_layer(
    values: npt.ArrayLike, shape: tuple[int, ...], name: str, kind: type[np.generic]
) -> npt.NDArray[Any]:
    array = np.asarray(values)
    if array.shape != shape:
        raise ImageDataError(f"{name} has shape {array.shape}, but the data has {shape}")
    if kind is np.bool_ and array.dtype != np.bool_:
        raise ImageDataError(f"mask must be boolean (True = bad pixel), got dtype {array.dtype}")
    if kind is np.float64 and array.dtype.kind != "f":
        array = array.astype(np.float64)
    return array


def _native(array: npt.NDArray[Any]) -> npt.NDArray[Any]:
    """``array`` in native byte order (FITS stores big-endian; SEP and friends want native)."""
    if array.dtype.isnative:
        return array
    return array.astype(array.dtype.newbyteorder("="))


def _read_only(array: npt.NDArray[Any]) -> npt.NDArray[Any]:
    """A read-only view: the caller's array keeps its own flags."""
    view = array.view()
    view.flags.writeable = False
    return view


def _header_copy(header: fits.Header | Mapping[str, Any] | None) -> fits.Header:
    if header is None:
        return fits.Header()
    if isinstance(header, fits.Header):
        return header.copy()
    copied = fits.Header()
    for keyword, value in header.items():
        copied[keyword] = value
    return copied


def _without_structural(header: fits.Header) -> fits.Header:
    cleaned = header.copy(strip=False)
    for keyword in _STRUCTURAL:
        cleaned.remove(keyword, ignore_missing=True, remove_all=True)
    for keyword in [k for k in cleaned if k.startswith("NAXIS")]:
        cleaned.remove(keyword, ignore_missing=True, remove_all=True)
    return cleaned


def _positive(value: Any) -> float | None:
    """``value`` as a positive finite float, or None."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    number = float(value)
    return number if math.isfinite(number) and number > 0 else None
