"""Rooms: floor polygons (given, or derived from the model), ceilings, and the windows that bound each room.

A room's windows are found geometrically, not by name: a window bounds a room when its glazing
lies over the room's floor outline grown by ``window_margin_m`` (the wall it sits in) and between
the room's floor and ceiling, and the room lies on its inner side (:func:`bounds_room`). The
project's ``windows:`` globs only narrow that set; a glob that picks a window which does not bound
the room is an input error naming both. This keeps a room from seeing the sun through another
room's window behind a partition.

A room given by name and level gets its floor from the plan (:mod:`~en17037cli.scene.section`,
:func:`room_cell` picks its region); its ceiling and floor cover come from the levels of the
horizontal faces (:mod:`~en17037cli.scene.levels`). Automatic rooms
(:mod:`~en17037cli.scene.auto_rooms`, above this module) are one :func:`make_room` per region.
"""
from __future__ import annotations

import fnmatch
from dataclasses import dataclass

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals, window_axes
from en17037cli.project.settings import RoomSpec
from en17037cli.scene.furniture import furnished_floor
from en17037cli.scene.levels import FLOOR_COVER, derive_ceiling, floor_cover, floor_faces
from en17037cli.scene.model import INTERIOR, Room, Scene, Window
from en17037cli.scene.section import (
    CUT_HEIGHT_M,
    Plan,
    _segments,
    cells_with_windows,
    describe,
    level_windows,
    plan_of,
    wall_off,
    window_cell,
)

#: Share of a window's width (or, for roof glazing, of its plan area) that must lie over the grown floor.
MIN_OVER_FLOOR_SHARE = 0.5
#: Glazing steeper than this (|normal z| below it) is a wall window, tested by its plan trace.
WALL_WINDOW_MAX_NZ = 0.5
#: Points along a wall window's width tested against the floor outline.
WIDTH_SAMPLES = 11
#: The sweep from a wall window towards each side starts this far off its plane, so that glazing
#: on the floor's very outline (a wall of no thickness) is not on both sides at once [m].
SIDE_OFFSET_M = 1e-3
#: Heights closer than this are equal when comparing glazing with floor and ceiling [m].
HEIGHT_TOL_M = 0.01


@dataclass(frozen=True)
class Bounding:
    """Whether and how a window bounds a room: ``share`` of its width over the grown floor on the
    room's side, the outward ``normal`` that side gives, and a one-line ``reason``."""

    bounds: bool
    share: float
    normal: np.ndarray
    reason: str


def floor_components(scene: Scene, floor_z: float):
    """Polygons of the horizontal interior faces within 2 cm of ``floor_z`` [m, local], unioned."""
    import shapely

    tris = scene.faces_of(scene.layer == INTERIOR)
    normals, areas = triangle_normals(tris)
    flat = (np.abs(normals[:, 2]) > 0.999) & np.all(np.abs(tris[..., 2] - floor_z) < 0.02, axis=1) & (areas > 0)
    if not np.any(flat):
        return []
    union = shapely.union_all(shapely.make_valid(shapely.polygons(tris[flat][..., :2]))).buffer(1e-6).buffer(-1e-6)
    return [union] if union.geom_type == "Polygon" else [g for g in getattr(union, "geoms", []) if g.geom_type == "Polygon"]


