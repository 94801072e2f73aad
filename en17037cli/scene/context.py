"""A city model around the checked building: does it stand on the model's ground, and does any of
its faces run through a room?

A city tile (CityJSON, CityGML) gives heights above its datum (Zurich's LoD2 396-621 m above sea
level, the 3D BAG's NAP heights about 0) and a model drawn in local coordinates has its ground
floor at z 0: placed in plan only, the city stands hundreds of metres above or below the building
and every figure is silently wrong. Two checks after the rooms are made, each a warning that
says what to do:

- **Height:** the city's ground near the building (the median, over the city objects nearest the
  model's plan, of each object's lowest point there: a building's walls reach its ground, a
  terrain's faces are the ground) against the model's lowest floor (its lowest storey or room
  floor). Beyond :data:`HEIGHT_TOLERANCE_M` the warning gives the z offset and the project key that
  applies it (``model.files[i].transform.translate_m``, docs/project-file.md).
- **Through a room:** a face of the city model lying inside a room's volume (more than
  :data:`INSIDE_MARGIN_M` above its floor, below its ceiling, inside its floor's outline): a block
  of vegetation or a terrain at another height, or the checked building as the city draws it. The
  warning names the object and the ``exclude`` key that leaves it out.
"""
from __future__ import annotations

import numpy as np

from en17037cli.scene.model import INTERIOR, Scene

#: The city's ground near the building may lie this far above or below the model's lowest floor
#: without a warning [m]: a raised ground floor, a gentle slope, a datum's rounding.
HEIGHT_TOLERANCE_M = 1.0
#: Distances [m] around the model's plan searched in turn for city objects, until at least
#: :data:`MIN_GROUND_OBJECTS` are found (else the last that found any).
GROUND_RADII_M = (10.0, 25.0, 50.0, 100.0, 200.0, 500.0)
MIN_GROUND_OBJECTS = 3
#: A city face is inside a room when some of it lies more than this above the floor, below the
#: ceiling and inside the floor's outline [m] (a terrain flush with the floor, a wall touching it are not).
INSIDE_MARGIN_M = 0.1
#: Objects named one warning each; the others in one more, with the whole exclude list.
MAX_NAMED = 5


def context_warnings(scene: Scene, files, where: str) -> list[str]:
    """Warnings about the city models of ``scene`` (``scene.context``): see the module docstring.

    Parameters
    ----------
    scene : a Scene with its rooms made (local frame, world = local + origin) [m]
    files : the project's ``model.files`` (:class:`~en17037cli.project.settings.ModelFile`), for
        the keys the warnings name
    where : the project file's name, for messages
    """
    if not scene.context or len(scene.triangles) == 0:
        return []
    part_ctx = np.full(len(scene.parts), -1, dtype=np.int64)
    for k, (_, _, lo, hi) in enumerate(scene.context):
        part_ctx[lo:hi] = k
    face_ctx = part_ctx[scene.part]
    own = (face_ctx < 0) & (scene.layer == INTERIOR)
    floor = lowest_floor(scene)
    box = None
    if own.any():
        xy = scene.vertices[scene.triangles[own]][..., :2].reshape(-1, 2)
        box = (xy.min(axis=0), xy.max(axis=0))
    out = []
    for k, (index, display, _, _) in enumerate(scene.context):
        mine = np.flatnonzero(face_ctx == k)
        if len(mine) == 0:
            continue
        key = f"model.files[{index}]"
        if floor is not None and box is not None:
            ground = ground_near(scene, mine, box)
            if ground is not None and abs(ground[0] - floor[0]) > HEIGHT_TOLERANCE_M:
                out.append(_height_warning(scene, where, key, display, files[index], floor, ground))
        out += _through_rooms(scene, mine, where, key, display)
    return out


def lowest_floor(scene: Scene) -> tuple[float, str] | None:
    """(z [m, local], what it is) of the model's lowest floor: its lowest storey
    (:func:`~en17037cli.scene.levels.storey_levels`) or room floor, whichever is lower; None
    when the model has neither."""
    from en17037cli.scene.levels import storey_levels

    levels = storey_levels(scene)
    found = [(levels[0], "its lowest storey")] if levels else []
    found += [(r.floor_z, f"room '{r.name}'") for r in scene.rooms if not r.problem]
    return min(found, key=lambda f: f[0]) if found else None  # the first of the lowest: the storey


