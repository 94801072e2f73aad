"""A flat modelled the way people model in SketchUp, Rhino or Blender: walls as closed box solids
(bottom faces included) with the openings left between boxes, a lintel box over each window and
door, a sill box under each window, glazing in the openings, floor and roof slabs, a downstand
beam, furniture, a stair, a neighbouring building; one or more storeys.

The L-shaped plan (interior, metres, z up, +y north): the living room 6.0 x 4.0 m (24 m²), the
bedroom 3.9 x 3.0 m (11.7 m²) north of it behind a 0.1 m partition with a 0.9 m door; outer walls
0.3 m thick, storeys 3.0 m apart, rooms 2.7 m high (slabs 0.3 m). Its answers are known by
construction: :data:`ROOMS` gives each room's floor area, ceiling height and windows.
"""
from __future__ import annotations

from dataclasses import dataclass

#: Interior plan of each room: (x0, y0, x1, y1) [m].
ROOMS = {"living": (0.0, 0.0, 6.0, 4.0), "bedroom": (0.0, 4.1, 3.9, 7.1)}
#: The windows of each room: name -> (room, wall side, along-wall from, to [m], sill, head [m]).
WINDOWS = {"glass living south": ("living", "S", 1.0, 3.0, 0.8, 2.2),
           "glass living east": ("living", "E", 1.0, 2.5, 0.9, 2.2),
           "glass bedroom north": ("bedroom", "N", 1.0, 2.5, 0.9, 2.2)}
WALL_M, STOREY_M, ROOM_HEIGHT_M = 0.3, 3.0, 2.7
#: The wardrobe's plan (x0, y0, x1, y1) [m]: against the bedroom's east wall (x = 3.9), 0.9 m², 7.7 % of the bedroom.
WARDROBE = (3.3, 4.6, 3.9, 6.1)


@dataclass
class Flat:
    storeys: int = 1
    furniture: bool = True
    stair: bool = True
    beam: bool = True
    neighbour: bool = True
    glazing_offset_m: float = 0.0  # > 0: the living room's south glazing floats this far outside its wall
    west_wall: bool = True  # False: the west wall left out (an open plan, a wall missing from the model)
    door_head_m: float = 2.1  # ROOM_HEIGHT_M: the door's opening runs up to the ceiling (no lintel)
    #: > 0: a 0.6 x 1.5 m wardrobe this high against the bedroom's east wall (its inside hollow, as
    #: a carcass of boards is drawn); ROOM_HEIGHT_M: a closet whose sides reach the ceiling
    wardrobe_m: float = 0.0


def box(x0, y0, z0, x1, y1, z1) -> list:
    """A closed box solid: six quads, outward normals (counterclockwise seen from outside)."""
    p = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return [[p[i] for i in f] for f in faces]


def _wall(axis: str, fixed0: float, fixed1: float, a0: float, a1: float, z0: float, openings) -> list:
    """A wall from a0 to a1 along ``axis`` ('x' or 'y'), fixed0..fixed1 across it, from z0 to
    z0 + room height, as boxes around its ``openings`` (along from, to, sill, head)."""
    pieces, at = [], a0
    h = z0 + ROOM_HEIGHT_M
    for o0, o1, sill, head in sorted(openings):
        pieces.append((at, o0, z0, h))
        if sill > 0:
            pieces.append((o0, o1, z0, z0 + sill))
        pieces.append((o0, o1, z0 + head, h))  # the lintel
        at = o1
    pieces.append((at, a1, z0, h))
    out = []
    for p0, p1, q0, q1 in pieces:
        if p1 - p0 > 1e-9 and q1 - q0 > 1e-9:
            out += box(p0, fixed0, q0, p1, fixed1, q1) if axis == "x" else box(fixed0, p0, q0, fixed1, p1, q1)
    return out


def _pane(side: str, at: float, a0: float, a1: float, z0: float, z1: float) -> list:
    """A glazing quad in the plane across the wall at ``at`` (y for S/N walls, x for E/W)."""
    if side in "SN":
        return [[(a0, at, z0), (a1, at, z0), (a1, at, z1), (a0, at, z1)]]
    return [[(at, a0, z0), (at, a1, z0), (at, a1, z1), (at, a0, z1)]]


