"""The plan of a storey as the walls draw it: the regions the opaque geometry encloses at a level.

A room given by name and level (no ``floor`` polygon) gets the region its walls enclose, as a
person reads a plan: the model is cut by horizontal planes a little above the floor
at eye height (:data:`CUT_HEIGHT_M`), the cut segments of the opaque faces and of the glazing are
noded and polygonized (shapely), and each bounded face wide enough for a person is a *cell*.
Wall bottoms, stair treads, furniture tops and slab edges are never floor: faces are not floor,
regions are. An opening of a wall at that height is closed where a cut near the floor or above
door heads (:data:`BRIDGE_HEIGHTS_M`) finds the wall going on in its own line across it on both
ends: the wall under a sill (so the room ends at the wall's inner face, not at the glazing), the
lintel over a door; a beam across the room or a counter along a wall, which meet the walls
square, add nothing. Small closed loops inside a cell (table legs, columns, a kitchen island) belong to the room's
floor; larger ones (:data:`MIN_HOLE_M2`: a stair well, a shaft, a courtyard) stay holes.

The cell of a room is the one its windows open from (a probe from each window's centre into
the building, at most its wall's thickness away: :func:`window_cell`), or the one holding a point
the user gives (:func:`~en17037cli.scene.rooms.room_cell`, which picks it). This module is the plan
only: it knows the levels of the horizontal faces below it (:mod:`~en17037cli.scene.levels`) and
nothing of rooms (:mod:`~en17037cli.scene.rooms`) or automatic rooms above it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from en17037cli.geometry import cut_triangles, in_triangle
from en17037cli.scene.levels import derive_ceiling
from en17037cli.scene.model import INTERIOR, WINDOW, Scene, Window

#: Height of the plan cut above the floor [m]: the lower eye height of EN 17037, where the view is
#: judged, above tables, counters, beds and sofas (a cut near the floor takes the footprint of
#: every counter and bed along a wall off the room: a 0.6 m counter on a 3 m wall is 7.5 % of
#: a 24 m² room).
CUT_HEIGHT_M = 1.2
#: Heights of the cuts whose wall pieces close the openings of the plan's walls where they continue
#: a wall in its own line on both ends [m]: near the floor, the wall under a sill (the room ends at
#: the wall's inner face, not at the glazing); above door heads (2.0 - 2.1 m), the lintel over a door.
BRIDGE_HEIGHTS_M = (0.1, 2.25)
#: Segments closer than this are the same line; ends closer than this meet [m].
SNAP_M = 1e-3
#: Glazing outside its wall by less than this is a frame's rebate or threshold, not a pane moved
#: off its wall (ArchiCAD's FZK-Haus: a terrace door's glass 2 cm outside a 1 cm threshold) [m].
OFF_WALL_MIN_M = 0.05
#: The plan's coordinates are rounded to this grid before noding (robust intersections) [m]: a
#: micron, far below any drawing's precision, so a derived floor stays where the walls are.
PRECISION_M = 1e-6
#: Gaps between wall pieces narrower than this close (a drawing's tolerance: a pane a few mm
#: short of its jambs, ends that do not meet) [m].
GAP_M = 0.02
#: Closed loops inside a cell smaller than this are furniture, columns or fittings on the room's
#: floor; larger ones are holes of it (a stair well, a shaft) [m²].
MIN_HOLE_M2 = 4.0
#: A cell narrower than twice this (its largest inscribed circle) is the footprint of a wall, a
#: jamb or a post cut by the plan, not a room [m].
MIN_ROOM_HALF_WIDTH_M = 0.35
#: A window's probe goes at most this far into the building past the glazing [m] (the thickest
#: wall with its reveal, as ``window_margin_m``'s default).
PROBE_DEPTH_M = 1.2


@dataclass
class Plan:
    """The plan at one floor level [m, local frame]: the cut ``walls`` (shapely MultiLineString) and
    the bounded ``cells`` (shapely Polygons, holes smaller than :data:`MIN_HOLE_M2` filled)."""

    floor_z: float
    walls: object
    cells: list
    covered: object = None  # cell index -> bool (:func:`_covered`), where the plan came from a scene
    #: the bounded regions too narrow or small for a room: the inside of a wall solid, a reveal, a
    #: doorway under its lintel, the inside of a wardrobe (:mod:`~en17037cli.scene.furniture`)
    nooks: list = field(default_factory=list)


def _segments(scene: Scene, z: float, layers=(INTERIOR, WINDOW)) -> np.ndarray:
    """(k, 2, 2) [m]: the segments a horizontal plane at ``z`` cuts from the faces of ``layers``."""
    tris = scene.faces_of(np.isin(scene.layer, layers))
    if len(tris) == 0:
        return np.zeros((0, 2, 2))
    near = (tris[..., 2].min(axis=1) <= z) & (tris[..., 2].max(axis=1) > z)
    ok, a, b = cut_triangles(tris[near], np.array([z]))
    seg = np.stack([a[0][ok[0]], b[0][ok[0]]], axis=1)
    return seg[np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1) > SNAP_M]


def _bridges(lower, segs: np.ndarray, upper: np.ndarray, guard=None):
    """The pieces of another cut's segments (``upper``) that close a gap of the plan's walls
    (``lower``, the union of ``segs``) in their own line: each end of the piece meets a wall
    segment parallel to it (a lintel over a door, the wall under a sill), not one square to it (a
    beam, a counter's side).

    ``guard``: ``lower`` buffered by :data:`SNAP_M`, prepared (:func:`_guard`; made here if not
    given). Only the segments that cross its outline are cut against it (an overlay with the whole
    storey's walls each: the cost of a curtain-walled storey); those inside it have no gap, those
    clear of it are all gap, as the overlay gives them.
    """
    import shapely

    if len(upper) == 0 or lower.is_empty:
        return []
    guard = _guard(lower) if guard is None else guard
    lines = shapely.linestrings(upper)
    inside, touch = shapely.within(lines, guard), shapely.intersects(lines, guard)
    cross = touch & ~inside
    lines[cross] = shapely.difference(lines[cross], guard)
    gaps = shapely.line_merge(shapely.union_all(lines[~inside]))
    pieces = [g for g in shapely.get_parts(gaps) if g.geom_type == "LineString" and g.length > 10 * SNAP_M]
    if not pieces:
        return []
    a, v = segs[:, 0], segs[:, 1] - segs[:, 0]
    vlen = np.linalg.norm(v, axis=1)
    out = []
    for piece in pieces:  # few pieces per storey: the gaps of its walls
        c = np.asarray(piece.coords)[[0, -1]]
        d = (c[1] - c[0]) / max(piece.length, 1e-12)
        parallel = np.abs(d[0] * v[:, 1] - d[1] * v[:, 0]) < 0.02 * vlen
        ok = True
        for end in c:  # the distance from the end to each segment, vectorised
            t = np.clip(np.einsum("kj,kj->k", end - a, v) / np.maximum(vlen ** 2, 1e-24), 0.0, 1.0)
            dist = np.linalg.norm(a + t[:, None] * v - end, axis=1)
            on_line = np.abs((end - a)[:, 0] * v[:, 1] - (end - a)[:, 1] * v[:, 0]) < 2 * SNAP_M * vlen
            ok &= bool(np.any(parallel & on_line & (dist < 2 * SNAP_M)))
        if ok:  # the piece stops SNAP_M short of the walls (the buffer): lengthened to cross them
            out.append(shapely.LineString([c[0] - 3 * SNAP_M * d, c[1] + 3 * SNAP_M * d]))
    return out


def _guard(lower):
    """``lower`` buffered by :data:`SNAP_M`, prepared for the predicates of :func:`_bridges`."""
    import shapely

    guard = lower.buffer(SNAP_M)
    shapely.prepare(guard)
    return guard


def plan_at(scene: Scene, floor_z: float) -> Plan:
    """The :class:`Plan` of ``scene`` at ``floor_z`` [m, local]."""
    import shapely

    segs = _segments(scene, floor_z + CUT_HEIGHT_M)
    if len(segs) == 0:
        return Plan(floor_z, shapely.MultiLineString(), [])
    lower = shapely.union_all(shapely.linestrings(segs))
    guard = _guard(lower)  # once for both cuts
    walls = shapely.union_all([lower, *(b for h in BRIDGE_HEIGHTS_M
                                        for b in _bridges(lower, segs, _segments(scene, floor_z + h), guard))])
    cells = enclosed(walls)
    wide = [not c.is_empty and c.area > 1e-4 and shapely.length(shapely.maximum_inscribed_circle(c, SNAP_M)) >= MIN_ROOM_HALF_WIDTH_M
            for c in cells]
    rooms = [c for c, ok in zip(cells, wide) if ok]
    memo: dict[int, bool] = {}

    def covered(i: int) -> bool:
        if i not in memo:
            memo[i] = _covered(scene, rooms[i], floor_z)
        return memo[i]

    return Plan(floor_z, walls, rooms, covered, [c for c, ok in zip(cells, wide) if not ok and not c.is_empty])


def enclosed(walls) -> list:
    """The regions the cut lines ``walls`` (shapely, local xy [m]) bound, holes smaller than
    :data:`MIN_HOLE_M2` filled: the walls thickened by half a gap each side (gaps of a drawing's
    tolerance close, lines need not be noded), each free region off the outside grown back by as much."""
    import shapely

    if walls.is_empty:
        return []
    thick = shapely.set_precision(walls, PRECISION_M).buffer(GAP_M / 2, cap_style="square", join_style="mitre")
    x0, y0, x1, y1 = thick.bounds
    outside = shapely.box(x0 - 1.0, y0 - 1.0, x1 + 1.0, y1 + 1.0)
    free = [p for p in shapely.get_parts(outside.difference(thick)) if not p.intersects(outside.exterior)]
    return [fill_small_holes(p.buffer(GAP_M / 2, join_style="mitre")) for p in free]


def _covered(scene: Scene, cell, floor_z: float) -> bool:
    """Whether a region has a roof: horizontal interior faces at least a room's height above its
    floor cover half of it (:func:`~en17037cli.scene.levels.derive_ceiling` finds one). A courtyard
    or a roofless light well is a region the walls enclose with nothing over it."""
    return not derive_ceiling(scene, cell, floor_z)[1].startswith("no ceiling")


def fill_small_holes(cell):
    """``cell`` with its holes smaller than :data:`MIN_HOLE_M2` filled (furniture, columns)."""
    import shapely

    parts = [p for p in shapely.get_parts(cell) if p.geom_type == "Polygon"]
    if not parts:
        return shapely.Polygon()
    p = max(parts, key=lambda q: q.area)  # a cell split by a face touching its outline: its main part
    holes = [h for h in p.interiors if shapely.Polygon(h).area >= MIN_HOLE_M2]
    return shapely.Polygon(p.exterior, holes)


def window_cell(plan: Plan, window: Window, depth_m: float = PROBE_DEPTH_M) -> tuple[int | None, float, np.ndarray]:
    """The cell a wall window opens from: probes from its centre along its horizontal normal, on
    each side, find the first cell within ``depth_m`` [m]; the side with a cell is the room's
    (outside is no cell). Returns (cell index or None, distance from the glazing to the cell [m],
    the window's outward horizontal normal). Roof glazing: the cell under its centre."""
    import shapely

    n = np.asarray(window.normal, float)
    c = window.centroid[:2]
    if abs(n[2]) >= 0.5:  # roof light: the cell below it
        hit = [i for i, cell in enumerate(plan.cells) if cell.contains(shapely.points(c))]
        return (hit[0] if hit else None), 0.0, np.array([0.0, 0.0])
    h = n[:2] / max(np.linalg.norm(n[:2]), 1e-12)
    steps = np.arange(0.005, depth_m + 1e-9, 0.005)
    cells = np.array(plan.cells, dtype=object)
    shapely.prepare(cells)
    first: dict[float, tuple[int | None, float, float]] = {}
    for side in (1.0, -1.0):
        pts = shapely.points(c[None, :] + side * steps[:, None] * h[None, :])
        hit: tuple[int | None, float, float] = (None, np.inf, np.inf)
        for i, cell in enumerate(cells):
            inside = shapely.contains(cell, pts)
            if inside.any() and steps[np.argmax(inside)] < hit[1]:
                k = int(np.argmax(inside))
                out = np.flatnonzero(~inside[k:])
                hit = (i, float(steps[k]), float(steps[k + out[0]]) if len(out) else np.inf)  # (cell, in at, out at)
        first[side] = hit
    (ip, dp, op), (im, dm, om) = first[1.0], first[-1.0]
    if ip is not None and ip == im and max(dp, dm) <= 0.011:  # the glazing inside its cell (an inner pane):
        side = 1.0 if op < om else -1.0  # the outside is where the cell ends first
        return ip, 0.0, side * h
    if ip is None and im is None:
        return None, np.inf, h
    side = 1.0 if dp <= dm else -1.0
    if ip is not None and im is not None and ip != im and plan.covered is not None:  # a region each side
        roofed = {s_: plan.covered(first[s_][0]) for s_ in (1.0, -1.0)}
        if roofed[1.0] != roofed[-1.0]:  # a room and a courtyard (nothing over it): the room's window
            side = 1.0 if roofed[1.0] else -1.0
    i = first[side][0]
    d = float(plan.cells[i].distance(shapely.Point(c)))  # exact, not the probe's 5 mm step
    return i, d, -side * h  # the room lies towards side * h: outward is the other way


#: A window is a candidate of a level's rooms when the middle of its glazing lies this high above
#: the floor or lower (and above it): a storey's windows, not those of the storey above [m].
WINDOW_MID_MAX_M = 2.6


def plan_of(scene: Scene, floor_z: float) -> Plan:
    """:func:`plan_at`, made once per scene and level."""
    plans = scene.__dict__.setdefault("_plans", {})
    key = round(float(floor_z), 4)
    if key not in plans:
        plans[key] = plan_at(scene, floor_z)
    return plans[key]


def level_windows(scene: Scene, floor_z: float) -> list[Window]:
    """The windows of a level [m, local]: those whose glazing's middle lies between ``floor_z`` and
    :data:`WINDOW_MID_MAX_M` above it, and roof lights higher up that see the level
    (:func:`roof_lights_over`: a roof light in a 2.7 m ceiling has its middle near 2.9 m)."""
    low = [w for w in scene.windows if floor_z < 0.5 * (w.sill_z + w.head_z) <= floor_z + WINDOW_MID_MAX_M]
    return low + roof_lights_over(scene, floor_z)


#: A roof light lights a level when the first opaque face straight below its glazing's middle lies
#: this far below the level's floor at most (finishes, a sunken floor) [m] ...
ROOF_LIGHT_BELOW_M = 0.05


def roof_lights_over(scene: Scene, floor_z: float) -> list[Window]:
    """Roof lights (glazing facing up more than sideways) whose glazing lies above the level's eye
    height, its middle higher than :data:`WINDOW_MID_MAX_M` above the floor, and sees the level: the first opaque face straight below the glazing's middle lies between
    :data:`ROOF_LIGHT_BELOW_M` under ``floor_z`` and the eye height (:data:`CUT_HEIGHT_M`) above it
    (the floor, or a table on it), not a slab between (the storey above's floor) [m, local]. A
    light well or an atrium's void lets it see a lower level, which it then lights."""
    out = []
    roofs = [w for w in scene.windows if abs(float(w.normal[2])) >= 0.5 and w.sill_z > floor_z + CUT_HEIGHT_M
             and 0.5 * (w.sill_z + w.head_z) > floor_z + WINDOW_MID_MAX_M]
    if not roofs:
        return out
    opaque = scene.triangles[scene.layer != WINDOW]
    tri = scene.vertices[opaque]  # (f, 3, 3)
    lo, hi = tri[..., :2].min(axis=1), tri[..., :2].max(axis=1)
    for w in roofs:  # one pass per roof light, vectorised over the faces under it
        c = w.centroid[:2]
        near = np.flatnonzero(np.all((lo <= c) & (hi >= c), axis=1))
        z = _z_under(tri[near], c)
        z = z[z < w.sill_z - SNAP_M]
        if len(z) and floor_z - ROOF_LIGHT_BELOW_M <= z.max() <= floor_z + CUT_HEIGHT_M:
            out.append(w)
    return out


def _z_under(tri: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Heights [m] at plan point ``c`` of the triangles (k, 3, 3) whose plan holds it
    (:func:`~en17037cli.geometry.in_triangle`, edges included), from each triangle's plane;
    vertical triangles (no plan area) are left out."""
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    ok = (np.abs(n[:, 2]) > 1e-12) & in_triangle(np.broadcast_to(c, (len(tri), 2)), tri[..., :2])
    a, n = tri[ok, 0], n[ok]
    return a[:, 2] - (n[:, 0] * (c[0] - a[:, 0]) + n[:, 1] * (c[1] - a[:, 1])) / n[:, 2]


def cells_with_windows(scene: Scene, plan: Plan, windows: list[Window]) -> dict[int, list[Window]]:
    """Cell index -> the windows (of ``windows``) that open from it (:func:`window_cell`)."""
    out: dict[int, list[Window]] = {}
    for w in windows:
        i, _, _ = window_cell(plan, w)
        if i is not None:
            out.setdefault(i, []).append(w)
    return out


def describe(cell, origin) -> str:
    """``24.0 m² around (3.0, 2.0)`` in the model's coordinates [m]."""
    c = cell.representative_point()
    return f"{cell.area:.1f} m² around ({c.x + origin[0]:.1f}, {c.y + origin[1]:.1f})"


def wall_off(scene: Scene, plan: Plan, window: Window, d: float, outward: np.ndarray) -> str:
    """Why a wall window's glazing does not sit in its wall's opening, or "": going from the glazing
    into the room (``d`` [m] to the room's region, against ``outward``), the wall under the sill
    or over the head (the cuts of :data:`BRIDGE_HEIGHTS_M`) is crossed before the region: the
    glazing lies outside the wall's outer face."""
    import shapely

    if d <= 2 * SNAP_M or not np.any(outward):
        return ""
    c = window.centroid[:2]
    ray = shapely.LineString([c, c - d * np.asarray(outward, float)])
    segs = np.concatenate([_segments(scene, plan.floor_z + h) for h in BRIDGE_HEIGHTS_M])
    if len(segs) == 0:
        return ""
    hits = shapely.intersection(shapely.linestrings(segs), ray)
    pts = [np.asarray(p.coords)[0] for h in hits if not h.is_empty for p in shapely.get_parts(h) if p.geom_type == "Point"]
    e = [float(np.linalg.norm(p - c)) for p in pts]
    e = [x for x in e if 10 * SNAP_M < x < d - 10 * SNAP_M]
    if not e or min(e) < OFF_WALL_MIN_M:
        return ""
    off = min(e)
    return (f"lies {off:.2f} m outside its wall (its glazing {d:.2f} m from the room, the wall {d - off:.2f} m thick): "
            "glazing belongs in the wall's opening; check the model (a pane moved off its wall) or its layer rules")
