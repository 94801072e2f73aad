"""Continuous scores and the sensitivity study, against values worked out by hand.

The box room (en17037cli.samples.box): a 2 x 1.4 m opening x in [-1, 1], z in [0.8, 2.2] in the
plane y = 0 (no wall thickness), the room behind it (y > 0), ground z = 0 outside and a 10 m
building 25 m away; tests/oracles.py has the closed forms of its sight angles and layer solid angles.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from en17037cli import standard
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.standard import LevelThresholds
from tests.oracles import layer_solid_angles, sight_angle_deg

SIGHT = LevelThresholds(14.0, 28.0, 54.0)
HOURS = LevelThresholds(1.5, 3.0, 4.0)


def test_score_equals_the_level_at_each_threshold_and_interpolates():
    assert standard.score_from_value([0.0, 14.0, 28.0, 54.0, 1e9, np.inf], SIGHT).tolist() == [0, 1, 2, 3, 3, 3]
    assert standard.score_from_value([7.0, 21.0, 41.0], SIGHT).tolist() == [0.5, 1.5, 2.5]
    assert standard.score_from_value([2.25, 3.5], HOURS).tolist() == [1.5, 2.5]
    assert np.isnan(standard.score_from_value([np.nan], HOURS)[0])


@given(st.floats(0, 100), st.floats(1e-6, 5))
@settings(max_examples=200, deadline=None)
def test_score_is_monotone_continuous_and_floors_to_the_level(x, dx):
    """Non-decreasing; Lipschitz with the steepest segment's slope (1 / 14 per degree), so continuous
    across every threshold; its floor is the level."""
    a, b = standard.score_from_value([x, x + dx], SIGHT)
    assert a <= b <= a + dx / 14.0 + 1e-12
    assert math.floor(a + 1e-12) == int(standard.level_from_value([x], SIGHT)[0]) or a == 3.0


@given(st.lists(st.floats(0, 90), min_size=1, max_size=40), st.sampled_from([0.5, 0.75, 0.9, 1.0]))
@settings(max_examples=200, deadline=None)
def test_area_quantile_gives_the_room_level(values, fraction):
    """The value reached by the area fraction of the points gives the same level as counting the
    points that reach each level (clause 5.2's share of the utilised area)."""
    q = standard.area_quantile(values, fraction)
    level, _ = standard.room_level(standard.level_from_value(values, SIGHT), fraction)
    assert int(standard.level_from_value([q], SIGHT)[0]) == level


def test_margins():
    assert standard.margins(26.4, 1, SIGHT) == pytest.approx((1.6, 12.4))
    assert standard.margins(60.0, 3, SIGHT) == (None, pytest.approx(6.0))
    assert standard.margins(10.0, 0, SIGHT) == (pytest.approx(4.0), None)


def run_check(tmp_path, view=None, rooms=None, sunlight=None, overrides=()):
    from click.testing import CliRunner

    from en17037cli.cli import cli

    p = box_room_project(tmp_path / "box", BoxRoom(), sunlight=sunlight, view=view)
    if rooms is not None:
        import yaml

        doc = yaml.safe_load(p.read_text())
        doc["rooms"][0].update(rooms)
        p.write_text(yaml.safe_dump(doc, sort_keys=False))
    args = ["check", str(p), "--out", str(tmp_path / "out"), "-q", "--no-plots"]
    for o in overrides:
        args += ["--set", o]
    r = CliRunner().invoke(cli, args)
    assert r.exit_code in (0, 1), r.output
    return p, json.loads((tmp_path / "out" / "report.json").read_text())


@pytest.mark.parametrize("offset", [0.0, 0.5])
def test_sight_angle_score_follows_the_grid_offset_by_hand(tmp_path, offset):
    """Utilised area x in [-1.5, 1.5], y in [0.5, 5.5] (4 x 6 m floor less 0.5 m); a 0.9 m grid centred
    on it: x +-0.45, +-1.35 and y 0.75 .. 5.25 (4 x 6 points); shifted by half a cell: x -0.9, 0,
    0.9 and y 1.2 .. 4.8 (3 x 5). Each point's sight angle is the opening's angle in plan,
    atan((1 - x) / y) + atan((1 + x) / y); the room's is the 18th / 12th largest (75 %), its score
    linear between 14, 28 and 54 deg."""
    s_m = 0.9
    xs = (np.arange(4) - 1.5) * s_m if offset == 0 else (np.arange(3) - 1.0) * s_m
    ys = 3.0 + (np.arange(6) - 2.5) * s_m if offset == 0 else 3.0 + (np.arange(5) - 2.0) * s_m
    angles = sorted((sight_angle_deg(x, y) for x in xs for y in ys), reverse=True)
    q = angles[math.ceil(0.75 * len(angles)) - 1]
    _, report = run_check(tmp_path, view={"grid_spacing_m": s_m, "grid_offset": offset, "eye_heights_m": [1.2],
                                          "angular_resolution_deg": 3.0, "refine_levels": 1})
    eye = report["rooms"][0]["view"]["eye_heights"][0]
    assert len(eye["points"]) == len(xs) * len(ys)
    sight = next(p for p in report["rooms"][0]["view"]["score"]["by_criterion"] if p["criterion"] == "horizontal_sight_angle")
    assert abs(sight["quantity"] - q) <= 1e-3  # the engine's sight angle: within 3e-4 deg of the closed form
    assert abs(sight["score"] - float(standard.score_from_value([q], SIGHT)[0])) <= 1e-4


def test_layers_sensitivity_to_the_threshold_by_hand(tmp_path):
    """One viewpoint (0, 2, 1.2) m: sky, landscape and ground through the opening by the closed form.
    Thresholds just below and above each layer's solid angle switch that layer off, so the layer
    level steps high -> medium -> minimum -> none as the layers drop out in order of size, and the
    room that requires medium 'depends on layer threshold'."""
    from en17037cli.studies.sensitivity import sensitivity

    p0 = (0.0, 2.0, 1.2)
    sky, land, ground = layer_solid_angles(p0)
    small, mid = sorted([sky, ground])
    ladder = [0.0, small * 0.99, small * 1.01, mid * 1.01, land * 1.01]
    # hand-worked layer levels: all three; all three; landscape + the larger one; landscape alone; none
    expected_layers = [3, 3, 2, 1, 0]
    p, _ = run_check(tmp_path, view={"eye_heights_m": [1.2], "angular_resolution_deg": 1.0, "refine_levels": 3},
                     rooms={"view_points": [list(p0)], "requirements": {"view": "medium"}})
    import yaml

    doc = yaml.safe_load(p.read_text())
    doc["sensitivity"] = {"ranges": {"view.layer_threshold_sr": ladder, "view.eye_heights_m": [],
                                     "view.distance_method": [], "view.distance_statistic": [], "view.grid_offset": [],
                                     "view.grid_spacing_m": [], "view.wall_margin_m": []}}
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    res = sensitivity(p, tmp_path / "study", log=lambda m: None)
    rows = [r for r in csv_rows(tmp_path / "study" / "sensitivity.csv") if r["choice"] == "view.layer_threshold_sr"]
    # the point's view level is the lowest of its criteria: sight angle 2 atan(1 / 2) = 53.13 deg (medium),
    # distance 27 m (medium), layers as above
    assert [standard.level_index(r["level"]) for r in rows] == [min(2, e) for e in expected_layers]
    view = next(r for r in res["rooms"] if r["check"] == "view")
    assert view["level"] == "medium" and view["verdict"] == "depends on layer threshold"
    assert (tmp_path / "study" / "sensitivity.html").is_file()


def csv_rows(path):
    import csv

    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_the_mullion_reading_moves_the_sight_angle_level_by_hand(tmp_path):
    """Two 5 cm mullion plates 2 cm inside the opening (x = +-0.35) and one viewpoint (0, 3.85, 1.2) m:
    the opening subtends 2 atan(1 / 3.85) = 29.12 deg (medium, 28 deg), the mullions' shadows 0.74 deg
    each (atan2 by hand), 27.63 deg left (minimum). With view.mullions_block false the opening is
    measured between its reveals: the level moves, and a room that requires medium depends on it."""
    import yaml

    from en17037cli.samples import MULLION_GAP
    from en17037cli.studies.sensitivity import sensitivity

    x0, y0 = 0.0, 3.85
    opening = sight_angle_deg(x0, y0)
    shadows = sum(np.degrees(np.arctan2(xm + 0.025 - x0, y0 - MULLION_GAP) - np.arctan2(xm - 0.025 - x0, y0 - MULLION_GAP))
                  for xm in (-0.35, 0.35))
    assert SIGHT.minimum < opening - shadows < SIGHT.medium < opening
    p = box_room_project(tmp_path / "box", BoxRoom(mullions=(-0.35, 0.35)), sunlight=None,
                         view={"eye_heights_m": [1.2], "angular_resolution_deg": 3.0, "refine_levels": 1})
    doc = yaml.safe_load(p.read_text())
    doc["rooms"][0].update({"view_points": [[x0, y0, 1.2]], "requirements": {"view": "medium"}})
    doc["sensitivity"] = {"ranges": {k: [] for k in ("view.layer_threshold_sr", "view.eye_heights_m", "view.distance_method",
                                                      "view.distance_statistic", "view.grid_offset", "view.grid_spacing_m",
                                                      "view.wall_margin_m")}}
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    res = sensitivity(p, tmp_path / "study", log=lambda m: None)
    rows = {r["value"]: r for r in csv_rows(tmp_path / "study" / "sensitivity.csv") if r["choice"] == "view.mullions_block"}
    assert list(rows) == ["false"]  # true is the project's own setting
    # sight angle medium without the mullions; distance (25 m, medium) and layers (all three) do not limit it
    assert standard.level_index(rows["false"]["level"]) == 2
    view = next(r for r in res["rooms"] if r["check"] == "view")
    assert view["level"] == "minimum" and view["verdict"] == "depends on mullion reading"


def test_a_room_beyond_every_choice_is_robust(tmp_path):
    """The box room's sunlight on 1-3 February from a south window: every date and every P passes
    minimum (hours well above 1.5 h): robust pass."""
    from en17037cli.studies.sensitivity import sensitivity

    p = box_room_project(tmp_path / "b", BoxRoom(), view=None,
                         sunlight={"date": "worst", "period": {"start": "02-01", "end": "02-03"}})
    res = sensitivity(p, tmp_path / "s", log=lambda m: None)
    (sun,) = res["rooms"]
    hours = [float(r["score"]) for r in csv_rows(tmp_path / "s" / "sensitivity.csv") if r["check"] == "sunlight"]
    assert sun["verdict"] == "robust pass" and min(hours) >= 1.0  # a score of 1 is 1.5 h
    assert {r["value"] for r in csv_rows(tmp_path / "s" / "sensitivity.csv") if r["choice"] == "sunlight.date"} == {
        "2026-02-01", "2026-02-02", "2026-02-03"}


def test_session_scores_read_each_file_once_and_match_the_report(tmp_path, monkeypatch):
    """Two runs in a session read the model once; the scores equal report.json's."""
    import en17037cli
    from en17037cli.scene import load

    p, report = run_check(tmp_path, view={"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 3.0,
                                          "refine_levels": 1}, sunlight={"date": "02-01", "period": {"start": "02-01", "end": "02-01"}})
    reads = []
    original = load.read_model
    monkeypatch.setattr(load, "read_model", lambda path, options: reads.append(path) or original(path, options))
    session = en17037cli.Session()
    a = session.scores(en17037cli.load_project(p))
    b = session.scores(en17037cli.load_project(p, ["sunlight.date=02-01"]))
    assert a == b and len(reads) == len(set(reads)) >= 1
    room = report["rooms"][0]
    assert a["box room"] == {"view": pytest.approx(room["view"]["score"]["value"], abs=1e-4),
                             "sunlight": pytest.approx(room["sunlight"]["score"]["value"], abs=1e-4)}
