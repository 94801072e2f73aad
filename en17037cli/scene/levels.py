"""The levels of a model's horizontal faces: its storeys' floors, a region's floor and its ceiling.

The bottom of the room derivation, below the plan (:mod:`~en17037cli.scene.section`): the
horizontal interior faces of a scene (:func:`horizontal_faces`), the heights of its storeys
(:func:`storey_levels`), the share of a region with a floor under it (:func:`floor_cover`: a void or a
well has none) and the ceiling over a floor (:func:`derive_ceiling`: a region the walls enclose
with nothing over it is a courtyard, not a room).
"""
from __future__ import annotations

import numpy as np

from en17037cli.geometry import in_triangle, triangle_normals
from en17037cli.scene.model import INTERIOR, Scene

#: A room is at least this high: horizontal interior faces lower than this above the floor are
#: furniture or steps, not its ceiling [m] ...
MIN_ROOM_HEIGHT_M = 1.8
#: ... and without a ceiling found over its floor, windows up to this height above the floor are its own [m].
DEFAULT_ROOM_HEIGHT_M = 4.0
#: The ceiling is the lowest level of horizontal faces covering this share of the floor [-] ...
CEILING_COVER = 0.5
#: ... faces within this height of each other being one level [m].
CEILING_LEVEL_M = 0.01
#: A level of upward-facing horizontal interior faces is a storey's floor when they cover at least this [m²].
MIN_LEVEL_AREA_M2 = 4.0
#: Floor faces within this height of each other are one level [m].
LEVEL_TOL_M = 0.01
#: The clear height over a level is measured at this many points spread over its faces by area.
LEVEL_SAMPLES = 256


