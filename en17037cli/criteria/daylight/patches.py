"""The Reinhart subdivision of the sky (gendaymtx's and rcontrib's ``reinhartb.cal`` patches), in numpy.

Rows of 30, 30, 24, 24, 18, 12, 6 patches (each times MF, MF rows per row of the Tregenza layout),
90 / (7 MF + 0.5) degrees of altitude each, then the zenith cap; azimuth from the model's +y
(north), clockwise seen from above (towards +x), a patch centred on each multiple of 360 / n.
gendaymtx numbers the ground 0 and the patches from 1; reinhartb.cal numbers the patches from 0 and
the ground -1.

References: C. Reinhart (2001) sky subdivision; Radiance ``lib/reinhartb.cal`` (G. Ward, 2014).
"""
from __future__ import annotations

import numpy as np


def reinhart_bins(mf: int) -> int:
    """Patches of the Reinhart subdivision MF, ground included: 1 + 144 MF² + 1 (145 + 1 for MF 1)."""
    return 144 * mf * mf + 2


def row_counts(mf: int) -> np.ndarray:
    """Patches in each row of altitude, the zenith cap last (7 MF + 1 rows)."""
    return np.r_[np.repeat(np.array([30, 30, 24, 24, 18, 12, 6]) * mf, mf), 1]


def row_width_deg(mf: int) -> float:
    """Altitude of a row [deg]: 90 / (7 MF + 0.5) (the cap takes the last half row)."""
    return 90.0 / (7 * mf + 0.5)


def patch_bin(directions: np.ndarray, mf: int) -> np.ndarray:
    """reinhartb.cal's ``rbin`` of unit directions (n, 3): the patch (0 .. 144 MF², the cap last), -1
    at or below the horizon."""
    d = np.asarray(directions, float).reshape(-1, 3)
    alt = np.degrees(np.arcsin(np.clip(d[:, 2], -1.0, 1.0)))
    azi = np.degrees(np.arctan2(d[:, 0], d[:, 1])) % 360.0
    counts = row_counts(mf)
    first = np.r_[0, np.cumsum(counts)[:-1]]
    row = np.clip(np.floor(alt / row_width_deg(mf)).astype(np.int64), 0, len(counts) - 1)
    inc = 360.0 / counts[row]
    k = np.where(359.9999 - 0.5 * inc - azi > 0, np.floor((azi + 0.5 * inc) / inc), 0).astype(np.int64)
    return np.where(alt > 0, first[row] + k, -1)


def patch_solid_angles(mf: int) -> np.ndarray:
    """(144 MF² + 1,) solid angle of each patch [sr]: a row between altitudes a0 and a1 of n patches
    gives each 2 π (sin a1 - sin a0) / n; the cap 2 π (1 - sin a)."""
    counts = row_counts(mf)
    w = np.radians(row_width_deg(mf))
    a0 = np.arange(len(counts)) * w
    a1 = np.minimum(a0 + w, np.pi / 2)
    a1[-1] = np.pi / 2
    band = 2.0 * np.pi * (np.sin(a1) - np.sin(a0))
    return np.repeat(band / counts, counts)


def patch_directions(mf: int) -> np.ndarray:
    """(bins, 3) unit directions of the patch centres in gendaymtx's order (row 0, the ground:
    straight down), each row's centre altitude and each patch's centre azimuth."""
    counts = row_counts(mf)[:-1]
    rowalt = row_width_deg(mf)
    out = [np.array([0.0, 0.0, -1.0])]
    for r, n in enumerate(counts):  # the rows (7 MF)
        alt = np.radians((r + 0.5) * rowalt)
        az = np.radians(np.arange(n) * 360.0 / n)
        out.append(np.column_stack([np.sin(az) * np.cos(alt), np.cos(az) * np.cos(alt), np.full(n, np.sin(alt))]))
    out.append(np.array([0.0, 0.0, 1.0]))
    return np.vstack(out)
