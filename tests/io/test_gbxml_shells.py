"""gbXML spaces whose ShellGeometry is not the room's closed volume (issue 35): Revit 2009's
AnalyticalShell beside the ClosedShell, and Revit 2025's shells with walls and ceilings drawn
short. Each room's floor is its Space's Area and each window is in its room; the files are
written by the tests (tests/io/gbxml_files.py) from a description of those exports."""
from __future__ import annotations

import shapely
import yaml
from click.testing import CliRunner
from gbxml_files import FT, HOUSE_FT, L_Z, l_floor_area, old_revit_house, open_shell_room, write

from en17037cli.cli import cli
from en17037cli.io.gbxml import read_gbxml
from en17037cli.project import load_project
from en17037cli.scene.build import build_scene

#: Areas are compared within 0.1 %: the floor is the shell's own polygon, exact but for the
#: exporter's digits (and the feet-to-metres product).
REL = 1e-3


def project(folder, text: str) -> str:
    write(folder, text)
    doc = {"version": 1, "name": "gbxml", "model": {"files": [{"path": "model.xml"}]},
           "location": {"timezone": "UTC"}, "rooms": [{"gbxml_spaces": "*"}], "view": {}, "sunlight": {}}
    (folder / "p.yaml").write_text(yaml.safe_dump(doc))
    return str(folder / "p.yaml")


def test_an_analytical_shell_beside_the_closed_shell_is_not_the_rooms_volume(tmp_path):
    """Revit 2009's gbXML of a house (feet, no version attribute, no BuildingStorey): each Space's
    ShellGeometry holds the room's ClosedShell and an AnalyticalShell on the walls' centre lines up
    to the next level. Read together they made the upstairs rooms' floors the ceiling of the
    ClosedShell (z + 9 ft) and the windows lie in no room (3 of 9 windowed spaces assessed)."""
    mesh = read_gbxml(write(tmp_path, old_revit_house()))
    by_name = {s.name: s for s in mesh.spaces}
    for name, (storey, x0, y0, x1, y1, _) in HOUSE_FT.items():
        s = by_name[name]
        assert abs(shapely.Polygon(s.footprint).area - (x1 - x0) * (y1 - y0) * FT ** 2) <= REL * (x1 - x0) * (y1 - y0) * FT ** 2
        assert abs(s.floor_z - storey * 10.0 * FT) < 1e-9 and abs(s.top_z - (storey * 10.0 + 9.0) * FT) < 1e-9
    scene = build_scene(load_project(project(tmp_path, old_revit_house())))
    rooms = {r.name: r for r in scene.rooms}
    assert sorted(rooms) == sorted(HOUSE_FT)
    for name, r in rooms.items():
        assert [w.name for w in r.windows] == [f"window {name}"], (name, r.window_reasons)
    assert not [w for w in scene.warnings if "differs from the Area" in w], scene.warnings


def test_a_shell_with_walls_and_ceiling_drawn_short_keeps_its_whole_floor(tmp_path):
    """Revit 2025 (Terlago, an Italian block of flats) writes ShellGeometry that is not closed: the
    floor and part of the ceiling, walls on their outer faces stopping short. The floor was the floor
    faces with the room's inside above them by ray parity: on an open shell, half of them (Soggiorno
    7.0 m² of its 15.6 m² Area). Now: the faces with nothing of the shell under them."""
    mesh = read_gbxml(write(tmp_path, open_shell_room()))
    (s,) = mesh.spaces
    assert abs(shapely.Polygon(s.footprint).area - l_floor_area()) <= REL * l_floor_area()
    assert abs(s.floor_z - L_Z[0]) < 1e-9
    scene = build_scene(load_project(project(tmp_path, open_shell_room())))
    (room,) = scene.rooms
    assert [w.name for w in room.windows] == ["S-24-E-W-53-W-1"]
    assert not [w for w in scene.warnings if "differs from the Area" in w], scene.warnings


def test_a_floor_off_the_spaces_area_is_warned(tmp_path):
    """The check on the reading: a floor read at 62 % of the Area the file gives is named with both."""
    text = open_shell_room().replace(f"<Area>{l_floor_area()!r}</Area>", f"<Area>{l_floor_area() / 0.62!r}</Area>")
    r = CliRunner().invoke(cli, ["validate", project(tmp_path, text)], catch_exceptions=False)
    assert "the floor read of 1 space differs from the Area the file gives by more than 10%: '24 Soggiorno' 15.6 m² " \
           "(Area 25.2 m²)" in r.output, r.output


def test_a_floor_in_two_pieces_a_wall_apart_is_one_floor(tmp_path):
    """Revit 2025 (Tamas-House) writes some bedrooms' floors as two pieces of the ClosedShell, 0.21 m
    apart, the Space's Area their sum; only the larger piece was kept (14.8 of 19.2 m²). Here a
    space of two boxes 0.2 m apart along a 3 m side: one floor of 12 + 6 m² and the 0.6 m² strip
    between them; pieces farther apart are not joined (the larger kept, the Area warning says so)."""
    from gbxml_files import box_shell, document, space, surface

    def mesh(gap: float):
        shell = box_shell(0, 3, 0, 4, 0, 2.7) + box_shell(0, 3, 4 + gap, 6 + gap, 0, 2.7)
        wall = surface("w", "ExteriorWall", [(0, 0, 0), (3, 0, 0), (3, 0, 2.7), (0, 0, 2.7)], ("sp",),
                       [("o", "FixedWindow", [(1, 0, 1), (2, 0, 1), (2, 0, 2), (1, 0, 2)], "win")])
        return read_gbxml(write(tmp_path / str(gap), document([space("sp", "bedroom", shell)], [wall])))

    (s,) = mesh(0.2).spaces
    assert abs(shapely.Polygon(s.footprint, s.holes).area - 18.6) < 1e-6
    (far,) = mesh(1.0).spaces
    assert abs(shapely.Polygon(far.footprint, far.holes).area - 12.0) < 1e-6
