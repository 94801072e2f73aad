"""The sky component (:mod:`en17037cli.criteria.daylight.sky_component`) against independent
integrals: a midpoint sum of the CIE overcast luminance over the glazing written here, point by
point, and the whole daylight factor of a black room through ``en17037 check``.

The midpoint sum is the reference's own code path (world coordinates of the pane, cos / r² dA, no
cells, no rays): 400 x 300 pieces over a 2 x 1.4 m pane err by O(h²), at most 1.5e-6 of the value
at these points (measured against 1600 x 1200; a triangle's mask, 800 x 600 against 3200 x 2400:
3.3e-6), which the tolerances add, with a margin, to the engine's bound.
"""
from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest
import yaml

from en17037cli.criteria.daylight.sky import cie_overcast_luminance, glass_transmittance
from en17037cli.criteria.daylight.sky_component import SkyTolerance, sky_component
from en17037cli.criteria.view.frames import RoomGeometry, window_frame
from en17037cli.criteria.view.rays import ViewRays
from en17037cli.raytrace import RayEngine
from en17037cli.samples.box import BoxRoom, box_room_polygons, box_room_project
from en17037cli.scene.model import INTERIOR, WINDOW, Window

#: Relative error allowed the midpoint reference (400 x 300 pieces; measured: at most 1.5e-6).
MIDPOINT_REL = 1e-5


def midpoint_sky_component(points, corner, edge_u, edge_v, tv, inside=None, nu=400, nv=300):
    """Sky component [-] of points (n, 3) through a plane parallelogram pane corner + s edge_u + t
    edge_v (s, t in [0, 1]) under the CIE overcast sky, nothing obstructing: the midpoint sum of
    L(γ)/L_z cos θ τ(i) cos_pane / r² dA over ``nu`` x ``nv`` pieces, divided by 7 π / 9; pieces whose
    (s, t) fail ``inside`` (a mask function) are left out; directions below the horizon add nothing."""
    s = (np.arange(nu) + 0.5) / nu
    t = (np.arange(nv) + 0.5) / nv
    S, T = np.meshgrid(s, t, indexing="ij")
    keep = np.ones(S.shape, bool) if inside is None else inside(S, T)
    X = corner + S[..., None] * edge_u + T[..., None] * edge_v
    normal = np.cross(edge_u, edge_v)
    area = np.linalg.norm(normal) / (nu * nv)
    normal /= np.linalg.norm(normal)
    out = []
    for p in np.asarray(points, float):  # the reference's own loop, one point at a time
        r = X - p
        dist = np.linalg.norm(r, axis=-1)
        d = r / dist[..., None]
        cos_pane = np.abs(d @ normal)
        up = np.maximum(d[..., 2], 0.0)
        f = cie_overcast_luminance(np.arcsin(up)) * up * glass_transmittance(cos_pane, tv) * cos_pane / dist**2
        out.append(float((f * keep).sum() * area / (7.0 * np.pi / 9.0)))
    return np.array(out)


def _room_points(b: BoxRoom, spacing=0.5, z=0.85):
    xs = np.arange(-b.width / 2 + 0.5 + spacing / 2, b.width / 2 - 0.5, spacing)  # cell centres, as grid_points
    ys = np.arange(b.wall_thickness + 0.5 + spacing / 2, b.wall_thickness + b.depth - 0.5, spacing)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, z)])


def _engine_for(polys: dict, window_keys=("glazing",)):
    """A ray engine, view rays and the room geometry of a box room's polygons (model frame)."""
    tris, layer, names = [], [], []
    for name, quads in polys.items():
        for q in quads:
            q = np.asarray(q, float)
            for k in range(1, len(q) - 1):  # fan
                tris.append([q[0], q[k], q[k + 1]])
                layer.append(WINDOW if name in window_keys else INTERIOR)
                names.append(name)
    tris = np.array(tris)
    verts = tris.reshape(-1, 3)
    faces = np.arange(len(verts)).reshape(-1, 3)
    layer = np.array(layer)
    win = np.flatnonzero(layer == WINDOW)
    engine = RayEngine(verts, faces, {"opaque": layer != WINDOW, "win": win})
    normal = np.array([0.0, -1.0, 0.0])
    w = Window("glazing", 0, win, tris[win], normal, 0.0)
    f = window_frame(w, 0)
    wof = np.full(len(faces), -1)
    wof[win] = 0
    rg = RoomGeometry([f], wof, tris[win], np.zeros(len(win), int), "win")
    return engine, ViewRays(engine, SimpleNamespace(layer=layer)), rg


@pytest.mark.parametrize("tv", [1.0, 0.7])
def test_rectangular_window_every_point(tv):
    # the black box of issue 36: 4 x 6 x 3 m, a 2 x 1.4 m window, nothing outside but the ground; the
    # engine's value lies within its bound (plus the reference's own error) of the midpoint sum at
    # all 60 points of the reference plane, from 0.1 % to 12 % D
    b = BoxRoom(building_height=0.0)
    engine, view_rays, rg = _engine_for(box_room_polygons(b))
    pts = _room_points(b)
    sc = sky_component(view_rays, rg, pts, np.array([tv]))
    ref = midpoint_sky_component(pts, np.array([-1.0, 0.0, 0.8]), np.array([2.0, 0, 0]), np.array([0, 0, 1.4]), tv)
    assert ref.min() > 1e-3 and ref.max() > 0.1
    err = np.abs(sc.value - ref)
    assert np.all(err <= sc.bound + MIDPOINT_REL * ref), np.column_stack([sc.value, ref, sc.bound])[err > sc.bound]
    # and the bound is within the tolerance: 0.5 % of SC or 0.005 % D
    assert np.all(sc.bound <= np.maximum(0.005 * sc.value, 5e-5))
    engine.close()