def flat_polygons(f: Flat | None = None) -> dict:
    """Polygons per object name: ``walls``, ``slabs``, ``beam``, ``furniture``, ``stair``, ``door``
    openings are gaps; glazing ``glass <room> <side>[ <storey>]``; ``neighbour``; ``ground``."""
    f = f or Flat()
    t = WALL_M
    out: dict = {"walls": [], "slabs": [], "ground": [[(-60, -60, 0), (60, -60, 0), (60, 60, 0), (-60, 60, 0)]]}
    for k in range(f.storeys):
        z = k * STOREY_M
        suffix = "" if k == 0 else f" {k + 1}"
        win = {s: [] for s in "SNEW"}
        for name, (_, side, a0, a1, sill, head) in WINDOWS.items():
            win[side].append((name, a0, a1, sill, head))
        w = out["walls"]
        w += _wall("x", -t, 0.0, -t, 6.0 + t, z, [(a0, a1, s, h) for _, a0, a1, s, h in win["S"]])  # south
        w += _wall("y", 6.0, 6.0 + t, 0.0, 4.0, z, [(a0, a1, s, h) for _, a0, a1, s, h in win["E"]])  # living east
        w += _wall("x", 4.0, 4.0 + t, 3.9 + t, 6.0 + t, z, [])  # living north, east of the bedroom
        w += _wall("y", 3.9, 3.9 + t, 4.0, 7.1 + t, z, [])  # bedroom east
        w += _wall("x", 7.1, 7.1 + t, -t, 3.9 + t, z, [(a0, a1, s, h) for _, a0, a1, s, h in win["N"]])  # north
        if f.west_wall:
            w += _wall("y", -t, 0.0, -t, 7.1 + t, z, [])  # west
        w += _wall("x", 4.0, 4.1, 0.0, 3.9, z, [(2.5, 3.4, 0.0, f.door_head_m)])  # partition with the door
        out["slabs"] += box(-t, -t, z - 0.3, 6.0 + t, 4.0 + t, z) + box(-t, 4.0, z - 0.3, 3.9 + t, 7.1 + t, z)
        for name, (_, side, a0, a1, sill, head) in WINDOWS.items():
            at = {"S": -t / 2, "N": 7.1 + t / 2, "E": 6.0 + t / 2}[side]
            if name == "glass living south" and f.glazing_offset_m:
                at = -t - f.glazing_offset_m
            out[name + suffix] = _pane(side, at, a0, a1, z + sill, z + head)
        if f.beam:
            out.setdefault("beam", []).extend(box(0.0, 1.9, z + 2.4, 6.0, 2.1, z + ROOM_HEIGHT_M))
        if f.furniture:
            fur = out.setdefault("furniture", [])
            fur += box(4.0, 2.5, z, 5.0, 3.3, z + 0.75)  # a table
            fur += box(5.4, 0.0, z, 6.0, 3.0, z + 0.9)  # a kitchen counter along the east wall
            fur += box(0.0, 5.1, z, 1.6, 7.1, z + 0.5)  # a bed against the west and north walls
        if f.wardrobe_m:
            out.setdefault("wardrobe", []).extend(box(*WARDROBE[:2], z, *WARDROBE[2:], z + f.wardrobe_m))
        if f.stair and k + 1 < f.storeys:
            out.setdefault("stair", []).extend(
                sum((box(0.2, 0.3 + 0.28 * i, z, 1.1, 0.58 + 0.28 * i, z + 0.18 * (i + 1)) for i in range(8)), []))
    top = f.storeys * STOREY_M
    out["slabs"] += box(-t, -t, top - 0.3, 6.0 + t, 4.0 + t, top) + box(-t, 4.0, top - 0.3, 3.9 + t, 7.1 + t, top)
    if f.neighbour:
        out["neighbour"] = box(-10.0, -30.0, 0.0, 20.0, -20.0, 12.0)
    return out


def room_truth(name: str, storey: int = 0) -> tuple[float, float, tuple[str, ...]]:
    """(floor area [m²], ceiling height above the floor [m], window names) of a room by construction."""
    x0, y0, x1, y1 = ROOMS[name]
    suffix = "" if storey == 0 else f" {storey + 1}"
    return (x1 - x0) * (y1 - y0), ROOM_HEIGHT_M, tuple(sorted(w + suffix for w, v in WINDOWS.items() if v[0] == name))