def horizontal_faces(scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """The horizontal interior faces of ``scene`` (|normal z| > 0.999, with area) and their mean
    heights: (k, 3, 3) [m, local], (k,) [m]; made once per scene (ceilings and floors of every room
    look them up)."""
    hit = scene.__dict__.get("_horizontal")
    if hit is None:
        tris = scene.faces_of(scene.layer == INTERIOR)
        normals, areas = triangle_normals(tris)
        keep = (np.abs(normals[:, 2]) > 0.999) & (areas > 0)
        hit = scene.__dict__["_horizontal"] = (tris[keep], tris[keep][..., 2].mean(axis=1))
    return hit


def storey_levels(scene: Scene) -> list[float]:
    """Heights [m, local] of the model's floors, from the lowest up.

    A level of horizontal interior faces (facing up or down: surface models turn them either way,
    EnergyPlus draws a zone's floor facing down, out of the zone) covering at least
    :data:`MIN_LEVEL_AREA_M2` is a floor when the clear height above it, to the next horizontal face
    over the same spot, is at least a room's (:data:`MIN_ROOM_HEIGHT_M`)
    over most of it (the median over :data:`LEVEL_SAMPLES` points spread over its faces by area:
    furniture and the walls standing on it cover little of a floor): a slab's underside, a ceiling
    with a plenum over it, the tops of walls under a slab are not. Of floors
    closer than a room's height (a raised floor) the one of the largest area.
    """
    tris = scene.faces_of(scene.layer == INTERIOR)
    normals, areas = triangle_normals(tris)
    hor = (np.abs(normals[:, 2]) > 0.999) & (areas > 0)
    if not hor.any():
        return []
    tri, a = tris[hor], areas[hor]
    z = tri[..., 2].mean(axis=1)
    key = np.round(z / LEVEL_TOL_M).astype(np.int64)
    levels, inverse = np.unique(key, return_inverse=True)
    total = np.bincount(inverse, a)
    lo, hi = tri[..., :2].min(axis=1), tri[..., :2].max(axis=1)
    floors = []
    for k in np.flatnonzero(total >= MIN_LEVEL_AREA_M2):  # a few dozen levels
        mine = np.flatnonzero(inverse == k)
        zk = float(np.median(z[mine]))
        pts = _area_samples(tri[mine, :, :2], a[mine], LEVEL_SAMPLES)
        above = np.flatnonzero(z > zk + LEVEL_TOL_M)
        clear = np.full(len(pts), np.inf)
        if len(above):
            box = np.all((lo[above][None] <= pts[:, None]) & (hi[above][None] >= pts[:, None]), axis=2)  # (p, h)
            pi, hi_ = np.nonzero(box)
            on = in_triangle(pts[pi], tri[above[hi_]][..., :2])
            np.minimum.at(clear, pi[on], z[above[hi_[on]]] - zk)
        if np.median(clear) >= MIN_ROOM_HEIGHT_M:
            floors.append((zk, float(total[k])))
    chosen: list[float] = []
    for zk, _ in sorted(floors, key=lambda f: -f[1]):  # the largest first
        if all(abs(zk - c) >= MIN_ROOM_HEIGHT_M for c in chosen):
            chosen.append(zk)
    return sorted(chosen)


def _area_samples(tri: np.ndarray, area: np.ndarray, n: int) -> np.ndarray:
    """(n, 2) points in triangles (k, 3, 2), each triangle drawn with probability proportional to its
    area, uniform inside it (Turk 1990, Graphics Gems p. 24); a fixed seed: the same points each run."""
    rng = np.random.default_rng(0)
    k = rng.choice(len(tri), size=n, p=area / area.sum())
    r1, r2 = np.sqrt(rng.random(n)), rng.random(n)
    t = tri[k]
    return (1 - r1)[:, None] * t[:, 0] + (r1 * (1 - r2))[:, None] * t[:, 1] + (r1 * r2)[:, None] * t[:, 2]


#: A region has a floor (it is no void over a room or a well) when floor faces lie under this share of it [-] ...
FLOOR_COVER = 0.5
#: ... within this height of its level [m] (finishes, a sunken floor).
FLOOR_TOL_M = 0.15


def floor_faces(scene: Scene, floor_z: float) -> np.ndarray:
    """Which of :func:`horizontal_faces` lie within :data:`FLOOR_TOL_M` of
    ``floor_z`` [m, local]: (k,) bool."""
    return np.abs(horizontal_faces(scene)[1] - floor_z) <= FLOOR_TOL_M


def floor_cover(scene: Scene, cell, floor_z: float) -> float:
    """Share of a region (shapely Polygon, local xy [m]) that horizontal interior faces within
    :data:`FLOOR_TOL_M` of ``floor_z`` [m, local] cover in plan: a room's floor, where the void over
    a double-height room, a stair or light well have none."""
    import shapely

    tris = horizontal_faces(scene)[0]
    x0, y0, x1, y1 = cell.bounds
    lo, hi = tris[..., :2].min(axis=1), tris[..., :2].max(axis=1)
    cand = floor_faces(scene, floor_z) & (lo[:, 0] < x1) & (hi[:, 0] > x0) & (lo[:, 1] < y1) & (hi[:, 1] > y0)
    if not cand.any() or cell.area <= 0:
        return 0.0
    polys = shapely.make_valid(shapely.polygons(tris[cand][..., :2]))
    return float(shapely.union_all(polys).intersection(cell).area / cell.area)


def derive_ceiling(scene: Scene, floor, floor_z: float) -> tuple[float, str]:
    """Ceiling level [m, local] over a floor: the lowest level of horizontal interior faces at least
    :data:`MIN_ROOM_HEIGHT_M` above it whose faces cover at least :data:`CEILING_COVER` of the floor
    in plan (a lintel, a beam or a soffit covers a strip: not the ceiling); else the level covering
    most of it; else floor + :data:`DEFAULT_ROOM_HEIGHT_M`."""
    import shapely

    tris, z = horizontal_faces(scene)
    cand = z >= floor_z + MIN_ROOM_HEIGHT_M
    x0, y0, x1, y1 = floor.bounds
    lo, hi = tris[..., :2].min(axis=1), tris[..., :2].max(axis=1)
    cand &= (lo[:, 0] < x1) & (hi[:, 0] > x0) & (lo[:, 1] < y1) & (hi[:, 1] > y0)  # over the floor's box
    if np.any(cand) and floor.area > 0:
        level = np.round(z[cand] / CEILING_LEVEL_M).astype(np.int64)
        polys = shapely.make_valid(shapely.polygons(tris[cand][..., :2]))
        cover = {}
        for lv in np.unique(level):  # a few levels over a room: slab, beams, lintels
            cover[lv] = shapely.union_all(polys[level == lv]).intersection(floor).area / floor.area
        ok = [lv for lv in sorted(cover) if cover[lv] >= CEILING_COVER]
        best = ok[0] if ok else max(cover, key=lambda lv: (cover[lv], -lv))
        if cover[best] > 0:
            zc = float(z[cand][level == best].min())
            return zc, (f"the lowest horizontal interior faces over the floor covering {cover[best]:.0%} of it"
                        + ("" if ok else f" (none covers {CEILING_COVER:.0%})"))
    return floor_z + DEFAULT_ROOM_HEIGHT_M, f"no ceiling found over the floor: floor + {DEFAULT_ROOM_HEIGHT_M:g} m"
