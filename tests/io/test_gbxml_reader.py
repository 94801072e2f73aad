"""gbXML reader: the box room written as a gbXML space gives the OBJ box room's report (in metres,
in feet, turned with its CADModelAzimuth, with Revit's InteriorWall quirk), glazing sides, bad
files, and the real Revit export of ../shared (skipped only when that folder is absent)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner
from gbxml_files import box_room_gbxml, box_shell, document, space, surface, write

from en17037cli.cli import cli
from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals
from en17037cli.io import read_model
from en17037cli.io.gbxml import read_gbxml
from en17037cli.samples import BoxRoom, box_room_project

pytest.importorskip("lxml")

ROOT = Path(__file__).resolve().parents[2]
URBAN = ROOT.parent / "shared" / "data" / "real-models" / "Urban_House_MEP.xml"
SUN = {"date": "02-01", "period": {"start": "02-01", "end": "02-01"}}
# 1.4 m, not 1.5 m: the box's utilised width is 3 m, an exact multiple of 1.5 m where the grid's column count
# flips on the last bit of the floor polygon's float arithmetic (a derived floor and a space's footprint differ there)
VIEW = {"grid_spacing_m": 1.4, "eye_heights_m": [1.2], "angular_resolution_deg": 2.0, "refine_levels": 2}


def area(mesh, mask=None) -> float:
    tris = mesh.triangles if mask is None else mesh.triangles[mask]
    return float(triangle_normals(mesh.vertices[tris])[1].sum())


def of(mesh, **attrs) -> np.ndarray:
    return np.isin(mesh.part, [i for i, q in enumerate(mesh.parts) if all(q.attrs.get(k) == v for k, v in attrs.items())])


def run(args) -> tuple[int, str]:
    r = CliRunner().invoke(cli, args, catch_exceptions=False)
    return r.exit_code, r.output


def gbxml_project(directory: Path, text: str, north: bool = False) -> Path:
    """The box-room project with the gbXML file as its model and one room per gbXML space."""
    p = box_room_project(directory, BoxRoom(), sunlight=SUN, view=VIEW)
    write(directory, text)
    doc = yaml.safe_load(p.read_text())
    doc["model"]["files"] = [{"path": "model.xml", "layers": [{"match": "ground", "layer": "ground"}]}]
    if north:
        del doc["model"]["true_north_deg"]  # from the file's CADModelAzimuth
    doc["rooms"] = [{"gbxml_spaces": "*"}]
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p


def rooms_of(project: Path, out: Path) -> list:
    code, text = run(["check", str(project), "--out", str(out), "--no-plots", "-q"])
    assert code in (0, 1), text
    return json.loads((out / "report.json").read_text())["rooms"]


@pytest.fixture(scope="module")
def obj_rooms(tmp_path_factory):
    d = tmp_path_factory.mktemp("obj")
    return rooms_of(box_room_project(d, BoxRoom(), sunlight=SUN, view=VIEW), d / "r")


def figures(rooms: list) -> list:
    """The rooms' figures, each eye height's viewpoints in a fixed order: the grid's own order sorts on
    coordinates that differ in their last bits between a derived floor and a space's footprint; the
    windows' element ids (an OBJ has none) left out."""
    out = []
    for r in rooms:
        view = json.loads(json.dumps(r["view"]))
        for eh in view.get("eye_heights", []):
            eh["points"] = sorted(eh["points"], key=lambda q: tuple(round(c, 6) for c in q["point"]))
        sun = json.loads(json.dumps(r["sunlight"]))
        for w in sun.get("windows", []):  # the model's own id of the window (a gbXML Opening's): not geometry
            w.pop("element_id", None)
        windows = [{k: v for k, v in w.items() if k != "source"} for w in r["windows"]]  # the file's own ids: not geometry
        out.append((r["name"], r["floor_area_m2"], windows, view, sun))
    return out


# --- by construction: the box room as a gbXML space --------------------------------------------


