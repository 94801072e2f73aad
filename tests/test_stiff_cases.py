"""Stiff and extreme cases: awkward models, places and knobs give a clear result or a clear error.

Box room (en17037cli.samples.BoxRoom): opening x in [-1, 1], z in [0.8, 2.2] in the plane y = 0,
facing south (-y), room at y > 0, a 10 m building across a 25 m street.
"""
from __future__ import annotations

import datetime as dt

import numpy as np
import pytest
import tolerances as tol
import yaml
from click.testing import CliRunner
from oracles import (
    hour_angle_hours,
    layer_solid_angles,
    local_midnight,
    rect_solid_angle_y0,
    sight_angle_deg,
    sun_declination,
    sun_hours_exact,
    sun_position,
    triangle_solid_angle_lhuilier,
)

from en17037cli.cli import cli
from en17037cli.errors import InputError
from en17037cli.project import load_project
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.scene import build_scene

ONE_DAY = {"date": "02-01", "period": {"start": "02-01", "end": "02-01"}}


def run_points(b, pts):
    return b.view_points(pts)


def exact_glazing(b, pts):
    """The room's windows' solid angle [sr] from each world point, by L'Huilier triangles."""
    tris = np.concatenate([w.triangles for w in b.room.windows]) + b.scene.origin
    return np.array([sum(triangle_solid_angle_lhuilier(p, t) for t in tris) for p in np.asarray(pts, float)])


def assert_layers(r, pts, box, i_max=None):
    for i, p in enumerate(pts[:i_max]):
        exacts = layer_solid_angles(p, box.window_x, box.window_z, box.street, box.building_height)
        for key, exact in zip(("sky", "landscape", "ground"), exacts):
            err = abs(r.solid.sr[key][i] - exact)
            assert err <= tol.solid_angle_sr(exact), (i, key, r.solid.sr[key][i], exact)
            assert err <= r.solid.err_sr[key][i] + 1e-12, (i, key, r.solid.sr[key][i], exact, r.solid.err_sr[key][i])


# --- viewpoints on awkward lines and planes -------------------------------------------------

def test_viewpoint_in_the_window_plane_is_moved_inside_and_sees_the_half_space(build):
    b = build(BoxRoom())
    res = b.view_room(view_points=[[0.0, 0.0, 1.5], [1.5, 0.0, 1.5]])
    assert any("lay on a glazing plane and were moved 1 mm" in n for n in res.notes)
    v = res.eye_heights[0].values
    pts = res.eye_heights[0].points_local + b.scene.origin
    assert np.allclose(pts[:, 1], 0.001)
    # on the glass: almost the whole half space, 1 mm from a 2 x 1.4 m window
    assert abs(v.sight.angle_deg[0] - sight_angle_deg(0.0, 0.001)) <= tol.SIGHT_ANGLE_DEG  # 179.885 deg
    assert abs(v.solid.glazing_sr[0] - exact_glazing(b, pts[:1])[0]) < tol.TILING_SR
    total = v.solid.sr["sky"][0] + v.solid.sr["landscape"][0] + v.solid.sr["ground"][0]
    assert abs(total - v.solid.glazing_sr[0]) < 1e-9  # nothing blocks it
    # in the wall plane beside the window: the window is seen edge-on; the grazing sight angle is
    # the angle between the window's two ends from 1 mm in front of the plane
    expected = sight_angle_deg(1.5, 0.001)
    assert abs(v.sight.angle_deg[1] - expected) <= tol.SIGHT_ANGLE_DEG
    assert abs(v.solid.glazing_sr[1] - exact_glazing(b, pts[1:])[0]) < tol.TILING_SR


@pytest.mark.parametrize("p", [[1.0, 2.0, 1.2], [-1.0, 4.0, 1.7], [0.5, 3.0, 2.2], [0.0, 1.0, 0.8]])
def test_viewpoints_on_the_window_edge_lines(build, p):
    """Points on the lines of the jambs, the head and the sill: rays graze the window's edges."""
    box = BoxRoom()
    b = build(box)
    r = run_points(b, [p])
    assert abs(r.sight.angle_deg[0] - sight_angle_deg(p[0], p[1])) <= tol.SIGHT_ANGLE_DEG
    assert abs(r.solid.glazing_sr[0] - exact_glazing(b, [p])[0]) < tol.TILING_SR
    assert_layers(r, [p], box)


