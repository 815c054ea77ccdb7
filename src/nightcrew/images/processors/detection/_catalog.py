"""The source catalog's columns, shared by every detector (and read by offsets, photometry, seeing).

=============  =====================================================================
``x``, ``y``   centroid, 0-based pixels (x = column)
``flux``       total flux above background (data units)
``peak``       highest pixel above background (data units)
``background`` background level at the source (data units); ``peak + background`` is the raw peak
``fwhm``       full width at half maximum (pixels); NaN when the detector does not measure it
``ellipticity`` ``1 - b/a`` (0 for a round source); NaN when not measured
``flags``      bit flags: SEP's own (1 blended, 2 truncated at the edge, ...) and :data:`FLAG_SATURATED`
=============  =====================================================================
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from astropy.table import Table  # type: ignore[import-untyped]

__all__ = ["COLUMNS", "FLAG_SATURATED", "catalog_table"]

#: The raw peak reaches the saturation level.
FLAG_SATURATED = 0x100

COLUMNS = ("x", "y", "flux", "peak", "background", "fwhm", "ellipticity", "flags")


def catalog_table(columns: dict[str, npt.ArrayLike]) -> Table:
    """A catalog with the :data:`COLUMNS` first (missing ones as NaN, flags as 0), then extra columns."""
    length = len(np.asarray(columns["x"]))
    table = Table()
    for name in COLUMNS:
        if name in columns:
            values = np.asarray(columns[name])
        elif name == "flags":
            values = np.zeros(length, np.int32)
        else:
            values = np.full(length, np.nan)
        table[name] = values.astype(np.int32 if name == "flags" else np.float64)
    for name, extra in columns.items():
        if name not in COLUMNS:
            table[name] = np.asarray(extra)
    return table