def test_box_room_as_gbxml_space_gives_the_obj_report(tmp_path, obj_rooms):
    rooms = rooms_of(gbxml_project(tmp_path / "m", box_room_gbxml()), tmp_path / "r")
    assert figures(rooms) == figures(obj_rooms)
    assert rooms[0]["floor_source"] == "the gbXML Space's footprint"


def test_feet_and_a_turned_model_with_its_cad_azimuth_give_the_same_figures(tmp_path, obj_rooms):
    feet = rooms_of(gbxml_project(tmp_path / "ft", box_room_gbxml(unit="Feet")), tmp_path / "rft")
    assert figures(feet) == figures(obj_rooms)
    # the model turned 30 deg counterclockwise: its +Y axis now points 30 deg east of north (CADModelAzimuth 30)
    turned = rooms_of(gbxml_project(tmp_path / "t", box_room_gbxml(turn_deg=30.0, azimuth=30.0), north=True), tmp_path / "rt")
    s0, s1 = obj_rooms[0]["sunlight"], turned[0]["sunlight"]
    assert abs(s1["hours_h"] - s0["hours_h"]) < 1e-3  # 3.6 s: the exact method's bisection tolerance, float noise of the turn
    assert turned[0]["view"]["level"] == obj_rooms[0]["view"]["level"]
    wrong = rooms_of(gbxml_project(tmp_path / "w", box_room_gbxml(turn_deg=30.0, azimuth=0.0), north=True), tmp_path / "rw")
    assert abs(wrong[0]["sunlight"]["hours_h"] - s0["hours_h"]) > 0.05  # the azimuth is what restores the answer


def test_revit_interior_wall_with_the_room_on_both_sides_is_an_exterior_window(tmp_path, obj_rooms):
    text = box_room_gbxml(facade_kind="InteriorWall")
    p = gbxml_project(tmp_path / "q", text)
    assert figures(rooms_of(p, tmp_path / "r")) == figures(obj_rooms)
    code, out = run(["validate", str(p)])
    assert code == 0
    assert "1 glazing(s) reclassified by what lies on their two sides" in out
    assert "glazing (on InteriorWall s-facade, the same space on both sides)" in out
    assert "read model.xml: gbXML 0.37 in Meters: 1 space, 12 surfaces" in out and "1 exterior window (1 reclassified" in out


def test_glazing_between_two_spaces_is_interior_and_hints_go_to_the_inner_space(tmp_path):
    # two 4 x 4 x 3 m rooms side by side (x 0..4 and 4..8), a window in the south wall of each and glazing between them
    shells = [box_shell(0, 4, 0, 4, 0, 3), box_shell(4, 8, 0, 4, 0, 3)]
    win = lambda x: [(x, 0.0, 1.0), (x + 2, 0.0, 1.0), (x + 2, 0.0, 2.0), (x, 0.0, 2.0)]  # noqa: E731
    part = [(4.0, 1.0, 1.0), (4.0, 3.0, 1.0), (4.0, 3.0, 2.0), (4.0, 1.0, 2.0)]
    surfs = [surface("wa", "ExteriorWall", [(0, 0, 0), (4, 0, 0), (4, 0, 3), (0, 0, 3)], ("a",), [("wa1", "OperableWindow", win(1), "A window")]),
             surface("wb", "ExteriorWall", [(4, 0, 0), (8, 0, 0), (8, 0, 3), (4, 0, 3)], ("b",), [("wb1", "FixedWindow", win(5), "B window")]),
             surface("ab", "ExteriorWall", [(4, 0, 0), (4, 4, 0), (4, 4, 3), (4, 0, 3)], ("a",), [("g", "FixedWindow", part, "partition")]),
             surface("sk", "Roof", [(0, 0, 3), (8, 0, 3), (8, 4, 3), (0, 4, 3)], ("a", "b"), [("d", "NonSlidingDoor", [(1, 1, 3), (2, 1, 3), (2, 2, 3), (1, 2, 3)], "hatch")])]
    m = read_gbxml(write(tmp_path, document([space("a", "Room A", shells[0]), space("b", "Room B", shells[1])], surfs)))
    layer = {q.attrs["id"]: (q.layer, q.window, q.attrs.get("surface")) for q in m.parts}
    assert layer["wa1"] == ("window", "wa1", None) and layer["wb1"] == ("window", "wb1", None)
    assert layer["g"] == ("interior", None, "interior glazing")  # the file says exterior wall of A; B is behind it
    assert layer["d"] == ("interior", None, None)
    assert {s.name: s.windows for s in m.spaces} == {"Room A": ("wa1",), "Room B": ("wb1",)}
    assert any("1 glazing(s) between two spaces" in n and "partition (Room A | Room B)" in n for n in m.notes)
    assert abs(area(m, of(m, id="ab")) - (12.0 - 2.0)) < 1e-9  # the glazing cut out of its wall
    assert abs(area(m, of(m, id="sk")) - (32.0 - 1.0)) < 1e-9  # the hatch cut out of the roof
    sa = next(s for s in m.spaces if s.name == "Room A")
    assert (sa.storey, sa.zones, sa.kind, sa.floor_z, sa.top_z) == ("Ground floor", ("Flat 1",), "gbXML Space", 0.0, 3.0)
    x, y = sa.footprint[:, 0], sa.footprint[:, 1]
    assert abs(0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) - 16.0) < 1e-9  # the 4 x 4 m floor
    assert m.site.latitude == 52.0 and m.site.longitude == 4.36 and m.site.true_north_deg is None


