"""Pure shift estimation between a reference and a current signal (1-D profiles or 2-D stamps).

Two steps: :func:`integer_shift` finds the whole-pixel lag at the peak of the cross-correlation
(FFT), :func:`refine_shift` then fits the sub-pixel remainder by least squares, shifting the
reference with cubic-spline interpolation (local, so a star at one edge does not ring through the
whole signal as a Fourier shift would). Shifts are ``current - reference``: a star at ``p`` in
the reference is at ``p + shift`` in the current signal.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy import ndimage, optimize, signal  # type: ignore[import-untyped]

__all__ = ["integer_shift", "refine_shift"]

FloatArray = npt.NDArray[np.float64]


def integer_shift(reference: FloatArray, current: FloatArray, max_shift: int) -> tuple[int, ...]:
    """Whole-pixel shift maximising the cross-correlation summed over a stack.

    Parameters
    ----------
    reference, current
        Stacks of equal shape ``(n, *signal_shape)`` (1-D or 2-D signals), background removed.
    max_shift
        Largest shift searched along each axis (pixels).

    Returns
    -------
    tuple of int
        The shift along each signal axis (for 2-D: ``(dy, dx)``).
    """
    axes = tuple(range(1, reference.ndim))
    flipped = reference[(slice(None), *[slice(None, None, -1)] * len(axes))]
    correlation = signal.fftconvolve(current, flipped, mode="full", axes=axes).sum(axis=0)
    # In "full" mode, lag 0 sits at index (size - 1) along each axis.
    zero = [size - 1 for size in reference.shape[1:]]
    window = tuple(
        slice(max(0, z - max_shift), min(correlation.shape[k], z + max_shift + 1)) for k, z in enumerate(zero)
    )
    cut = correlation[window]
    peak = np.unravel_index(int(np.argmax(cut)), cut.shape)
    return tuple(int(p) + w.start - z for p, w, z in zip(peak, window, zero, strict=True))


def refine_shift(reference: FloatArray, current: FloatArray, margin: int = 3) -> FloatArray:
    """Sub-pixel shift (within ±1.5 px) between aligned stacks, by least squares.

    Each reference signal, shifted and scaled by its own best factor (a star may be brighter or
    fainter in the current frame), is compared with the current signal away from ``margin``
    pixels at the edges.

    Parameters
    ----------
    reference, current
        Stacks of equal shape ``(n, *signal_shape)``, already aligned to the whole pixel.
    margin
        Edge pixels left out of the comparison (shifting brings in extrapolated values there).

    Returns
    -------
    ndarray
        The shift along each signal axis (for 2-D: ``[dy, dx]``).
    """
    dims = reference.ndim - 1
    inner = (slice(None), *[slice(margin, size - margin) for size in reference.shape[1:]])
    coefficients = reference
    for axis in range(1, reference.ndim):
        coefficients = ndimage.spline_filter1d(coefficients, order=3, axis=axis, mode="nearest")
    target = current[inner].reshape(len(current), -1)

    def residuals(shift: FloatArray) -> FloatArray:
        moved = coefficients
        for axis, amount in enumerate(shift, start=1):
            moved = _spline_shift(moved, float(amount), axis)
        flat = moved[inner].reshape(len(moved), -1)
        scale = (flat * target).sum(axis=1) / np.maximum((flat**2).sum(axis=1), 1e-300)
        return np.asarray((target - scale[:, None] * flat).ravel(), np.float64)

    fit = optimize.least_squares(residuals, np.zeros(dims), bounds=(-1.5, 1.5), x_scale=0.3, diff_step=1e-3)
    return np.asarray(fit.x, np.float64)


def _spline_shift(coefficients: FloatArray, shift: float, axis: int) -> FloatArray:
    """Cubic B-spline with ``coefficients`` along ``axis`` evaluated at ``i - shift`` (|shift| <= 2).

    The same values as ``ndimage.shift(..., order=3, prefilter=False)`` away from the edges, as
    four weighted slices instead of a general interpolation: ~20x faster on small stacks.
    """
    start = np.floor(-shift)
    f = -shift - start
    weights = (
        (1 - f) ** 3 / 6,
        (3 * f**3 - 6 * f**2 + 4) / 6,
        (-3 * f**3 + 3 * f**2 + 3 * f + 1) / 6,
        f**3 / 6,
    )
    pad = 4
    widths = [(0, 0)] * coefficients.ndim
    widths[axis] = (pad, pad)
    padded = np.pad(coefficients, widths, mode="edge")
    size = coefficients.shape[axis]
    result = np.zeros_like(coefficients)
    for j, weight in enumerate(weights, start=-1):
        first = pad + int(start) + j
        index = [slice(None)] * coefficients.ndim
        index[axis] = slice(first, first + size)
        result += weight * padded[tuple(index)]
    return result
