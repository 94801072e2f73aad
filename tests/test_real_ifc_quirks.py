"""What real IFC exports do that the project's own sample did not, one quirk per test, each on a
one-room model written with ifcopenshell.api (en17037cli.samples.ifc.Builder):

* a window whose glass has no transparent style (older ArchiCAD, BlenderBIM): its pane from its geometry;
* a window's own frame flush with its glass: its frame, never "glazing on an opaque face";
* glass on the face of a wall that has no opening for it: quarantined, naming the wall by
  class, Name and GlobalId, with what a project file can do about it;
* a railing in the room in front of a jamb: point P stays on the wall's room-side face;
* space boundaries that name one of the room's two windows: both are its windows;
* ``*`` written for stored attributes (Renga): read as unset, the elements kept;
* a project whose spaces give no room: never a pass;
* the README's "From BIM" project, as written.

The room: 6 x 5 m inside 0.3 m walls, 2.7 m high; a south window 2.0 x 1.4 m (sill 0.8 m), an
east window 1.2 x 1.2 m; glass 6 mm thick in an 8 cm frame set 2 cm into the wall.
"""
from __future__ import annotations

import re
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli import pipeline
from en17037cli.cli import cli
from en17037cli.project import load_project
from en17037cli.scene import build_scene
from tests.ifc_box import box_shell

pytest.importorskip("ifcopenshell")
ROOT = Path(__file__).resolve().parents[1]
SUN = {"date": "03-21", "period": {"start": "03-21", "end": "03-21"}}
WALL = 0.3


def one_room(path: Path, *, glass: str = "glass", railing: bool = False, name_both: bool = False,
             uncut: bool = False, store: bool = False, store_name: tuple[str, str] = ("S1", "Store"),
             frames_only: bool = False, schema: str = "IFC4") -> Path:
    """Write the one-room model (see the module docstring); ``glass``: the glass's style ('frame'
    for an opaque one), ``railing``: a 5 cm rail 5 cm inside the south window's east jamb,
    ``name_both``: space boundaries for both windows (else the south one only), ``uncut``: an
    extra window whose glass lies on the west wall's outer face with no opening, ``store``: a
    windowless second space, ``frames_only``: windows with no glass at all."""
    b, st, walls = box_shell(schema)
    room = b.space("R1", "Room", st, [(WALL, WALL), (6.3, WALL), (6.3, 5.3), (WALL, 5.3)], 0.0, 2.7)
    if store:
        b.space(*store_name, st, [(10, 10), (12, 10), (12, 12), (10, 12)], 0.0, 2.7)
    b.styles["glass"] = b.styles[glass]
    b.window("W south", st, walls[0], (3.3, 0.0, 1.5), (0, -1, 0), (1, 0, 0), 2.0, 1.4, spaces=[room], glass=not frames_only)
    b.window("W east", st, walls[1], (6.6, 2.8, 1.5), (1, 0, 0), (0, 1, 0), 1.2, 1.2, spaces=[room] if name_both else [],
             glass=not frames_only)
    if railing:
        r = b.entity("IfcRailing", "Stair rail")
        b.place(r, st)
        b.represent(r, [b.prism([(4.25, 0.35), (4.9, 0.35), (4.9, 0.4), (4.25, 0.4)], 0.0, 2.0)])
    if uncut:  # glass on the west wall's outer face, no opening: the wall hides it
        w = b.entity("IfcWindow", "W west")
        b.place(w, st)
        pane = np.array([(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)])
        b.represent(w, [b.plate(pane, [], (0.0, 2.8, 1.5), (0, 1, 0), (0, 0, 1), (1, 0, 0), 0.006)], style="glass")
    return b.write(path)


def project(tmp: Path, ifc: Path, rooms=None, **extra) -> Path:
    doc = {"version": 1, "name": "one room", "model": {"files": [{"path": str(ifc)}]},
           "location": {"timezone": "Europe/Amsterdam"}, "rooms": rooms or [{"ifc_spaces": "*"}],
           "sunlight": SUN, "requirements": {"view": "none", "sunlight": "minimum"}, **extra}
    p = tmp / "project.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p


def scene_of(tmp: Path, **kw):
    return build_scene(load_project(project(tmp, one_room(tmp / "room.ifc", **kw)), []))


def test_glass_without_a_transparent_style_is_taken_from_the_geometry(tmp_path):
    """Glass styled like the frame (opaque): the thin plate in the wall's plane is the pane, said
    in a note; without it the room had no window."""
    s = scene_of(tmp_path, glass="frame")
    room = s.rooms[0]
    assert sorted(w.name for w in room.windows) == ["W east", "W south"]
    south = next(w for w in room.windows if w.name == "W south")
    assert south.area_m2 == pytest.approx((2.0 - 0.12) * (1.4 - 0.12), abs=1e-9)  # the glass: 6 cm frame all round
    assert any("panes taken from their geometry" in n for n in s.notes)