def test_triangle_window_clipped_cells():
    # a pane that is not a rectangle (the lower-left half of the opening): cells cut by its outline
    # weigh their clipped solid angle, with the integrand's range over them in the bound
    b = BoxRoom(building_height=0.0, triangle_window=True)
    engine, view_rays, rg = _engine_for(box_room_polygons(b))
    pts = _room_points(b, spacing=1.0)
    sc = sky_component(view_rays, rg, pts, np.array([0.7]))
    ref = midpoint_sky_component(pts, np.array([-1.0, 0.0, 0.8]), np.array([2.0, 0, 0]), np.array([0, 0, 1.4]), 0.7,
                                 inside=lambda s, t: s + t <= 1.0, nu=800, nv=600)
    # the midpoint mask of a triangle errs along its hypotenuse: 3.3e-6 of the value here (measured)
    assert np.all(np.abs(sc.value - ref) <= sc.bound + 2 * MIDPOINT_REL * ref), np.column_stack([sc.value, ref, sc.bound])
    assert np.all(sc.bound <= np.maximum(0.005 * sc.value, 5e-5))
    engine.close()


def test_unobstructed_point_is_the_whole_sky():
    # a point under a 2 km open roof light 1 m above it sees the sky down to atan(1/1000) above the
    # horizon: SC = 1 less the sky below that, ∫ ℓ sin γ cos γ 2π dγ / (7π/9) ≈ 9 γ0² / 14 = 6.4e-7
    half = 1000.0
    polys = {"glazing": [[(-half, -half, 1.0), (half, -half, 1.0), (half, half, 1.0), (-half, half, 1.0)]]}
    tris = np.array([[[-half, -half, 1.0], [half, -half, 1.0], [half, half, 1.0]],
                     [[-half, -half, 1.0], [half, half, 1.0], [-half, half, 1.0]]])
    engine = RayEngine(tris.reshape(-1, 3), np.arange(6).reshape(2, 3), {"opaque": np.zeros(2, bool), "win": [0, 1]})
    w = Window("roof", 0, np.array([0, 1]), tris, np.array([0.0, 0.0, 1.0]), 4e6)
    rg = RoomGeometry([window_frame(w, 0)], np.zeros(2, int), tris, np.zeros(2, int), "win")
    sc = sky_component(ViewRays(engine, SimpleNamespace(layer=np.array([WINDOW, WINDOW]))), rg, np.zeros((1, 3)),
                       np.array([1.0]), SkyTolerance(resolution_deg=1.0))
    assert sc.value[0] == pytest.approx(1.0 - 9.0 * 1e-6 / 14.0, abs=sc.bound[0] + 1e-6)
    assert sc.bound[0] <= 0.005
    del polys
    engine.close()


@pytest.fixture(scope="module")
def black_room_report(tmp_path_factory):
    """The black room of issue 36 through ``en17037 check`` at the defaults: every surface and the
    ground black, a 2 x 1.4 m window of glazing tv 0.7 (Radiance's glass), nothing outside."""
    pytest.importorskip("pyradiance")
    from click.testing import CliRunner

    from en17037cli.cli import cli

    d = tmp_path_factory.mktemp("black-room")
    b = BoxRoom(building_height=0.0)
    path = box_room_project(d, b, view=None, sunlight=None)
    doc = yaml.safe_load(path.read_text())
    for r in doc["model"]["files"][0]["layers"]:
        if r["layer"] == "window":
            r["transmittance"] = 0.7
        else:
            r["reflectance"] = 0.0
    doc["daylight"] = {"median_diffuse_lx": 15000, "reflectance": {"ground": 0.0}}
    doc["requirements"] = {"daylight": "minimum"}
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    out = d / "out"
    res = CliRunner().invoke(cli, ["check", str(path), "--out", str(out), "--no-plots", "--quiet"], catch_exceptions=False)
    assert res.exit_code in (0, 1), res.output
    return b, json.loads((out / "report.json").read_text())


def test_black_room_daylight_factor_is_the_closed_form(black_room_report):
    # issue 36's check: in a black room D is the sky component alone, so at every point of the grid
    # (60 at 0.5 m, 0.1 % to 12 % D) the reported D lies within its reported error of the
    # independent integral; the reflected part is exactly 0 (every ray ends on black, or on the sky
    # straight through the glass, which the gather leaves out) and so is its interval
    b, report = black_room_report
    sec = report["rooms"][0]["daylight"]
    pts = np.array([p["point"] for p in sec["points"]])
    d = np.array([p["daylight_factor_pct"] for p in sec["points"]])
    err = np.array([p["daylight_factor_error_pct"] for p in sec["points"]])
    assert len(pts) == 60
    assert all(p["reflected_pct"] == 0.0 and p["reflected_error_pct"] == 0.0 for p in sec["points"])
    ref = 100.0 * midpoint_sky_component(pts, np.array([-1.0, 0.0, 0.8]), np.array([2.0, 0, 0]), np.array([0, 0, 1.4]), 0.7)
    # report.json rounds D to 4 decimals (5e-5 % D)
    assert np.all(np.abs(d - ref) <= err + MIDPOINT_REL * ref + 5e-5), np.column_stack([d, ref, err])
    assert np.all(err <= np.maximum(0.005 * d, 0.005) + 1e-4)
    assert sec["error_estimates"]["kinds"] == {"sky_component": "bound", "reflected": "99 % confidence interval"}
