"""Daylight provision (5.1): the rules of Table A.1, the two aggregation orders, the EPW reader, the
glazing conversion, the project file's daylight section and a small climate-based run."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli import standard
from en17037cli.cli import cli
from en17037cli.criteria.daylight.assess import climate_shares, upper_median
from en17037cli.criteria.daylight.radiance import glass_transmissivity
from en17037cli.samples.box import BoxRoom, box_room_project
from en17037cli.samples.weather import synthetic_epw
from en17037cli.standard import Thresholds
from en17037cli.weather.epw import read_epw

THRESHOLDS = Thresholds.from_dict(standard.THRESHOLDS)


def test_daylight_level_table_a1():
    lv = lambda t, m: standard.daylight_level(t, m)  # noqa: E731
    full = {"minimum": 1.0, "medium": 1.0, "high": 1.0}
    assert lv(full, full) == 3
    # medium's target on 50 % exactly, its minimum target on 94 %: minimum only
    assert lv({"minimum": 0.8, "medium": 0.5, "high": 0.1}, {"minimum": 0.99, "medium": 0.94, "high": 0.2}) == 1
    assert lv({"minimum": 0.49, "medium": 0.1, "high": 0.0}, full) == 0


def test_aggregation_orders_by_hand():
    # 4 points x 4 hours [lx]; target 300 lx (minimum level)
    e = np.array([[400, 400, 0, 0],      # 2 of 4 hours: half the hours -> reaches (hours_first)
                  [400, 0, 0, 0],        # 1 of 4
                  [400, 400, 400, 0],    # 3 of 4
                  [0, 0, 0, 0]], float)
    t, m, per_point = climate_shares(e, THRESHOLDS, "hours_first")
    assert per_point[300.0].tolist() == [0.5, 0.25, 0.75, 0.0]
    assert t["minimum"] == 0.5  # points 1 and 3 reach 300 lx on >= 50 % of the hours
    assert m["medium"] == 0.5  # medium's minimum target is 300 lx too
    assert m["minimum"] == 0.5 and t["medium"] == 0.0  # 100 lx: the same two points; 500 lx: none
    # points first: per hour the share of the plane >= 300 lx is 3/4, 2/4, 1/4, 0; the share reached on
    # at least half (2 of 4) of the hours is the 2nd largest: 1/2
    t2, _, _ = climate_shares(e, THRESHOLDS, "points_first")
    assert t2["minimum"] == 0.5
    # a case where the orders differ: every point lit on a different half of the hours
    e = np.array([[400, 400, 0, 0], [0, 400, 400, 0], [0, 0, 400, 400], [400, 0, 0, 400]], float)
    assert climate_shares(e, THRESHOLDS, "hours_first")[0]["minimum"] == 1.0  # each point: 2 of 4 hours
    assert climate_shares(e, THRESHOLDS, "points_first")[0]["minimum"] == 0.5  # each hour: 2 of 4 points
    assert upper_median([0.1, 0.9, 0.5], 0.5) == 0.5


def test_glass_transmissivity():
    # Radiance reference manual: tv 0.88 (clear single glazing) is tn 0.96; the conversion is exact at
    # normal incidence, tv = tn (1 - R)² / (1 - R² tn²) with R = ((1.52 - 1) / (1.52 + 1))² is its inverse
    assert float(glass_transmissivity(0.88)) == pytest.approx(0.96, abs=0.002)
    tn = glass_transmissivity(np.array([0.3, 0.7]))
    r = ((1.52 - 1) / (1.52 + 1)) ** 2
    assert tn * (1 - r) ** 2 / (1 - r * r * tn * tn) == pytest.approx([0.3, 0.7], abs=2e-3)


def test_epw_reader_and_median(tmp_path):
    w = read_epw(synthetic_epw(tmp_path / "s.epw"))
    assert len(w.hour) == 8760 and w.latitude == 52.0
    hours = w.daylight_hours()
    assert len(hours) == 4380 and np.all(np.diff(hours) > 0)
    top = np.sort(w.diffuse_lx)[::-1][:4380]  # the half of the year with the most diffuse light, by hand
    assert w.median_diffuse_lx() == pytest.approx(0.5 * (top[2189] + top[2190]))
    assert w.diffuse_lx[hours].min() >= np.sort(w.diffuse_lx)[::-1][4379]


def test_epw_start_day(tmp_path):
    # the synthetic year 2026 starts on a Thursday (1 January 2026, by the calendar) and its header says so
    path = synthetic_epw(tmp_path / "s.epw")
    lines = path.read_text().splitlines()
    assert lines[7] == "DATA PERIODS,1,1,Data,Thursday, 1/ 1,12/31"
    w = read_epw(path)
    assert w.start_weekday == 3 and w.weekday_note is None
    # a header naming another day for rows of one calendar year is read as written and noted
    lines[7] = "DATA PERIODS,1,1,Data,Sunday, 1/ 1,12/31"
    path.write_text("\n".join(lines) + "\n")
    w = read_epw(path)
    assert w.start_weekday == 6 and "Sunday" in w.weekday_note and "2026-01-01, is a Thursday" in w.weekday_note
    # a typical year stitched from months of different years (1986 January, ...) has no calendar to check against
    real = read_epw(REAL_EPW)
    assert real.start_weekday == 6 and real.weekday_note is None
    assert real.place == "Chicago Ohare Intl Ap, IL, USA" and real.median_diffuse_lx() == 15900.0


REAL_EPW = __import__("pathlib").Path(__file__).resolve().parents[1] / "sample_projects" / "weather" / \
    "USA_IL_Chicago-OHare.Intl.AP.725300_TMY3.epw"


def test_epw_errors(tmp_path):
    from en17037cli.errors import InputError

    p = tmp_path / "bad.epw"
    p.write_text("not,an,epw\n")
    with pytest.raises(InputError, match="not an EPW weather file"):
        read_epw(p)
    lines = synthetic_epw(tmp_path / "s.epw").read_text().splitlines()
    for bad, message in (("DATA PERIODS,1,4,Data,Thursday, 1/ 1,12/31", "4 records per hour"),
                         ("DATA PERIODS,1,1,Data,Thorsday, 1/ 1,12/31", "'Thorsday' is not a day of the week")):
        p.write_text("\n".join(lines[:7] + [bad] + lines[8:]) + "\n")
        with pytest.raises(InputError, match=message):
            read_epw(p)


def _project(tmp_path, daylight: dict, **box):
    path = box_room_project(tmp_path, BoxRoom(building_height=0.0, **box), view=None, sunlight=None)
    doc = yaml.safe_load(path.read_text())
    doc["daylight"] = daylight
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def test_daylight_section_errors(tmp_path):
    path = _project(tmp_path, {"method": "climate_based"})
    r = CliRunner().invoke(cli, ["validate", str(path)])
    assert r.exit_code == 2 and "daylight.weather: required by daylight.method: climate_based" in r.output
    path = _project(tmp_path, {})
    r = CliRunner().invoke(cli, ["validate", str(path)])
    assert r.exit_code == 2 and "daylight.median_diffuse_lx" in r.output
    path = _project(tmp_path, {"median_diffuse_lx": 14000, "radiance": {"ad": 0}})
    r = CliRunner().invoke(cli, ["validate", str(path)])
    assert r.exit_code == 2 and "daylight.radiance.ad" in r.output


def test_no_daylight_section_never_imports_pyradiance(tmp_path):
    path = box_room_project(tmp_path, BoxRoom(), sunlight=None, view={"grid_spacing_m": 2.0, "angular_resolution_deg": 5})
    code = ("import sys; from en17037cli.project.load import load_project; from en17037cli.pipeline import run; "
            f"run(load_project({str(path)!r})); print('pyradiance' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@pytest.fixture(scope="module")
def climate_report(tmp_path_factory):
    pytest.importorskip("pyradiance")
    d = tmp_path_factory.mktemp("climate")
    synthetic_epw(d / "site.epw")
    path = _project(d, {"method": "climate_based", "weather": "site.epw", "grid_spacing_m": 1.0, "sun_subdivision": 2,
                        "radiance": {"ab": 1, "ad": 128, "replicates": 2}})
    r = CliRunner().invoke(cli, ["check", str(path), "--out", str(d / "out"), "--no-plots", "--quiet"], catch_exceptions=False)
    assert r.exit_code in (0, 1), r.output
    return json.loads((d / "out" / "report.json").read_text()), (d / "out" / "daylight_points.csv").read_text()


def test_climate_based_run(climate_report):
    import jsonschema

    from en17037cli.schemas import load_schema

    report, csv_text = climate_report
    jsonschema.validate(report, load_schema("report"))
    sec = report["rooms"][0]["daylight"]
    assert sec["method"] == "climate_based" and sec["daylight_hours"] == 4380
    shares = [p["share_of_hours"] for p in sec["points"]]
    assert len(shares) == 15 and all(0 <= v <= 1 for s in shares for v in s.values())
    # a higher illuminance is reached on no more hours, point by point
    assert all(s["100"] >= s["300"] >= s["500"] >= s["750"] for s in shares)
    # near the window more hours reach 300 lx than at the back (the glazing faces -y)
    near = [p["share_of_hours"]["300"] for p in sec["points"] if p["point"][1] < 2]
    back = [p["share_of_hours"]["300"] for p in sec["points"] if p["point"][1] > 4]
    assert min(near) > max(back)
    assert csv_text.splitlines()[0].endswith("share_of_hours_750lx_error,room_source_ids")
    assert report["summary"]["rooms_daylight_required"] == 1


REAL_DUPLEX = __import__("pathlib").Path(__file__).resolve().parents[2] / "shared" / "data" / "real-models" / "Duplex_A_20110907.ifc"


@pytest.mark.skipif(not REAL_DUPLEX.is_file(), reason="../shared/data/real-models absent")
def test_real_ifc_carries_a_daylight_verdict(tmp_path):
    # a real Revit export, every IfcSpace: each room the other checks assess gets a 5.1 level; the
    # glazed living rooms (two windows each) see more daylight than the kitchens (one)
    pytest.importorskip("pyradiance")
    path = tmp_path / "project.yaml"
    path.write_text(yaml.safe_dump({
        "version": 1, "name": "Duplex", "model": {"files": [{"path": str(REAL_DUPLEX)}]},
        "location": {"timezone": "America/Chicago"}, "rooms": [{"ifc_spaces": "*"}],
        "daylight": {"median_diffuse_lx": 13300, "grid_spacing_m": 1.0, "radiance": {"ab": 2, "ad": 128, "replicates": 2}},
        "requirements": {"daylight": "minimum", "view": "none", "sunlight": "none"}}))
    r = CliRunner().invoke(cli, ["check", str(path), "--out", str(tmp_path / "out"), "--no-plots", "--quiet"],
                           catch_exceptions=False)
    assert r.exit_code == 1, r.output  # some rooms miss minimum
    rooms = {x["name"]: x["daylight"] for x in json.loads((tmp_path / "out" / "report.json").read_text())["rooms"]}
    judged = {k: v for k, v in rooms.items() if v and v["status"] in ("pass", "fail")}
    assert len(judged) >= 8 and all(v["level"] in standard.LEVELS for v in judged.values())
    living = [v["median_daylight_factor_pct"] for k, v in judged.items() if k.startswith("Living")]
    kitchen = [v["median_daylight_factor_pct"] for k, v in judged.items() if k.startswith("Kitchen")]
    assert living and kitchen and min(living) > max(kitchen)


def test_sensitivity_tries_the_aggregation_order(tmp_path):
    pytest.importorskip("pyradiance")
    from en17037cli.studies.sensitivity import sensitivity

    synthetic_epw(tmp_path / "site.epw")
    path = _project(tmp_path, {"method": "climate_based", "weather": "site.epw", "grid_spacing_m": 1.5, "sun_subdivision": 1,
                               "radiance": {"ab": 1, "ad": 64, "replicates": 2}})
    doc = yaml.safe_load(path.read_text())
    doc["sensitivity"] = {"ranges": {"daylight.radiance.ab": [2], "daylight.radiance.ad": [64], "daylight.sky_subdivision": [1]}}
    doc["requirements"] = {"daylight": "minimum"}
    path.write_text(yaml.safe_dump(doc))
    out = sensitivity(path, tmp_path / "sens", log=lambda m: None)
    rows = [r for r in out["rooms"] if r["check"] == "daylight"]
    assert len(rows) == 1
    csv_text = (tmp_path / "sens" / "sensitivity.csv").read_text()
    assert "daylight,daylight.aggregation,points_first" in csv_text  # the other order, tried
    assert "daylight,daylight.radiance.ab,2" in csv_text
    assert "daylight.radiance.ad" not in csv_text and "daylight.sky_subdivision" not in csv_text  # the project's own values


def test_replicates_lay_their_own_grids():
    # Radiance samples an n x n grid, n = floor(sqrt(ad) + 0.5) at a point of rtrace -I: replicates
    # whose -ad rounded to one n came out identical (512 and 548 are both 23 x 23), their spread 0
    from en17037cli.criteria.daylight.radiance import replicate_divisions

    for ad, reps in ((512, 4), (64, 8), (4096, 4), (100, 3)):
        n = [int(np.sqrt(a) + 0.5) for a in replicate_divisions(ad, reps)]
        assert len(set(n)) == reps and n[0] ** 2 >= ad