def ground_near(scene: Scene, faces: np.ndarray, box) -> tuple[float, int, float] | None:
    """The city's ground near the model: (z [m, local], objects, radius [m]).

    Each city object's lowest vertex within ``radius`` of the model's plan box (``box``: lower and
    upper xy corners [m, local]), for the first radius of :data:`GROUND_RADII_M` with at least
    :data:`MIN_GROUND_OBJECTS` such objects; the median over them. None when no object comes within
    the largest radius. Objects are the parts' ``id`` (one CityJSON object, one CityGML feature).
    """
    ids: dict = {}
    obj_of_part = np.array([ids.setdefault(p.attrs.get("id", f"#{i}"), len(ids)) for i, p in enumerate(scene.parts)],
                           dtype=np.int64)
    v = scene.vertices[scene.triangles[faces]].reshape(-1, 3)
    obj = np.repeat(obj_of_part[scene.part[faces]], 3)
    lo, hi = box
    # distance in plan from each vertex to the box (0 inside)
    d = np.hypot(np.maximum(np.maximum(lo[0] - v[:, 0], v[:, 0] - hi[0]), 0.0),
                 np.maximum(np.maximum(lo[1] - v[:, 1], v[:, 1] - hi[1]), 0.0))
    best = None
    for radius in GROUND_RADII_M:  # a few radii
        near = d <= radius
        if not near.any():
            continue
        base = np.full(len(ids), np.inf)
        np.minimum.at(base, obj[near], v[near, 2])
        found = base[np.isfinite(base)]
        best = (float(np.median(found)), len(found), radius)
        if len(found) >= MIN_GROUND_OBJECTS:
            break
    return best


def _num(x: float) -> str:
    """A coordinate as the project file would take it: 2 decimals, no trailing zeros."""
    s = f"{x:.2f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _height_warning(scene: Scene, where: str, key: str, display: str, spec, floor, ground) -> str:
    z0 = float(scene.origin[2])
    gz, n, radius = ground
    dz = floor[0] - gz  # move the city by this to stand it on the model's lowest floor
    t = spec.transform
    tx, ty, tz = (t.translate_m if t is not None else (0.0, 0.0, 0.0))
    rot = f"rotate_deg: {t.rotate_deg:g}, " if t is not None and t.rotate_deg else ""
    side = "above" if gz > floor[0] else "below"
    caveat = ("unless that floor lies below the ground (a basement)" if gz > floor[0] else
              "unless that floor stands above the ground (a raised ground floor, a model of upper storeys only)")
    return (f"{where}: {key} ({display}): the city model's ground near the building lies at z {gz + z0:.2f} m, "
            f"{abs(dz):.2f} m {side} the model's lowest floor (z {floor[0] + z0:.2f} m, {floor[1]}; the ground: the median "
            f"of the lowest points of {n} city object(s) within {radius:g} m of the model's plan): the two files stand at "
            f"different heights, {caveat}. To stand the city on the model's floor, set {key}.transform: "
            f"{{{rot}translate_m: [{_num(tx)}, {_num(ty)}, {_num(tz + dz)}]}}")


