"""Processors one by one and a pipeline built from YAML: behaviour, geometry, bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from nightcrew.config import build_object, load_config
from nightcrew.errors import ConfigError
from nightcrew.images import Image, ImageDataError, ImageError, MissingWcsError, Pipeline
from nightcrew.images.processors.detection._sep import detect_sources_sep
from nightcrew.images.processors.misc import CreateFilename, Flip, Mask, Normalise, SoftBin
from nightcrew.images.processors.offsets import AstrometryOffsets, FitsHeaderOffsets
from nightcrew.images.processors.photometry import PhotutilsPhotometry, SepPhotometry
from tests.images.frames import as_image, random_field, render

FIELD = random_field(256, 60, seed=7)
YAML = """\
class: nightcrew.images.Pipeline
steps:
  - class: nightcrew.images.processors.misc.RemoveBackground
    box_size: 32
  - class: nightcrew.images.processors.detection.SepSourceDetection
    threshold: 5.0
  - class: nightcrew.images.processors.photometry.SepPhotometry
    radii: [2.0, 4.0]
    unit: arcsec
  - class: nightcrew.images.processors.misc.MeasureFwhm
  - class: nightcrew.images.processors.offsets.NStarOffsets
    stars: 5
    max_shift: 10
"""


async def test_pipeline_from_yaml(tmp_path: Path) -> None:
    path = tmp_path / "guiding.yaml"
    path.write_text(YAML)
    pipeline = build_object(load_config(path))
    assert isinstance(pipeline, Pipeline)
    assert [type(step).__name__ for step in pipeline.steps] == [
        "RemoveBackground",
        "SepSourceDetection",
        "SepPhotometry",
        "MeasureFwhm",
        "NStarOffsets",
    ]
    image = as_image(render(FIELD, 256, seed=1))
    first = await pipeline(image)
    assert first.catalog is not None and "aperflux2" in first.catalog.colnames
    assert first.data.dtype == np.float32 and image.data.dtype == np.uint16  # input untouched
    assert first.metadata["offsets"].is_reference
    second = await pipeline(as_image(render(FIELD, 256, seed=2, shift=(3.0, -2.0))))
    assert (second.metadata["offsets"].dx, second.metadata["offsets"].dy) == pytest.approx(
        (3.0, -2.0), abs=0.1
    )
    assert Image.from_bytes(second.to_bytes()).catalog is not None


def test_bad_configuration_names_the_key() -> None:
    with pytest.raises(ConfigError, match="threshold"):
        build_object({"class": "nightcrew.images.processors.detection.SepSourceDetection", "threshold": -1})
    with pytest.raises(ConfigError, match="steps"):
        Pipeline([42])  # type: ignore[list-item]


async def test_sep_and_photutils_photometry_agree() -> None:
    image = await Pipeline(
        [{"class": "nightcrew.images.processors.detection.SepSourceDetection", "threshold": 10.0}]
    )(as_image(render(FIELD, 256, seed=1)))
    sep_flux = (await SepPhotometry(radii=[5.0])(image)).catalog["aperflux1"]  # type: ignore[index]
    photutils_flux = (await PhotutilsPhotometry(radii=[5.0])(image)).catalog["aperflux1"]  # type: ignore[index]
    np.testing.assert_allclose(sep_flux, photutils_flux, rtol=1e-3, atol=1.0)
    with pytest.raises(ImageError, match="needs a catalog"):
        await SepPhotometry()(Image(np.zeros((8, 8))))
    with pytest.raises(MissingWcsError, match="pixel scale"):
        await SepPhotometry(unit="arcsec")(Image(np.zeros((8, 8))).replace(catalog=image.catalog))


async def test_soft_bin_and_flip_keep_the_sky_where_it_was() -> None:
    image = as_image(render(FIELD, 256, seed=1))
    ra, dec = image.pixel_to_sky(100.0, 50.0)
    binned = await SoftBin(factor=2)(image)
    assert binned.shape == (128, 128)
    assert float(binned.data.sum()) == pytest.approx(float(image.data.astype(float).sum()))
    bx, by = binned.sky_to_pixel(ra, dec)
    assert (float(bx), float(by)) == pytest.approx((49.75, 24.75), abs=1e-6)
    flipped = await Flip(flip_x=True, flip_y=True)(image)
    assert flipped.data[0, 0] == image.data[-1, -1]
    fx, fy = flipped.sky_to_pixel(ra, dec)
    assert (float(fx), float(fy)) == pytest.approx((155.0, 205.0), abs=1e-6)


async def test_normalise_mask_and_filename() -> None:
    image = Image(np.full((4, 6), 200.0), header={"DATE-OBS": "2024-01-01T00:00:00", "IMAGETYP": "flat"})
    assert np.all((await Normalise()(image)).data == 1.0)
    bad = np.zeros((4, 6), bool)
    bad[1, 2] = True
    masked = await Mask(mask=bad)(image)
    assert masked.mask is not None and masked.mask.sum() == 1
    with pytest.raises(ImageDataError, match=r"mask has shape \(4, 6\), but the image has \(3, 3\)"):
        await Mask(mask=bad)(Image(np.zeros((3, 3))))
    named = await CreateFilename(pattern="/archive/{DATE-OBS}-{IMAGETYP}.fits")(image)
    assert named.metadata["filename"] == "/archive/2024-01-01T00-00-00-flat.fits"
    assert named.header["FNAME"] == "2024-01-01T00-00-00-flat.fits"
    with pytest.raises(ConfigError, match="absolute VFS file path"):
        CreateFilename(pattern="relative/{OBJECT}.fits")


async def test_header_and_astrometry_offsets() -> None:
    image = as_image(render(FIELD, 256, seed=1))
    image.header["TARGETX"], image.header["TARGETY"] = 130.5, 120.0
    offsets = (await FitsHeaderOffsets()(image)).metadata["offsets"]
    assert (offsets.dx, offsets.dy) == pytest.approx((130.5 - 128.5, 120.0 - 128.5))
    ra, dec = image.pixel_to_sky(140.0, 120.0)
    image.header["RA"], image.header["DEC"] = float(ra), float(dec)
    offsets = (await AstrometryOffsets()(image)).metadata["offsets"]
    assert (offsets.dx, offsets.dy) == pytest.approx((140.0 - 127.5, 120.0 - 127.5), abs=1e-6)
    with pytest.raises(MissingWcsError, match="needs a WCS"):
        await AstrometryOffsets()(Image(np.zeros((8, 8))))


def test_sep_detection_grows_its_pixel_stack_for_a_source_larger_than_it() -> None:
    # SEP's object-pixel stack starts small (it costs its size on every call) and grows on demand.
    rng = np.random.default_rng(5)
    data = rng.normal(1000.0, 10.0, (1000, 1000))
    data[200:800, 200:800] += 500.0  # 360 000 connected pixels above the threshold, in one source
    catalog = detect_sources_sep(data, threshold=5.0, box_size=1000)
    assert int(np.max(catalog["npix"])) > 300_000