def test_own_frame_is_no_error_and_an_uncut_wall_names_the_wall(tmp_path):
    """The frame around the glass is the window's own (nothing said). Glass lying on a wall's face
    with no opening: quarantined (never the model), named with the wall (class, Name, GlobalId)
    and the two things a project file can do (leave the window out, or the wall)."""
    assert scene_of(tmp_path).quarantined == []  # frame and glass of one product: fine
    (q,) = scene_of(tmp_path, uncut=True).quarantined
    msg = f"{q.element}: {q.reason}; {q.advice}"
    wall = re.search(r"lies on IfcWall 'Wall 3' \(([0-9A-Za-z_$]{22})\)", msg)
    assert wall is not None and "\n" not in msg and q.element.startswith("window 'W west'"), msg
    assert "{id: '" in msg and "layer: interior}" in msg and f"exclude: ['{wall[1]}']" in msg
    assert "cut the opening" not in msg


def test_a_railing_in_the_room_does_not_move_point_p(tmp_path):
    """A rail 5 cm inside the wall, across the south window's east jamb: P stays on the wall's
    room-side face, y = 0.3 m; the reveal is measured from the glass's outer face, 2 cm (frame
    set in) + 4 cm (half the frame) - 3 mm (half the glass) inside the wall's outer face:
    0.3 - 0.057 = 0.243 m. Probing the deepest face behind the glazing put P on the rail (0.343 m)."""
    depths = {}
    for rail in (False, True):
        sub = tmp_path / f"rail{rail}"
        sub.mkdir()
        r = pipeline.run(load_project(project(sub, one_room(sub / "room.ifc", railing=rail)), []))
        res = r.rooms[0].assessed("sunlight")
        k = [w.name for w in r.rooms[0].room.windows].index("W south")
        depths[rail] = (res.reveal_depths_m[k], (res.points_local[k] + r.scene.origin)[1])
    assert depths[True] == depths[False]
    glass_outer = 0.02 + (0.08 / 2 - 0.006 / 2)  # frame 2 cm in, glass centred in the 8 cm frame: its outer face
    assert depths[True][1] == pytest.approx(WALL, abs=1e-9)
    assert depths[True][0] == pytest.approx(WALL - glass_outer, abs=1e-9)


@pytest.mark.parametrize("name_both", [False, True])
def test_space_boundaries_confirm_never_remove(tmp_path, name_both):
    """The file's boundaries name the south window only (or both): the geometry gives both."""
    room = scene_of(tmp_path, name_both=name_both).rooms[0]
    reasons = room.window_reasons
    assert sorted(reasons) == ["W east", "W south"]
    assert "named by the model's space boundaries too" in reasons["W south"]
    assert ("named by the model's space boundaries" in reasons["W east"]) == name_both


def test_star_for_stored_attributes_is_read_as_unset(tmp_path):
    """Renga writes '*' (derived) for Name, Description, ObjectType of every element; ifcopenshell
    then leaves them out of its geometry: read as '$', the windows stay, with a note."""
    ifc = one_room(tmp_path / "room.ifc")
    text = ifc.read_text()
    starred, n = re.subn(r"(IFCWINDOW\('[^']+',[^,]*,)'(W [a-z]+)',\$,\$,", r"\1*,*,*,", text)
    assert n == 2
    bad = tmp_path / "starred.ifc"
    bad.write_text(starred)
    s = build_scene(load_project(project(tmp_path, bad), []))
    assert len(s.rooms[0].windows) == 2
    assert any("written '*' (derived)" in n and "IFCWINDOW" in n for n in s.notes)


def test_no_room_is_never_a_pass(tmp_path):
    """Only a windowless space picked (the Revit office whose boundaries name no window gave a
    green PASS over an empty table): status fail, and a warning saying why."""
    p = project(tmp_path, one_room(tmp_path / "room.ifc", store=True), rooms=[{"ifc_spaces": "S1"}])
    r = pipeline.run(load_project(p, []))
    assert r.rooms == [] and r.status == "fail"
    assert any(w.startswith("no room to assess: every space the project picks is left out") for w in r.warnings)


def test_spaces_named_alike_are_told_apart_by_globalid(tmp_path):
    """Two spaces both 'Room (R1)': the rooms get their GlobalIds, not a duplicate-name error."""
    s = build_scene(load_project(project(tmp_path, one_room(tmp_path / "room.ifc", store=True, store_name=("R1", "Room"))), []))
    assert len(s.rooms) == 1 and re.fullmatch(r"Room \(R1\) \[[0-9A-Za-z_$]{22}\]", s.rooms[0].name)
    assert len(s.left_out) == 1 and s.left_out[0].name.startswith("Room (R1) [") and not s.left_out[0].windows