def bounds_room(window: Window, floor, floor_z: float, ceiling_z: float, margin_m: float, z_world: float = 0.0) -> Bounding:
    """Whether ``window`` bounds the room with ``floor`` (shapely Polygon, local xy [m]) between
    ``floor_z`` and ``ceiling_z`` [m].

    A wall window bounds the room when at least half its height lies between floor and ceiling
    and at least :data:`MIN_OVER_FLOOR_SHARE` of its width, moved at most ``margin_m`` [m]
    horizontally to one side of its plane, lies over the floor; that side is the room's, and the
    outward normal points to the other. Roof glazing (flatter than :data:`WALL_WINDOW_MAX_NZ`)
    bounds it when its lowest point lies between the floor and the ceiling + margin (a light well)
    and that share of its plan area lies over the floor grown by the margin; it faces up.
    ``z_world`` [m] turns local heights into the model's for the reason.
    """
    import shapely

    lo, hi = window.sill_z, window.head_z
    n = np.asarray(window.normal, float)
    roof = abs(n[2]) >= WALL_WINDOW_MAX_NZ
    inside = min(hi, ceiling_z) - max(lo, floor_z)
    if (roof and not floor_z <= lo <= ceiling_z + margin_m) or (not roof and inside < 0.5 * (hi - lo) - HEIGHT_TOL_M):
        return Bounding(False, 0.0, n, f"its glazing (z {lo + z_world:.2f} to {hi + z_world:.2f} m) is not between floor "
                        f"(z {floor_z + z_world:.2f} m) and ceiling (z {ceiling_z + z_world:.2f} m)")
    if roof:
        plan = shapely.union_all(shapely.make_valid(shapely.polygons(window.triangles[..., :2])))
        share = plan.intersection(floor.buffer(margin_m, join_style="mitre")).area / max(plan.area, 1e-12)
        up = n if n[2] > 0 else -n
        ok = share >= MIN_OVER_FLOOR_SHARE
        return Bounding(ok, share, up, f"roof glazing, {share:.0%} of its plan area over the floor grown by {margin_m:g} m")
    a, _ = window_axes(n)
    h = n.copy()
    h[2] = 0.0
    h /= np.linalg.norm(h)
    s = window.triangles.reshape(-1, 3) @ a
    c = window.centroid
    t = np.linspace(0.05, 0.95, WIDTH_SAMPLES)
    along = s.min() + t * (s.max() - s.min()) - c @ a
    starts = c[None, :2] + along[:, None] * a[None, :2]
    share, length = {}, {}
    for side in (1.0, -1.0):  # the two sides of the glazing: +h and -h, from just off its plane
        lines = shapely.linestrings(np.stack([starts + side * SIDE_OFFSET_M * h[None, :2],
                                              starts + side * margin_m * h[None, :2]], axis=1))
        share[side] = float(np.mean(shapely.intersects(lines, floor)))
        length[side] = float(np.sum(shapely.length(shapely.intersection(lines, floor))))
    side = 1.0 if (share[1.0], length[1.0]) > (share[-1.0], length[-1.0]) else -1.0
    ok = share[side] >= MIN_OVER_FLOOR_SHARE
    outward = -side * n  # h is n's horizontal part: the room lies towards side * n
    return Bounding(ok, share[side], outward,
                    f"{share[side]:.0%} of its width within {margin_m:g} m of the floor outline, z {lo + z_world:.2f} to {hi + z_world:.2f} m")


def windows_near(scene: Scene, floor, floor_z: float, ceiling_z: float, margin_m: float) -> np.ndarray:
    """(w,) bool: the windows whose bounding box comes within ``margin_m`` [m] of the floor's
    bounding box in plan and reaches between ``floor_z`` and ``ceiling_z`` + margin [m]: a
    vectorised first pass, so that a building of many rooms does not test every window against
    every room (:func:`bounds_room` decides for these)."""
    if not scene.windows:
        return np.zeros(0, bool)
    lo, hi = scene.window_boxes()
    x0, y0, x1, y1 = floor.bounds
    tol = margin_m + HEIGHT_TOL_M
    return ((lo[:, 0] <= x1 + tol) & (hi[:, 0] >= x0 - tol) & (lo[:, 1] <= y1 + tol) & (hi[:, 1] >= y0 - tol)
            & (hi[:, 2] >= floor_z - HEIGHT_TOL_M) & (lo[:, 2] <= ceiling_z + tol))


def _globbed(window: Window, globs) -> str | None:
    return next((g for g in globs if fnmatch.fnmatchcase(window.name, g)), None)


