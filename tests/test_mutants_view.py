"""View engine and its geometry against hand values, shapely clipping and fixed tolerances
(mutation testing, docs/mutation.md).

Box room (en17037cli.samples.BoxRoom): opening x in [-1, 1], z in [0.8, 2.2] in the plane y = 0,
facing -y, room at y > 0; ground z = 0 and a long building face at y = -25 m, 10 m high.
Tolerances come from the settings (the bisection tolerance, the solid-angle grid) or from float32
rays, never from the engine's own error estimate.
"""
from __future__ import annotations

import numpy as np
import pytest
import shapely

from en17037cli.criteria.view.distance import pad_rows, ragged_statistic, weighted_statistic
from en17037cli.geometry import clipped_solid_angle, in_triangle, points_in_triangles, rectangle_solid_angle, triangle_solid_angle
from en17037cli.geometry.planar import area2, clip_halfplane
from en17037cli.samples import MULLION_GAP, BoxRoom
from tests.oracles import layer_solid_angles, rect_solid_angle_y0, sight_angle_deg

# float32 ray directions and distances (Embree): ~1e-7 relative, i.e. < 1e-5 deg of azimuth
FLOAT32_DEG = 1e-5


def mullion_sight_deg(p, box):
    """Sight angle past 5 cm mullion plates MULLION_GAP inside the glazing (as in the reference tests)."""
    x0, y0 = p[0], p[1]
    lost = sum(np.degrees(np.arctan2(xm + 0.025 - x0, y0 - MULLION_GAP) - np.arctan2(xm - 0.025 - x0, y0 - MULLION_GAP))
               for xm in box.mullions)
    return sight_angle_deg(x0, y0) - lost


MULLION_PTS = np.array([[0.0, 7.5, 1.2], [0.6, 6.0, 1.7], [-0.8, 7.0, 1.2], [0.2, 3.0, 1.2], [-0.3, 5.1, 1.7],
                        [0.45, 4.2, 1.2], [-0.55, 2.5, 1.7], [0.1, 6.6, 1.2]])


# --- horizontal sight angle: the fan's bisection and its own tolerance (view.sight_angle_method:
# fan; the plan method is tested against closed forms in tests/reference/test_sight_angle_plan.py)

def test_sight_angle_transitions_are_located_to_the_angle_tolerance(build):
    """Two mullions (each > 0.3 deg wide from these points, wider than the 0.2 deg fan step) give
    four transitions per point. Each is bisected until its bracket is at most angle_tolerance_deg
    (2e-4 deg) wide and reported at the bracket's midpoint: at most 1e-4 deg off each, so the
    sight angle is within 4 x 1e-4 deg of the hand value (plus float32 rays)."""
    tol = 2e-4
    box = BoxRoom(depth=8.0, mullions=(-0.35, 0.35))
    b = build(box, view={"horizontal_resolution_deg": 0.2, "angle_tolerance_deg": tol, "sight_angle_method": "fan"})
    r = b.view_points(MULLION_PTS)
    exact = np.array([mullion_sight_deg(p, box) for p in MULLION_PTS])
    assert r.sight.transitions.tolist() == [4] * len(MULLION_PTS)
    assert np.all(np.abs(r.sight.angle_deg - exact) <= 4 * 0.5 * tol + FLOAT32_DEG), r.sight.angle_deg - exact


def test_sight_angle_error_bound_and_ray_count_follow_the_settings(build):
    """Reported bound: the final bracket widths (each <= tolerance after ceil(log2(res / tol))
    halvings) plus the two end insets (tolerance / 2 each). Rays: ceil(width / res) + 1 fan
    samples and 10 bisection rays per transition (res / tol = 1000, 2^10 = 1024)."""
    tol, res = 2e-4, 0.2
    box = BoxRoom(depth=8.0, mullions=(-0.35, 0.35))
    b = build(box, view={"horizontal_resolution_deg": res, "angle_tolerance_deg": tol, "sight_angle_method": "fan"})
    r = b.view_points(MULLION_PTS)
    assert np.all(r.sight.angle_err_deg <= 4 * tol + 2 * 0.5 * tol + 1e-12), r.sight.angle_err_deg
    assert np.all(r.sight.angle_err_deg >= 2 * 0.5 * tol)  # the insets alone
    width = np.array([sight_angle_deg(p[0], p[1]) for p in MULLION_PTS])  # the fan spans the opening
    assert r.sight.rays.tolist() == (np.ceil(width / res - 1e-9) + 1 + 10 * 4).astype(int).tolist()