def test_touching_windows_and_many_triangles_give_the_one_window_answer(build):
    pts = np.array([[0.3, 2.0, 1.2], [-1.2, 4.5, 1.7]])
    one = build(BoxRoom(), sub="one")
    split = build(BoxRoom(window_split=40), sub="split")  # 40 glazing strips sharing edges
    assert len(split.room.windows) == 1
    r1, r2 = run_points(one, pts), run_points(split, pts)
    for get in (*(lambda r, k=k: r.solid.sr[k] for k in ("sky", "landscape", "ground")),
                lambda r: r.sight.angle_deg, lambda r: r.distance_m):
        assert np.allclose(get(r1), get(r2), atol=1e-9)


# --- modelling errors -----------------------------------------------------------------------

def test_glazing_over_an_uncut_wall_is_a_modelling_error_naming_both(tmp_path):
    path = box_room_project(tmp_path / "p", BoxRoom(uncut_wall=True))
    with pytest.raises(InputError) as e:
        build_scene(load_project(path))
    msg = str(e.value)
    assert "window 'glazing'" in msg and "'model: room'" in msg and "100%" in msg and "cut the opening" in msg
    r = CliRunner().invoke(cli, ["validate", str(path)])
    assert r.exit_code == 2 and r.output.count("\n") == 1
    out = tmp_path / "report"
    r = CliRunner().invoke(cli, ["check", str(path), "--out", str(out), "--quiet"])
    assert r.exit_code == 2 and r.output.count("\n") == 1 and not (out.exists() and any(out.iterdir()))
    # walls cut around the glazing in the same plane are the normal case
    build_scene(load_project(box_room_project(tmp_path / "q", BoxRoom())))


def test_nan_degenerate_and_duplicate_faces_are_dropped_and_counted(build, tmp_path):
    b0 = build(BoxRoom(), sub="clean")
    path = box_room_project(tmp_path / "dirty", BoxRoom())
    obj = path.parent / "model.obj"
    text = obj.read_text()
    n = sum(1 for line in text.splitlines() if line.startswith("v "))
    extra = ["o room", "v nan 0 0", "v 1 1 1", "v 2 2 2", "v 3 3 3",  # a NaN vertex, a zero-area (collinear) face
             f"f {n + 1} {n + 2} {n + 3}", f"f {n + 2} {n + 3} {n + 4}"]
    faces = [line for line in text.splitlines() if line.startswith(("o ", "f "))]  # every face once more
    obj.write_text(text + "\n".join(extra + faces) + "\n")
    s = build_scene(load_project(path))
    assert any("degenerate, NaN or infinite faces dropped" in w for w in s.warnings)
    assert len(s.triangles) == 2 * len(b0.scene.triangles)
    # duplicated faces (the glazing included) change nothing
    from tests.conftest import Built

    b1 = Built(path)
    pts = np.array([[0.3, 2.0, 1.2], [-1.2, 4.5, 1.7]])
    r0, r1 = run_points(b0, pts), run_points(b1, pts)
    b1.engine.close()
    for get in (*(lambda r, k=k: r.solid.sr[k] for k in ("sky", "landscape", "ground")), lambda r: r.solid.glazing_sr,
                lambda r: r.sight.angle_deg, lambda r: r.distance_m):
        assert np.allclose(get(r0), get(r1), atol=1e-9)


def test_a_layer_missing_entirely_leaves_sky_and_ground_by_direction(build, tmp_path):
    """No ground and no building faces: above the horizon is sky, below it ground."""
    path = box_room_project(tmp_path / "p", BoxRoom(building_height=0))
    doc = yaml.safe_load(path.read_text())
    for rule in doc["model"]["files"][0]["layers"]:
        if rule["match"] == "ground":
            rule["layer"] = "ignore"
    path.write_text(yaml.safe_dump(doc))
    from tests.conftest import Built

    b = Built(path)
    p = np.array([[0.3, 2.0, 1.2]])
    r = run_points(b, p)
    b.engine.close()
    sky = rect_solid_angle_y0(-1, 1, 1.2, 2.2, p[0])
    ground = rect_solid_angle_y0(-1, 1, 0.8, 1.2, p[0])
    assert abs(r.solid.sr["sky"][0] - sky) <= tol.solid_angle_sr(sky)
    assert abs(r.solid.sr["ground"][0] - ground) <= tol.solid_angle_sr(ground)
    assert r.solid.sr["landscape"][0] == 0 and np.isinf(r.distance_m[0])