def make_room(scene: Scene, spec: RoomSpec, where: str, chosen: list[tuple[Window, str]] | None = None) -> Room:
    """The :class:`Room` of ``spec``: its floor, ceiling and the windows that bound it, each
    window's normal turned away from the room. ``chosen``: the windows (outward normals set) and
    why each is the room's, where the caller matched them (rooms from a model's spaces:
    :func:`~en17037cli.scene.spaces.match_windows`), in place of the geometric rule."""
    import shapely

    floor_z = spec.floor_z - scene.origin[2]
    region = None
    if spec.floor is not None:
        poly = shapely.Polygon(spec.floor - scene.origin[:2])
        if not poly.is_valid or poly.area <= 0:
            raise InputError(f"{where}.floor: not a simple polygon with area; list its corners in order")
        source = "given"
    else:
        region = room_cell(scene, spec, floor_z, where)
        if region is not None:
            poly, cell, plan = region
            source = "the region the walls enclose at eye height"
            _warn_floorless(scene, spec, poly, floor_z, where)
        else:
            parts = floor_components(scene, floor_z)
            if not parts:
                return Room(name=spec.name, index=spec.index, floor_z=floor_z, floor=shapely.Polygon(), windows=[], spec=spec,
                            floor_source="none", problem=f"no walls and no horizontal interior faces at floor_z = "
                            f"{spec.floor_z:g} m; check floor_z or give 'floor' as a polygon [[x, y], ...]")
            if len(parts) > 1:
                named = [w for w in scene.windows if spec.windows and _globbed(w, spec.windows)]
                if not named:
                    raise InputError(f"{where}: {len(parts)} separate floors at floor_z; give 'floor' as a polygon "
                                     "[[x, y], ...] or name the room's windows (windows: [...]) to pick the floor beside them")
                near_pts = shapely.points(np.array([w.centroid[:2] for w in named]))
                poly = parts[int(np.argmin([float(np.min(shapely.distance(p, near_pts))) for p in parts]))]
            else:
                poly = parts[0]
            source = "derived from horizontal interior faces at floor_z (no walls enclose it)"
    if spec.ceiling_z is not None:
        ceiling_z, ceiling_source = spec.ceiling_z - scene.origin[2], "given"
    else:
        ceiling_z, ceiling_source = derive_ceiling(scene, poly, floor_z)
    if region is not None and spec.floor is None and not ceiling_source.startswith("no ceiling"):
        poly, added = furnished_floor(scene, plan, cell, ceiling_z)
        if added > 0:
            source += f", with {added:.2f} m² under furniture against its walls (it stops short of the ceiling)"
    windows, reasons = [], {}
    if spec.floor is None and region is not None and chosen is None:  # the walls' region: windows by the plan
        return _room_of_cell(scene, spec, where, poly, cell, plan, floor_z, ceiling_z, ceiling_source, source)
    near = windows_near(scene, poly, floor_z, ceiling_z, spec.window_margin_m)
    if chosen is not None:  # matched by the caller: no geometric rule here
        windows, reasons, near = [w for w, _ in chosen], {w.name: why for w, why in chosen}, np.zeros(len(near), bool)
    for w, close in zip(scene.windows, near):  # one test per window of the model near the room
        glob = _globbed(w, spec.windows) if spec.windows is not None else "*"
        if glob is None or (not close and spec.windows is None) or chosen is not None:
            continue  # a window far from the room cannot bound it; a named one gets its reason below
        b = bounds_room(w, poly, floor_z, ceiling_z, spec.window_margin_m, scene.origin[2])
        if not b.bounds:
            if spec.windows is None:
                continue
            raise InputError(f"{where}.windows: '{glob}' picks window '{w.name}', which does not bound room '{spec.name}' "
                             f"({b.reason}); remove it from the list, or fix floor, floor_z or window_margin_m")
        windows.append(w.facing(b.normal))
        reasons[w.name] = b.reason
    if spec.windows is not None and not windows:
        known = ", ".join(f"'{w.name}'" for w in scene.windows)
        raise InputError(f"{where}.windows: no window matches {list(spec.windows)}; windows found: {known}")
    problem = None if windows else (f"no window bounds the room (none lies within window_margin_m = {spec.window_margin_m:g} m "
                                    "of its floor outline, between floor and ceiling)")
    return Room(name=spec.name, index=spec.index, floor_z=floor_z, floor=poly, windows=windows, spec=spec,
                floor_source=source, ceiling_z=ceiling_z, ceiling_source=ceiling_source, window_reasons=reasons,
                problem=problem)


