"""Rooms in a block: a double-loaded slab of rooms, south-facing on one side and north-facing on the
other, storey over storey, every room with one window in its facade.

Frame: z up, +y north. The block spans x in [0, n * width], y in [0, 2 * depth + partition]; the
south facade is the plane y = 0, the north facade y = 2 * depth + partition. Rooms are separated by
partitions ``partition`` thick (two faces); every room has its own floor and ceiling faces, so the
floors of neighbouring rooms do not touch. Walls have no thickness: windows lie in the facade
planes. Outside: flat ground and, optionally, a long building across a street to the south.
Used by the tests (two rooms behind a partition) and the benchmark (a block of 216 rooms).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from en17037cli.samples.box import _rect_x, _rect_y, _rect_z, write_obj


@dataclass
class Block:
    storeys: int = 1
    rooms_per_side: int = 1
    width: float = 4.0  # [m] along x, partition to partition
    depth: float = 5.0  # [m] facade to the middle partition
    height: float = 3.0  # [m] storey height, floor to floor
    partition: float = 0.1  # [m]
    window_x: tuple = (1.0, 3.0)  # [m] within the room's width
    window_z: tuple = (0.8, 2.2)  # [m] above the floor
    north_windows: bool = True  # False: the north rooms have no window
    street: float = 25.0  # [m] to the building across the street to the south (0: none)
    building_height: float = 10.0  # [m]


def room_name(storey: int, side: str, i: int) -> str:
    """'1.S03': storey (1-based), side (S or N), room along x (1-based)."""
    return f"{storey + 1}.{side}{i + 1:02d}"


def block_rooms(b: Block) -> list[dict]:
    """Every room: name, side, floor polygon [[x, y]...] [m], floor_z [m], window name."""
    rooms = []
    y_mid0, y_mid1 = b.depth, b.depth + b.partition
    for s in range(b.storeys):
        z = s * b.height
        for i in range(b.rooms_per_side):
            x0, x1 = i * b.width + b.partition / 2, (i + 1) * b.width - b.partition / 2
            for side, (ya, yb) in (("S", (0.0, y_mid0)), ("N", (y_mid1, y_mid1 + b.depth))):
                if side == "N" and not b.north_windows:
                    window = None
                else:
                    window = f"W {room_name(s, side, i)}"
                rooms.append({"name": room_name(s, side, i), "side": side, "floor_z": z,
                              "floor": [[x0, ya], [x1, ya], [x1, yb], [x0, yb]], "window": window})
    return rooms


def block_polygons(b: Block) -> dict:
    """Polygons per object name: ``walls`` (interior), one glazing object per window, ``ground`` and
    ``building`` (the context)."""
    walls, objects = [], {}
    y_n = 2 * b.depth + b.partition
    length = b.rooms_per_side * b.width
    for s in range(b.storeys):
        z = s * b.height
        for i in range(b.rooms_per_side):
            x0 = i * b.width
            wx0, wx1 = x0 + b.window_x[0], x0 + b.window_x[1]
            wz0, wz1 = z + b.window_z[0], z + b.window_z[1]
            for side, y, has_window in (("S", 0.0, True), ("N", y_n, b.north_windows)):
                # the facade in front of this room, with a hole for its window
                if has_window:
                    walls += [_rect_y(y, x0, wx0, z, z + b.height), _rect_y(y, wx1, x0 + b.width, z, z + b.height),
                              _rect_y(y, wx0, wx1, z, wz0), _rect_y(y, wx0, wx1, wz1, z + b.height)]
                    objects[f"W {room_name(s, side, i)}"] = [_rect_y(y, wx0, wx1, wz0, wz1)]
                else:
                    walls.append(_rect_y(y, x0, x0 + b.width, z, z + b.height))
            for ya, yb in ((0.0, b.depth), (b.depth + b.partition, y_n)):  # floors and ceilings per room
                xa, xb = x0 + b.partition / 2, x0 + b.width - b.partition / 2
                walls += [_rect_z(z, xa, xb, ya, yb), _rect_z(z + b.height - 1e-3, xa, xb, ya, yb)]
            # partitions: across the block between the two rooms, and between neighbours along x
            walls += [_rect_y(b.depth, x0, x0 + b.width, z, z + b.height), _rect_y(b.depth + b.partition, x0, x0 + b.width, z, z + b.height)]
            for xp in (x0 + b.partition / 2, x0 + b.width - b.partition / 2):
                walls.append(_rect_x(xp, 0.0, y_n, z, z + b.height))
        walls += [_rect_x(0.0, 0.0, y_n, z, z + b.height), _rect_x(length, 0.0, y_n, z, z + b.height)]
    walls.append(_rect_z(b.storeys * b.height, 0.0, length, 0.0, y_n))  # the roof
    out = {"walls": walls, **objects}
    g = 400.0
    out["ground"] = [_rect_z(0.0, -g, g, -g, g)]
    if b.street > 0 and b.building_height > 0:
        s, H, L = b.street, b.building_height, max(length, 50.0) + 200.0
        out["building"] = [_rect_y(-s, -L, L, 0, H), _rect_y(-s - 10, -L, L, 0, H), _rect_z(H, -L, L, -s - 10, -s),
                           _rect_x(-L, -s - 10, -s, 0, H), _rect_x(L, -s - 10, -s, 0, H)]
    return out


def block_project(directory: Path, b: Block | None = None, rooms: list[str] | None = None, name_windows: bool = False,
                  **sections) -> Path:
    """Write the model and ``project.yaml`` of a block into ``directory``; return the project path.

    rooms : names of the rooms to check (default: all); each gets its ``floor`` polygon and
        ``floor_z``, and with ``name_windows`` its window by name (``windows: [...]``)
    sections : project sections to set (``view``, ``sunlight``, ``location``, ``requirements``);
        ``view=None`` or ``sunlight=None`` leaves the section out
    """
    import yaml

    b = b or Block()
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    write_obj(directory / "block.obj", block_polygons(b))
    layers = [{"match": "walls", "layer": "interior"}, {"match": "W *", "layer": "window"},
              {"match": "ground", "layer": "ground"}, {"match": "building", "layer": "landscape"}]
    specs = []
    for r in block_rooms(b):
        if rooms is not None and r["name"] not in rooms:
            continue
        spec = {"name": r["name"], "floor_z": r["floor_z"], "floor": r["floor"]}
        if name_windows and r["window"]:
            spec["windows"] = [r["window"]]
        specs.append(spec)
    project = {
        "version": 1, "name": f"Block of {len(specs)} rooms",
        "model": {"files": [{"path": "block.obj", "layers": layers}]},
        "location": sections.get("location") or {"latitude": 52.0, "longitude": 4.36, "timezone": "Europe/Amsterdam"},
        "rooms": specs,
        "requirements": sections.get("requirements") or {"view": "minimum", "sunlight": "minimum"},
    }
    for key in ("view", "sunlight"):
        value = sections.get(key, {})
        if value is not None:
            project[key] = value
    path = directory / "project.yaml"
    path.write_text(yaml.safe_dump(project, sort_keys=False), encoding="utf-8")
    return path
