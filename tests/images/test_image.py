"""Image: FITS round trip of every extension, VFS, WCS helpers, copies and bad input."""

from __future__ import annotations

import io

import numpy as np
import pytest
from astropy.io import fits  # type: ignore[import-untyped]
from astropy.table import Table  # type: ignore[import-untyped]

from nightcrew.images import Image, ImageDataError, ImageFormatError, MissingWcsError
from nightcrew.sim.projection import FrameGeometry, Pointing, pixel_to_sky, wcs_header
from nightcrew.vfs import MemoryFile, VirtualFileSystem

POINTING = Pointing(150.0, 20.0, 25.0)
GEOMETRY = FrameGeometry(120, 100, 0.75)


def full_image() -> Image:
    rng = np.random.default_rng(3)
    data = rng.integers(900, 1200, size=(100, 120), dtype=np.uint16)
    mask = np.zeros(data.shape, bool)
    mask[5, 7] = mask[50, 60] = True
    header = wcs_header(POINTING, GEOMETRY)
    header["EXPTIME"] = (12.5, "Exposure time [s]")
    header["IMAGETYP"] = "object"
    catalog = Table({"x": [10.25, 20.5], "y": [30.0, 40.75], "flux": [1e4, 2e3], "flags": [0, 1]})
    return Image(data, header=header, mask=mask, uncertainty=rng.uniform(1, 2, data.shape), catalog=catalog)


def assert_same(a: Image, b: Image) -> None:
    assert a.data.dtype == b.data.dtype
    np.testing.assert_array_equal(a.data, b.data)
    assert a.mask is not None and b.mask is not None
    np.testing.assert_array_equal(a.mask, b.mask)
    assert a.uncertainty is not None and b.uncertainty is not None
    np.testing.assert_array_equal(a.uncertainty, b.uncertainty)
    assert a.catalog is not None and b.catalog is not None
    assert a.catalog.colnames == b.catalog.colnames
    for name in a.catalog.colnames:
        np.testing.assert_array_equal(a.catalog[name], b.catalog[name])
    assert a.header["IMAGETYP"] == b.header["IMAGETYP"]
    for keyword in ("EXPTIME", "CRVAL1", "CD1_2"):  # FITS prints floats with 16-17 digits
        assert a.header[keyword] == pytest.approx(b.header[keyword], rel=1e-14)


def test_fits_round_trip_keeps_every_extension() -> None:
    image = full_image()
    content = image.to_bytes()
    with fits.open(io.BytesIO(content)) as hdul:
        assert [hdu.name for hdu in hdul] == ["PRIMARY", "MASK", "UNCERT", "CAT"]
    back = Image.from_bytes(content)
    assert_same(image, back)
    assert back.data.dtype.isnative  # FITS is big-endian; readers get native arrays
    assert "BZERO" not in back.header  # uint16 scaling keywords do not leak into the header


def test_image_without_extensions_and_with_empty_primary() -> None:
    data = np.arange(12, dtype=np.float32).reshape(3, 4)
    back = Image.from_bytes(Image(data).to_bytes())
    assert back.mask is None and back.uncertainty is None and back.catalog is None
    np.testing.assert_array_equal(back.data, data)
    hdul = fits.HDUList([fits.PrimaryHDU(), fits.ImageHDU(data, name="SCI")])
    buffer = io.BytesIO()
    hdul.writeto(buffer)
    np.testing.assert_array_equal(Image.from_bytes(buffer.getvalue()).data, data)


async def test_vfs_round_trip() -> None:
    vfs = VirtualFileSystem({"cache": MemoryFile()})
    image = full_image()
    await image.to_vfs(vfs, "/cache/a.fits")
    assert_same(image, await Image.from_vfs(vfs, "/cache/a.fits"))
    await vfs.write_bytes("/cache/b.fits", b"SIMPLE  = nonsense")
    with pytest.raises(ImageFormatError, match=r"^/cache/b.fits: not a valid FITS image"):
        await Image.from_vfs(vfs, "/cache/b.fits")


