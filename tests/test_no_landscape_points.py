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