def test_sight_angle_without_transitions_is_exact(build):
    """No reveal, no mullion: every fan ray leaves, the fan interval is the window's azimuth range
    computed exactly; only the insets are estimated."""
    b = build(BoxRoom(), view={"horizontal_resolution_deg": 5.0, "angle_tolerance_deg": 0.01, "sight_angle_method": "fan"})
    pts = np.array([[0.3, 2.0, 1.2], [-1.5, 0.5, 1.7], [1.9, 0.2, 1.2]])
    r = b.view_points(pts)
    exact = [sight_angle_deg(p[0], p[1]) for p in pts]
    assert np.allclose(r.sight.angle_deg, exact, rtol=0, atol=1e-9)
    assert r.sight.transitions.tolist() == [0, 0, 0]
    assert np.allclose(r.sight.angle_err_deg, 0.01, rtol=0, atol=1e-12)  # two insets of tolerance / 2


def test_sight_angle_of_a_window_facing_azimuth_zero(build):
    """The model turned 90 deg: the window faces +x, so its fan straddles azimuth 0 = 2 pi and is
    split there; the sight angle is the same hand value."""
    b = build(BoxRoom(), rotate_deg=90.0)
    pts = np.array([[0.3, 2.0, 1.2], [-1.2, 5.5, 1.7], [1.5, 0.6, 1.2]])
    c, s = 0.0, 1.0  # rotation by 90 deg counter-clockwise: (x, y) -> (-y, x)
    rotated = np.column_stack([c * pts[:, 0] - s * pts[:, 1], s * pts[:, 0] + c * pts[:, 1], pts[:, 2]])
    r = b.view_points(rotated)
    exact = np.array([sight_angle_deg(p[0], p[1]) for p in pts])
    assert np.allclose(r.sight.angle_deg, exact, rtol=0, atol=1e-9), r.sight.angle_deg - exact
    assert np.allclose(r.distance_m, 25.0, atol=1e-3)


def test_no_window_at_eye_height_from_any_point(build):
    """Every eye above the window head: no horizontal ray meets a window, nothing is traced."""
    b = build(BoxRoom())
    r = b.view_points(np.array([[0.4, 3.0, 2.3], [-0.5, 2.0, 2.5]]))
    assert r.sight.angle_deg.tolist() == [0.0, 0.0] and r.sight.angle_err_deg.tolist() == [0.0, 0.0]
    assert r.sight.rays.tolist() == [0, 0] and r.sight.transitions.tolist() == [0, 0]


def test_a_tolerance_coarser_than_the_fan_step_bisects_nothing(build):
    """angle_tolerance_deg >= horizontal_resolution_deg: the fan samples are already that close, so
    no bisection ray is traced and each transition's bracket is one fan step (<= 0.2 deg)."""
    box = BoxRoom(depth=8.0, mullions=(-0.35, 0.35))
    b = build(box, view={"horizontal_resolution_deg": 0.2, "angle_tolerance_deg": 0.4, "sight_angle_method": "fan"})
    r = b.view_points(MULLION_PTS[:3])
    width = np.array([sight_angle_deg(p[0], p[1]) for p in MULLION_PTS[:3]])
    assert r.sight.rays.tolist() == (np.ceil(width / 0.2 - 1e-9) + 1).astype(int).tolist()
    exact = np.array([mullion_sight_deg(p, box) for p in MULLION_PTS[:3]])
    assert np.all(np.abs(r.sight.angle_deg - exact) <= 4 * 0.5 * 0.2 + FLOAT32_DEG)


def test_eye_at_the_head_height_sees_the_limit_from_inside(build):
    """An eye exactly at the window head (2.2 m) is moved 1e-6 m down: the full window width."""
    b = build(BoxRoom())
    r = b.view_points(np.array([[0.4, 3.0, 2.2], [0.4, 3.0, 0.8], [0.4, 3.0, 2.3]]))
    assert abs(r.sight.angle_deg[0] - sight_angle_deg(0.4, 3.0)) <= 1e-9
    assert abs(r.sight.angle_deg[1] - sight_angle_deg(0.4, 3.0)) <= 1e-9
    assert r.sight.angle_deg[2] == 0.0  # above the window: no horizontal ray meets it