def test_yaml_exponent_floats_are_numbers_in_files_and_overrides(tmp_path):
    """PyYAML alone reads 1e-5 as the string '1e-5' (YAML 1.1); project files use YAML 1.2 floats."""
    from en17037cli.project.yaml12 import parse_yaml

    assert parse_yaml("a: 1e-5\nb: -2E3\nc: .5\nd: 02-01\ne: 10") == {"a": 1e-5, "b": -2000.0, "c": 0.5, "d": "02-01", "e": 10}
    path = box_room_project(tmp_path / "p", BoxRoom(), view={"angle_tolerance_deg": 1e-5})
    text = path.read_text()
    path.write_text(text.replace("angle_tolerance_deg: 1.0e-05", "angle_tolerance_deg: 1e-5"))
    assert "angle_tolerance_deg: 1e-5" in path.read_text()  # as a person would type it
    p = load_project(path, ["sunlight.tolerance_s=1e-2"])
    assert p.config["view"]["angle_tolerance_deg"] == 1e-5 and p.config["sunlight"]["tolerance_s"] == 0.01


# --- extreme sizes --------------------------------------------------------------------------

@pytest.mark.parametrize("box, pts", [
    (BoxRoom(wall_thickness=1.0), [[0.3, 3.0, 1.2], [-1.5, 2.0, 1.7]]),  # 1 m reveals
    (BoxRoom(window_x=(-0.005, 0.005), window_z=(1.195, 1.205)), [[0.0, 1.0, 1.2], [0.5, 3.0, 1.2]]),  # 1 cm window
    # 50 m glass facade; the building and ground long enough to fill its view (the hand values assume it)
    (BoxRoom(width=52.0, window_x=(-25.0, 25.0), building_length=8000.0, ground_size=8000.0),
     [[0.0, 2.0, 1.2], [20.0, 1.0, 1.7]]),
    (BoxRoom(depth=100.0), [[0.0, 99.0, 1.2], [1.5, 60.0, 1.7]]),  # 100 m deep room
], ids=["wall-1m", "window-1cm", "facade-50m", "room-100m"])
def test_extreme_sizes_match_the_hand_values(build, box, pts):
    b = build(box)
    pts = np.asarray(pts, float)
    if box.wall_thickness:
        pts[:, 1] += box.wall_thickness
    r = run_points(b, pts)
    half = (box.window_x[1] - box.window_x[0]) / 2
    for i, p in enumerate(pts):
        expected = sight_angle_deg(p[0], p[1], half=half, reveal=box.wall_thickness)
        assert abs(r.sight.angle_deg[i] - expected) <= tol.SIGHT_ANGLE_DEG, (i, r.sight.angle_deg[i], expected)
    assert np.allclose(r.solid.glazing_sr, exact_glazing(b, pts), rtol=1e-9, atol=1e-12)  # exact tiling
    if not box.wall_thickness:
        assert_layers(r, pts, box)


# --- places and dates -----------------------------------------------------------------------

def _hours(build, lat, lon, tz, date="02-01", north=0.0, **sun):
    b = build(BoxRoom(building_height=0), location={"latitude": lat, "longitude": lon, "timezone": tz},
              sunlight={"date": date, "period": {"start": date, "end": date}, "refraction": False, **sun},
              view=None, true_north_deg=north, sub=f"s{lat}_{lon}_{north}")
    return b.sunlight()


def _declination(date, utc_offset_h=0.0):
    noon = dt.datetime.fromisoformat(f"2026-{date}T12:00:00+00:00").timestamp() - utc_offset_h * 3600
    return float(sun_declination([noon])[0])


def test_polar_night_gives_zero_hours_not_an_error(build):
    r = _hours(build, 78.0, 15.6, "Arctic/Longyearbyen")
    assert r.hours[0] == 0.0 and r.level == 0 and r.error_h[0] == 0.0


