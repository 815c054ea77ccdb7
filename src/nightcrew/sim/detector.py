"""Camera physics: flat/vignetting, dark current and hot pixels, cosmic rays, binning, noise, ADC.

All images here are expected or sampled electrons (float32) until :func:`digitize` turns them
into 16-bit ADU.

Noise model (:func:`sample_noise`): photon (Poisson) noise plus Gaussian read noise. Pixels
expecting at least ``exact_poisson_below`` electrons use the normal approximation
``lam + sqrt(lam + rn^2) * z`` (one Gaussian draw covers both noises; the Poisson skewness,
1/sqrt(lam), is < 0.25 there); pixels expecting fewer draw an exact Poisson count plus read noise.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from nightcrew.sim.projection import Window

__all__ = [
    "add_cosmic_rays",
    "bin_image",
    "digitize",
    "hot_pixels",
    "sample_noise",
    "vignetting_flat",
]

Float32Array = npt.NDArray[np.float32]
IntArray = npt.NDArray[np.int64]

ADC_MAX = 65535


def vignetting_flat(chip_width: int, chip_height: int, window: Window, strength: float) -> Float32Array:
    """Multiplicative flat over ``window`` (unbinned): ``1 - strength * (r / r_corner)^2``.

    ``r`` is the distance from the chip centre, ``r_corner`` the centre-to-corner distance, so the
    corners receive ``1 - strength`` of the light the centre receives.
    """
    if not 0.0 <= strength < 1.0:
        raise ValueError(f"vignetting strength must be within [0, 1), got {strength}")
    cx, cy = (chip_width - 1) / 2.0, (chip_height - 1) / 2.0
    r_corner2 = cx * cx + cy * cy or 1.0
    u = np.arange(window.x, window.x + window.width, dtype=np.float32) - np.float32(cx)
    v = np.arange(window.y, window.y + window.height, dtype=np.float32) - np.float32(cy)
    k = np.float32(strength / r_corner2)
    return np.asarray(np.float32(1.0) - k * (v * v)[:, None] - k * (u * u)[None, :], dtype=np.float32)


def hot_pixels(
    chip_width: int, chip_height: int, *, fraction: float, seed: int, max_rate_e_per_s: float = 200.0
) -> tuple[IntArray, IntArray, npt.NDArray[np.float64]]:
    """The camera's fixed hot pixels: rows, columns and dark rates (e-/s, log-uniform 1..max).

    The same ``seed`` always yields the same set, like a real sensor's defects.
    """
    rng = np.random.default_rng([seed, 0x407])
    count = round(fraction * chip_width * chip_height)
    rows = rng.integers(0, chip_height, count)
    cols = rng.integers(0, chip_width, count)
    rates = 10.0 ** rng.uniform(0.0, math.log10(max_rate_e_per_s), count)
    return rows, cols, rates


def add_cosmic_rays(
    image: Float32Array, *, count: int, rng: np.random.Generator, mean_e_per_pixel: float = 2000.0
) -> None:
    """Add ``count`` cosmic-ray hits to ``image`` in place: short straight tracks of 1-6 pixels.

    Each track starts at a random pixel with a random direction; each pixel on it gets an
    exponentially distributed deposit of mean ``mean_e_per_pixel`` electrons.
    """
    rows, cols = image.shape
    for _ in range(count):
        length = int(rng.integers(1, 7))
        angle = rng.uniform(0.0, 2.0 * math.pi)
        steps = np.arange(length)
        r = np.rint(rng.uniform(0, rows) + steps * math.sin(angle)).astype(np.int64)
        c = np.rint(rng.uniform(0, cols) + steps * math.cos(angle)).astype(np.int64)
        ok = (r >= 0) & (r < rows) & (c >= 0) & (c < cols)
        image[r[ok], c[ok]] += rng.exponential(mean_e_per_pixel, int(ok.sum())).astype(np.float32)


def bin_image(image: Float32Array, binning: int) -> Float32Array:
    """Sum ``binning x binning`` blocks (charge binning); partial blocks at the edges are dropped."""
    if binning == 1:
        return image
    rows, cols = image.shape[0] // binning, image.shape[1] // binning
    trimmed = image[: rows * binning, : cols * binning]
    return np.asarray(trimmed.reshape(rows, binning, cols, binning).sum(axis=(1, 3)), dtype=np.float32)


def sample_noise(
    expected_e: Float32Array,
    *,
    read_noise_e: float,
    rng: np.random.Generator,
    exact_poisson_below: float = 20.0,
) -> Float32Array:
    """A noisy realisation (electrons) of ``expected_e``: photon noise plus read noise (see module doc)."""
    lam = np.maximum(expected_e, np.float32(0.0))
    noise = rng.standard_normal(lam.shape, dtype=np.float32)
    rn2 = np.float32(read_noise_e**2)
    out = lam + np.sqrt(lam + rn2) * noise
    low = (lam < exact_poisson_below) & (lam > 0)
    if low.any():
        out[low] = rng.poisson(lam[low]).astype(np.float32) + np.float32(read_noise_e) * noise[low]
    return out


def digitize(
    electrons: Float32Array, *, gain_e_per_adu: float, bias_adu: float, full_well_e: float | None = None
) -> npt.NDArray[np.uint16]:
    """ADU = bias + electrons / gain, rounded and clipped to the 16-bit range [0, 65535]."""
    if gain_e_per_adu <= 0:
        raise ValueError(f"gain_e_per_adu must be positive, got {gain_e_per_adu}")
    e = electrons if full_well_e is None else np.minimum(electrons, np.float32(full_well_e))
    adu = e * np.float32(1.0 / gain_e_per_adu) + np.float32(bias_adu)
    np.clip(adu, 0.0, ADC_MAX, out=adu)
    return np.asarray(np.rint(adu, out=adu), dtype=np.uint16)
