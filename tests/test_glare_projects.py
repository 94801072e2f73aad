"""Protection from glare (5.4) on whole projects: the seed office (sample_projects/seed-office/
project-glare.yaml) and a real IFC house (AC20-FZK-Haus, ../shared/data/real-models) each carry a
5.4 verdict in every report format; the project file's glare section and its errors; the exit codes."""
from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import jsonschema
import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.samples.weather import synthetic_epw
from en17037cli.schemas import load_schema

pytest.importorskip("pyradiance")
ROOT = Path(__file__).resolve().parents[1]
SEED = ROOT / "sample_projects" / "seed-office" / "project-glare.yaml"
SEED_EPW = SEED.parent / "weather" / "delft-synthetic.epw"
FZK = ROOT.parent / "shared" / "data" / "real-models" / "AC20-FZK-Haus.ifc"
FORMATS = ("report.json", "report.md", "report.html", "rooms.csv", "glare_points.csv", "glare_hours.csv")


def seed_weather() -> Path:
    """The seed office's synthetic weather (make samples writes it; the same file every time)."""
    if not SEED_EPW.is_file():
        SEED_EPW.parent.mkdir(parents=True, exist_ok=True)
        synthetic_epw(SEED_EPW, lat=52.0116, lon=4.3571)
    return SEED_EPW


def check(project: Path, out: Path, *args: str):
    r = CliRunner().invoke(cli, ["check", str(project), "--out", str(out), *args])
    return r, {n: (out / n).read_text("utf-8") for n in FORMATS if (out / n).exists()}


@pytest.fixture(scope="module")
def seed(tmp_path_factory):
    seed_weather()
    out = tmp_path_factory.mktemp("seed-glare")
    return check(SEED, out)


def test_seed_office_glare_in_every_format(seed):
    r, files = seed
    assert r.exit_code == 1, r.output  # fails by design: glare protection misses minimum
    doc = json.loads(files["report.json"])
    jsonschema.validate(doc, load_schema("report"))
    g = doc["rooms"][0]["glare"]
    assert g["status"] == "fail" and g["level"] == "none" and g["required"] == "minimum"
    assert g["usage_hours"] == 2610  # 261 weekdays of 2026, 08:00 to 18:00
    assert len(g["positions"]) == 3 and {p["label"].rsplit(", ", 1)[-1] for p in g["positions"]} >= {"towards", "left", "right"}
    worst = g["positions"][g["worst_position"]]
    assert worst["dgp_5pct"] == g["dgp_5pct"] == max(p["dgp_5pct"] for p in g["positions"])
    # the 5 % rule as the report states it: more than 130 hours over 0.45 at the worst view
    assert worst["hours_over"]["0.45"] > 130 and g["limiting"]["margin"] < 0
    assert g["sun_in_view_hours"] > 0 and g["transmittance_needed_sun_hidden"] is not None
    ref = g["reference_check"]
    assert len(ref["hours"]) == 3 and ref["max_abs_dgp_difference"] <= 0.05  # measured 0.020 (docs/glare.md)
    assert g["moments"] and all(m["dgp"] is not None for m in g["moments"])
    both = g["with_sunlight"]
    assert both["passes_sunlight_fails_glare"] and both["sunlight_level"] == "high"
    assert doc["summary"]["rooms_glare_required"] == 1 and doc["summary"]["rooms_glare_pass"] == 0
    # the hours of the worst view, in the JSON and in glare_hours.csv
    rows = list(csv.DictReader(io.StringIO(files["glare_hours.csv"])))
    assert len(rows) == 2610 and float(rows[0]["dgp"]) == g["hourly"]["dgp"][0]
    assert sum(float(x["dgp"]) > 0.45 for x in rows) == worst["hours_over"]["0.45"]
    points = list(csv.DictReader(io.StringIO(files["glare_points.csv"])))
    assert len(points) == 3 and float(points[g["worst_position"]]["dgp_5pct"]) == worst["dgp_5pct"]
    assert "Protection from glare: none" in files["report.md"] and "Sunlight and glare together" in files["report.md"]
    assert "Protection from glare" in files["report.html"] and "5.4 (protection from glare)" in files["report.html"]
    assert "glare-positions.png" in files["report.md"] and "glare-hours.png" in files["report.md"]
    assert any(line.startswith("office,glare,none,minimum,fail") for line in files["rooms.csv"].splitlines())
    assert "glare" in r.output and "DGP" in r.output
    # a batch's summary row of it: the level and status, no hours of sunlight
    from en17037cli.report.summary import room_rows

    row = next(x for x in room_rows(doc) if x["criterion"] == "glare")
    assert (row["level"], row["status"], row["hours_h"]) == ("none", "fail", None)


def test_seed_office_glare_hours_by_hand(seed):
    """The report's DGP exceeded in 5 % of the hours is the 131st largest of the worst view's hours."""
    _, files = seed
    g = json.loads(files["report.json"])["rooms"][0]["glare"]
    dgp = np.sort(np.array(g["hourly"]["dgp"]))[::-1]
    assert dgp[130] == pytest.approx(g["dgp_5pct"], abs=1e-4)