# --- bad files ---------------------------------------------------------------------------------


@pytest.mark.parametrize("case, expect", [
    ("malformed", "not well-formed XML"),
    ("no unit", "has no lengthUnit"),
    ("citygml", "not gbXML (root element 'CityModel', expected gbXML) (a CityGML file: give it the ending .gml)"),
    ("nan", "is not a number"),
])
def test_bad_files_exit_2_with_one_line(tmp_path, case, expect):
    text = box_room_gbxml()
    if case == "malformed":
        text = text[: len(text) // 2]
    elif case == "no unit":
        text = text.replace(' lengthUnit="Meters"', "")
    elif case == "citygml":
        text = '<?xml version="1.0"?><CityModel xmlns="http://www.opengis.net/citygml/2.0"/>'
    elif case == "nan":
        text = text.replace("<Coordinate>6.0</Coordinate>", "<Coordinate>six</Coordinate>", 1)
    p = gbxml_project(tmp_path / "b", text)
    with pytest.raises(InputError) as e:
        read_model(tmp_path / "b" / "model.xml")
    assert "\n" not in str(e.value) and expect in str(e.value)
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / "r"), "-q"])
    lines = [x for x in r.output.splitlines() if x.strip()]
    assert r.exit_code == 2 and len(lines) == 1 and expect in lines[0] and "model.xml" in lines[0]


# --- the real Revit export ----------------------------------------------------------------------


def _independent(path: Path) -> dict:
    """From the file itself, not the reader: each Space's Area [ft²], each glazed Opening's Newell area [ft²]."""
    from lxml import etree

    ns = "{http://www.gbxml.org/schema}"
    root = etree.parse(str(path)).getroot()
    out = {"space_area": {}, "glazing_area": {}}
    for s in root.iter(f"{ns}Space"):
        out["space_area"][s.findtext(f"{ns}Name")] = float(s.findtext(f"{ns}Area"))
    for o in root.iter(f"{ns}Opening"):
        if "Window" in o.get("openingType"):
            v = np.array([[float(c.text) for c in p] for p in o.find(f"{ns}PlanarGeometry").iter(f"{ns}CartesianPoint")])
            c = v - v.mean(axis=0)
            out["glazing_area"][o.get("id")] = 0.5 * np.linalg.norm(np.cross(c, np.roll(c, -1, axis=0)).sum(axis=0))
    return out