def room_cell(scene: Scene, spec, floor_z: float, where: str) -> tuple[object, int, Plan] | None:
    """The region the walls enclose for a room given by name and level: (polygon [m, local], cell
    index, plan), or None where the model has no wall at that level's eye height (the caller then
    takes the horizontal faces at ``floor_z``) or the room has no window to pick a region by. The cell holding ``spec.inside``, else the one the room's
    windows (its globs, else every window of the level) open from.

    Raises
    ------
    InputError
        ``inside`` in no region; the room's named windows opening from different regions; several
        regions with windows and nothing to choose between them; windows opening from no region
        (the walls do not close around them: the gap's position is named).
    """
    import shapely

    plan = plan_of(scene, floor_z)
    if not len(_segments(scene, floor_z + CUT_HEIGHT_M, (INTERIOR,))):
        return None  # no wall at eye height: the floor is the horizontal faces (the caller's rule)
    if spec.inside is not None:
        p = shapely.points(np.asarray(spec.inside, float) - scene.origin[:2])
        hit = [i for i, c in enumerate(plan.cells) if c.contains(p)]
        if not hit:
            raise InputError(f"{where}.inside: {list(spec.inside)} lies in no region the walls enclose at floor_z = "
                             f"{spec.floor_z:g} m (regions: {'; '.join(describe(c, scene.origin) for c in plan.cells[:6])}); "
                             "move the point into the room, or give floor: [[x, y], ...]")
        return plan.cells[hit[0]], hit[0], plan
    named = spec.windows is not None
    candidates = [w for w in (scene.windows if named else level_windows(scene, floor_z))
                  if not named or any(fnmatch.fnmatchcase(w.name, g) for g in spec.windows)]
    by_cell = cells_with_windows(scene, plan, candidates)
    if len(by_cell) > 1 and not named:  # regions without a floor (a void, a well) are not rooms where others have one
        floored = {i: ws for i, ws in by_cell.items() if floor_cover(scene, plan.cells[i], floor_z) >= FLOOR_COVER}
        by_cell = floored or by_cell
    if len(by_cell) == 1:
        i = next(iter(by_cell))
        return plan.cells[i], i, plan
    if len(by_cell) > 1:
        regions = "; ".join(f"{describe(plan.cells[i], scene.origin)}: {', '.join(repr(w.name) for w in ws[:3])}"
                            for i, ws in sorted(by_cell.items()))
        if named:
            raise InputError(f"{where}.windows: the windows named open from {len(by_cell)} different rooms ({regions}); "
                             "name the windows of this room only, or give floor: [[x, y], ...]")
        raise InputError(f"{where}: the walls enclose {len(by_cell)} rooms with windows at floor_z = {spec.floor_z:g} m "
                         f"({regions}); name this room's windows (windows: [...]) or give inside: [x, y] (or rooms: "
                         "[{auto: true, floor_z: ...}] for one room each)")
    if not candidates:
        return None  # no window to pick a region by: the caller's rule (and its "no window" problem)
    gap = leak(scene, plan, candidates[0], floor_z)
    raise InputError(f"{where}: the walls at floor_z = {spec.floor_z:g} m do not close around window "
                     f"'{candidates[0].name}'{gap} (an open plan, or a wall missing from the model); give the room's "
                     "floor: [[x, y], ...], or close the plan in the model")


