"""The convergence study on a small box-room project (the long studies stay out of CI)."""
from __future__ import annotations

import csv

import numpy as np
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.studies import convergence as study

SUN = {"date": "02-01", "period": {"start": "02-01", "end": "02-01"}}


def test_tolerance_ladder_converges_at_first_order(tmp_path):
    """Bisection halves the bracket per step: the error of the hours falls like the tolerance (the
    sampled method, whose brackets start at the timestep; the exact method's start at its knots)."""
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN)
    lad = study.Ladder("sunlight.tolerance_s", (30.0, 10.0, 1.0, 0.1), {"sunlight.tolerance_s": 0.001}, ("sun_time",),
                       extra={"sunlight.method": "sampled"})
    res = study.convergence(path, tmp_path / "out", (lad,), log=lambda m: None)
    errors = [r["error"] for r in res["rows"]]
    assert all(a >= b for a, b in zip(errors, errors[1:]))  # finer never worse
    assert 0.7 < res["orders"][("sunlight.tolerance_s", "sun_time")] < 1.3
    # each rung's own estimate covers its error (against a reference 1000 times finer)
    assert all(r["error"] <= r["estimate"] + 0.01 for r in res["rows"])
    assert all(r["over_estimate"] == 0 for r in res["rows"])  # day by day, not only the largest
    # targets: 2 s for hours; the cheapest rung within it is the coarsest that meets it
    ok = [r["value"] for r in res["rows"] if r["within_target"]]
    assert res["cheapest"]["sunlight.tolerance_s"] in ok
    rows = list(csv.DictReader((tmp_path / "out" / "convergence.csv").open()))
    assert len(rows) == 4 and rows[0]["quantity"] == "sun_time" and float(rows[-1]["error"]) <= 2.0


def test_view_ladder_and_command_line(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN, view={"grid_spacing_m": 2.0})
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["study", "convergence", str(path), "--out", str(out), "--ladder",
                                 "view.angle_tolerance_deg", "--target", "angle_deg=0.001", "--points", "3"])
    assert r.exit_code == 0, r.output
    assert "observed order of sight_angle" in r.output and "cheapest view.angle_tolerance_deg" in r.output
    rows = list(csv.DictReader((out / "convergence.csv").open()))
    err = np.array([float(x["error"]) for x in rows])
    assert np.all(err <= np.array([float(x["estimate"]) for x in rows]) + 1e-9)  # the bracket bounds the error
    assert err[-1] < 1e-3
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return
    assert (out / "convergence.png").stat().st_size > 1000


def test_unknown_ladder_and_target_are_input_errors(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=SUN)
    for args in (["--ladder", "view.nope"], ["--target", "speed=1"], ["--target", "angle_deg=x"]):
        r = CliRunner().invoke(cli, ["study", "convergence", str(path), "--out", str(tmp_path / "o"), *args])
        assert r.exit_code == 2 and r.output.startswith("error: ") and "--" in r.output and len(r.output.splitlines()) == 1


def test_daylight_ladders(tmp_path):
    """Daylight provision's two ladders on a box room: the sky component's bound falls with its
    tolerance and holds its error at every rung and point (the error itself need not fall: a coarse
    rung's cells across the building's edge happen to be counted at about their share); the paths'
    error and interval fall with their number (Monte Carlo) and each rung's interval with the
    reference's holds the difference at all but one of the 15 points."""
    import pytest
    import yaml

    pytest.importorskip("pyradiance")
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=None, view=None)
    doc = yaml.safe_load(path.read_text())
    doc["daylight"] = {"median_diffuse_lx": 14000, "grid_spacing_m": 1.0}
    doc["requirements"] = {"daylight": "minimum", "view": "none", "sunlight": "none"}
    path.write_text(yaml.safe_dump(doc))
    sky = study.Ladder("daylight.sky_component.rel_tolerance", (0.05, 0.02, 0.005), study.SKY_REFERENCE, ("sky_component",))
    paths = study.Ladder("daylight.radiance.max_rays", (64, 256, 1024), {"daylight.radiance.max_rays": 4096, **study.PATHS_EXTRA},
                         ("reflected",), extra=study.PATHS_EXTRA)
    res = study.convergence(path, tmp_path / "out", (sky, paths), log=lambda m: None)
    rows = {(r["ladder"], r["value"]): r for r in res["rows"]}
    est = [rows[("daylight.sky_component.rel_tolerance", v)]["estimate"] for v in (0.05, 0.02, 0.005)]
    assert est[0] >= est[1] > est[2]
    for v in (0.05, 0.02, 0.005):  # the bound covers the error (plus the reference's own), point by point
        assert rows[("daylight.sky_component.rel_tolerance", v)]["over_estimate"] == 0
    e = [rows[("daylight.radiance.max_rays", v)]["error"] for v in (64, 256, 1024)]
    est = [rows[("daylight.radiance.max_rays", v)]["estimate"] for v in (64, 256, 1024)]
    assert e[2] < e[0] and est[0] > est[1] > est[2]
    assert all(rows[("daylight.radiance.max_rays", v)]["over_estimate"] <= 1 for v in (64, 256, 1024))  # 15 points


def test_view_tolerance_ladder_bounds_its_error(tmp_path):
    """The view by decision against the exact mode (issue 44): at every rung of view.tolerance the
    exact solid angle of every point and layer lies within the decided one's interval (the rung's
    estimate is the farther end of its interval), and the interval narrows as the tolerance does
    (the error itself need not fall monotonically: a mixed cell's share of its rays is an estimate)."""
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=None, view={"grid_spacing_m": 1.0, "eye_heights_m": [1.2]})
    lad = next(x for x in study.LADDERS if x.knob == "view.tolerance")
    res = study.convergence(path, tmp_path / "out", (lad,), log=lambda m: None)
    rows = res["rows"]
    assert {r["quantity"] for r in rows} == {"sky", "landscape", "ground"}
    assert all(r["error"] <= r["estimate"] + 1e-12 for r in rows)
    assert all(r["over_estimate"] == 0 for r in rows)  # point by point, not only the largest
    for q in ("sky", "landscape", "ground"):
        bounds = [r["estimate"] for r in rows if r["quantity"] == q]
        assert all(a >= b for a, b in zip(bounds, bounds[1:])) and bounds[-1] < bounds[0]
        # 0.01 of the window's solid angle (under 1.3 sr from 1 m behind a 2 x 1.4 m window), either side
        assert bounds[-1] <= 2 * 0.01 * 1.3
