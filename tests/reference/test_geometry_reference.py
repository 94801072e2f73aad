"""Geometric functions against closed forms."""
import numpy as np
import pytest

from en17037cli.geometry import rectangle_solid_angle, triangle_solid_angle, triangulate_polygon, triangle_normals
from en17037cli.samples import rect_solid_angle_y0
from en17037cli.standard import level_from_layers, level_from_value, near_threshold, room_level, THRESHOLDS


def test_square_seen_from_its_centre_axis():
    # a 2a x 2a square at distance d on its axis: 4 atan(a^2 / (d sqrt(2 a^2 + d^2)))
    a, d = 1.0, 1.0
    exact = 4 * np.arctan(a * a / (d * np.sqrt(2 * a * a + d * d)))  # = 2 pi / 3 for a = d
    assert abs(exact - 2 * np.pi / 3) < 1e-12
    sq = np.array([[-a, d, -a], [a, d, -a], [a, d, a], [-a, d, a]])
    tris = np.array([sq[[0, 1, 2]], sq[[0, 2, 3]]])
    total = triangle_solid_angle(np.zeros((2, 3)), tris).sum()
    assert abs(total - exact) < 1e-12
    assert abs(rect_solid_angle_y0(-a, a, -a, a, (0, d, 0)) - exact) < 1e-12
    assert abs(4 * rectangle_solid_angle(a, a, d) - exact) < 1e-12


def test_octant_triangle_is_one_eighth_of_the_sphere():
    tri = np.eye(3)[None]
    assert abs(triangle_solid_angle(np.zeros((1, 3)), tri)[0] - 4 * np.pi / 8) < 1e-12


def test_concave_polygon_is_ear_clipped_to_its_true_area():
    # an L shape of area 3 (a 2 x 2 square minus a 1 x 1 corner); a fan from vertex 0 would cover 4 - 1 + ...
    L = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 2, 0], [0, 2, 0]], float)
    tris = triangulate_polygon(L)
    _, areas = triangle_normals(L[tris])
    assert len(tris) == 4 and abs(areas.sum() - 3.0) < 1e-12
    # a fan from vertex 2 would not: it covers area outside the polygon
    fan = np.array([[2, i, i + 1] for i in range(3, 5)] + [[2, 5, 0], [2, 0, 1]])
    assert triangle_normals(L[fan])[1].sum() > 3.0


def test_slightly_non_planar_polygon_still_triangulates():
    rng = np.random.default_rng(1)
    ang = np.linspace(0, 2 * np.pi, 9)[:-1]
    poly = np.column_stack([np.cos(ang), np.sin(ang), rng.uniform(-0.03, 0.03, 8)])  # 6 cm out of plane
    assert len(triangulate_polygon(poly)) == 6


@pytest.mark.parametrize("value,level", [(13.99, 0), (14, 1), (27.9, 1), (28, 2), (54, 3), (np.inf, 3), (np.nan, 0)])
def test_levels_compare_with_greater_or_equal(value, level):
    assert level_from_value([value], THRESHOLDS["horizontal_sight_angle_deg"])[0] == level


def test_layer_rule_of_table_a5():
    s, l, g = [True, False, True, True, False], [True, True, True, False, False], [True, False, False, True, True]
    assert level_from_layers(s, l, g).tolist() == [3, 1, 2, 0, 0]


def test_room_level_is_the_highest_reached_by_the_area_fraction():
    level, share = room_level([3, 3, 3, 2], 0.75)
    assert level == 3 and share["high"] == 0.75
    level, _ = room_level([3, 3, 2, 1], 0.75)
    assert level == 2


def test_near_threshold():
    t = THRESHOLDS["outside_distance_m"]
    assert near_threshold([19.9995], [0.001], t).tolist() == [True]
    assert near_threshold([19.99], [0.001], t).tolist() == [False]
    assert near_threshold([np.inf], [np.inf], t).tolist() == [False]
    # an exact value (zero error) cannot flip, even at a threshold
    assert near_threshold([20.0], [0.0], t).tolist() == [False]
    # a single threshold value (a view layer's solid angle): 0 sr exactly is not near 0 sr,
    # 4e-4 sr with a 5e-4 sr estimate is
    assert near_threshold([0.0, 4e-4, 2e-3], [0.0, 5e-4, 5e-4], [0.0]).tolist() == [False, True, False]