def test_wcs_and_pixel_scale_match_the_projection() -> None:
    image = full_image()
    assert image.wcs is not None
    assert image.pixel_scale == pytest.approx(0.75, rel=1e-9)
    x, y = np.array([0.0, 60.3, 119.0]), np.array([0.0, 44.1, 99.0])
    ra, dec = image.pixel_to_sky(x, y)
    ra_true, dec_true = pixel_to_sky(x, y, POINTING, GEOMETRY)
    np.testing.assert_allclose(ra, ra_true, atol=1e-9)
    np.testing.assert_allclose(dec, dec_true, atol=1e-9)
    back_x, back_y = image.sky_to_pixel(ra, dec)
    np.testing.assert_allclose(back_x, x, atol=1e-6)
    np.testing.assert_allclose(back_y, y, atol=1e-6)


def test_pixel_scale_from_header_keywords_without_wcs() -> None:
    data = np.zeros((4, 4))
    assert Image(data).pixel_scale is None
    assert Image(data, header={"PIXSCALE": 0.5}).pixel_scale == 0.5
    scale = Image(data, header={"XPIXSZ": 9.0, "FOCALLEN": 1600.0}).pixel_scale
    assert scale == pytest.approx(1.1602, abs=1e-4)
    assert Image(data).wcs is None
    with pytest.raises(MissingWcsError, match="no celestial WCS"):
        Image(data).pixel_to_sky(1.0, 1.0)


def test_copies_share_read_only_pixels_but_not_header_or_metadata() -> None:
    image = full_image()
    image.metadata["seeing"] = 1.2
    copy = image.copy()
    assert np.shares_memory(copy.data, image.data)
    with pytest.raises(ValueError, match="read-only"):
        copy.data[0, 0] = 1
    copy.header["EXPTIME"] = 1.0
    copy.metadata["seeing"] = 9.0
    assert copy.catalog is not None
    copy.catalog["x"][0] = -1.0
    assert image.header["EXPTIME"] == 12.5
    assert image.metadata["seeing"] == 1.2
    assert image.catalog is not None and image.catalog["x"][0] == 10.25
    caller = np.zeros((2, 2))
    Image(caller)
    caller[0, 0] = 1.0  # the caller's own array stays writable


def test_replace_checks_shapes() -> None:
    image = full_image()
    with pytest.raises(ImageDataError, match=r"mask has shape \(100, 120\), but the data has \(50, 60\)"):
        image.replace(data=np.zeros((50, 60)))
    smaller = image.replace(data=np.zeros((50, 60)), mask=None, uncertainty=None)
    assert smaller.shape == (50, 60)


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (np.zeros((2, 2), bool), "integer or floating point, got dtype bool"),
        (np.zeros((2, 2), complex), "integer or floating point, got dtype complex128"),
        (np.zeros(5), r"must be 2-D, got shape \(5,\)"),
        (np.zeros((0, 3)), r"empty \(shape \(0, 3\)\)"),
    ],
)
def test_bad_data_raises_one_clear_error(data: np.ndarray, message: str) -> None:
    with pytest.raises(ImageDataError, match=message):
        Image(data)


def test_mask_must_be_boolean() -> None:
    with pytest.raises(ImageDataError, match="mask must be boolean"):
        Image(np.zeros((2, 2)), mask=np.zeros((2, 2), np.uint8))


def test_not_fits() -> None:
    with pytest.raises(ImageFormatError, match="not a valid FITS image"):
        Image.from_bytes(b"hello")
    only_table = fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU(Table({"a": [1]}))])
    buffer = io.BytesIO()
    only_table.writeto(buffer)
    with pytest.raises(ImageFormatError, match="holds no image data"):
        Image.from_bytes(buffer.getvalue())
