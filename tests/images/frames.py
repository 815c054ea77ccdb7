"""Simulated frames with known truth for the image tests: stars placed in pixel coordinates."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nightcrew.images import Image
from nightcrew.sim.catalog import STAR_DTYPE
from nightcrew.sim.projection import Pointing, pixel_to_sky, wcs_header
from nightcrew.sim.render import (
    CameraModel,
    Conditions,
    Exposure,
    Optics,
    RenderedFrame,
    frame_geometry,
    render_frame,
)

POINTING = Pointing(150.0, 20.0, 25.0)
OPTICS = Optics(focal_length_mm=1600.0, optics_fwhm_arcsec=0.0)  # 1.16"/px
CONDITIONS = Conditions(seeing_arcsec=4.0)  # FWHM about 3.4 px


@dataclass(frozen=True)
class Field:
    """Stars in pixel coordinates of the frame (may extend beyond it) and their magnitudes."""

    x: npt.NDArray[np.float64]
    y: npt.NDArray[np.float64]
    mag: npt.NDArray[np.float64]


def random_field(
    size: int, count: int, *, seed: int, margin: float = 40.0, mags: tuple[float, float] = (11.0, 17.5)
) -> Field:
    """``count`` stars uniform over the frame plus ``margin``, magnitudes growing in number fainter."""
    rng = np.random.default_rng(seed)
    x = rng.uniform(-margin, size - 1 + margin, count)
    y = rng.uniform(-margin, size - 1 + margin, count)
    # Number counts grow by 10**0.3 per magnitude, like the real sky.
    u = rng.uniform(0.0, 1.0, count)
    lo, hi = 10 ** (0.3 * mags[0]), 10 ** (0.3 * mags[1])
    mag = np.log10(lo + u * (hi - lo)) / 0.3
    return Field(x, y, mag)


def camera(size: int) -> CameraModel:
    return CameraModel(chip_width=size, chip_height=size)


def render(
    field: Field,
    size: int,
    *,
    seed: int,
    shift: tuple[float, float] = (0.0, 0.0),
    exposure_time: float = 10.0,
    conditions: Conditions = CONDITIONS,
    cam: CameraModel | None = None,
) -> RenderedFrame:
    """The field rendered with every star moved by ``shift`` (dx, dy) pixels; noise from ``seed``."""
    cam = cam or camera(size)
    exposure = Exposure(exposure_time)
    geometry = frame_geometry(cam, OPTICS, exposure)
    ra, dec = pixel_to_sky(field.x + shift[0], field.y + shift[1], POINTING, geometry)
    stars = np.zeros(len(field.x), STAR_DTYPE)
    stars["ra"], stars["dec"], stars["mag"] = ra, dec, field.mag
    return render_frame(
        stars,
        pointing=POINTING,
        focus=0.0,
        camera=cam,
        optics=OPTICS,
        conditions=conditions,
        exposure=exposure,
        rng=np.random.default_rng(seed),
    )


def as_image(frame: RenderedFrame, exposure_time: float = 10.0) -> Image:
    """The frame as an Image with its exact WCS and the camera's usual keywords."""
    header = wcs_header(POINTING, frame.geometry)
    header["EXPTIME"] = exposure_time
    header["SATURATE"] = 65535
    header["GAIN"] = 1.5
    header["OBJECT"] = "field"
    return Image(frame.data, header=header)