# --- solid angles: the reported error ------------------------------------------------------------

PTS = np.array([[0.3, 2.0, 1.2], [-1.2, 5.5, 1.2], [1.5, 0.6, 1.7], [0.0, 3.0, 1.7]])


def test_layer_errors_stop_within_the_requested_tolerance(build):
    """Refinement stops once each layer's error estimate is within max(rel x value, abs); with
    enough levels it never reaches the last one, so every reported error is within that bound."""
    rel, abs_ = 0.005, 5e-4
    b = build(BoxRoom(), view={"refine_levels": 8, "solid_angle_rel_tolerance": rel, "solid_angle_abs_tolerance_sr": abs_})
    r = b.view_points(PTS)
    for key in ("sky", "landscape", "ground"):
        bound = np.maximum(rel * r.solid.sr[key], abs_)
        assert np.all(r.solid.err_sr[key] <= bound + 1e-15), (key, r.solid.err_sr[key], bound)
    # and the values are that close to the hand values (the estimate is half the mixed cells,
    # a bound on each cell's misassigned part)
    for i, p in enumerate(PTS):
        for key, exact in zip(("sky", "landscape", "ground"), layer_solid_angles(p)):
            assert abs(r.solid.sr[key][i] - exact) <= max(rel * exact, abs_) + 1e-12, (i, key)


def test_layer_error_is_half_the_cells_on_the_boundary_line(build):
    """No refinement: the cells of 1 deg are final. The building's top edge projects to one line
    of constant gnomonic beta, so the sky error is half the solid angle of one row of cells
    straddling it: at most half the window strip 1 deg either side of the line (hand formula),
    and at least the actual error."""
    box = BoxRoom()
    res = 1.0
    b = build(box, view={"refine_levels": 0, "angular_resolution_deg": res, "solid_angle_rel_tolerance": 0.0,
                         "solid_angle_abs_tolerance_sr": 0.0})
    # the building's top edge crosses the window from each of these points (sky and landscape seen)
    pts = np.array([[0.3, 2.0, 1.2], [0.8, 1.0, 1.7], [-0.5, 1.5, 1.2]])
    r = b.view_points(pts)
    for i, p in enumerate(pts):
        x0, y0, z0 = p
        z_top = z0 + (box.building_height - z0) * y0 / (y0 + box.street)  # the top edge on the glazing plane
        beta = np.arctan2(z_top - z0, y0)
        lo, hi = (z0 + y0 * np.tan(beta + s * np.radians(res)) for s in (-1, 1))
        strip = rect_solid_angle_y0(-1, 1, max(lo, 0.8), min(hi, 2.2), p)
        sky = layer_solid_angles(p)[0]
        assert abs(r.solid.sr["sky"][i] - sky) <= r.solid.err_sr["sky"][i] + 1e-12
        assert 0 < r.solid.err_sr["sky"][i] <= 0.5 * strip, (i, r.solid.err_sr["sky"][i], 0.5 * strip)


# --- outside distance: perpendicular to the window ----------------------------------------------

@pytest.mark.parametrize("method, statistic", [("horizontal", "mean"), ("horizontal", "p90"), ("horizontal", "median"),
                                               ("solid_angle", "min"), ("solid_angle", "p10")])
def test_outside_distance_to_a_parallel_facade_is_the_street_width(build, method, statistic):
    """Every direction through the window that meets the facade does so 25 m from the glazing
    plane: measured perpendicular to the window, every landscape sample is 25 m. An oblique slant
    distance would be 25 / cos of the angle off the normal: from these points every direction
    through the window is 40 to 80 deg off it (at least 32 m). The solid-angle method counts sky
    and ground as +inf, so it is judged by its low statistics (the facade is > 10 % of the view)."""
    b = build(BoxRoom(), view={"distance_method": method, "distance_statistic": statistic})
    pts = np.array([[1.5, 0.6, 1.7], [-1.8, 0.8, 1.2]])
    r = b.view_points(pts)
    assert np.all(np.abs(r.distance_m - 25.0) < 1e-3), r.distance_m  # float32 distances at 25-150 m: ~1e-5 m


@pytest.mark.parametrize("method", ["horizontal", "solid_angle"])
def test_outside_distance_is_infinite_without_landscape(build, method):
    b = build(BoxRoom(building_height=0), view={"distance_method": method, "distance_statistic": "min"})
    r = b.view_points(np.array([[0.3, 2.0, 1.2]]))
    assert np.isinf(r.distance_m[0])


