"""Hand-built models read as a person would (issue 27): flats modelled the usual way in SketchUp,
Rhino or Blender (walls as box solids with their bottom faces, lintels and sills, slabs, a beam,
furniture, a stair, a door in a partition, a neighbour), rooms declared by name and level only.
Every expected value is known by construction (en17037cli/samples/flat.py): the floor areas
24.0 and 11.7 m², the ceiling 2.7 m above the floor, the windows of each room."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from en17037cli.errors import InputError
from en17037cli.project import load_project
from en17037cli.samples.box import write_obj
from en17037cli.samples.flat import STOREY_M, Flat, flat_polygons, room_truth
from en17037cli.scene.build import build_scene

LAYERS = [{"match": "glass*", "layer": "window"}, {"match": "ground", "layer": "ground"},
          {"match": "neighbour", "layer": "landscape"}, {"match": "*", "layer": "interior"}]
UNIT_M = {"m": 1.0, "mm": 0.001, "in": 0.0254}


def project(tmp: Path, flat: Flat, rooms: list, units: str = "m", written_in: str = "m", y_up: bool = False) -> Path:
    """The flat written as one OBJ in ``written_in`` units (y-up if asked) and a project declaring ``units``."""
    objects = flat_polygons(flat)
    scale = 1.0 / UNIT_M[written_in]
    if y_up:  # Blender's y-up export of a z-up model: (x, y, z) -> (x, z, -y)
        objects = {k: [[(x, z, -y) for x, y, z in poly] for poly in v] for k, v in objects.items()}
    tmp.mkdir(parents=True, exist_ok=True)
    write_obj(tmp / "flat.obj", objects, scale=scale)
    doc = {"version": 1, "name": "flat", "model": {"units": units, "up_axis": "y" if y_up else "z",
                                                   "files": [{"path": "flat.obj", "layers": LAYERS}]},
           "location": {"latitude": 52.0, "longitude": 4.36, "timezone": "Europe/Amsterdam"},
           "rooms": rooms, "view": {}, "sunlight": {}, "requirements": {"view": "minimum", "sunlight": "minimum"}}
    (tmp / "project.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return tmp / "project.yaml"


def rooms_of(path: Path) -> dict:
    scene = build_scene(load_project(path))
    return {r.name: r for r in scene.rooms}, scene


def model_project(folder: Path, objects: dict, rooms: list, name: str = "p.yaml") -> Path:
    """``objects`` written as ``m.obj`` in ``folder`` (once) and a project ``name`` with ``rooms``."""
    from en17037cli.samples.box import write_obj

    folder.mkdir(parents=True, exist_ok=True)
    if not (folder / "m.obj").exists():
        write_obj(folder / "m.obj", objects)
    doc = {"version": 1, "name": "model", "model": {"files": [{"path": "m.obj", "layers": LAYERS}]},
           "location": {"latitude": 52.0, "longitude": 4.36, "timezone": "Europe/Amsterdam"},
           "rooms": rooms, "view": {}, "sunlight": {}}
    (folder / name).write_text(yaml.safe_dump(doc))
    return folder / name


def assert_room(room, name: str, storey: int = 0):
    area, height, windows = room_truth(name, storey)
    assert abs(room.floor.area - area) <= 0.01 * area, (room.name, room.floor.area, area)
    assert abs((room.ceiling_z - room.floor_z) - height) <= 0.01, (room.name, room.ceiling_z - room.floor_z)
    assert tuple(sorted(w.name for w in room.windows)) == windows, room.name


NAMED = [{"name": "living", "floor_z": 0, "windows": ["glass living*"]},
         {"name": "bedroom", "floor_z": 0, "windows": ["glass bedroom*"]}]


def test_each_room_gets_its_own_floor_ceiling_and_windows(tmp_path):
    """The L-shaped flat of the issue: before, both rooms got the whole flat's floor (the slab's top
    and every wall's bottom face at floor_z: 44.31 m²) and the door lintel's underside as ceiling (2.1 m)."""
    rooms, _ = rooms_of(project(tmp_path, Flat(), NAMED))
    assert_room(rooms["living"], "living")
    assert_room(rooms["bedroom"], "bedroom")
    living = rooms["living"]
    assert {w.name: tuple(np.round(w.normal, 6)) for w in living.windows} == {
        "glass living south": (0.0, -1.0, 0.0), "glass living east": (1.0, 0.0, 0.0)}


def test_a_point_inside_picks_the_room_and_nothing_picks_none(tmp_path):
    rooms, _ = rooms_of(project(tmp_path / "a", Flat(), [{"name": "bedroom", "floor_z": 0, "inside": [2.0, 6.0]}]))
    assert_room(rooms["bedroom"], "bedroom")
    with pytest.raises(InputError, match=r"the walls enclose 2 rooms with windows at floor_z = 0 m .*inside: \[x, y\]"):
        rooms_of(project(tmp_path / "b", Flat(), [{"name": "room", "floor_z": 0}]))


def test_two_storeys_of_wall_solids_with_auto_rooms(tmp_path):
    rooms, _ = rooms_of(project(tmp_path, Flat(storeys=2), [{"auto": True}]))
    assert len(rooms) == 4
    for storey in (0, 1):
        here = {r.name: r for r in rooms.values() if abs(r.floor_z + 0 - (storey * STOREY_M - 0)) < 10}
        assert here
    by_level: dict = {}
    scene_rooms = list(rooms.values())
    for r in scene_rooms:
        by_level.setdefault(round(float(r.spec.floor_z), 3), []).append(r)
    assert sorted(by_level) == [0.0, STOREY_M]
    for storey, z in enumerate(sorted(by_level)):
        got = sorted(by_level[z], key=lambda r: r.floor.area)
        assert_room(got[0], "bedroom", storey)
        assert_room(got[1], "living", storey)


def test_auto_at_one_level_and_names_that_do_not_move(tmp_path):
    a, _ = rooms_of(project(tmp_path / "a", Flat(storeys=2), [{"auto": True, "floor_z": 3.0}]))
    b, _ = rooms_of(project(tmp_path / "b", Flat(storeys=2), [{"auto": True, "floor_z": 3.0}]))
    assert list(a) == list(b) and len(a) == 2 and all(n.startswith("z 3.00 room at (") for n in a)


def test_a_y_up_export_reads_the_same(tmp_path):
    rooms, _ = rooms_of(project(tmp_path, Flat(furniture=False), NAMED, y_up=True))
    assert_room(rooms["living"], "living")
    assert_room(rooms["bedroom"], "bedroom")


def test_sketchup_inches_read_right_when_declared(tmp_path):
    rooms, _ = rooms_of(project(tmp_path, Flat(), NAMED, units="in", written_in="in"))
    assert_room(rooms["living"], "living")


@pytest.mark.parametrize("written, declared, looks", [("mm", "m", "mm"), ("in", "m", "in"), ("m", "mm", "m")])
def test_a_model_in_another_unit_than_declared_is_an_error_naming_the_unit(tmp_path, written, declared, looks):
    path = project(tmp_path, Flat(), NAMED, units=declared, written_in=written)
    with pytest.raises(InputError, match=rf"model.files\[0\] \(flat.obj\): its windows are .* m tall read in {declared} "
                                         rf"\(model.units\), not a building's size; it looks like {looks} .*set model.units: {looks}"):
        load_project(path) and build_scene(load_project(path))


def test_glazing_off_its_wall_is_a_warning_naming_window_and_room(tmp_path):
    rooms, scene = rooms_of(project(tmp_path, Flat(glazing_offset_m=0.5), NAMED))
    warn = [w for w in scene.warnings if "glass living south" in w]
    assert len(warn) == 1 and "of room 'living' lies 0.50 m outside its wall" in warn[0], scene.warnings
    assert "the wall 0.30 m thick" in warn[0]
    clean = rooms_of(project(tmp_path / "ok", Flat(), NAMED))[1]
    assert not [w for w in clean.warnings if "outside its wall" in w]
    # 3 cm outside (a pane in a frame's rebate, a door's glass beyond its threshold): not a pane off its wall
    rebate = rooms_of(project(tmp_path / "rebate", Flat(glazing_offset_m=0.03), NAMED))[1]
    assert not [w for w in rebate.warnings if "outside its wall" in w], rebate.warnings
    moved = rooms_of(project(tmp_path / "moved", Flat(glazing_offset_m=0.08), NAMED))[1]
    assert [w for w in moved.warnings if "lies 0.08 m outside its wall" in w], moved.warnings


def test_a_glob_picking_another_rooms_window_is_an_error(tmp_path):
    rooms = [{"name": "living", "floor_z": 0, "windows": ["glass living*", "glass bedroom north"]}]
    with pytest.raises(InputError, match=r"rooms\[0\] 'living'\.windows: the windows named open from 2 different rooms"):
        rooms_of(project(tmp_path, Flat(), rooms))


def test_an_open_plan_is_an_error_naming_the_gap(tmp_path):
    with pytest.raises(InputError, match=r"the walls at floor_z = 0 m do not close around window 'glass .*' "
                                         r"\(the walls open near \(-0\.\d, \d\.\d\)\).*give the room's floor"):
        rooms_of(project(tmp_path, Flat(west_wall=False), NAMED))


def test_two_named_rooms_the_walls_do_not_separate_are_an_error_not_one_floor_twice(tmp_path):
    """A door opening up to the ceiling (no lintel) joins the living room and the bedroom at eye
    height: the two rooms declared by name would each get the whole 35.79 m² region (24 + 11.7 +
    the 0.9 x 0.1 m doorway), silently. With auto rooms that region is one room with all three
    windows, as the rule says."""
    with pytest.raises(InputError, match=r"rooms 'living' and 'bedroom' get the same floor \(35\.8 m² around .*"
                                         r"do not separate them.*give each room its floor.*or declare them as one room"):
        rooms_of(project(tmp_path / "named", Flat(door_head_m=2.7), NAMED))
    rooms, _ = rooms_of(project(tmp_path / "auto", Flat(door_head_m=2.7), [{"auto": True, "floor_z": 0}]))
    (room,) = rooms.values()
    assert abs(room.floor.area - (24.0 + 11.7 + 0.09)) <= 0.01 * 35.79
    assert sorted(w.name for w in room.windows) == ["glass bedroom north", "glass living east", "glass living south"]
    with_lintel, _ = rooms_of(project(tmp_path / "lintel", Flat(), NAMED))  # the guard: a lintel keeps two rooms
    assert_room(with_lintel["living"], "living")
    assert_room(with_lintel["bedroom"], "bedroom")


def test_validate_draws_each_storey_as_read(tmp_path):
    """``validate --plan DIR``: one picture per floor level, named by it."""
    import subprocess
    import sys

    pytest.importorskip("matplotlib")
    path = project(tmp_path, Flat(storeys=2), [{"auto": True}])
    proc = subprocess.run([sys.executable, "-m", "en17037cli", "validate", str(path), "--plan", str(tmp_path / "plan")],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    pngs = sorted(p.name for p in (tmp_path / "plan").glob("*.png"))
    assert pngs == ["plan-z0.00.png", "plan-z3.00.png"]
    assert proc.stdout.count("plan as read: ") == 2
    assert all((tmp_path / "plan" / p).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in pngs)


def test_a_gltf_from_blender_reads_the_same(tmp_path):
    """Blender's glTF export: y-up metres by the format, one named node per object."""
    trimesh = pytest.importorskip("trimesh")
    scene = trimesh.Scene()
    for name, polys in flat_polygons(Flat()).items():
        verts, faces = [], []
        for poly in polys:
            k = len(verts)
            verts += [(x, z, -y) for x, y, z in poly]  # z-up -> glTF's y-up
            faces += [(k, k + i, k + i + 1) for i in range(1, len(poly) - 1)]
        scene.add_geometry(trimesh.Trimesh(np.array(verts), np.array(faces), process=False), node_name=name, geom_name=name)
    tmp_path.mkdir(exist_ok=True)
    (tmp_path / "flat.glb").write_bytes(scene.export(file_type="glb"))
    doc = {"version": 1, "name": "flat", "model": {"files": [{"path": "flat.glb", "layers": LAYERS}]},
           "location": {"latitude": 52.0, "longitude": 4.36, "timezone": "Europe/Amsterdam"}, "rooms": NAMED,
           "view": {}, "sunlight": {}}
    (tmp_path / "project.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    rooms, _ = rooms_of(tmp_path / "project.yaml")
    assert_room(rooms["living"], "living")
    assert_room(rooms["bedroom"], "bedroom")


def roof_lit(storeys: int) -> dict:
    """Rooms 5 x 4 m lit only by a 1 x 1 m roof light in the roof over the top storey (its glass at
    the roof's top, 3.0 m above that floor: its middle higher than any wall window's), walls 0.25 m,
    rooms 2.7 m high, storeys 3.0 m apart; the lower storeys get a south window each."""
    from en17037cli.samples.flat import box

    t, H, out = 0.25, 2.7, {"walls": [], "slabs": [], "ground": [[(-60, -60, 0), (60, -60, 0), (60, 60, 0), (-60, 60, 0)]]}
    for k in range(storeys):
        z = 3.0 * k
        top = k == storeys - 1
        out["walls"] += (box(-t, -t, z, 5 + t, 0, z + H) if top else
                         box(-t, -t, z, 1, 0, z + H) + box(3, -t, z, 5 + t, 0, z + H) + box(1, -t, z, 3, 0, z + 0.9)
                         + box(1, -t, z + 2.2, 3, 0, z + H))
        out["walls"] += box(-t, 4, z, 5 + t, 4 + t, z + H) + box(-t, 0, z, 0, 4, z + H) + box(5, 0, z, 5 + t, 4, z + H)
        roof = z + H
        if top:  # the roof with a 1 x 1 m opening, the glass on its top
            out["slabs"] += (box(-t, -t, roof, 2, 4 + t, roof + 0.3) + box(3, -t, roof, 5 + t, 4 + t, roof + 0.3)
                             + box(2, -t, roof, 3, 1.5, roof + 0.3) + box(2, 2.5, roof, 3, 4 + t, roof + 0.3))
            out["glass roof"] = [[(2, 1.5, roof + 0.3), (3, 1.5, roof + 0.3), (3, 2.5, roof + 0.3), (2, 2.5, roof + 0.3)]]
        else:
            out["slabs"] += box(-t, -t, roof, 5 + t, 4 + t, roof + 0.3)
            out[f"glass south {k + 1}"] = [[(1, -0.12, z + 0.9), (3, -0.12, z + 0.9), (3, -0.12, z + 2.2), (1, -0.12, z + 2.2)]]
    out["neighbour"] = box(-10.0, -30.0, 0.0, 20.0, -20.0, 12.0)
    return out


def test_a_room_lit_by_a_roof_light_alone_gets_its_walls_region_and_auto_finds_it(tmp_path):
    """A roof light's middle lies higher above its floor (2.85 to 3.0 m) than any wall window's: it
    was no window of its level, so a room given by name took its floor from the slab (24.75 m²,
    the walls' footprint included) and auto found no room. It lights the level it sees straight
    below; the storey under it (behind a slab) is not lit by it."""
    for storeys in (1, 2):
        d, objects = tmp_path / f"s{storeys}", roof_lit(storeys)
        rooms, _ = rooms_of(model_project(d, objects, [{"name": "top", "floor_z": 3.0 * (storeys - 1)}], "named.yaml"))
        assert abs(rooms["top"].floor.area - 20.0) <= 0.2 and [w.name for w in rooms["top"].windows] == ["glass roof"]
        rooms, scene = rooms_of(model_project(d, objects, [{"auto": True}], "auto.yaml"))
        got = sorted((round(float(r.floor_z + scene.origin[2]), 2), round(r.floor.area, 1), tuple(w.name for w in r.windows))
                     for r in rooms.values())
        want = [(3.0 * k, 20.0, ("glass roof",) if k == storeys - 1 else (f"glass south {k + 1}",)) for k in range(storeys)]
        assert got == want, got


def courtyard_block() -> dict:
    """A 16 x 16 m block of four rooms round a 6 x 6 m courtyard (walls 0.25 m, rooms 2.7 m high,
    a roof over the rooms, nothing over the courtyard); the south room has a window on the street
    and one onto the courtyard, its glass flush with the wall's courtyard face."""
    from en17037cli.samples.flat import box

    t, H = 0.25, 2.7
    walls = (box(-t, -t, 0, 7, 0, H) + box(9, -t, 0, 16 + t, 0, H) + box(7, -t, 0, 9, 0, 0.9) + box(7, -t, 2.2, 9, 0, H)
             + box(-t, 16, 0, 16 + t, 16 + t, H) + box(-t, 0, 0, 0, 16, H) + box(16, 0, 0, 16 + t, 16, H)
             + box(5 - t, 11, 0, 11 + t, 11 + t, H) + box(5 - t, 5 - t, 0, 5, 11 + t, H) + box(11, 5 - t, 0, 11 + t, 11 + t, H)
             + box(5, 5 - t, 0, 7, 5, H) + box(9, 5 - t, 0, 11, 5, H) + box(7, 5 - t, 0, 9, 5, 0.9) + box(7, 5 - t, 2.2, 9, 5, H)
             + box(0, 5 - t, 0, 5 - t, 5, H) + box(11 + t, 5 - t, 0, 16, 5, H) + box(0, 11, 0, 5 - t, 11 + t, H)
             + box(11 + t, 11, 0, 16, 11 + t, H))
    roof = (box(-t, -t, H, 16 + t, 5, H + 0.3) + box(-t, 11, H, 16 + t, 16 + t, H + 0.3) + box(-t, 5, H, 5, 11, H + 0.3)
            + box(11, 5, H, 16 + t, 11, H + 0.3))
    return {"walls": walls, "slabs": box(-t, -t, -0.3, 16 + t, 16 + t, 0) + roof,
            "glass court": [[(7, 5, 0.9), (9, 5, 0.9), (9, 5, 2.2), (7, 5, 2.2)]],
            "glass street": [[(7, -t / 2, 0.9), (9, -t / 2, 0.9), (9, -t / 2, 2.2), (7, -t / 2, 2.2)]],
            "ground": [[(-60, -60, 0), (60, -60, 0), (60, 60, 0), (-60, 60, 0)]],
            "neighbour": box(-10.0, -30.0, 0.0, 30.0, -20.0, 12.0)}


def test_a_window_onto_a_courtyard_is_the_rooms_not_the_courtyards(tmp_path):
    """A courtyard is a region the walls enclose with nothing over it; glazing flush with its
    courtyard face lies nearer the courtyard than the room, and was the courtyard's: auto made the
    courtyard a 36 m² room with that window and the south room lost it."""
    rooms, scene = rooms_of(model_project(tmp_path, courtyard_block(), [{"auto": True}]))
    (room,) = rooms.values()  # the south room: the only one with windows
    assert abs(room.floor.area - 16 * 4.75) <= 0.01 * 76  # x 0..16, y 0..4.75 (the courtyard's wall and partitions)
    assert sorted(w.name for w in room.windows) == ["glass court", "glass street"]
    court = next(w for w in room.windows if w.name == "glass court")
    assert np.allclose(court.normal, [0, 1, 0])  # it faces the courtyard, away from the room


def double_height() -> dict:
    """Two storeys 3 m apart, 10 x 5 m inside (walls 0.25 m): a double-height living room x 0..6
    (5.7 m high, no slab at 3 m) beside rooms x 6.1..10 on both storeys; a south window low and one
    high in each part."""
    from en17037cli.samples.flat import box

    t, top = 0.25, 5.7

    def band(z0, z1, holes):
        out, at = [], -t
        for a, b, s, h in holes:
            out += box(at, -t, z0, a, 0, z1) + box(a, -t, z0, b, 0, s) + box(a, -t, h, b, 0, z1)
            at = b
        return out + box(at, -t, z0, 10 + t, 0, z1)

    walls = (band(0, 3, [(1, 3, 0.9, 2.2), (7, 9, 0.9, 2.2)]) + band(3, top, [(1, 3, 3.9, 5.2), (7, 9, 3.9, 5.2)])
             + box(-t, 5, 0, 10 + t, 5 + t, top) + box(-t, 0, 0, 0, 5, top) + box(10, 0, 0, 10 + t, 5, top) + box(6, 0, 0, 6.1, 5, top))
    out = {"walls": walls, "slabs": box(-t, -t, -0.3, 10 + t, 5 + t, 0) + box(6.1, 0, 2.7, 10, 5, 3.0) + box(-t, -t, top, 10 + t, 5 + t, top + 0.3),
           "ground": [[(-60, -60, 0), (60, -60, 0), (60, 60, 0), (-60, 60, 0)]], "neighbour": box(-10.0, -30.0, 0.0, 20.0, -20.0, 12.0)}
    for name, x0, z0, z1 in (("glass low L", 1, 0.9, 2.2), ("glass high L", 1, 3.9, 5.2), ("glass low R", 7, 0.9, 2.2),
                             ("glass high R", 7, 3.9, 5.2)):
        out[name] = [[(x0, -0.12, z0), (x0 + 2, -0.12, z0), (x0 + 2, -0.12, z1), (x0, -0.12, z1)]]
    return out


def test_the_void_over_a_double_height_room_is_no_room(tmp_path):
    """At the upper storey the walls of a double-height living room enclose its void, with the high
    window: auto made it a 30 m² room with no floor. The living room below has both its windows."""
    rooms, scene = rooms_of(model_project(tmp_path, double_height(), [{"auto": True}]))
    got = sorted((round(float(r.floor_z + scene.origin[2]), 2), round(r.floor.area, 1), sorted(w.name for w in r.windows))
                 for r in rooms.values())
    assert got == [(0.0, 19.5, ["glass low R"]), (0.0, 30.0, ["glass high L", "glass low L"]), (3.0, 19.5, ["glass high R"])], got
    assert any("1 region(s) at z 3.00 m with windows but no floor" in n for n in scene.notes)


def test_a_room_given_by_name_over_the_void_is_warned_and_one_without_windows_skips_the_void(tmp_path):
    rooms, scene = rooms_of(model_project(tmp_path, double_height(), [{"name": "up", "floor_z": 3, "windows": ["glass high L"]},
                                                                      {"name": "right", "floor_z": 3}]))
    assert [w for w in scene.warnings if "room 'up' has no floor under its region at floor_z = 3 m" in w]
    assert not [w for w in scene.warnings if "room 'right'" in w]
    assert abs(rooms["right"].floor.area - 19.5) < 0.2 and [w.name for w in rooms["right"].windows] == ["glass high R"]
