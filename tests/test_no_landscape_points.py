"""A model without landscape (a building exported alone): its view layers are not assessable, but
the sight angle and outside distance of every viewpoint are still written to view_points.csv."""
from __future__ import annotations

import csv
import json
import math

from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.samples import BoxRoom, box_room_project


def test_points_of_a_room_whose_layers_are_not_assessable_are_in_the_csv(tmp_path):
    project = box_room_project(tmp_path / "p", BoxRoom(building_height=0), sunlight=None, view={"grid_spacing_m": 1.0,
                                                                                                 "eye_heights_m": [1.2]})
    r = CliRunner().invoke(cli, ["check", str(project), "--out", str(tmp_path / "r"), "--no-plots", "-q",
                                 "--set", "requirements.sunlight=none"], catch_exceptions=False)
    assert r.exit_code == 1, r.output  # not assessable is not a pass
    room = json.loads((tmp_path / "r" / "report.json").read_text())["rooms"][0]
    assert room["view"]["status"] == "not_assessable" and "no landscape" in room["view"]["reason"]
    rows = list(csv.DictReader((tmp_path / "r" / "view_points.csv").open()))
    points = room["view"]["eye_heights"][0]["points"]
    assert len(rows) == len(points) > 0
    (x0, x1) = BoxRoom().window_x
    for row in rows:  # the window from x0 to x1 in the facade y = 0, the room at y > 0: closed form in plan
        x, y = float(row["x_m"]), float(row["y_m"])
        want = math.degrees(math.atan((x1 - x) / y) - math.atan((x0 - x) / y))
        assert abs(float(row["horizontal_sight_angle_deg"]) - want) < 1e-3, row


def test_the_layers_of_a_model_without_landscape_are_not_traced_and_nothing_else_moves(tmp_path):
    """Most of a view's cost is the layers' solid angles (SampleHouse4: 27 of 28 s); where no layer
    can be judged they are not traced (null, the method says so), and the sight angle and outside
    distance are those of the full run: the same run with ``view.distance_method: solid_angle``
    (which needs the solid angles) traces them, and its sight angles are the same."""
    project = box_room_project(tmp_path / "p", BoxRoom(building_height=0), sunlight=None, view={"grid_spacing_m": 1.0,
                                                                                                 "eye_heights_m": [1.2]})

    def view(*sets):
        args = ["check", str(project), "--out", str(tmp_path / "r"), "--no-plots", "-q", "--set", "requirements.sunlight=none"]
        r = CliRunner().invoke(cli, args + [a for s in sets for a in ("--set", s)], catch_exceptions=False)
        assert r.exit_code == 1, r.output
        return json.loads((tmp_path / "r" / "report.json").read_text())["rooms"][0]["view"]

    skipped, traced = view(), view("view.distance_method=solid_angle")
    assert skipped["error_estimates"]["max_solid_angle_error_sr"] is None
    assert skipped["error_estimates"]["method"]["solid_angle_sr"].startswith("not traced: the model has no landscape")
    assert traced["error_estimates"]["max_solid_angle_error_sr"] is not None
    a, b = skipped["eye_heights"][0]["points"], traced["eye_heights"][0]["points"]
    assert len(a) == len(b) > 0
    for p, q in zip(a, b):
        assert p["solid_angle_sr"] == {"sky": None, "landscape": None, "ground": None} and p["window_solid_angle_sr"] is None
        assert q["solid_angle_sr"]["sky"] > 0.01  # the sky through the window, traced
        assert p["point"] == q["point"] and p["horizontal_sight_angle_deg"] == q["horizontal_sight_angle_deg"]


def test_a_view_whose_layers_cannot_be_judged_maps_sight_angle_and_distance_only(tmp_path):
    """No landscape: the layers were not traced and no point has a level, so a map of either would
    show 'none' over the whole room; the sight angle and distance maps are drawn, both printed."""
    project = box_room_project(tmp_path / "p", BoxRoom(building_height=0), sunlight=None, view={"grid_spacing_m": 1.0,
                                                                                                 "eye_heights_m": [1.2]})
    r = CliRunner().invoke(cli, ["check", str(project), "--out", str(tmp_path / "r"), "-q", "--set", "requirements.sunlight=none"],
                           catch_exceptions=False)
    assert r.exit_code == 1, r.output
    maps = sorted(p.name.split("-view-")[1] for p in (tmp_path / "r" / "figures").glob("*-view-*.png"))
    assert maps == ["1.2m-distance.png", "1.2m-sight-angle.png"], maps