def leak(scene: Scene, plan: Plan, window: Window, floor_z: float) -> str:
    """Where the region a window opens from runs out of the walls: `` (the walls open near (x, y))``
    from the horizontal faces at ``floor_z`` (the slab) minus the walls, or "" where the model
    gives no floor there."""
    import shapely

    tris = scene.faces_of(scene.layer == INTERIOR)
    flat = np.all(np.abs(tris[..., 2] - floor_z) < 0.02, axis=1)
    if not flat.any():
        return ""
    slab = shapely.union_all(shapely.make_valid(shapely.polygons(tris[flat][..., :2])))
    free = slab.difference(plan.walls.buffer(0.01))
    n = np.asarray(window.normal, float)[:2]
    n = n / max(np.linalg.norm(n), 1e-12)
    probes = shapely.points(window.centroid[None, :2] + np.outer(np.r_[-1.0, 1.0] * 0.5, n))
    for part in shapely.get_parts(free):
        if shapely.contains(part, probes).any():
            edge = part.exterior.difference(plan.walls.buffer(0.02))
            if not edge.is_empty:
                c = edge.centroid
                return f" (the walls open near ({c.x + scene.origin[0]:.1f}, {c.y + scene.origin[1]:.1f}))"
    return ""


def _warn_floorless(scene: Scene, spec: RoomSpec, poly, floor_z: float, where: str) -> None:
    """A warning where a room's region has no floor at its level while the level has floors
    elsewhere (:func:`~en17037cli.scene.levels.floor_cover`): the void over a double-height
    room or a well, picked by a window of the room below or a point in the void."""
    if floor_cover(scene, poly, floor_z) < FLOOR_COVER and floor_faces(scene, floor_z).any():
        scene.warnings.append(f"{where}: room '{spec.name}' has no floor under its region at floor_z = {spec.floor_z:g} m "
                              "(the void over a double-height room, a well?); check floor_z, inside and windows "
                              "(validate --plan DIR draws the region)")


def _room_of_cell(scene: Scene, spec: RoomSpec, where: str, poly, cell: int, plan, floor_z: float, ceiling_z: float,
                  ceiling_source: str, floor_source: str = "the region the walls enclose at eye height") -> Room:
    """A room whose floor is a region of the plan (:mod:`~en17037cli.scene.section`): its windows are
    those that open from that region (a probe from the glazing into the building meets it first)
    with half their height between floor and ceiling; a window named by the spec's globs that
    opens from another region, or from none, is an input error naming both."""
    windows, reasons = [], {}
    for w in scene.windows:
        glob = _globbed(w, spec.windows) if spec.windows is not None else "*"
        if glob is None:
            continue
        i, d, outward = window_cell(plan, w)
        lo, hi = w.sill_z, w.head_z
        roof = abs(float(w.normal[2])) >= WALL_WINDOW_MAX_NZ
        inside = min(hi, ceiling_z) - max(lo, floor_z)
        height_ok = (floor_z <= lo <= ceiling_z + spec.window_margin_m) if roof else inside >= 0.5 * (hi - lo) - HEIGHT_TOL_M
        if i != cell or not height_ok:
            if spec.windows is None:
                continue
            why = (f"its glazing (z {lo + scene.origin[2]:.2f} to {hi + scene.origin[2]:.2f} m) is not between floor and "
                   f"ceiling" if i == cell else "it opens from another room" if i is not None else
                   "it opens from no region the walls enclose within 1.2 m of its glazing")
            raise InputError(f"{where}.windows: '{glob}' picks window '{w.name}', which does not bound room '{spec.name}' "
                             f"({why}); remove it from the list, or give floor: [[x, y], ...]")
        n = np.asarray(w.normal, float)
        windows.append(w.facing(n if (n[2] > 0 if roof else float(np.dot(n[:2], outward)) >= 0) else -n))
        reasons[w.name] = (f"opens from the room's region, its glazing {d:.2f} m from it, z {lo + scene.origin[2]:.2f} to "
                           f"{hi + scene.origin[2]:.2f} m" if not roof else "roof glazing over the room's region")
        off = wall_off(scene, plan, w, d, outward)
        if off:
            scene.warnings.append(f"{where}: window '{w.name}' of room '{spec.name}' {off}")
    if spec.windows is not None and not windows:
        known = ", ".join(f"'{w.name}'" for w in scene.windows)
        raise InputError(f"{where}.windows: no window matches {list(spec.windows)}; windows found: {known}")
    problem = None if windows else "no window opens from the region the walls enclose"
    return Room(name=spec.name, index=spec.index, floor_z=floor_z, floor=poly, windows=windows, spec=spec,
                floor_source=floor_source, ceiling_z=ceiling_z, ceiling_source=ceiling_source, window_reasons=reasons,
                problem=problem)