def _through_rooms(scene: Scene, faces: np.ndarray, where: str, key: str, display: str) -> list[str]:
    """One warning per city object with faces inside a room (at most :data:`MAX_NAMED`, then one for the rest)."""
    import shapely

    rooms = [r for r in scene.rooms if not r.problem and not r.floor.is_empty]
    if not rooms:
        return []
    bounds = np.array([r.floor.bounds for r in rooms])  # the rooms' box: a tile's far faces go at once
    z = scene.vertices[scene.triangles[faces], 2]
    xy = scene.vertices[scene.triangles[faces], :2]
    near = ((z.max(axis=1) > min(r.floor_z for r in rooms)) & (z.min(axis=1) < max(_top(r) for r in rooms))
            & (xy[..., 0].max(axis=1) > bounds[:, 0].min()) & (xy[..., 0].min(axis=1) < bounds[:, 2].max())
            & (xy[..., 1].max(axis=1) > bounds[:, 1].min()) & (xy[..., 1].min(axis=1) < bounds[:, 3].max()))
    faces = faces[near]
    tri = scene.vertices[scene.triangles[faces]]  # (m, 3, 3) local
    zlo, zhi = tri[..., 2].min(axis=1), tri[..., 2].max(axis=1)
    xlo, xhi = tri[..., :2].min(axis=1), tri[..., :2].max(axis=1)
    hits: dict = {}  # object part index -> {room name: (lowest, highest) [m above its floor]}
    for room in rooms:  # a few rooms
        inner = room.floor.buffer(-INSIDE_MARGIN_M)
        if inner.is_empty:
            continue
        z0, z1 = room.floor_z + INSIDE_MARGIN_M, _top(room) - INSIDE_MARGIN_M
        bx0, by0, bx1, by1 = inner.bounds
        cand = np.flatnonzero((zhi > z0) & (zlo < z1) & (xhi[:, 0] > bx0) & (xlo[:, 0] < bx1)
                              & (xhi[:, 1] > by0) & (xlo[:, 1] < by1))
        if len(cand) == 0:
            continue
        pts, ok = clip_to_slab(tri[cand], z0, z1)
        has = ok.any(axis=1)
        cand, pts, ok = cand[has], pts[has], ok[has]
        if len(cand) == 0:
            continue
        counts = ok.sum(axis=1)
        hulls = shapely.convex_hull(shapely.multipoints(pts[ok][:, :2], indices=np.repeat(np.arange(len(cand)), counts)))
        inside = shapely.intersects(hulls, inner)
        if not inside.any():
            continue
        z = pts[inside][..., 2] - room.floor_z
        zmin = np.where(ok[inside], z, np.inf).min(axis=1)
        zmax = np.where(ok[inside], z, -np.inf).max(axis=1)
        fp = scene.part[faces[cand[inside]]]
        for p in np.unique(fp).tolist():  # the parts (objects) in this room: few
            a, b = hits.setdefault(p, {}).get(room.name, (np.inf, -np.inf))
            hits[p][room.name] = (min(a, float(zmin[fp == p].min())), max(b, float(zmax[fp == p].max())))
    by_obj: dict = {}  # object id -> (class, {room: (lo, hi)})
    for p, rooms in hits.items():
        part = scene.parts[p]
        oid = part.attrs.get("id", part.label)
        cls, seen = by_obj.setdefault(oid, (part.attrs.get("class", "object"), {}))
        for name, (a, b) in rooms.items():
            a0, b0 = seen.get(name, (np.inf, -np.inf))
            seen[name] = (min(a, a0), max(b, b0))
    out = []
    for oid, (cls, rooms) in list(by_obj.items())[:MAX_NAMED]:
        lo = min(a for a, _ in rooms.values())
        hi = max(b for _, b in rooms.values())
        names = ", ".join(f"'{n}'" for n in list(rooms)[:4]) + (f" and {len(rooms) - 4} more" if len(rooms) > 4 else "")
        out.append(f"{where}: {key} ({display}): {cls} '{oid}' runs through {len(rooms)} room(s) ({names}): its faces lie "
                   f"inside them, {lo:.2f}-{hi:.2f} m above their floors, where it hides the view and the sun (the city "
                   f"model overlaps the building, or stands at another height); leave it out with {key}.exclude: "
                   f"['{oid}'], or place the file ({key}.transform)")
    if len(by_obj) > MAX_NAMED:
        rest = list(by_obj)[MAX_NAMED:]
        out.append(f"{where}: {key} ({display}): {len(rest)} more city object(s) run through rooms; to leave every one out: "
                   f"{key}.exclude: [{', '.join(repr(o) for o in by_obj)}]")
    return out


def _top(room) -> float:
    """A room's ceiling [m, local]; 4 m over its floor where it has none."""
    return room.ceiling_z if np.isfinite(room.ceiling_z) else room.floor_z + 4.0


def clip_to_slab(tri: np.ndarray, z0: float, z1: float) -> tuple[np.ndarray, np.ndarray]:
    """Points spanning the part of each triangle between the planes z = z0 and z = z1 [m]: its
    vertices between them and its edges' crossings of each plane (the clipped polygon's corners).

    Parameters
    ----------
    tri : (c, 3, 3) float [m]; z0 < z1 [m]

    Returns
    -------
    points : (c, 9, 3) float [m]; valid : (c, 9) bool, which points are corners (a triangle wholly
        outside the slab has none)
    """
    a = tri
    b = np.roll(tri, -1, axis=1)  # edges (0, 1), (1, 2), (2, 0)
    za, zb = a[..., 2], b[..., 2]
    pts, ok = [a], [(za >= z0) & (za <= z1)]
    dz = zb - za
    flat = np.abs(dz) < 1e-12
    for h in (z0, z1):
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(flat, -1.0, (h - za) / np.where(flat, 1.0, dz))
        pts.append(a + t[..., None] * (b - a))
        ok.append((t >= 0.0) & (t <= 1.0))
    return np.concatenate(pts, axis=1), np.concatenate(ok, axis=1)