@pytest.mark.skipif(not URBAN.is_file(), reason="../shared/data/real-models absent")
def test_real_revit_gbxml():
    m = read_model(URBAN)
    ft2 = 0.3048 ** 2
    assert (m.units, m.site.latitude, m.site.longitude, m.site.true_north_deg) == ("m", 42.213, -71.033, 0.0)
    assert "gbXML 0.37 in Feet: 26 spaces, 245 surfaces" in m.summary, m.summary
    assert "14 exterior windows (9 reclassified from their surface's type), 2 interior glazings" in m.summary  # the README's 9 of 14
    ind = _independent(URBAN)
    for s in m.spaces:  # the footprint from the shell against Revit's own room area
        fp = s.footprint
        a = 0.5 * abs(np.dot(fp[:, 0], np.roll(fp[:, 1], -1)) - np.dot(fp[:, 1], np.roll(fp[:, 0], -1)))
        holes = sum(0.5 * abs(np.dot(h[:, 0], np.roll(h[:, 1], -1)) - np.dot(h[:, 1], np.roll(h[:, 0], -1))) for h in s.holes)
        assert abs((a - holes) - ind["space_area"][s.name] * ft2) < 0.02 * ind["space_area"][s.name] * ft2, s.name
    windows = [q for q in m.parts if q.layer == "window"]
    assert len(windows) == 14
    for q in windows:  # the glazing as the file draws it, in m² (feet scaled exactly)
        assert abs(area(m, of(m, id=q.attrs["id"])) - ind["glazing_area"][q.attrs["id"]] * ft2) < 1e-9
    living = next(s for s in m.spaces if s.name == "9 1st Floor Living Room")
    assert living.windows == ("aim2414",) and abs(living.floor_z - 12 * 0.3048) < 1e-12


@pytest.mark.skipif(not URBAN.is_file(), reason="../shared/data/real-models absent")
def test_real_revit_gbxml_project(tmp_path):
    (tmp_path / URBAN.name).write_bytes(URBAN.read_bytes())
    p = tmp_path / "project.yaml"
    p.write_text(yaml.safe_dump({
        "version": 1, "name": "Urban house", "model": {"units": "m", "up_axis": "z", "files": [{"path": URBAN.name}]},
        "location": {"timezone": "America/New_York"}, "rooms": [{"gbxml_spaces": "*"}],
        "sunlight": SUN, "requirements": {"view": "medium", "sunlight": "minimum"}}, sort_keys=False))
    code, out = run(["validate", str(p)])
    assert code == 0, out
    assert "room '9 1st Floor Living Room'" in out and "room '22 Master Bedroom'" in out
    assert "space '11 Kitchen': not a room of the check: no window opens into it" in out  # its only glazing is interior
    code, out = run(["check", str(p), "--out", str(tmp_path / "r"), "--only", "sunlight", "--no-plots", "-q"])
    assert code in (0, 1), out
    rooms = {r["name"]: r for r in json.loads((tmp_path / "r" / "report.json").read_text())["rooms"]}
    assert len(rooms) == 9
    south = rooms["14 Dining Room"]["sunlight"]["hours_h"]  # windows facing due south (azimuth 180), 42.2 N on 1 February
    east = rooms["19 Bath"]["sunlight"]["hours_h"]  # one window facing due east
    assert south > 7.0 and 1.5 < east < 5.0


def test_spaces_sharing_a_name_become_rooms_named_with_their_ids(tmp_path):
    from en17037cli.scene.spaces import room_name

    shells = [box_shell(0, 4, 0, 4, 0, 3), box_shell(4, 8, 0, 4, 0, 3)]
    surfs = [surface("f", "SlabOnGrade", [(0, 0, 0), (8, 0, 0), (8, 4, 0), (0, 4, 0)], ("a", "b"))]
    m = read_gbxml(write(tmp_path, document([space("a", "Office", shells[0]), space("b", "Office", shells[1])], surfs)))
    assert sorted(room_name(s) for s in m.spaces) == ["Office (a)", "Office (b)"]


