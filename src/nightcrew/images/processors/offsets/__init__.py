"""Offsets of the field on the detector, in ``image.metadata["offsets"]`` as :class:`Offsets`.

Relative to a reference image (the first one; see :class:`ReferenceOffsets`):
:class:`ProjectedOffsets` (row/column sums) and :class:`NStarOffsets` (boxes around bright
stars). Against a fixed position: :class:`BrightestStarOffsets`, :class:`FitsHeaderOffsets` and
:class:`AstrometryOffsets` (needs a WCS).
"""

from nightcrew.images.processors.offsets._absolute import (
    AstrometryOffsets,
    BrightestStarOffsets,
    FitsHeaderOffsets,
)
from nightcrew.images.processors.offsets._nstar import NStarOffsets, nstar_offsets
from nightcrew.images.processors.offsets._projected import ProjectedOffsets, projected_offsets
from nightcrew.images.processors.offsets._reference import ReferenceOffsets
from nightcrew.images.processors.offsets._result import OFFSETS_KEY, Offsets

__all__ = [
    "OFFSETS_KEY",
    "AstrometryOffsets",
    "BrightestStarOffsets",
    "FitsHeaderOffsets",
    "NStarOffsets",
    "Offsets",
    "ProjectedOffsets",
    "ReferenceOffsets",
    "nstar_offsets",
    "projected_offsets",
]
