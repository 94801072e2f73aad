"""Synthetic scenes whose answers are known by hand: a box room, one window, ground, one building.

Frame: z up, +y north. The room spans x in [-w/2, w/2], y in [t, t + depth], z in [0, height];
the facade's outer face is the plane y = 0 with the glazing in it, facing south (-y); the wall is
t thick (reveals of depth t). Outside: ground z = 0 for y < 0 and a long building whose face
parallel to the facade is at y = -street (the street width), ``building_height`` tall.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass
class BoxRoom:
    width: float = 4.0
    depth: float = 6.0
    height: float = 3.0
    wall_thickness: float = 0.0
    window_x: tuple = (-1.0, 1.0)
    window_z: tuple = (0.8, 2.2)
    street: float = 25.0
    building_height: float = 10.0  # 0: no building
    building_length: float = 400.0
    ground_size: float = 400.0
    shutter: bool = False
    window_split: int = 1  # split the glazing into this many columns of triangles
    triangle_window: bool = False  # glaze only the lower-left half of the opening; an opaque panel fills the rest
    mullions: tuple = ()  # x of the centre of each mullion: an opaque plate MULLION_GAP inside the glazing
    mullion_width: float = 0.05
    second_pane: float = 0.0  # > 0: a second glazing pane this far inside the first (double glazing)
    uncut_wall: bool = False  # the facade wall runs on behind the glazing, with no opening cut
    gap: float = 0.0  # > 0: two panes with an opaque strip this wide between them, at x = 0
    round_window: int = 0  # > 0: a round pane of this many segments in the opening, in a 5 cm frame ring 2 cm inside


#: Mullion plates stand this far inside the glazing plane (room side) [m].
MULLION_GAP = 0.02


def _quad(a, b, c, d):
    return [a, b, c, d]


def _rect_y(y, x0, x1, z0, z1):
    return _quad((x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1))


def _rect_x(x, y0, y1, z0, z1):
    return _quad((x, y0, z0), (x, y1, z0), (x, y1, z1), (x, y0, z1))


def _rect_z(z, x0, x1, y0, y1):
    return _quad((x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z))


def _wall_with_hole(y, b: BoxRoom):
    hw = b.width / 2
    (wx0, wx1), (wz0, wz1) = b.window_x, b.window_z
    return [_rect_y(y, -hw, wx0, 0, b.height), _rect_y(y, wx1, hw, 0, b.height),
            _rect_y(y, wx0, wx1, 0, wz0), _rect_y(y, wx0, wx1, wz1, b.height)]


def _round_window(b: BoxRoom):
    """A round pane inscribed in the opening (triangles fanned from its centre) and a frame ring:
    quads between radii r and r + 5 cm, MULLION_GAP inside the glazing plane, like a tessellated
    round frame exported from BIM."""
    (wx0, wx1), (wz0, wz1) = b.window_x, b.window_z
    cx, cz, r = (wx0 + wx1) / 2, (wz0 + wz1) / 2, min(wx1 - wx0, wz1 - wz0) / 2
    t = np.linspace(0.0, 2 * np.pi, b.round_window + 1)
    ring = lambda rad, y: [(cx + rad * np.cos(a), y, cz + rad * np.sin(a)) for a in t]  # noqa: E731
    rim, inner, outer = ring(r, 0.0), ring(r, MULLION_GAP), ring(r + 0.05, MULLION_GAP)
    glazing = [[(cx, 0.0, cz), rim[i], rim[i + 1]] for i in range(b.round_window)]
    frame = [[inner[i], inner[i + 1], outer[i + 1], outer[i]] for i in range(b.round_window)]
    return glazing, frame


def box_room_polygons(b: BoxRoom) -> dict:
    """Polygons per object name: ``room``, ``glazing``, ``ground``, ``building`` (and ``shutter``)."""
    hw, t = b.width / 2, b.wall_thickness
    (wx0, wx1), (wz0, wz1) = b.window_x, b.window_z
    room = _wall_with_hole(0.0, b)
    if t > 0:
        room += _wall_with_hole(t, b)
        room += [_rect_x(wx0, 0, t, wz0, wz1), _rect_x(wx1, 0, t, wz0, wz1),
                 _rect_z(wz0, wx0, wx1, 0, t), _rect_z(wz1, wx0, wx1, 0, t)]
    y1 = t + b.depth
    room += [_rect_z(0.0, -hw, hw, t, y1), _rect_z(b.height, -hw, hw, t, y1),
             _rect_x(-hw, t, y1, 0, b.height), _rect_x(hw, t, y1, 0, b.height), _rect_y(y1, -hw, hw, 0, b.height)]
    xs = np.linspace(wx0, wx1, b.window_split + 1)
    glazing = [_rect_y(0.0, xs[i], xs[i + 1], wz0, wz1) for i in range(b.window_split)]
    if b.triangle_window:
        glazing = [[(wx0, 0.0, wz0), (wx1, 0.0, wz0), (wx0, 0.0, wz1)]]
        room.append([(wx1, 0.0, wz0), (wx1, 0.0, wz1), (wx0, 0.0, wz1)])
    if b.gap > 0:
        g2 = b.gap / 2
        glazing = [_rect_y(0.0, wx0, -g2, wz0, wz1), _rect_y(0.0, g2, wx1, wz0, wz1)]
        room.append(_rect_y(0.0, -g2, g2, wz0, wz1))
    if b.round_window:
        glazing, ring = _round_window(b)
        room += ring
    if b.second_pane > 0:
        glazing.append(_rect_y(b.second_pane, wx0, wx1, wz0, wz1))
    for xm in b.mullions:
        room.append(_rect_y(MULLION_GAP, xm - b.mullion_width / 2, xm + b.mullion_width / 2, wz0 - 0.1, wz1 + 0.1))
    if b.uncut_wall:
        room.append(_rect_y(0.0, wx0, wx1, wz0, wz1))
    g = b.ground_size / 2
    ground = [_rect_z(0.0, -g, g, -g, 0.0)]
    L, s, H = b.building_length / 2, b.street, b.building_height
    building = [_rect_y(-s, -L, L, 0, H), _rect_y(-s - 10, -L, L, 0, H), _rect_z(H, -L, L, -s - 10, -s),
                _rect_x(-L, -s - 10, -s, 0, H), _rect_x(L, -s - 10, -s, 0, H)]
    out = {"room": room, "glazing": glazing, "ground": ground}
    if H > 0:
        out["building"] = building
    if b.shutter:
        out["shutter"] = [_rect_y(0.05, wx0 - 0.05, wx1 + 0.05, wz0 - 0.05, wz1 + 0.05)]
    return out


def write_obj(path: Path, objects: dict, offset=(0.0, 0.0, 0.0), rotate_deg: float = 0.0, scale: float = 1.0,
              shuffle_seed: int | None = None) -> None:
    """Write polygons per object name as an OBJ file (quads as n-gon faces).

    Each vertex v is written as scale * (R v + offset), R a rotation by ``rotate_deg``
    counter-clockwise about +z; ``shuffle_seed`` writes the faces in a random order (an object
    name may then open several runs of faces).
    """
    lines = ["# generated by en17037cli.samples"]
    n = 0
    off = np.asarray(offset, dtype=float)
    c, s_ = np.cos(np.radians(rotate_deg)), np.sin(np.radians(rotate_deg))
    rot = np.array([[c, -s_, 0.0], [s_, c, 0.0], [0.0, 0.0, 1.0]])
    items = [(name, poly) for name, polys in objects.items() for poly in polys]
    if shuffle_seed is not None:
        order = np.random.default_rng(shuffle_seed).permutation(len(items))
        items = [items[i] for i in order]
    current = None
    for name, poly in items:
        if name != current:
            lines.append(f"o {name}")
            current = name
        for v in poly:
            x, y, z = scale * (rot @ np.asarray(v, dtype=float) + off)
            lines.append(f"v {x:.9f} {y:.9f} {z:.9f}")
        lines.append("f " + " ".join(str(n + i + 1) for i in range(len(poly))))
        n += len(poly)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


#: Model units for the ``scale`` of :func:`box_room_project`.
SCALE_UNITS = {1.0: "m", 100.0: "cm", 1000.0: "mm"}


#: The default of a project section: present, with every key at its default ({}).
DEFAULTS: dict = {}


def box_room_project(directory: Path, b: BoxRoom | None = None, offset=(0.0, 0.0, 0.0), name="Synthetic street",
                     sunlight: dict | None = DEFAULTS, view: dict | None = DEFAULTS, location: dict | None = None,
                     rotate_deg: float = 0.0, scale: float = 1.0, split_files: bool = False,
                     shuffle_seed: int | None = None, true_north_deg: float | None = None, description: str | None = None) -> Path:
    """Write the model and ``project.yaml`` of a box-room scene into ``directory``; return the project path.

    ``rotate_deg`` turns the model counter-clockwise about +z (true north is turned with it),
    ``scale`` writes it in cm (100) or mm (1000), ``split_files`` writes one OBJ per object and
    ``shuffle_seed`` shuffles the face order: the answers must not change. ``true_north_deg``
    overrides the true north that follows the rotation. ``view`` / ``sunlight``: the project's
    sections; None leaves the section out. ``description``: the project's description (its reports print it).
    """
    import yaml

    b = b or BoxRoom()
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    objects = box_room_polygons(b)
    kw = dict(offset=offset, rotate_deg=rotate_deg, scale=scale, shuffle_seed=shuffle_seed)
    layers = [{"match": "room", "layer": "interior"}, {"match": "shutter", "layer": "interior"},
              {"match": "glazing", "layer": "window"}, {"match": "ground", "layer": "ground"},
              {"match": "building", "layer": "landscape"}]
    layers = [r for r in layers if r["match"] in objects]  # a rule that matches nothing is a warning
    units = SCALE_UNITS[float(scale)]
    if split_files:
        files = []
        for obj, polys in objects.items():
            write_obj(directory / f"{obj}.obj", {obj: polys}, **kw)
            files.append({"path": f"{obj}.obj", "layers": [r for r in layers if r["match"] == obj]})
    else:
        write_obj(directory / "model.obj", objects, **kw)
        files = [{"path": "model.obj", "layers": layers}]
    project = {
        "version": 1,
        "name": name,
        **({"description": description} if description else {}),
        "model": {"units": units, "up_axis": "z", "true_north_deg": float((-rotate_deg) % 360.0 if true_north_deg is None else true_north_deg), "files": files},
        "location": location or {"latitude": 52.0, "longitude": 4.36, "timezone": "Europe/Amsterdam"},
        "rooms": [{"name": "box room", "floor_z": float(offset[2])}],
        "view": {} if view is DEFAULTS else view,
        "sunlight": {} if sunlight is DEFAULTS else sunlight,
        "requirements": {"view": "medium", "sunlight": "minimum"},
    }
    for key in ("view", "sunlight"):  # None leaves the section out (the check does not run)
        if project[key] is None:
            del project[key]
    path = directory / "project.yaml"
    path.write_text(yaml.safe_dump(project, sort_keys=False), encoding="utf-8")
    return path
