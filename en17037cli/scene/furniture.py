"""Furniture against a wall is not a wall: the floor under a wardrobe belongs to the room.

The plan of a storey is cut at eye height (:mod:`~en17037cli.scene.section`), where a wardrobe,
a tall cabinet or a bookcase against a wall is cut like the wall: its footprint becomes a small
region of its own beside the room (its inside, between its front and the wall), and the room's
floor came out short by it (a 0.6 x 1.5 m wardrobe in an 11.7 m² bedroom: 7.7 %), silently. A wall
reaches the ceiling; furniture does not. So a region of the eye-height cut beside the room that
is no room itself (:attr:`Plan.nooks`, or a region smaller than :data:`~section.MIN_HOLE_M2`),
touches no other room, and lies open to the room just under the ceiling (a cut
:data:`CEILING_GAP_M` below it finds it in the same region as part of the room) is furniture:
its footprint is the room's floor. The inside of a wall solid, a reveal or a doorway stays out
(the wall, the lintel closes it there); a closet whose walls reach the ceiling stays out.
"""
from __future__ import annotations

from en17037cli.scene.model import INTERIOR, WINDOW, Scene
from en17037cli.scene.section import CUT_HEIGHT_M, MIN_HOLE_M2, SNAP_M, Plan, _segments, enclosed, fill_small_holes

#: The cut that tells furniture from walls lies this far below the room's ceiling [m]: a wardrobe
#: reaching within it of the ceiling is taken as a wall (built-in, floor to ceiling).
CEILING_GAP_M = 0.1


def regions_at(scene: Scene, z: float) -> list:
    """The regions the opaque faces and glazing enclose in a horizontal cut at ``z`` [m, local],
    made once per scene and height."""
    import shapely

    memo = scene.__dict__.setdefault("_regions_at", {})
    key = round(float(z), 4)
    if key not in memo:
        segs = _segments(scene, z, (INTERIOR, WINDOW))
        memo[key] = enclosed(shapely.union_all(shapely.linestrings(segs))) if len(segs) else []
    return memo[key]


def furnished_floor(scene: Scene, plan: Plan, i: int, ceiling_z: float) -> tuple[object, float]:
    """The floor of the room whose region is ``plan.cells[i]`` with its ceiling at ``ceiling_z`` [m,
    local]: the region with the footprints of the furniture against its walls (module docstring);
    (polygon, the area added [m²])."""
    import shapely

    cell = plan.cells[i]
    big = [c for j, c in enumerate(plan.cells) if j != i and c.area >= MIN_HOLE_M2]
    small = [c for j, c in enumerate(plan.cells) if j != i and c.area < MIN_HOLE_M2]
    near = [r for r in [*plan.nooks, *small] if r.distance(cell) <= 2 * SNAP_M
            and all(r.distance(c) > 2 * SNAP_M for c in big)]
    if not near or ceiling_z - CEILING_GAP_M <= plan.floor_z + CUT_HEIGHT_M:
        return cell, 0.0
    high = regions_at(scene, ceiling_z - CEILING_GAP_M)
    furniture = []
    for r in near:  # a few regions beside a room
        p = r.representative_point()
        top = next((h for h in high if h.contains(p)), None)
        if top is not None and top.intersection(cell).area > r.area:
            furniture.append(r)
    if not furniture:
        return cell, 0.0
    merged = shapely.union_all([cell, *furniture]).buffer(SNAP_M, join_style="mitre").buffer(-SNAP_M, join_style="mitre")
    merged = fill_small_holes(merged)
    return (merged, merged.area - cell.area) if merged.area > cell.area else (cell, 0.0)
