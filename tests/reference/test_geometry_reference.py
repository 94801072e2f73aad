"""Geometric functions against closed forms."""
import numpy as np
import pytest
from oracles import rect_solid_angle_y0

from en17037cli.geometry import rectangle_solid_angle, triangle_normals, triangle_solid_angle, triangulate_polygon
from en17037cli.standard import THRESHOLDS, LevelThresholds, level_from_layers, level_from_value, near_threshold, room_level


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
    assert level_from_value([value], LevelThresholds(**THRESHOLDS["horizontal_sight_angle_deg"]))[0] == level


def test_layer_rule_of_table_a5():
    sky, land, ground = [True, False, True, True, False], [True, True, True, False, False], [True, False, False, True, True]
    assert level_from_layers(sky, land, ground).tolist() == [3, 1, 2, 0, 0]


def test_room_level_is_the_highest_reached_by_the_area_fraction():
    level, share = room_level([3, 3, 3, 2], 0.75)
    assert level == 3 and share["high"] == 0.75
    level, _ = room_level([3, 3, 2, 1], 0.75)
    assert level == 2


def test_near_threshold():
    t = LevelThresholds(**THRESHOLDS["outside_distance_m"])
    assert near_threshold([19.9995], [0.001], t).tolist() == [True]
    assert near_threshold([19.99], [0.001], t).tolist() == [False]
    assert near_threshold([np.inf], [np.inf], t).tolist() == [False]
    # an exact value (zero error) cannot flip, even at a threshold
    assert near_threshold([20.0], [0.0], t).tolist() == [False]
    # a single threshold value (a view layer's solid angle): 0 sr exactly is not near 0 sr,
    # 4e-4 sr with a 5e-4 sr estimate is
    assert near_threshold([0.0, 4e-4, 2e-3], [0.0, 5e-4, 5e-4], [0.0]).tolist() == [False, True, False]


def test_offset_rectangles_and_clipped_triangles_against_triangle_sums():
    """Any rectangle on the unit-distance plane (foot inside or outside it) equals the sum of its
    two Van Oosterom-Strackee triangles; a triangle clipped to a rectangle equals the fan of the
    clipped polygon, worked out here by hand for a right triangle cut by a vertical line."""
    from en17037cli.geometry import clipped_solid_angle, offset_rectangle_solid_angle

    rng = np.random.default_rng(3)
    x0, y0 = rng.uniform(-5, 5, (2, 200))
    x1, y1 = x0 + rng.uniform(0.01, 4, 200), y0 + rng.uniform(0.01, 4, 200)
    c = np.stack([np.stack([x0, y0, np.ones(200)], 1), np.stack([x1, y0, np.ones(200)], 1),
                  np.stack([x1, y1, np.ones(200)], 1), np.stack([x0, y1, np.ones(200)], 1)], 1)
    o = np.zeros((200, 3))
    vo = triangle_solid_angle(o, c[:, [0, 1, 2]]) + triangle_solid_angle(o, c[:, [0, 2, 3]])
    assert np.allclose(offset_rectangle_solid_angle(x0, x1, y0, y1), vo, rtol=1e-10, atol=1e-14)
    # right triangle (0,0) (2,0) (0,2) cut at x <= 1: the quadrilateral (0,0) (1,0) (1,1) (0,2)
    om, cen = clipped_solid_angle(np.array([[[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]]]), np.array([[-1.0, 1.0, -1.0, 3.0]]))
    quad = np.array([[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 2, 1]], float)
    exact = triangle_solid_angle(np.zeros((2, 3)), np.array([quad[[0, 1, 2]], quad[[0, 2, 3]]])).sum()
    assert abs(om[0] - exact) < 1e-12
    # area centroid of that quadrilateral: triangles (0,0)(1,0)(1,1) area 1/2 and (0,0)(1,1)(0,2) area 1
    expected = (0.5 * np.array([2 / 3, 1 / 3]) + 1.0 * np.array([1 / 3, 1.0])) / 1.5
    assert np.allclose(cen[0], expected, atol=1e-12)