@pytest.mark.skipif(not FZK.is_file(), reason="../shared/data/real-models is absent")
def test_real_ifc_house_glare_in_every_format(tmp_path):
    pytest.importorskip("ifcopenshell")
    synthetic_epw(tmp_path / "site.epw", lat=49.1, lon=8.44)  # the house's IfcSite: 49°6' N, 8°26' E
    doc = {"version": 1, "name": "FZK-Haus", "model": {"files": [{"path": str(FZK)}]}, "location": {"timezone": "Europe/Berlin"},
           "rooms": [{"ifc_spaces": "*"}], "sunlight": {"date": "worst"},
           # one reference hour per room and fewer rays: the test judges the house's reading, not the accuracy
           "glare": {"weather": "site.epw", "view_rays": 8000, "reference": {"hours": 1}, "radiance": {"ad": 1024, "replicates": 2}},
           "requirements": {"view": "none", "sunlight": "minimum", "glare": "minimum"}}
    path = tmp_path / "fzk.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    r, files = check(path, tmp_path / "out", "--no-plots")
    assert r.exit_code == 1, r.output
    rep = json.loads(files["report.json"])
    jsonschema.validate(rep, load_schema("report"))
    rooms = [room for room in rep["rooms"] if room.get("glare")]
    assert len(rooms) == 6  # the six spaces with windows
    for room in rooms:
        g = room["glare"]
        assert g["status"] in ("pass", "fail") and g["usage_hours"] == 2610
        assert len(g["positions"]) == 3 * len(room["windows"])
        assert g["reference_check"]["max_abs_dgp_difference"] <= 0.1
    levels = {room["name"]: room["glare"]["level"] for room in rooms}
    assert set(levels.values()) - {"none"}  # not every room fails: the north rooms see no sun
    points = list(csv.DictReader(io.StringIO(files["glare_points.csv"])))
    assert len(points) == sum(len(room["glare"]["positions"]) for room in rooms)
    assert len(list(csv.DictReader(io.StringIO(files["glare_hours.csv"])))) == 6 * 2610
    assert files["report.md"].count("**Protection from glare:") == 6
    assert files["report.html"].count("<h3>Protection from glare:") == 6


def _box_project(tmp_path, glare: dict, **extra) -> Path:
    from en17037cli.samples.box import BoxRoom, box_room_project

    path = box_room_project(tmp_path / "box", BoxRoom(), sunlight={"date": "worst"})
    doc = yaml.safe_load(path.read_text())
    doc["glare"] = glare
    doc.setdefault("requirements", {})["view"] = "none"
    doc.update(extra)
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


@pytest.mark.parametrize("glare, words", [
    ({}, "glare.weather: the annual glare check needs an EPW weather file"),
    ({"weather": "nowhere.epw"}, "glare.weather: file not found"),
    ({"times": ["21 December, noon"]}, "glare.times[0]"),
    ({"times": ["2026-12-21T12:00"], "usage": {"start": "18:00", "end": "08:00"}}, "glare.usage: start 18:00 is not before end 08:00"),
    ({"times": ["2026-12-21T12:00"], "positions": [{"x": 500, "y": 500, "z": 1.2, "direction_deg": 180}]},
     "glare.positions[0]: (500, 500, 1.2) stands over no room's floor"),
    ({"times": ["2026-12-21T12:00"], "dgp_limits": {"minimum": 0.35, "medium": 0.40, "high": 0.45}}, "glare.dgp_limits"),
    ({"times": ["2026-12-21T12:00"], "shading": {"transmittance": 0}}, "glare.shading"),
])
def test_bad_glare_sections_are_one_line_errors(tmp_path, glare, words):
    path = _box_project(tmp_path, glare)
    r = CliRunner().invoke(cli, ["check", str(path), "--out", str(tmp_path / "out")])
    assert r.exit_code == 2 and words in r.output, r.output
    assert not (tmp_path / "out" / "report.json").exists()  # no partial report


def test_point_in_time_checks_without_weather_are_not_a_verdict(tmp_path):
    """Without a weather file the moments are evaluated (CIE clear sky with sun) but the room's level is
    not assessable: the required check fails (exit 1), never a pass on nothing."""
    path = _box_project(tmp_path, {"times": ["2026-06-21T13:00"], "directions": ["towards"], "reference": {"hours": 0}})
    r, files = check(path, tmp_path / "out", "--no-plots", "--only", "glare")
    assert r.exit_code == 1, r.output
    g = json.loads(files["report.json"])["rooms"][0]["glare"]
    assert g["status"] == "not_assessable" and "no weather file" in g["reason"]
    assert len(g["moments"]) == 1 and 0.0 < g["moments"][0]["dgp"] <= 1.0 and "gensky" in g["moments"][0]["sky"]


def test_sensitivity_study_tries_the_glare_choices(tmp_path):
    """study sensitivity assesses 5.4 under the open choices it is given (here the usage time on every day
    and the low-light correction; the others' ranges emptied), each a row of sensitivity.csv."""
    synthetic_epw(tmp_path / "site.epw")
    empty = {k: [] for k in ("glare.facade_distance_m", "glare.eye_height_m", "glare.directions", "glare.source_threshold_cd_m2",
                             "glare.sky_subdivision")}
    path = _box_project(tmp_path, {"weather": "../site.epw", "view_rays": 5000, "reference": {"hours": 0},
                                   "radiance": {"ad": 512, "replicates": 2}},
                        sensitivity={"ranges": {**empty, "glare.usage": ["all days"], "glare.low_light_correction": [True]}},
                        sunlight={"date": "worst", "period": {"start": "02-01", "end": "02-02"}})
    r = CliRunner().invoke(cli, ["study", "sensitivity", str(path), "--out", str(tmp_path / "s")])
    assert r.exit_code == 0, r.output
    rows = [x for x in csv.DictReader(open(tmp_path / "s" / "sensitivity.csv")) if x["check"] == "glare"]
    assert [(x["choice"], x["value"]) for x in rows] == [("default", "project"), ("glare.usage", "all days"),
                                                         ("glare.low_light_correction", "True")]
    doc = json.loads((tmp_path / "s" / "sensitivity.json").read_text())
    glare = next(x for x in doc["rooms"] if x["check"] == "glare")
    assert glare["required"] == "minimum" and glare["verdict"] in ("robust pass", "robust fail") or glare["verdict"].startswith("depends")