#: Two rooms whose floors, at one level, share more than this part of the smaller one are one region
#: the tool read for both (a door or passage without a lintel between them) [-].
SHARED_FLOOR_SHARE = 0.5


def check_shared_floors(rooms: list[Room], origin: np.ndarray, where: str) -> None:
    """Stop where the tool gave two rooms the same floor: rooms at one level (within 5 cm) whose
    floors overlap over more than :data:`SHARED_FLOOR_SHARE` of the smaller one, at least one of
    them derived from the model (the region the walls enclose, or its horizontal faces). Two
    rooms declared by name whose walls do not separate them (a door opening up to the ceiling,
    a passage, a wall missing) would otherwise both be assessed over the whole region, silently.
    Given floors and a model's spaces are the user's or the model's own word and may overlap.

    Raises
    ------
    InputError
        naming both rooms, the region (area and a point in it) and the two ways out.
    """
    derived = [r for r in rooms if not r.floor.is_empty and r.floor_source != "given"
               and not r.floor_source.endswith("footprint")]
    for i, a in enumerate(derived):
        for b in derived[i + 1:]:
            if abs(a.floor_z - b.floor_z) > 0.05:
                continue
            small = min(a.floor.area, b.floor.area)
            if small <= 0 or a.floor.intersection(b.floor).area <= SHARED_FLOOR_SHARE * small:
                continue
            given = _given_elsewhere(a, b, describe(a.floor, origin))
            if given:
                raise InputError(f"{where}: {given}")
            raise InputError(
                f"{where}: rooms '{a.name}' and '{b.name}' get the same floor ({describe(a.floor, origin)}, "
                f"z {a.floor_z + origin[2]:g} m): the walls at eye height do not separate them (an opening from "
                "floor to ceiling between them, such as a door or a passage without a lintel, or a wall missing "
                "from the model); give each room its floor: [[x, y], ...] (validate --plan DIR draws the region), "
                "or declare them as one room")


def _given_elsewhere(a: Room, b: Room, region: str) -> str:
    """Why two rooms got one region when a window picked for one of them by its ``windows:`` globs
    is a window of the other (it opens from the region the other room is in): that window named,
    "" when they share no window named so (then the walls do not separate them)."""
    shared = [w.name for w in a.windows if w.name in {v.name for v in b.windows}]
    for name in shared:  # usually one
        by = [r for r in (a, b) if r.spec.windows is not None and _globbed_name(name, r.spec.windows)]
        if len(by) == 1:
            x, y = by[0], (b if by[0] is a else a)
            return (f"room '{x.name}' is given window '{name}' (windows: {list(x.spec.windows)}), which opens from the "
                    f"region of room '{y.name}' ({region}); a window opens from one room: give '{x.name}' the windows "
                    "of its own region, or inside: [x, y], or floor: [[x, y], ...]")
        if len(by) == 2:
            return (f"rooms '{a.name}' and '{b.name}' are both given window '{name}', which opens from one region "
                    f"({region}); a window opens from one room: give each room the windows of its own region, or "
                    "inside: [x, y], or floor: [[x, y], ...]")
    return ""


def _globbed_name(name: str, globs) -> bool:
    return any(fnmatch.fnmatchcase(name, g) for g in globs)
