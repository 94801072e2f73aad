"""The en17037 command: exit codes, one-line errors, reports, determinism."""
from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.report.write import REPORT_FILES
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.schemas import load_schema

ROOT = Path(__file__).resolve().parents[1]
SEED = ROOT / "sample_projects" / "seed-office" / "project.yaml"
FAST = ["--set", "view.eye_heights_m=[1.2]", "--set", "view.grid_spacing_m=1.5", "--set", "view.angular_resolution_deg=3",
        "--set", "view.refine_levels=1", "--set", "sunlight.period.end=02-03", "--set", "sunlight.date=02-02"]


def invoke(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


@pytest.fixture
def project(tmp_path):
    return box_room_project(tmp_path / "box", BoxRoom(), sunlight={"date": "worst"}, view={"grid_spacing_m": 1.0})


def edit(path: Path, fn):
    doc = yaml.safe_load(path.read_text())
    fn(doc)
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def test_check_writes_valid_reports_and_exit_code(project, tmp_path):
    out = tmp_path / "out"
    r = invoke("check", project, "--out", out, "--quiet", *FAST, "--set", "requirements.view=high")
    # box room: a 25 m street caps the outside distance at 'medium' < required 'high' -> exit 1
    assert r.exit_code == 1, r.output
    for name in REPORT_FILES:
        assert (out / name).is_file()
    report = json.loads((out / "report.json").read_text())
    jsonschema.Draft202012Validator(load_schema("report")).validate(report)
    room = report["rooms"][0]
    assert room["view"]["status"] == "fail" and report["status"] == "fail"
    assert room["sunlight"]["windows"][0]["point_p_m"] == [0.0, 0.001, 1.2]
    assert len(room["sunlight"]["days"]) == 3
    assert report["inputs"]["model_files"]["model.obj"].startswith("sha256:")
    md = (out / "report.md").read_text()
    assert "| box room | view out (5.2) | " + room["view"]["level"] + " | high | **FAIL** | outside distance: 0 % of points reach high" in md
    assert room["view"]["eye_heights"][0]["level_by_criterion"]["outside_distance"] == "medium"
    # requiring only 'minimum' makes it pass: exit 0
    r = invoke("check", project, "--out", out, "--quiet", *FAST, "--set", "requirements.view=minimum")
    assert r.exit_code == 0, r.output


def test_reports_are_byte_identical_apart_from_timings(project, tmp_path):
    texts = []
    for k in range(2):
        out = tmp_path / f"o{k}"
        invoke("check", project, "--out", out, "--quiet", *FAST)
        report = json.loads((out / "report.json").read_text())
        report.pop("timings_s")
        texts.append((json.dumps(report), *((out / n).read_text() for n in REPORT_FILES[1:]),
                      *(p.read_bytes() for p in sorted((out / "figures").iterdir()))))
    assert texts[0] == texts[1]


def test_only_runs_one_check(project, tmp_path):
    out = tmp_path / "out"
    r = invoke("check", project, "--out", out, "--quiet", "--only", "sunlight", *FAST)
    report = json.loads((out / "report.json").read_text())
    # view is required (medium) but did not run: not assessed, which fails the run
    assert report["rooms"][0]["view"] == {"level": None, "required": "medium", "status": "not_assessed",
                                          "reason": "--only sunlight left it out"}
    assert report["inputs"]["checks_run"] == ["sunlight"]
    assert r.exit_code == 1
    r = invoke("check", project, "--out", out, "--quiet", "--only", "sunlight", "--set", "requirements.view=none", *FAST)
    assert json.loads((out / "report.json").read_text())["rooms"][0]["view"] is None and r.exit_code == 0


def _bad(tmp_path, project, fn, expected: str):
    out = tmp_path / "out"
    out.mkdir(exist_ok=True)
    (out / "notes.txt").write_text("mine")  # a user's file in the report folder
    edit(project, fn) if fn else None
    r = invoke("check", project, "--out", out, "--quiet")
    assert r.exit_code == 2, r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1, r.output
    assert expected in lines[0], lines[0]
    assert not any((out / n).exists() for n in REPORT_FILES)  # no partial report
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"] and (out / "notes.txt").read_text() == "mine"


def test_missing_model_file(tmp_path, project):
    _bad(tmp_path, project, lambda d: d["model"]["files"][0].update(path="nope.obj"), "model.files[0].path: file not found")


def test_unknown_key(tmp_path, project):
    _bad(tmp_path, project, lambda d: d["view"].update(grid=1), "view: unknown key 'grid'")


def test_wrong_type(tmp_path, project):
    _bad(tmp_path, project, lambda d: d["rooms"][0].update(floor_z="ground floor"), "rooms[0].floor_z: expected number, got \"ground floor\"")


def test_unknown_layer(tmp_path, project):
    _bad(tmp_path, project, lambda d: d["model"]["files"][0]["layers"][0].update(layer="walls"),
         "model.files[0].layers[0].layer: expected one of window, interior, ground, landscape, ignore, got \"walls\"")


def test_face_matching_no_rule(tmp_path, project):
    _bad(tmp_path, project, lambda d: d["model"]["files"][0]["layers"].pop(), "face")


def test_room_without_windows(tmp_path, project):
    _bad(tmp_path, project, lambda d: d["rooms"][0].update(windows=["skylight*"]),
         "rooms[0] 'box room'.windows: no window matches ['skylight*']; windows found: 'glazing'")


def test_corrupt_obj(tmp_path, project):
    (project.parent / "model.obj").write_text("v 1 2\nf 1 2 3\n")
    _bad(tmp_path, project, None, "model.obj:1: corrupt OBJ vertex line")


def test_unknown_time_zone(tmp_path, project):
    _bad(tmp_path, project, lambda d: d["location"].update(timezone="Europe/Atlantis"),
         "location.timezone: unknown IANA time zone 'Europe/Atlantis'")


def test_missing_project_file(tmp_path):
    r = invoke("check", tmp_path / "none.yaml", "--quiet")
    assert r.exit_code == 2 and "none.yaml: project file not found" in r.output


def test_bad_set_override(project):
    r = invoke("check", project, "--quiet", "--set", "sunlight.timestep_min=-3")
    assert r.exit_code == 2 and "sunlight.timestep_min: expected a value >= 0.0166, got -3" in r.output


def test_validate_prints_layers_and_windows(project):
    r = invoke("validate", project)
    assert r.exit_code == 0
    assert "faces per layer: window 2, interior 18, ground 2, landscape 10" in r.output
    assert "window 'glazing': 2.800 m², outward normal (0.0000, -1.0000, 0.0000)" in r.output


def test_validate_seed_office():
    r = invoke("validate", SEED)
    assert r.exit_code == 0, r.output
    assert "window 'Geometry Window glazing': 4.060 m²" in r.output  # 2.90 m x 1.40 m
    assert "outward normal (0.3817, -0.9243, 0.0000)" in r.output


def test_seed_office_sunlight_reports_all_49_days(tmp_path):
    out = tmp_path / "seed"
    r = invoke("check", SEED, "--out", out, "--quiet", "--only", "sunlight", "--set", "requirements.view=none",
               "--set", "requirements.daylight=none")
    assert r.exit_code == 0, r.output
    s = json.loads((out / "report.json").read_text())["rooms"][0]["sunlight"]
    assert len(s["days"]) == 49 and s["days"][0]["date"] == "2026-02-01" and s["days"][-1]["date"] == "2026-03-21"
    # P: horizontal centre of the window, sill 10.35 + 0.3 = 10.65 m, on the room side of the opening
    p = s["windows"][0]["point_p_m"]
    assert abs(p[2] - 10.65) < 1e-6
    assert all(d["intervals"][0][0].endswith("+01:00") for d in s["days"] if d["intervals"])


def test_schema_command_prints_json():
    r = invoke("schema", "project")
    assert json.loads(r.output)["title"] == "en17037cli project file"


def test_installed_console_script(project, tmp_path):
    exe = shutil.which("en17037", path=str(Path(sys.executable).parent))
    assert exe, "console script not installed"
    p = subprocess.run([exe, "check", str(project), "--out", str(tmp_path / "sub"), "--only", "sunlight",
                        "--set", "requirements.view=none", *FAST],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "reports in" in p.stderr


def test_seed_office_view_runs_at_both_eye_heights(tmp_path):
    out = tmp_path / "seedview"
    r = invoke("check", SEED, "--out", out, "--quiet", "--only", "view", "--set", "view.grid_spacing_m=1.5",
               "--set", "view.angular_resolution_deg=4", "--set", "view.refine_levels=1")
    assert r.exit_code == 1, r.output  # sunlight is required but left out by --only: not assessed
    report = json.loads((out / "report.json").read_text())
    jsonschema.Draft202012Validator(load_schema("report")).validate(report)
    v = report["rooms"][0]["view"]
    assert [e["eye_height_m"] for e in v["eye_heights"]] == [1.2, 1.7]
    pts = v["eye_heights"][0]["points"]
    # the floor (3.9 x 8.5 m between the walls' inner faces, notched by the columns) inset by 0.5 m, and a
    # 1.5 m grid centred on its 2.9 x 7.5 m rectangle: 2 lines across; 7.5 m is a multiple of 1.5 m, so
    # 5 lines along (6 m, 0.75 m in from each end: grid_lines never puts a line on the outline), and
    # all 2 x 5 points lie inside the notched outline
    assert len(pts) == 10
    # bounded by hand: each point's sight angle is at most the angle between the glazing's two ends
    # (x, y of the window's corners in geometry/ref_room_window.obj) seen from the point, and the
    # two 5 cm mullions and 5 cm reveals take less than a third of it from at least 1 m away
    import numpy as np
    ends = np.array([[-36.0302391, 36.2457428], [-33.3497925, 37.3526268]])  # glazing ends, model x, y [m]
    for p in pts:
        a, b = ends - np.array(p["point"][:2])
        full = np.degrees(np.arccos(a @ b / np.linalg.norm(a) / np.linalg.norm(b)))
        assert 2 / 3 * full <= p["horizontal_sight_angle_deg"] <= full + 3e-4, (p, full)
    # counted, not silent: 90 zero-area faces of the context (ear-clipping slivers of self-intersecting n-gons)
    assert "90 degenerate, NaN or infinite faces dropped" in report["warnings"]
    assert any(re.fullmatch(r"[1-9]\d* degenerate, NaN or infinite faces dropped", w) for w in report["warnings"])
    assert "| office | view out (5.2) | minimum | medium | **FAIL** | sight angle: 60 % of points reach medium at 1.2 m eye height, 75 % needed |" in (out / "report.md").read_text()