def test_a_space_drawn_off_its_walls_keeps_the_windows_its_surfaces_name(tmp_path):
    """Revit 2025's gbXML of an office draws some spaces' ShellGeometry short of the walls that
    bound them (non-manifold shells: 418 edges of one used once): 28 of its 68 exterior windows
    then lay in no room. Here the box room's shell drawn 3 m back from its facade: the facade's
    AdjacentSpaceId names the space, so the window is the room's, and validate says the geometry
    does not confirm it. Before: the window in no room, the room left out."""
    b = BoxRoom()
    hw, d, h = b.width / 2, b.depth, b.height
    text = box_room_gbxml(b).replace(space("sp1", "box room", box_shell(-hw, hw, 0.0, d, 0.0, h)),
                                     space("sp1", "box room", box_shell(-hw, hw, 3.0, d + 3.0, 0.0, h)))
    assert "3.0</Coordinate>" in text
    p = gbxml_project(tmp_path / "m", text)
    code, out = run(["validate", str(p)])
    assert code == 0, out
    assert "window 'glazing'" in out and "in no room" not in out
    assert "named by the model's space boundaries; the space as drawn lies 3.00 m from its glazing" in out


def test_a_windowed_space_with_no_floor_is_left_out_by_name_never_dropped(tmp_path):
    """A gbXML Space whose shell and floor surface are missing (Revit 2009's ZNETH had six): it is
    listed as left out with its window, and the run cannot pass; before, it vanished from the
    count of spaces with windows not assessed."""
    import re

    text = re.sub(r"<ShellGeometry .*?</ShellGeometry>", "", box_room_gbxml())
    text = re.sub(r'<Surface [^>]*surfaceType="SlabOnGrade".*?</Surface>', "", text, flags=re.S)
    p = gbxml_project(tmp_path / "m", text)
    code, _ = run(["check", str(p), "--out", str(tmp_path / "r"), "--no-plots", "-q"])
    rep = json.loads((tmp_path / "r" / "report.json").read_text())
    assert code == 1 and rep["status"] == "fail"
    (lo,) = rep["spaces_left_out"]
    assert lo["name"] == "box room" and lo["windows"] == ["glazing"] and "no floor" in lo["reason"]
    assert rep["summary"]["spaces_with_windows_not_assessed"] == 1


def test_a_file_that_says_feet_and_writes_metres_is_read_in_the_unit_its_rooms_say(tmp_path):
    """A gbXML whose lengthUnit is Feet but whose coordinates are metres (Ladybug Spider's SPEED
    generator: 4.0 "ft" storeys, rooms 1.22 m tall) gave rooms nobody stands in: point P above every
    window's head, no utilised area, every room NOT ASSESSABLE on reasons that hid the cause. Its
    spaces' median height is implausible in Feet and likely in Meters: it is read in Meters, with a
    warning naming both; a file honestly in Feet is read as it says, with no warning."""
    b = BoxRoom()
    says_feet = box_room_gbxml(b).replace('lengthUnit="Meters"', 'lengthUnit="Feet"')
    m = read_gbxml(write(tmp_path / "lie", says_feet))
    metres = read_gbxml(write(tmp_path / "m", box_room_gbxml(b)))
    assert np.allclose(m.vertices, metres.vertices, atol=1e-9) and not any("lengthUnit" in w for w in metres.warnings)
    assert any("read in Feet" in w and "read in Meters instead" in w for w in m.warnings), m.warnings
    assert m.summary.startswith("gbXML 0.37 in Meters")
    honest = read_gbxml(write(tmp_path / "ft", box_room_gbxml(b, unit="Feet")))
    assert not any("lengthUnit" in w for w in honest.warnings)
    assert np.allclose(np.sort(honest.vertices, axis=0)[[0, -1]], np.sort(m.vertices, axis=0)[[0, -1]], atol=1e-6)