# --- weighted statistics by hand ------------------------------------------------------------------

def test_weighted_statistics_by_hand():
    v = np.array([[3.0, 1.0, 2.0, np.inf], [0.5, 4.0, 6.0, np.nan], [1.0, 2.0, 3.0, 4.0]])
    w = np.array([[1.0, 1.0, 1.0, 1.0], [0.0, 1.0, 3.0, 0.0], [0.0, 0.0, 0.0, 0.0]])
    # row 0: sorted 1, 2, 3, inf with cumulative weights 1, 2, 3, 4 (total 4)
    # row 1: 0.5 has no weight; 4 (w 1), 6 (w 3): cumulative 1, 4
    val, gap = weighted_statistic(v, w, "median")
    assert val[:2].tolist() == [2.0, 6.0] and np.isnan(val[2])
    assert gap[:2].tolist() == [1.0, 2.0] and np.isnan(gap[2])  # largest step to a weighted neighbour
    val, gap = weighted_statistic(v, w, "min")
    assert val[:2].tolist() == [1.0, 4.0] and gap[:2].tolist() == [1.0, 2.0]
    val, _ = weighted_statistic(v, w, "p25")
    assert val[:2].tolist() == [1.0, 4.0]  # 25 % of the total weight (1) is reached at the first weighted value
    val, _ = weighted_statistic(v, w, "p26")
    assert val[:2].tolist() == [2.0, 6.0]
    val, gap = weighted_statistic(v, w, "p100")
    assert val[0] == np.inf and val[1] == 6.0 and gap[0] == 0.0  # an infinite gap is not a resolution
    val, gap = weighted_statistic(v, w, "mean")
    assert val[0] == np.inf and val[1] == (4.0 + 18.0) / 4 and np.isnan(val[2])
    assert gap.tolist() == [0.0, 0.0, 0.0]
    val, _ = weighted_statistic(np.array([[2.0, 4.0]]), np.array([[1.0, 3.0]]), "mean")
    assert val.tolist() == [3.5]


def test_ragged_rows_are_padded_and_summarised_per_row():
    row = np.array([2, 0, 2, 2, 0])
    vals = np.array([5.0, 1.0, 7.0, 6.0, 3.0])
    wts = np.array([1.0, 2.0, 1.0, 1.0, 1.0])
    V, W = pad_rows(row, vals, wts, 4)
    assert V.shape == (4, 3)
    assert V[0, :2].tolist() == [1.0, 3.0] and V[2].tolist() == [5.0, 7.0, 6.0]
    assert W[0].tolist() == [2.0, 1.0, 0.0] and W[1].tolist() == [0.0, 0.0, 0.0] and W[3].sum() == 0
    val, _ = ragged_statistic(row, vals, wts, 4, "median")
    assert val[0] == 1.0 and val[2] == 6.0 and np.isnan(val[1]) and np.isnan(val[3])
    val, _ = ragged_statistic(np.zeros(0, int), np.zeros(0), np.zeros(0), 2, "median")
    assert np.isnan(val).all() and val.shape == (2,)


# --- planar geometry and clipped solid angles against shapely -------------------------------------