@pytest.mark.parametrize("lat, lon, tz, offset", [
    (0.0, 0.0, "UTC", 0.0),  # the equator
    (28.6, 77.2, "Asia/Kolkata", 5.5),  # a half-hour time zone
    (52.0, 179.9, "Etc/GMT-12", 12.0),  # next to the antimeridian, east ...
    (52.0, -179.9, "Etc/GMT+12", -12.0),  # ... and west
])
def test_unobstructed_hours_match_the_hour_angle_formula_anywhere(build, lat, lon, tz, offset):
    """South window, no obstruction, 11 deg minimum altitude, 1 February: in front of the window
    the whole day at these latitudes, so the formula applies (declination at local noon)."""
    r = _hours(build, lat, lon, tz)
    expected = hour_angle_hours(lat, _declination("02-01", offset), 11.0)
    assert abs(r.hours[0] - expected) < 3 / 60, (r.hours[0], expected)  # declination drift over the day


def test_southern_hemisphere_north_window_sees_the_sun_only_north_of_the_prime_vertical(build):
    """34 S in February, window facing true north (true north along the model's -Y):
    the sun stands north of the east-west line between the hour angles +-acos(tan dec / tan lat)."""
    lat = -34.0
    r = _hours(build, lat, 18.4, "Etc/GMT-1", north=180.0)
    dec = _declination("02-01", 1.0)
    expected = 2 * np.degrees(np.arccos(np.tan(np.radians(dec)) / np.tan(np.radians(lat)))) / 15
    assert abs(r.hours[0] - expected) < 3 / 60, (r.hours[0], expected)


def test_sun_exactly_at_the_minimum_altitude_at_noon_counts_for_no_time(build):
    """The day's highest altitude (SPA, every second, no refraction) as the minimum altitude: the
    sun touches it for an instant; a little higher it never reaches it."""
    lat, date = 52.0, "02-01"
    t0 = dt.datetime.fromisoformat(f"2026-{date}T10:00:00+00:00").timestamp()
    t = t0 + np.arange(0, 4 * 3600, 1.0)
    elev, _ = sun_position(t, lat, 0.0, refraction=False)
    top = float(elev.max())
    r = _hours(build, lat, 0.0, "UTC", min_altitude_deg=top)
    assert r.hours[0] < 10 / 3600  # an instant, not an interval
    r = _hours(build, lat, 0.0, "UTC", min_altitude_deg=top + 0.01)
    assert r.hours[0] == 0.0


def test_sun_grazing_the_window_plane_at_the_equinox(build):
    """At the equinox the sun rises and sets in the window's plane (due east and west): with no
    minimum altitude the window sees it from sunrise to sunset."""
    r = _hours(build, 52.0, 0.0, "UTC", date="03-20", min_altitude_deg=0.0)
    expected = hour_angle_hours(52.0, _declination("03-20"), 0.0)
    assert abs(r.hours[0] - expected) < 5 / 60


# --- extremes of the knobs ------------------------------------------------------------------

@pytest.mark.parametrize("timestep_min, tolerance_s", [(1 / 60, 1.0), (60.0, 1.0), (5.0, 0.01)])
def test_timestep_and_tolerance_extremes(build, timestep_min, tolerance_s):
    r = _hours(build, 52.0, 0.0, "UTC", timestep_min=timestep_min, tolerance_s=tolerance_s)
    t0 = local_midnight("02-01")
    exact, _ = sun_hours_exact(t0, t0 + 86400, 52.0, 0.0, [lambda e, v: e - 11.0, lambda e, v: -v[:, 1]])
    # two changes a day (sunrise and sunset over 11 deg in front of the south window), each within
    # the tolerance of its bisection
    assert abs(r.hours[0] - exact) * 3600 <= 2 * tolerance_s, (r.hours[0], exact)
    assert r.error_h[0] * 3600 <= 2 * tolerance_s


def test_grid_spacing_larger_than_the_room_gives_one_point(build):
    b = build(BoxRoom(), view={"grid_spacing_m": 50.0})
    res = b.view_room()
    assert [len(e.points_local) for e in res.eye_heights] == [1, 1]


@pytest.mark.parametrize("threshold, visible", [(0.0, True), (4 * np.pi, False)])
def test_layer_thresholds_of_zero_and_four_pi(build, threshold, visible):
    b = build(BoxRoom(), view={"layer_threshold_sr": float(threshold)})
    r = run_points(b, [[0.3, 2.0, 1.2]])
    assert bool(r.visible["sky"][0]) is visible and bool(r.visible["landscape"][0]) is visible
    assert r.level_by_criterion["layers"][0] == (3 if visible else 0)
