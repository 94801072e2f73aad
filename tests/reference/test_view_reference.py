"""View engine against values worked out by hand on the box room (en17037cli.samples.BoxRoom).

Room: window x in [-1, 1], z in [0.8, 2.2] in the plane y = 0, facing -y; room at y > 0. Outside:
ground z = 0 and a long building face at y = -25 m, 10 m high.
"""
from __future__ import annotations

import numpy as np
import pytest
import tolerances as tol
from oracles import layer_solid_angles, rect_solid_angle_y0, sight_angle_deg

from en17037cli.samples import BoxRoom

POINTS = np.array([[0.3, 2.0, 1.2], [-1.2, 5.5, 1.2], [1.5, 0.6, 1.7], [0.0, 3.0, 1.7], [-1.5, 1.0, 1.2]])


def run(b, pts_world):
    return b.view_points(pts_world, frame_depth_m=0.5)


def test_sight_angle_solid_angles_and_distance_match_hand_values(build):
    box = BoxRoom()
    b = build(box)
    r = run(b, POINTS)
    errors = {k: [] for k in ("sky", "landscape", "ground")}
    for i, p in enumerate(POINTS):
        assert abs(r.sight.angle_deg[i] - sight_angle_deg(p[0], p[1])) <= tol.SIGHT_ANGLE_DEG
        sky, land, ground = layer_solid_angles(p)
        for key, exact in (("sky", sky), ("landscape", land), ("ground", ground)):
            err = abs(r.solid.sr[key][i] - exact)
            assert err <= tol.solid_angle_sr(exact), (key, i, r.solid.sr[key][i], exact)
            errors[key].append(err)
        assert abs(r.solid.glazing_sr[i] - rect_solid_angle_y0(-1, 1, 0.8, 2.2, p)) < tol.TILING_SR
        # a facade parallel to the window across a 25 m street gives 25 m in every direction
        assert abs(r.distance_m[i] - 25.0) < tol.DISTANCE_M
    for key, err in errors.items():  # the estimates cover the errors, and not tenfold
        assert r.solid.err_sr[key].max() <= tol.SOLID_ANGLE_ESTIMATE_MAX_SR
        tol.check_estimate(err, r.solid.err_sr[key], what=key)
    # from the back of the room the building hides the sky entirely (z_top > window head); an
    # exact zero is not 'near' the 0 sr layer threshold
    assert r.solid.sr["sky"][1] == 0.0 and not r.visible["sky"][1]
    assert not r.near[1]


@pytest.mark.parametrize("reveal", [0.4])
def test_reveals_reduce_the_sight_angle_to_inner_and_outer_edges(build, reveal):
    box = BoxRoom(wall_thickness=reveal)
    b = build(box)
    pts = POINTS.copy()
    pts[:, 1] += reveal  # keep the points at the same distance from the inner wall face
    r = run(b, pts)
    for i, p in enumerate(pts):
        expected = sight_angle_deg(p[0], p[1], reveal=reveal)
        assert abs(r.sight.angle_deg[i] - expected) <= tol.SIGHT_ANGLE_DEG, (i, r.sight.angle_deg[i], expected)
    # the reveals' edges are placed in plan: the estimate (a round-off bound) covers each error, and
    # not tenfold what a float64 closed form can resolve
    errors = [r.sight.angle_deg[i] - sight_angle_deg(p[0], p[1], reveal=reveal) for i, p in enumerate(pts)]
    tol.check_estimate(errors, r.sight.angle_err_deg, floor=tol.SIGHT_ANGLE_ROUNDOFF_DEG, what="sight angle")


def test_closed_shutter_gives_no_view(build):
    b = build(BoxRoom(shutter=True))
    r = run(b, POINTS)
    for key in ("sky", "landscape", "ground"):
        assert np.all(r.solid.sr[key] == 0.0), key
    assert np.all(r.sight.angle_deg == 0.0)
    assert np.all(r.level == 0)


def test_no_leak_through_shared_edges_of_a_split_window(build):
    """A million rays aimed at the shared edges of a window split into 50 strips of triangles,
    behind a closed shutter: not one may leave; without the shutter every one must."""
    shut = build(BoxRoom(shutter=True, window_split=50), sub="shut")
    open_ = build(BoxRoom(window_split=50), sub="open")
    rng = np.random.default_rng(0)
    n = 1_000_000
    xs = np.linspace(-1, 1, 51)[1:-1]
    target = np.column_stack([rng.choice(xs, n), np.zeros(n), rng.uniform(0.81, 2.19, n)])
    half = n // 2  # half the rays on the diagonals of the strips' triangles
    strip = rng.integers(0, 50, half)
    u = rng.uniform(0.01, 0.99, half)
    x0 = -1 + strip * 0.04
    target[:half, 0] = x0 + 0.04 * u
    target[:half, 2] = 0.8 + 1.4 * u
    origin = np.column_stack([rng.uniform(-1.8, 1.8, n), rng.uniform(0.5, 5.5, n), rng.uniform(0.3, 2.7, n)])
    d = target - origin
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    from en17037cli.criteria.view.rays import BLOCKED
    from en17037cli.scene import room_window_group

    cls = open_.view_rays.through_windows(room_window_group(open_.room), open_.scene.to_local(origin), d)[0]
    assert np.count_nonzero(cls == BLOCKED) == 0
    # The panel overlaps the opening by 5 cm only: a grazing ray can pass beside it, which is
    # geometry, not a leak. Keep the rays that cross the panel's plane (y = 0.05) on the panel,
    # half of them aimed at its own diagonal (the edge its two triangles share).
    s_diag = rng.uniform(0.001, 0.999, half)
    on_diag = np.column_stack([-1.05 + 2.1 * s_diag, np.full(half, 0.05), 0.75 + 1.5 * s_diag])
    d2 = on_diag - origin[:half]
    d2 /= np.linalg.norm(d2, axis=1, keepdims=True)
    origin2 = np.concatenate([origin, origin[:half]])
    d_all = np.concatenate([d, d2])
    t = (0.05 - origin2[:, 1]) / d_all[:, 1]
    hit = origin2 + t[:, None] * d_all
    on_panel = (np.abs(hit[:, 0]) < 1.05 - 1e-6) & (hit[:, 2] > 0.75 + 1e-6) & (hit[:, 2] < 2.25 - 1e-6)
    assert on_panel.sum() > 1_000_000
    cls = shut.view_rays.through_windows(room_window_group(shut.room), shut.scene.to_local(origin2[on_panel]), d_all[on_panel])[0]
    assert np.count_nonzero(cls != BLOCKED) == 0
    # the split window is still one window
    assert len(open_.scene.windows) == 1 and len(open_.scene.windows[0].face_ids) == 100


def test_room_levels_from_the_grid(build):
    b = build(BoxRoom(), view={"grid_spacing_m": 1.0})
    res = b.view_room()
    assert [e.eye_height_m for e in res.eye_heights] == [1.2, 1.7]
    for e in res.eye_heights:
        v = e.values
        pts = e.points_local + b.scene.origin
        expected = np.array([sight_angle_deg(x, y) for x, y in pts[:, :2]])
        assert np.all(np.abs(v.sight.angle_deg - expected) <= 1e-3)
        # 25 m street: the distance criterion is 'medium' (>= 20 m, < 50 m) at every point
        assert np.all(v.level_by_criterion["outside_distance"] == 2)
        assert e.level_by_criterion["outside_distance"] == 2
        # the room level is the lowest of the three criteria
        assert e.level == min(e.level_by_criterion.values())