def test_in_triangle_edges_vertices_and_both_orientations():
    tri = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    pts = np.array([[0.5, 0.5], [1.0, 1.0], [0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [0.0, 1.0],  # inside, edges, vertices
                    [1.0 + 1e-6, 1.0], [-1e-6, 0.5], [0.5, -1e-6], [3.0, 3.0]])  # just outside each edge, far
    expected = [True] * 6 + [False] * 4
    assert in_triangle(pts, np.broadcast_to(tri, (len(pts), 3, 2))).tolist() == expected
    cw = tri[::-1]  # clockwise: the same answers
    assert in_triangle(pts, np.broadcast_to(cw, (len(pts), 3, 2))).tolist() == expected
    for perm in ([1, 2, 0], [2, 0, 1]):  # every edge in every slot
        assert in_triangle(pts, np.broadcast_to(tri[perm], (len(pts), 3, 2))).tolist() == expected
    assert points_in_triangles(pts, np.stack([tri, tri + 10.0])).tolist() == expected
    assert points_in_triangles(np.array([[10.5, 10.5]]), np.stack([tri, tri + 10.0])).tolist() == [True]
    assert area2(tri) == 4.0 and area2(cw) == 4.0


def test_clip_halfplane_by_hand():
    sq = np.array([[[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]])
    out, n = clip_halfplane(sq, np.array([4]), 0, np.array([0.5]), 1.0)  # keep x >= 0.5
    assert n.tolist() == [4]
    assert np.allclose(out[0, :4], [[0.5, 0.0], [2.0, 0.0], [2.0, 2.0], [0.5, 2.0]])
    out, n = clip_halfplane(sq, np.array([4]), 1, np.array([0.5]), -1.0)  # keep y <= 0.5
    assert n.tolist() == [4]
    assert np.allclose(out[0, :4], [[0.0, 0.0], [2.0, 0.0], [2.0, 0.5], [0.0, 0.5]])
    out, n = clip_halfplane(sq, np.array([4]), 0, np.array([3.0]), 1.0)  # nothing left
    assert n.tolist() == [0]
    # a triangle stored in 4 slots (count 3): the unused slot is ignored
    tri = np.array([[[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [9.0, 9.0]]])
    out, n = clip_halfplane(tri, np.array([3]), 0, np.array([1.0]), -1.0)  # keep x <= 1
    assert n.tolist() == [4]
    assert np.allclose(out[0, :4], [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 2.0]])


def _fan_solid_angle(coords):
    """Solid angle of a convex polygon on the plane z = 1 seen from the origin: fan of exact triangles."""
    c = np.asarray(coords)[:-1]
    if len(c) < 3:
        return 0.0
    p3 = np.column_stack([c, np.ones(len(c))])
    tris = np.array([[p3[0], p3[i], p3[i + 1]] for i in range(1, len(c) - 1)])
    return float(triangle_solid_angle(np.zeros((len(tris), 3)), tris).sum())


def test_clipped_solid_angle_and_centroid_against_shapely():
    """Random triangles clipped to random rectangles on the unit-distance plane: the solid angle
    of shapely's intersection polygon (exact fan of triangles) and its area centroid."""
    rng = np.random.default_rng(7)
    m = 300
    tri = rng.uniform(-3, 3, (m, 3, 2))
    x0, y0 = rng.uniform(-3, 2, (2, m))
    rect = np.column_stack([x0, x0 + rng.uniform(0.1, 3, m), y0, y0 + rng.uniform(0.1, 3, m)])
    tri[:20] = rect[:20, None, [0, 2]] + rng.uniform(0.01, 0.09, (20, 3, 2))  # 20 triangles wholly inside
    om, cen = clipped_solid_angle(tri, rect)
    n_empty = n_full = 0
    for i in range(m):
        poly = shapely.Polygon(tri[i]).intersection(shapely.box(rect[i, 0], rect[i, 2], rect[i, 1], rect[i, 3]))
        if poly.area < 1e-12:
            n_empty += 1
            assert om[i] < 1e-9 and (np.isnan(cen[i]).all() or poly.area > 0)
            continue
        poly = shapely.geometry.polygon.orient(poly)
        n_full += shapely.Polygon(tri[i]).within(shapely.box(rect[i, 0], rect[i, 2], rect[i, 1], rect[i, 3]))
        assert abs(om[i] - _fan_solid_angle(poly.exterior.coords)) < 1e-10, i
        assert np.allclose(cen[i], [poly.centroid.x, poly.centroid.y], atol=1e-9), i
    assert n_empty > 10 and n_full > 2 and m - n_empty > 100  # every case is exercised


def test_clipped_solid_angle_of_a_triangle_cut_by_all_four_sides():
    # a large triangle around a small rectangle: the clip is the rectangle itself
    om, cen = clipped_solid_angle(np.array([[[-10.0, -10.0], [10.0, -10.0], [0.0, 10.0]]]), np.array([[0.2, 0.7, -0.3, 0.4]]))
    x0, x1, y0, y1 = 0.2, 0.7, -0.3, 0.4
    exact = rect_solid_angle_y0(x0, x1, y0, y1, (0.0, 1.0, 0.0))  # the same rectangle on the plane y = 1
    assert abs(om[0] - exact) < 1e-12
    assert np.allclose(cen[0], [0.45, 0.05], atol=1e-12)


def test_rectangle_solid_angle_corner_formula():
    # Omega = atan(a b / (d sqrt(a^2 + b^2 + d^2)))
    for a, b, d in ((1.0, 2.0, 3.0), (0.5, 4.0, 0.25), (2.0, 2.0, 1.0)):
        assert abs(rectangle_solid_angle(a, b, d) - np.arctan(a * b / (d * np.sqrt(a * a + b * b + d * d)))) < 1e-13


def test_round_window_cells_add_up_to_the_exact_pane(build):
    """A round pane of 48 triangles (frame ring 2 cm inside): cells are clipped against its many
    triangles (the inside / outside box test first); their weights must add up to the sum of the
    exact solid angles of the pane's triangles."""
    from en17037cli.samples.box import _round_window

    box = BoxRoom(round_window=48)
    b = build(box, view={"angular_resolution_deg": 2.0, "refine_levels": 2})
    pts = np.array([[0.3, 2.0, 1.2], [-0.6, 1.0, 1.7], [1.4, 0.7, 1.5]])
    r = b.view_points(pts)
    glazing, _ = _round_window(box)
    tris = np.array(glazing, dtype=float)
    for i, p in enumerate(pts):
        exact = triangle_solid_angle(np.repeat(p[None], len(tris), 0), tris).sum()
        assert abs(r.solid.glazing_sr[i] - exact) < 1e-9, (i, r.solid.glazing_sr[i], exact)
        total = sum(r.solid.sr[k][i] for k in ("sky", "landscape", "ground"))
        # the frame ring (5 cm, 2 cm inside) hides a thin annulus of the pane's edge; nothing else
        assert total <= exact + 1e-9


def test_clipped_heptagon_uses_every_fan_triangle():
    """A triangle cut by all four sides of a rectangle leaves a heptagon (three cut corners): the
    most vertices a clip can have, so the last fan slot is used. Checked against shapely."""
    rect = np.array([[-1.0, 1.0, -1.0, 1.0]])
    # edges x + y = 1.5 (cuts the top-right corner), y - 3x = 2.6 (top-left), x - 3y = 2.6 (bottom-right);
    # the bottom-left corner lies inside
    lines = [(1.0, 1.0, 1.5), (-3.0, 1.0, 2.6), (1.0, -3.0, 2.6)]

    def meet(a, b):
        m = np.array([[a[0], a[1]], [b[0], b[1]]])
        return np.linalg.solve(m, [a[2], b[2]])
    tri = np.array([[meet(lines[0], lines[1]), meet(lines[1], lines[2]), meet(lines[2], lines[0])]])
    poly = shapely.Polygon(tri[0]).intersection(shapely.box(-1, -1, 1, 1))
    assert len(poly.exterior.coords) - 1 == 7
    om, cen = clipped_solid_angle(tri, rect)
    assert abs(om[0] - _fan_solid_angle(shapely.geometry.polygon.orient(poly).exterior.coords)) < 1e-12
    assert np.allclose(cen[0], [poly.centroid.x, poly.centroid.y], atol=1e-12)


@pytest.mark.parametrize("res", [5.0, 9.0])
def test_unobstructed_triangular_window_layers_add_up_to_its_solid_angle(build, res):
    """No building: every direction through the glass is sky or ground. Coarse cells near the
    triangle's acute corners have no corner sample inside the glass; their extra sample inside
    the glazing must still give them a layer, so the layers add up to the exact solid angle."""
    box = BoxRoom(triangle_window=True, building_height=0)
    b = build(box, view={"angular_resolution_deg": res, "refine_levels": 0})
    pts = np.array([[0.3, 2.0, 1.2], [-0.8, 0.5, 1.7], [1.2, 0.4, 1.2], [0.9, 0.3, 2.0]])
    r = b.view_points(pts)
    tri = np.array([[[-1.0, 0.0, 0.8], [1.0, 0.0, 0.8], [-1.0, 0.0, 2.2]]])
    for i, p in enumerate(pts):
        exact = float(triangle_solid_angle(p[None], tri)[0])
        total = sum(r.solid.sr[k][i] for k in ("sky", "landscape", "ground"))
        assert abs(r.solid.glazing_sr[i] - exact) < 1e-9 and abs(total - exact) < 1e-9, (i, total, exact)
        assert r.solid.sr["landscape"][i] == 0.0  # no building: no landscape, whatever lies outside the outline
