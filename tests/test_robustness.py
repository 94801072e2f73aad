"""Real models never break it: the defects of issue 12, each with a CLI-level test.

Rooms of a block (en17037cli.samples.block): 4 x 5 m rooms, 2 x 1.4 m windows (x 1..3 m, z 0.8..2.2 m
above the floor) in the facades y = 0 (south rooms 'S') and y = 10.1 (north rooms 'N'), a 0.1 m
partition between them, a 10 m building across a 25 m street to the south.
"""
from __future__ import annotations

import json
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.geometry import triangle_solid_angle
from en17037cli.report.folder import MANIFEST, TMP_PREFIX
from en17037cli.report.write import REPORT_FILES
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.samples.block import Block, block_project

SUN = {"date": "worst", "period": {"start": "02-01", "end": "02-03"}}
FAST_VIEW = {"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 3.0, "refine_levels": 1}


def invoke(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


def edit(path: Path, fn) -> Path:
    doc = yaml.safe_load(path.read_text())
    fn(doc)
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def one_line_error(r, *expected):
    assert r.exit_code == 2, r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), r.output
    for e in expected:
        assert e in lines[0], lines[0]
    return lines[0]


# --- wrong answers without a warning --------------------------------------------------------

def test_a_room_takes_only_the_windows_that_bound_it(tmp_path):
    """The north bedroom of a two-room block sees no sun, although the living room's south window
    is in the same model: its windows are the ones in its own walls."""
    path = block_project(tmp_path / "b", Block(), rooms=["1.N01"], view=None, sunlight=SUN)
    out = tmp_path / "out"
    r = invoke("check", path, "--out", out, "-q")
    assert r.exit_code == 1, r.output
    room = json.loads((out / "report.json").read_text())["rooms"][0]
    assert [w["name"] for w in room["windows"]] == ["W 1.N01"]
    assert room["windows"][0]["outward_normal"] == [0.0, 1.0, 0.0]  # north, away from the room
    # 52 N in February: the sun never stands north of the east-west line above 11 deg
    assert room["sunlight"]["hours_h"] == 0.0 and room["sunlight"]["level"] == "none"
    # the living room, alone, gets its own south window and sun through it
    path = block_project(tmp_path / "s", Block(), rooms=["1.S01"], view=None, sunlight=SUN)
    r = invoke("check", path, "--out", tmp_path / "out2", "-q")
    room = json.loads((tmp_path / "out2" / "report.json").read_text())["rooms"][0]
    assert [w["name"] for w in room["windows"]] == ["W 1.S01"] and room["sunlight"]["hours_h"] > 1.5


def test_a_glob_that_picks_another_rooms_window_is_an_error_naming_both(tmp_path):
    path = block_project(tmp_path / "b", Block(), rooms=["1.N01"], view=None, sunlight=SUN)
    edit(path, lambda d: d["rooms"][0].update(windows=["W 1.S01"]))
    for cmd in ("check", "validate"):  # validate says what check says
        line = one_line_error(invoke(cmd, path, "-q") if cmd == "check" else invoke(cmd, path),
                              "rooms[0] '1.N01'.windows: 'W 1.S01' picks window 'W 1.S01', which does not bound room '1.N01'")
    assert "within 1.2 m of the floor outline" in line


def test_validate_lists_each_rooms_windows_and_why(tmp_path):
    path = block_project(tmp_path / "b", Block(storeys=2), view=None, sunlight=SUN)
    r = invoke("validate", path)
    assert r.exit_code == 0, r.output
    out = r.output
    # the ground-floor room does not take the window of the room above (z 3.8 to 5.2 m)
    assert "room '1.S01': floor 19.50 m² at z 0.000 m (given), ceiling at z 2.999 m (the lowest horizontal interior faces over the floor covering 100% of it), 1 window(s)" in out
    assert "  window 'W 1.S01': 2.800 m², outward normal (0.0000, -1.0000, 0.0000), 2 faces; bounds the room: 100% of its width within 1.2 m of the floor outline, z 0.80 to 2.20 m" in out
    assert "  window 'W 2.N01': 2.800 m², outward normal (0.0000, 1.0000, 0.0000), 2 faces; bounds the room: 100% of its width within 1.2 m of the floor outline, z 3.80 to 5.20 m" in out


def test_several_floors_at_floor_z_need_a_floor_or_the_windows(tmp_path):
    path = block_project(tmp_path / "b", Block(), rooms=["1.N01"], view=None, sunlight=SUN)
    edit(path, lambda d: d["rooms"][0].pop("floor"))
    one_line_error(invoke("check", path, "-q"), "rooms[0] '1.N01': the walls enclose 2 rooms with windows at floor_z = 0 m")
    edit(path, lambda d: d["rooms"][0].update(windows=["W 1.N*"]))  # the floor beside the named window
    assert invoke("check", path, "-q", "--out", tmp_path / "o").exit_code == 1  # a north room: no sun in February
    assert json.loads((tmp_path / "o" / "report.json").read_text())["rooms"][0]["floor_area_m2"] == 19.5


def test_a_required_check_that_did_not_run_fails(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=None)  # no view section
    out = tmp_path / "out"
    r = invoke("check", path, "--out", out, "-q")
    assert r.exit_code == 1
    report = json.loads((out / "report.json").read_text())
    assert report["rooms"][0]["view"] == {"level": None, "required": "medium", "status": "not_assessed",
                                          "reason": "the project has no 'view' section"}
    assert report["status"] == "fail" and report["rooms"][0]["status"] == "fail"
    assert "| box room | view out (5.2) | - | medium | **NOT ASSESSED** | the project has no 'view' section |" in (out / "report.md").read_text()
    r = invoke("check", path, "--out", out, "-q", "--set", "requirements.view=none")
    assert r.exit_code == 0 and json.loads((out / "report.json").read_text())["rooms"][0]["view"] is None


def test_glazing_no_ray_can_pass_is_a_warning(tmp_path):
    """Glazing 10 cm inside a 30 cm wall with no opening cut: the wall's faces on both sides are
    more than 1 mm away, so no ray from the room reaches the glass."""
    box = BoxRoom(wall_thickness=0.3)
    path = box_room_project(tmp_path / "p", box, sunlight=SUN, view=FAST_VIEW)
    model = path.parent / "model.obj"
    # close the opening with the wall's inner face (y = 0.3) and move the glazing to y = 0.1
    text = model.read_text().replace("o glazing\n", "o glazing\n")
    lines = text.splitlines()
    out_lines, obj = [], None
    for line in lines:
        if line.startswith("o "):
            obj = line[2:]
        if obj == "glazing" and line.startswith("v "):
            x, y, z = map(float, line.split()[1:])
            line = f"v {x:.9f} {0.1:.9f} {z:.9f}"
        out_lines.append(line)
    n = sum(1 for line in out_lines if line.startswith("v "))
    out_lines += ["o room", "v -1 0.3 0.8", "v 1 0.3 0.8", "v 1 0.3 2.2", "v -1 0.3 2.2", f"f {n + 1} {n + 2} {n + 3} {n + 4}"]
    model.write_text("\n".join(out_lines) + "\n")
    warning = ("room 'box room', window 'glazing': no ray from the room leaves through it (an opaque face lies between the "
               "room and the glazing, or beyond it: a wall with no opening cut?); it adds no view and no sun")
    r = invoke("validate", path)
    assert r.exit_code == 0 and f"warning: {warning}" in r.output, r.output
    r = invoke("check", path, "--out", tmp_path / "o", "-q")
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    assert warning in report["warnings"] and report["rooms"][0]["sunlight"]["hours_h"] == 0.0


def test_layer_rules_that_match_nothing_and_a_model_without_interior_are_warnings(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    edit(path, lambda d: d["model"]["files"][0]["layers"].insert(0, {"match": "Tree*", "layer": "landscape",
                                                                     "obstructs_sun": False}))
    r = invoke("validate", path, "--objects")
    assert r.exit_code == 0
    assert ("warning: project.yaml: model.files[0].layers[0] (match: 'Tree*', layer: landscape): matches no object of "
            "model.obj; check the name (validate --objects lists them)") in r.output
    assert "object model: object=room: layer interior, 18 faces" in r.output
    assert "object model: object=building: layer landscape, 10 faces" in r.output
    edit(path, lambda d: d["model"]["files"][0]["layers"].__setitem__(1, {"match": "room", "layer": "landscape"}))
    r = invoke("validate", path)
    assert "warning: no face is on the 'interior' layer" in r.output


# --- crashes that must become results or input errors ---------------------------------------

def test_an_eye_height_with_no_window_gives_sight_angle_zero(tmp_path):
    """An eye at 0.5 m is below the 0.8 m sill: no horizontal ray meets a window."""
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=None, view={**FAST_VIEW, "eye_heights_m": [0.5, 1.2]})
    out = tmp_path / "o"
    r = invoke("check", path, "--out", out, "-q", "--set", "requirements.sunlight=none")
    assert r.exit_code == 1, r.output  # the 0.5 m eye height reaches no level: the room's view is 'none'
    eyes = json.loads((out / "report.json").read_text())["rooms"][0]["view"]["eye_heights"]
    low = eyes[0]
    assert low["eye_height_m"] == 0.5 and low["level_by_criterion"]["horizontal_sight_angle"] == "none"
    assert all(p["horizontal_sight_angle_deg"] == 0.0 for p in low["points"])
    assert eyes[1]["level_by_criterion"]["horizontal_sight_angle"] != "none"


def round_window_scene(directory: Path, segments: int) -> Path:
    return box_room_project(directory, BoxRoom(round_window=segments), sunlight=None,
                            view={"grid_spacing_m": 1.0, "eye_heights_m": [1.2]})


def test_a_finely_tessellated_round_window_keeps_memory_bounded(tmp_path):
    """A round pane of 2000 segments in a 5 cm frame ring (4000 frame vertices). Before: 8 GB at 200
    segments, out of memory. Now the whole check stays under 600 MB (a child process's peak RSS)."""
    path = round_window_scene(tmp_path / "p", 2000)
    # peak RSS of the child's own address space (VmHWM): ru_maxrss would count the forking pytest's memory
    code = ("import sys; from en17037cli.cli import main; sys.argv = ['en17037', 'check', sys.argv[1], '-q', "
            "'--out', sys.argv[2], '--set', 'requirements.sunlight=none']\ntry:\n    main()\nexcept SystemExit as e:\n"
            "    hwm = [ln for ln in open('/proc/self/status') if ln.startswith('VmHWM')][0].split()[1]\n"
            "    print(e.code, hwm)")
    p = subprocess.run([sys.executable, "-c", code, str(path), str(tmp_path / "o")], capture_output=True, text=True, timeout=300)
    code, rss_kb = p.stdout.split()
    assert code in ("0", "1"), p.stderr
    assert int(rss_kb) / 1024 < 600, rss_kb
    # the cells still add up to the pane's exact solid angle (sum of its triangles' solid angles)
    report = json.loads((tmp_path / "o" / "report.json").read_text())
    pt = report["rooms"][0]["view"]["eye_heights"][0]["points"][0]
    from en17037cli.samples.box import _round_window

    glazing, _ = _round_window(BoxRoom(round_window=2000))
    tris = np.array(glazing, dtype=float)
    exact = triangle_solid_angle(np.repeat(np.array([pt["point"]], float), len(tris), 0), tris).sum()
    assert abs(pt["glazing_solid_angle_sr"] - exact) < 2e-6  # report rounding to 6 decimals


def test_point_p_above_the_head_of_one_window_leaves_the_other(tmp_path):
    """A second, low window (x 1.3..1.8 m, z 0.2..1.0 m) in the south wall: the rule's P (1.2 m
    above the floor) lies above its head, so it is not assessable; the room's sunlight uses the
    main window."""
    from en17037cli.samples.box import _rect_y, box_room_polygons, write_obj

    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=None)
    objects = box_room_polygons(BoxRoom())
    objects["room"].remove(_rect_y(0.0, 1.0, 2.0, 0, 3.0))  # the wall east of the main opening ...
    objects["room"] += [_rect_y(0.0, 1.0, 1.3, 0, 3.0), _rect_y(0.0, 1.8, 2.0, 0, 3.0),  # ... with a hole cut
                        _rect_y(0.0, 1.3, 1.8, 0, 0.2), _rect_y(0.0, 1.3, 1.8, 1.0, 3.0)]
    objects["glazing low"] = [_rect_y(0.0, 1.3, 1.8, 0.2, 1.0)]
    write_obj(path.parent / "model.obj", objects)
    r = invoke("check", path, "--out", tmp_path / "o", "-q", "--set", "requirements.view=none")
    assert r.exit_code == 0, r.output
    s = json.loads((tmp_path / "o" / "report.json").read_text())["rooms"][0]["sunlight"]
    low = [w for w in s["windows"] if w["name"] == "glazing low"][0]
    assert low["point_p_m"] is None and low["status"] == "not_assessable"
    assert ("window 'glazing low': point P at max(floor + 1.2 m, sill + 0.3 m) = 1.200 m above the floor lies above the "
            "window head (1.000 m)") in low["reason"]
    main = [w for w in s["windows"] if w["name"] == "glazing"][0]
    assert main["point_p_m"] == [0.0, 0.001, 1.2] and s["status"] == "pass"
    # the sun seen from the main window's P is the box room's own: the low window adds nothing
    plain = box_room_project(tmp_path / "plain", BoxRoom(), sunlight=SUN, view=None)
    invoke("check", plain, "--out", tmp_path / "o2", "-q", "--set", "requirements.view=none")
    assert s["hours_h"] == json.loads((tmp_path / "o2" / "report.json").read_text())["rooms"][0]["sunlight"]["hours_h"]


