"""Facade probes: where on each wall the screen looks, one per storey every ``spacing_m``.

A wall polygon (:mod:`~en17037cli.district.walls`) is drawn in its own plane, in (s, z): s along
its horizontal u = (-n_y, n_x, 0) / |...| (n its outward normal, the ring's Newell normal), z up.
Storeys stand on the building's lowest point: storey k's floor is at z_ground + k h (h
``storey_height_m``). On each storey the virtual window (``window`` width w by height, its sill
``sill_height_m`` over the floor) must lie on the wall: the centres s where it does are found from
the polygon's horizontal cross-sections at the window's sill and head and at every vertex height
between (exact for the convex and stepped outlines of LoD1-2 walls; a notch narrower than the
cross-sections is missed), shrunk by w / 2. Along each such interval of length l the probes stand
every ``spacing_m`` (a) apart, n = floor(l / a) + 1 of them, centred; each stands for (l + w) / n
of the wall's length over one storey height (its ``area_m2``, the weight of the building's shares).

Point P is the virtual window's by EN 17037 Annex A.3: on the room-side plane of the opening at its
horizontal centre, max(floor + 1.2 m, sill + 0.3 m) high. The window is flush with the facade, so
that plane is the wall's. The rays start :data:`PROBE_OFFSET_M` in front of it (the float32 ray
tracer's round-off in a kilometre-wide tile is about 1e-3 m), and see the half-space in front of
the facade: from P, a flush window of any size spans all of it but a sliver along the facade's
plane (docs/district.md).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.district.walls import WALL_MAX_NZ, CityBuilding, newell_normal

#: The rays start this far in front of the facade [m]
PROBE_OFFSET_M = 0.01
#: Cross-sections are taken this far inside the window's sill and head [m] (a sill on a polygon's edge)
EDGE_M = 1e-6


@dataclass
class Probes:
    """The probes of some buildings, one row each (arrays of equal length).

    building, wall, poly : (p,) int, index into the buildings, the building's walls and the wall's
    polygons; storey : (p,) int; point : (p, 3) [m] P on the facade (the model's CRS); normal : (p, 3) unit,
    horizontal, outward; area_m2 : (p,) [m²] the facade each stands for
    """

    building: np.ndarray
    wall: np.ndarray
    poly: np.ndarray
    storey: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    area_m2: np.ndarray

    def __len__(self) -> int:
        return len(self.building)

    def take(self, keep) -> Probes:
        return Probes(*(a[keep] for a in (self.building, self.wall, self.poly, self.storey, self.point, self.normal,
                                          self.area_m2)))


def wall_frame(ring: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """(h, u, origin, n): the wall's outward horizontal normal, its horizontal axis, a point of its
    plane and its normal; None for a polygon that is not upright
    (:data:`~en17037cli.district.walls.WALL_MAX_NZ`)."""
    n = newell_normal(ring)
    if not np.any(n) or abs(n[2]) > WALL_MAX_NZ:
        return None
    h = np.array([n[0], n[1], 0.0])
    h /= np.linalg.norm(h)
    return h, np.array([-h[1], h[0], 0.0]), np.asarray(ring, float).mean(axis=0), n


def cross_section(rings_sz: list[np.ndarray], z: float) -> list[tuple[float, float]]:
    """Intervals of s where the horizontal line at height z lies inside a polygon given by rings in
    (s, z) (outer first, then holes): crossings of every edge sorted, taken in pairs (even-odd)."""
    xs = []
    for r in rings_sz:
        a, b = r, np.roll(r, -1, axis=0)
        lo, hi = np.minimum(a[:, 1], b[:, 1]), np.maximum(a[:, 1], b[:, 1])
        cross = (lo <= z) & (hi > z)  # half-open: a vertex on the line counts once
        t = (z - a[cross, 1]) / (b[cross, 1] - a[cross, 1])
        xs.extend((a[cross, 0] + t * (b[cross, 0] - a[cross, 0])).tolist())
    xs.sort()
    return [(xs[i], xs[i + 1]) for i in range(0, len(xs) - 1, 2)]


def intersect(a: list[tuple[float, float]], b: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Intersection of two sorted lists of disjoint intervals."""
    out, i, j = [], 0, 0
    while i < len(a) and j < len(b):
        lo, hi = max(a[i][0], b[j][0]), min(a[i][1], b[j][1])
        if hi > lo:
            out.append((lo, hi))
        if a[i][1] < b[j][1]:
            i += 1
        else:
            j += 1
    return out


def window_centres(rings_sz: list[np.ndarray], z0: float, z1: float, width: float) -> list[tuple[float, float]]:
    """Intervals of the centres s of a window [s - width/2, s + width/2] x [z0, z1] lying on the
    polygon: the cross-sections at z0, z1 and every vertex height between, intersected, shrunk by
    width / 2 (empty intervals dropped)."""
    levels = {z0 + EDGE_M, z1 - EDGE_M}
    levels |= {float(z) for r in rings_sz for z in r[:, 1] if z0 < z < z1}
    spans = None
    for z in sorted(levels):
        cut = cross_section(rings_sz, z)
        spans = cut if spans is None else intersect(spans, cut)
        if not spans:
            return []
    half = 0.5 * width
    return [(lo + half, hi - half) for lo, hi in spans if hi - lo >= width]


def along(c0: float, c1: float, spacing: float) -> np.ndarray:
    """Centres every ``spacing`` along [c0, c1], n = floor((c1 - c0) / spacing) + 1 of them, centred."""
    length = max(c1 - c0, 0.0)
    n = int(np.floor(length / spacing + 1e-9)) + 1
    return c0 + 0.5 * (length - (n - 1) * spacing) + spacing * np.arange(n)


def place_probes(buildings: list[CityBuilding], settings, first: int = 0) -> Probes:
    """The probes of ``buildings`` (indices counted from ``first``), before the shared-wall test
    (:mod:`~en17037cli.district.compute`). See the module docstring."""
    rows: list = []
    h, w = settings.storey_height_m, settings.window_width_m
    sill, head, p_up = settings.sill_height_m, settings.sill_height_m + settings.window_height_m, settings.p_above_floor_m
    for bi, b in enumerate(buildings):  # buildings, walls and polygons: a few hundred rows of geometry each
        if b.problem:
            continue
        for wi, wall in enumerate(b.walls):
            for pi, poly in enumerate(wall.polygons):
                frame = wall_frame(poly[0])
                if frame is None:
                    continue
                n, u, o, plane = frame
                rings = [np.column_stack([(r - o) @ u, r[:, 2]]) for r in poly]
                top = max(float(r[:, 1].max()) for r in rings)
                for k in range(int(max(0.0, (top - b.z_ground - head) // h)) + 1):  # the storeys whose window can fit
                    floor = b.z_ground + k * h
                    for c0, c1 in window_centres(rings, floor + sill, floor + head, w):
                        s = along(c0, c1, settings.spacing_m)
                        share = (c1 - c0 + w) / len(s) * h
                        rows.extend((first + bi, wi, pi, k, o, u, n, plane, float(si), floor + p_up, share) for si in s)
    if not rows:
        z = np.zeros(0)
        return Probes(z.astype(int), z.astype(int), z.astype(int), z.astype(int), np.zeros((0, 3)), np.zeros((0, 3)), z)
    bi, wi, pi, k, o, u, n, plane, s, zp, share = (np.array(c) for c in zip(*rows))
    foot = o + s[:, None] * u
    point = np.column_stack([foot[:, :2], zp])
    # on the wall's plane plane . (x - o) = 0 at height zp: moved along n (0 for an upright wall)
    d = -np.einsum("ij,ij->i", plane, point - o) / np.einsum("ij,ij->i", plane, n)
    return Probes(bi, wi, pi, k, point + d[:, None] * n, n, share)
