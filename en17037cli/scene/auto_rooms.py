"""Automatic rooms: ``rooms: [{auto: true, floor_z: Z}]`` makes every region the walls enclose at
that level (:mod:`~en17037cli.scene.section`) with a window opening from it a room; without
``floor_z``, at every storey of the model (each level of horizontal interior faces of at least
:data:`MIN_LEVEL_AREA_M2` with a room's height clear above it: a floor slab, not a table top, a
stair tread or a plenum's floor)."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from en17037cli.geometry import in_triangle, triangle_normals
from en17037cli.project.settings import RoomSpec
from en17037cli.scene.model import INTERIOR, Room, Scene
from en17037cli.scene.rooms import MIN_ROOM_HEIGHT_M, horizontal_faces

#: A level of upward-facing horizontal interior faces is a storey's floor when they cover at least this [m²].
MIN_LEVEL_AREA_M2 = 4.0
#: Floor faces within this height of each other are one level [m].
LEVEL_TOL_M = 0.01
#: The clear height over a level is measured at this many points spread over its faces by area.
LEVEL_SAMPLES = 256


def storey_levels(scene: Scene) -> list[float]:
    """Heights [m, local] of the model's floors, from the lowest up.

    A level of horizontal interior faces (facing up or down: surface models turn them either way,
    EnergyPlus draws a zone's floor facing down, out of the zone) covering at least
    :data:`MIN_LEVEL_AREA_M2` is a floor when the clear height above it, to the next horizontal face
    over the same spot, is at least a room's (:data:`~en17037cli.scene.rooms.MIN_ROOM_HEIGHT_M`)
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


#: An automatic room needs floor faces under this share of its region [-] ...
FLOOR_COVER = 0.5
#: ... within this height of its level [m] (finishes, a sunken floor).
FLOOR_TOL_M = 0.15


def floor_faces(scene: Scene, floor_z: float) -> np.ndarray:
    """Which of :func:`~en17037cli.scene.rooms.horizontal_faces` lie within :data:`FLOOR_TOL_M` of
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


def auto_rooms(scene: Scene, spec: RoomSpec, where: str) -> list[Room]:
    """One room per region with a window at ``spec.floor_z`` (or at every storey), named
    ``z 3.00 room at (2.0, 4.5)`` (the level and a point inside the region, in the model's
    coordinates), made like a room given by name and ``inside`` point."""
    if not spec.auto_all_storeys:
        return _rooms_at(scene, spec, where, [spec.floor_z - scene.origin[2]])
    rooms = _rooms_at(scene, spec, where, storey_levels(scene))
    if not rooms:
        scene.notes.append(f"{where}: auto found no region the walls enclose with a window")
    return rooms


def _rooms_at(scene: Scene, spec: RoomSpec, where: str, levels: list[float]) -> list[Room]:
    from en17037cli.scene.rooms import make_room
    from en17037cli.scene.section import cells_with_windows, level_windows, plan_of

    rooms = []
    for z in levels:
        plan = plan_of(scene, z)
        found = cells_with_windows(scene, plan, level_windows(scene, z))
        floored = {i: floor_cover(scene, plan.cells[i], z) >= FLOOR_COVER for i in found}
        if any(floored.values()):  # a level with floors: a region without one is a void, not a room
            void = [i for i in found if not floored[i]]
            for i in void:
                found.pop(i)
            if void:
                scene.notes.append(f"{where}: {len(void)} region(s) at z {z + scene.origin[2]:.2f} m with windows but no floor "
                                   "(the void over a double-height room, a well) are not rooms")
        for i in sorted(found, key=lambda k: (round(plan.cells[k].centroid.y, 1), round(plan.cells[k].centroid.x, 1))):
            p = plan.cells[i].representative_point()
            x, y = p.x + scene.origin[0], p.y + scene.origin[1]
            name = f"z {z + scene.origin[2]:.2f} room at ({x:.1f}, {y:.1f})"
            room_spec = replace(spec, name=name, floor_z=z + scene.origin[2], inside=np.array([x, y]), auto=False,
                                auto_all_storeys=False)
            rooms.append(make_room(scene, room_spec, f"{where} '{name}'"))
    if not rooms and not spec.auto_all_storeys:
        scene.notes.append(f"{where}: auto found no region the walls enclose with a window at floor_z = {spec.floor_z:g} m")
    return rooms
