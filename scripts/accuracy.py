"""Measure the error of the default settings against closed-form answers (docs/accuracy.md).

View: the synthetic box room (en17037cli.samples), a 0.25 m grid of viewpoints at both eye
heights, against the hand formulas for the sight angle, the layer solid angles (rectangle
formula) and the street width. Sunlight: hour-angle formula at 40/52/60 N, 1 Feb and 1 Mar.
Usage: python scripts/accuracy.py [--set key=value ...]
"""
import datetime as dt
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from en17037cli.criteria.sunlight.assess import assess_room as assess_sunlight
from en17037cli.criteria.sunlight.solar_position import declination
from en17037cli.criteria.view.assess import assess_points
from en17037cli.criteria.view.frames import room_geometry
from en17037cli.criteria.view.rays import ViewRays
from en17037cli.project import load_project
from en17037cli.raytrace import RayEngine
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.scene import build_scene

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from oracles import layer_solid_angles, sight_angle_deg  # noqa: E402 - the tests' closed forms


def main(overrides):
    box = BoxRoom()
    with tempfile.TemporaryDirectory() as tmp:
        path = box_room_project(Path(tmp), box, sunlight={}, view={})
        project = load_project(path, overrides)
        scene = build_scene(project)
        engine = RayEngine(scene.vertices, scene.triangles, scene.ray_groups())
        xs, ys = np.meshgrid(np.arange(-1.75, 1.76, 0.25), np.arange(0.5, 5.76, 0.25))
        pts = np.array([[x, y, z] for z in (1.2, 1.7) for x, y in zip(xs.ravel(), ys.ravel())])
        t = time.perf_counter()
        r = assess_points(ViewRays(engine, scene), room_geometry(scene, scene.rooms[0]), scene.to_local(pts), project.view,
                          project.thresholds)
        elapsed = time.perf_counter() - t
        exact_angle = np.array([sight_angle_deg(x, y) for x, y, _ in pts])
        exact = np.array([layer_solid_angles(p) for p in pts])
        print(f"view, {len(pts)} points, {elapsed:.2f} s, {engine.rays_traced / len(pts):.0f} ray queries per point")
        print(f"  sight angle: max |error| {np.max(np.abs(r.sight.angle_deg - exact_angle)):.2e} deg "
              f"(max estimate {np.max(r.sight.angle_err_deg):.2e})")
        for i, k in enumerate(("sky", "landscape", "ground")):
            err = np.abs(r.solid.sr[k] - exact[:, i])
            rel = err / np.maximum(exact[:, i], 1e-12)
            bound = np.maximum(0.01 * exact[:, i], 1e-3)
            print(f"  {k:9s}: max |error| {err.max():.2e} sr, max relative {rel[exact[:, i] > 1e-3].max():.2%}, "
                  f"points over max(1%, 1e-3 sr): {np.count_nonzero(err > bound)}, error > estimate: {np.count_nonzero(err > r.solid.err_sr[k] + 1e-12)}")
        print(f"  distance: max |error| {np.max(np.abs(r.distance_m - box.street)):.2e} m")
        engine.close()
    worst = 0.0
    for lat in (40.0, 52.0, 60.0):
        for date in ("02-01", "03-01"):
            with tempfile.TemporaryDirectory() as tmp:
                path = box_room_project(Path(tmp), BoxRoom(building_height=0), view=None,
                                        location={"latitude": lat, "longitude": 0.0, "timezone": "UTC"},
                                        sunlight={"date": date, "period": {"start": date, "end": date}, "refraction": False, "min_altitude_deg": 0})
                project = load_project(path, overrides)
                scene = build_scene(project)
                engine = RayEngine(scene.vertices, scene.triangles, scene.ray_groups())
                res = assess_sunlight(engine, scene, scene.rooms[0], project.sunlight, project.location, project.thresholds)
                noon = dt.datetime.fromisoformat(f"2026-{date}T12:00:00+00:00").timestamp()
                dec = np.radians(declination([noon])[0])
                phi = np.radians(lat)
                H = np.degrees(np.arccos(-np.tan(phi) * np.tan(dec)))
                worst = max(worst, abs(res.hours[0] - 2 * H / 15))
                engine.close()
    print(f"sunlight vs hour-angle formula (declination at noon), 6 cases: max |difference| {worst * 3600:.0f} s")


if __name__ == "__main__":
    args = sys.argv[1:]
    main([a for a in args if a != "--set"])