def test_the_readme_from_bim_project_runs_as_written(tmp_path):
    """The README's "From BIM" YAML, unchanged, next to a building.ifc: the sample house, and the
    Duplex of the real corpus where it is present. Coarse view settings only (--set)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    block = next(b for b in re.findall(r"```yaml\n(.*?)```", text, re.S) if "ifc_spaces" in b and "building.ifc" in b)
    models = [ROOT / "sample_projects" / "ifc-house" / "house.ifc",
              ROOT.parent / "shared" / "data" / "real-models" / "Duplex_A_20110907.ifc"]
    fast = ["view.grid_spacing_m=3", "view.eye_heights_m=[1.2]", "view.angular_resolution_deg=4", "view.refine_levels=0"]
    for model in (m for m in models if m.is_file()):
        folder = tmp_path / model.stem
        folder.mkdir()
        shutil.copy(model, folder / "building.ifc")
        (folder / "project.yaml").write_text(block, encoding="utf-8")
        args = ["check", str(folder / "project.yaml"), "--out", str(folder / "out"), "-q", "--no-plots"]
        r = CliRunner().invoke(cli, args + [x for s in fast for x in ("--set", s)], catch_exceptions=False)
        assert r.exit_code in (0, 1), (model.name, r.output)
        assert yaml.safe_load(block)["version"] == 1


def light_well(path: Path, *, open_ceiling: bool) -> Path:
    """A hall (a 4 x 4 m IfcSpace, 2.4 m high) under a roof light: a 1 x 1 m window in a 0.2 m roof
    slab at z 3.0 to 3.2, above a 1.2 x 1.2 m light well walled from the hall's ceiling (a slab at
    z 2.4 to 2.5) up to the roof; ``open_ceiling``: the ceiling is cut round the well (as the
    Duplex's Revit 2020 re-export draws it), else it runs closed under it. The roof is the only
    host the file names (0.2 m), so the hall lies 0.7 m beyond it."""
    from en17037cli.samples.ifc import Builder

    b = Builder("IFC4")
    st = b.storey("Ground", 0.0)
    b.locate(52.0, 4.36, 0.0)
    b.space("H1", "Hall", st, [(0, 0), (4, 0), (4, 4), (0, 4)], 0.0, 2.4)
    roof = b.slab("Roof", st, [(-1, -1), (5, -1), (5, 5), (-1, 5)], 3.0, 0.2)
    lo, hi = 1.4, 2.6  # the well, x and y
    if open_ceiling:
        for k, part in enumerate([[(0, 0), (4, 0), (4, lo), (0, lo)], [(0, hi), (4, hi), (4, 4), (0, 4)],
                                  [(0, lo), (lo, lo), (lo, hi), (0, hi)], [(hi, lo), (4, lo), (4, hi), (hi, hi)]]):
            b.slab(f"Ceiling {k}", st, part, 2.4, 0.1)
    else:
        b.slab("Ceiling", st, [(0, 0), (4, 0), (4, 4), (0, 4)], 2.4, 0.1)
    for k, (p, q) in enumerate([((lo, lo), (hi, lo)), ((hi, lo), (hi, hi)), ((hi, hi), (lo, hi)), ((lo, hi), (lo, lo))]):
        b.wall(f"Well {k}", st, *p, *q, 2.5, 0.5, thickness=0.05)
    b.window("Roof light", st, roof, (2.0, 2.0, 3.2), (0, 0, 1), (1, 0, 0), 1.0, 1.0)
    return b.write(path)


def test_a_roof_light_over_a_light_well_opens_into_the_hall_below(tmp_path):
    """The hall lies 0.7 m below the roof light's glass, beyond its 0.2 m host: with the ceiling
    cut round the well nothing opaque lies between, so the light is the hall's, and P lies where
    the well meets the hall (z 2.4, the space's top: the room-side end of the opening; the Revit
    2011 export of the Duplex names the well's slabs as hosts and gets the same P). With the
    ceiling closed under the well the light opens into no space, and validate says so."""
    ifc = light_well(tmp_path / "open.ifc", open_ceiling=True)
    r = pipeline.run(load_project(project(tmp_path, ifc, requirements={"sunlight": "minimum"}), []))
    room = r.rooms[0].room
    assert [w.name for w in room.windows] == ["Roof light"]
    assert "nothing opaque between" in room.window_reasons["Roof light"]
    res = r.rooms[0].assessed("sunlight")
    p = res.points_local[0] + r.scene.origin
    assert p[:2] == pytest.approx([2.0, 2.0], abs=1e-6) and p[2] == pytest.approx(2.4, abs=1e-6)
    closed = tmp_path / "closed"
    closed.mkdir()
    ifc = light_well(closed / "closed.ifc", open_ceiling=False)
    out = CliRunner().invoke(cli, ["validate", str(project(closed, ifc))])
    assert "window 'Roof light': in no room" in out.output, out.output


def test_windows_drawn_as_frames_only_get_a_pane_in_their_opening(tmp_path):
    """No glass in the file at all (Autodesk Architectural Desktop's IFC2x exports draw a frame
    and a sash): the opening the frame leaves is the pane, 6 cm inside the frame's outer edge all
    round, in the middle of its depth; said in a note. Before: exit 2, no face on the window layer."""
    s = scene_of(tmp_path, frames_only=True)
    room = s.rooms[0]
    areas = {w.name: w.area_m2 for w in room.windows}
    assert areas == pytest.approx({"W south": (2.0 - 0.12) * (1.4 - 0.12), "W east": (1.2 - 0.12) * (1.2 - 0.12)}, abs=1e-9)
    south = next(w for w in room.windows if w.name == "W south")
    y = south.triangles[..., 1] + s.origin[1]
    assert np.allclose(y, 0.02 + 0.04, atol=1e-9)  # the frame from 2 to 10 cm inside the wall's outer face
    assert any("modelled as frames only" in n for n in s.notes)


@pytest.mark.parametrize("old", ["IFC2X2_FINAL", "IFC2X_FINAL"])
def test_an_ifc2x_file_is_read_as_ifc2x3(tmp_path, old):
    """ifcopenshell reads no schema before IFC2X3; IFC2X3 kept the classes of IFC2x and IFC2x2:
    the same model with its header naming the older schema reads the same, with a note."""
    ifc = one_room(tmp_path / "room.ifc", schema="IFC2X3")
    want = build_scene(load_project(project(tmp_path, ifc), []))
    text = ifc.read_bytes()
    assert b"FILE_SCHEMA(('IFC2X3'))" in text
    older = tmp_path / "older"
    older.mkdir()
    (older / "room.ifc").write_bytes(text.replace(b"FILE_SCHEMA(('IFC2X3'))", f"FILE_SCHEMA(('{old}'))".encode()))
    got = build_scene(load_project(project(older, older / "room.ifc"), []))
    assert [(w.name, w.area_m2) for w in got.rooms[0].windows] == [(w.name, w.area_m2) for w in want.rooms[0].windows]
    assert any(f"schema {old} (before IFC2X3), read as IFC2X3" in n for n in got.notes)


def test_two_windows_of_one_name_keep_their_own_point_p(tmp_path):
    """Two IfcWindows both named 'Fenster' (ArchiCAD 11 names a hall's two windows alike) on the
    room's south and east walls: told apart by their GlobalIds in every report, and each P on the
    room-side face of its own wall, within its own window's width: never the other's."""
    b, st, walls = box_shell()
    room = b.space("R1", "Hall", st, [(WALL, WALL), (6.3, WALL), (6.3, 5.3), (WALL, 5.3)], 0.0, 2.7)
    for name, wall, centre, n, u in (("W a", walls[0], (3.3, 0.0, 1.5), (0, -1, 0), (1, 0, 0)),
                                     ("W b", walls[1], (6.6, 2.8, 1.5), (1, 0, 0), (0, 1, 0))):
        b.window(name, st, wall, centre, n, u, 1.2, 1.4, spaces=[room]).Name = "Fenster"
    p = project(tmp_path, b.write(tmp_path / "hall.ifc"), sunlight={"date": "03-21", "period": {"start": "03-21", "end": "03-21"}})
    r = pipeline.run(load_project(p, []))
    res = r.rooms[0].assessed("sunlight")
    names = [w.name for w in r.rooms[0].room.windows]
    assert len(set(names)) == 2 and all(re.fullmatch(r"Fenster \([0-9A-Za-z_$]{22}\)", n) for n in names), names
    for w, pt in zip(r.rooms[0].room.windows, r.scene.to_world(res.points_local)):
        c = r.scene.to_world(w.centroid)
        inward = -np.asarray(w.normal)
        depth = (pt - c) @ inward  # behind its own glass, on its own wall's room-side face
        assert 0.2 < depth < WALL + 1e-9, (w.name, depth)
        along = np.linalg.norm((pt - c) - depth * inward - ((pt - c) @ [0, 0, 1]) * np.array([0, 0, 1.0]))
        assert along < 0.6, (w.name, along)  # within the 1.2 m window's half-width