def test_a_room_whose_only_window_has_no_point_p_is_not_assessable(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(window_z=(0.2, 1.0)), sunlight=SUN, view=None)
    r = invoke("validate", path)
    assert r.exit_code == 0 and "  sunlight: NOT ASSESSABLE: no window of the room has a point P: window 'glazing'" in r.output
    out = tmp_path / "o"
    r = invoke("check", path, "--out", out, "-q", "--set", "requirements.view=none")
    assert r.exit_code == 1
    s = json.loads((out / "report.json").read_text())["rooms"][0]["sunlight"]
    assert s["status"] == "not_assessable" and s["level"] is None and "above the window head" in s["reason"]


@pytest.mark.parametrize("value, shown", [(".nan", "rooms[0].floor_z"), (".inf", "rooms[0].floor_z"),
                                          ("1e400", "rooms[0].floor_z"), ("-.inf", "rooms[0].floor_z")])
def test_nan_and_infinity_in_the_project_file_name_the_key(tmp_path, value, shown):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    path.write_text(path.read_text().replace("floor_z: 0.0", f"floor_z: {value}"))
    for cmd in ("check", "validate"):
        one_line_error(invoke(cmd, path), f"project.yaml: {shown}: not a finite number")


def test_nan_in_a_set_override_names_the_key(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    one_line_error(invoke("check", path, "--set", "view.grid_spacing_m=.nan"), "view.grid_spacing_m: not a finite number")


def test_a_project_file_that_is_not_utf8(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    path.write_bytes(path.read_bytes().replace(b"Synthetic", b"Synth\xe9tic"))
    one_line_error(invoke("check", path), "project.yaml: not UTF-8 text (byte", "save the project file as UTF-8")


def test_unknown_time_zone_without_a_sunlight_section(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=None, view=FAST_VIEW,
                            location={"latitude": 52.0, "longitude": 4.0, "timezone": "Mars/Olympus"})
    one_line_error(invoke("check", path), "location.timezone: unknown IANA time zone 'Mars/Olympus'")


def test_an_obj_with_a_byte_order_mark_keeps_its_first_vertex(tmp_path):
    from en17037cli.io.obj import read_obj

    p = tmp_path / "bom.obj"
    p.write_bytes(b"\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    m = read_obj(p)
    assert m.vertices.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]] and m.triangles.tolist() == [[0, 1, 2]]


def test_degenerate_glazing_is_named(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    model = path.parent / "model.obj"
    lines, obj, out = model.read_text().splitlines(), None, []
    for line in lines:
        if line.startswith("o "):
            obj = line[2:]
        if obj == "glazing" and line.startswith("v "):
            x, y, z = map(float, line.split()[1:])
            line = f"v {x:.9f} {y:.9f} 1.5"  # every glazing vertex at one height: zero area
        out.append(line)
    model.write_text("\n".join(out) + "\n")
    one_line_error(invoke("check", path), "every face of the 1 object(s) on the 'window' layer is degenerate")


def test_stl_with_a_wrong_header_count(tmp_path):
    import struct

    import trimesh

    from en17037cli.io import read_model

    trimesh.creation.box(extents=(2.0, 3.0, 4.0)).export(tmp_path / "box.stl")
    data = bytearray((tmp_path / "box.stl").read_bytes())
    (tmp_path / "more.stl").write_bytes(data[:80] + struct.pack("<I", 20) + data[84:])
    m = read_model(tmp_path / "more.stl")
    assert m.triangles.shape == (12, 3)
    assert m.warnings == ["more.stl: binary STL header says 20 triangles, the file holds 12; all of them were read"]
    (tmp_path / "cut.stl").write_bytes(data[:-7])
    with pytest.raises(Exception, match="cut.stl: binary STL header says 12 triangles but the file holds 593 bytes"):
        read_model(tmp_path / "cut.stl")


# --- bounded cost -----------------------------------------------------------------------------

def test_a_tiny_grid_spacing_stops_before_any_work(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    t = time.perf_counter()
    line = one_line_error(invoke("check", path, "--set", "view.grid_spacing_m=1e-4"),
                          "rooms[0] 'box room': about ", "viewpoints", "raise --max-points")
    assert time.perf_counter() - t < 10
    # 4 and 6 m are multiples of 1e-4 m: 4 / 1e-4 x 6 / 1e-4 grid points over the 4 x 6 m floor (grid_lines
    # keeps the outermost lines off the outline: one line less than length / spacing + 1)
    assert "about 2,400,000,000 viewpoints" in line
    one_line_error(invoke("validate", path, "--set", "view.grid_spacing_m=1e-4"), "viewpoints")


def test_a_floor_given_in_millimetres_stops_before_any_work(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=None, view=FAST_VIEW)
    edit(path, lambda d: d["rooms"][0].update(floor=[[-2000, 0], [2000, 0], [2000, 6000], [-2000, 6000]]))
    one_line_error(invoke("check", path), "rooms[0] 'box room': about", "check the floor's units")


def test_max_points_raises_the_budget(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=None, view=FAST_VIEW)
    one_line_error(invoke("check", path, "--max-points", "3", "--set", "requirements.sunlight=none"), "budget of 3 viewpoints")
    r = invoke("check", path, "--max-points", "1000", "-q", "--out", tmp_path / "o", "--set", "requirements.sunlight=none")
    assert r.exit_code == 0  # 12 viewpoints, within the budget of 1000; view 'medium' as required


def test_yaml_alias_bomb_and_oversized_files_are_rejected_up_front(tmp_path):
    bomb = ["version: 1", "a: &a [x, x, x, x, x, x, x, x, x, x]"]
    for i in range(1, 9):
        bomb.append(f"{chr(97 + i)}: &{chr(97 + i)} [*{chr(96 + i)}, *{chr(96 + i)}, *{chr(96 + i)}, *{chr(96 + i)}, "
                    f"*{chr(96 + i)}, *{chr(96 + i)}, *{chr(96 + i)}, *{chr(96 + i)}, *{chr(96 + i)}, *{chr(96 + i)}]")
    (tmp_path / "bomb.yaml").write_text("\n".join(bomb) + "\n")
    t = time.perf_counter()
    one_line_error(invoke("validate", tmp_path / "bomb.yaml"), "YAML aliases expand to more than 1,000,000 values")
    assert time.perf_counter() - t < 5
    big = tmp_path / "big.yaml"
    big.write_text("version: 1\nname: " + "x" * (6 * 1024 * 1024) + "\n")
    one_line_error(invoke("check", big), "big.yaml: project file is 6.3 MB, over the 5 MB")


# --- output folders -----------------------------------------------------------------------

def test_an_input_error_touches_nothing_and_foreign_files_survive(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.json").write_text("my own report")
    (out / "notes.md").write_text("mine")
    one_line_error(invoke("check", path, "--out", out), "report.json there was written by someone else (no en17037 manifest)")
    assert (out / "report.json").read_text() == "my own report" and (out / "notes.md").read_text() == "mine"
    assert sorted(p.name for p in out.iterdir()) == ["notes.md", "report.json"]


def test_reports_replace_only_our_own_and_another_project_cannot_take_the_folder(tmp_path):
    a = box_room_project(tmp_path / "a", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    b = box_room_project(tmp_path / "b", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.md").write_text("mine")
    assert invoke("check", a, "--out", out, "-q").exit_code == 0
    manifest = json.loads((out / MANIFEST).read_text())
    figures = [f"figures/01-box-room-view-1.2m-{k}.png" for k in ("sight-angle", "distance", "layers", "level")]
    figures += ["figures/01-box-room-sunlight-hours.png", "figures/01-box-room-sunlight-fisheye-1.png"]
    assert manifest == {"tool": "en17037cli", "project": str(a.resolve()), "files": sorted([*REPORT_FILES, *figures])}
    assert invoke("check", a, "--out", out, "-q").exit_code == 0  # the same project replaces its reports
    assert invoke("check", a, "--out", out, "-q", "--no-plots").exit_code == 0  # ... and its pictures go with them
    assert sorted(p.name for p in out.iterdir()) == sorted([MANIFEST, "notes.md", *REPORT_FILES])
    one_line_error(invoke("check", b, "--out", out), f"daylight_points.csv there was written by project {a.resolve()}")  # the first of the files, sorted
    assert (out / "notes.md").read_text() == "mine"
    assert not [p for p in out.parent.iterdir() if p.name.startswith(TMP_PREFIX)]


def test_default_report_folder_is_per_project_file(tmp_path):
    a = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    b = a.parent / "variant.yaml"
    b.write_text(a.read_text())
    for p in (a, b):
        assert invoke("check", p, "-q").exit_code == 0
    assert (a.parent / "en17037-report" / "project" / "report.json").is_file()
    assert (a.parent / "en17037-report" / "variant" / "report.json").is_file()


@pytest.mark.parametrize("kind", ["read-only", "under-a-file", "proc"])
def test_an_output_folder_that_cannot_be_written(tmp_path, kind):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    if kind == "read-only":
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o500)
        out, expected = ro / "out", "is not writable"
        if os.access(ro, os.W_OK):  # root ignores the mode bits
            pytest.skip("running as root: a read-only folder is writable")
    elif kind == "under-a-file":
        (tmp_path / "afile").write_text("x")
        out, expected = tmp_path / "afile" / "out", "afile is a file, not a folder"
    else:
        out, expected = Path("/proc/en17037-out"), "--out /proc/en17037-out"
    one_line_error(invoke("check", path, "--out", out), expected)


def _spawn_check(path: Path, out: Path):
    # SIGINT back to its default in the child: a shell's background job (``make test &``) starts
    # with it ignored, and Python then installs no KeyboardInterrupt for it, as a user would expect
    return subprocess.Popen([sys.executable, "-m", "en17037cli", "check", str(path), "--out", str(out), "-q"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


#: A stopped run must be gone this long after its signal [s]: within a second on a quiet machine
#: (the exception unwinds, temporaries go, picture workers end; no wait for the engine's threads);
#: the bound leaves room for a loaded CI machine. Before issue 43 a run stopped while its view tasks
#: were queued waited for all of them (the 40 s of work below: "not exited 60 s later").
STOP_WITHIN_S = 5.0


@pytest.mark.parametrize("delay", [0.4, 1.5, 4.0])
@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signals_exit_by_convention_and_leave_no_temporaries(tmp_path, sig, code, delay):
    """At any moment of the run (importing, reading, tracing on the engine's threads), Ctrl-C or
    SIGTERM ends it promptly, by convention, with no temporaries and never part of a report."""
    # about 40 s of work (0.05 m grid, 0.5 deg cells): the signal arrives well before its end
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight={"date": "worst"},
                            view={"grid_spacing_m": 0.05, "angular_resolution_deg": 0.5})
    out = tmp_path / "out"
    proc = _spawn_check(path, out)
    time.sleep(delay)
    sent = time.perf_counter()
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    took = time.perf_counter() - sent
    assert proc.returncode == code, err
    assert err.strip().splitlines()[-1] in ("error: interrupted", "error: terminated")
    assert took < STOP_WITHIN_S, f"exited {took:.1f} s after the signal"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(TMP_PREFIX)]
    # either no report at all, or a whole set: never part of one
    present = [n for n in REPORT_FILES if (out / n).exists()]
    assert present in ([], list(REPORT_FILES))


def test_usage_errors_are_one_line(tmp_path):
    one_line_error(invoke("check"), "Missing argument 'PROJECT_FILE'", "(see cli check --help)")  # CliRunner names the program after the function
    one_line_error(invoke("nope"), "No such command 'nope'")
    one_line_error(invoke("check", "x.yaml", "--only", "glint"), "Invalid value for '--only'")


def test_memory_of_this_process_is_sane():
    """Guard for the tests above: they run in this process, which must not have grown past 2 GB."""
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024 < 2048
