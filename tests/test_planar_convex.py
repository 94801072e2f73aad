"""Convex outlines answered with half-planes (the view engine's arched and round panes), against
shapely's exact predicates: random convex polygons and boxes, and boxes whose corners sit exactly on
the polygon's vertices and edges (the degenerate placements of issue 28)."""
from __future__ import annotations

import numpy as np
import pytest
import shapely

from en17037cli.geometry import boxes_vs_convex, convex_halfplanes, points_in_convex


def convex(rng, n):
    hull = shapely.MultiPoint(rng.uniform(-1, 1, (n, 2))).convex_hull
    ring = np.asarray(shapely.orient_polygons(hull).exterior.coords)[:-1]
    return hull, ring


@pytest.mark.parametrize("seed", range(20))
def test_boxes_and_points_against_shapely(seed):
    rng = np.random.default_rng(seed)
    poly, ring = convex(rng, rng.integers(3, 40))
    hp = convex_halfplanes(ring)
    lo, hi = ring.min(axis=0), ring.max(axis=0)
    extent = (lo[0], hi[0], lo[1], hi[1])
    m = 400
    c = rng.uniform(-1.3, 1.3, (m, 2))
    size = rng.uniform(0, 0.6, (m, 2)) * rng.choice([1e-6, 0.1, 1.0], (m, 1))
    x0, y0 = c[:, 0], c[:, 1]
    # every fifth box with a corner on a vertex of the polygon, every seventh on the middle of an edge
    v = ring[rng.integers(0, len(ring), m)]
    x0[::5], y0[::5] = v[::5, 0], v[::5, 1]
    mid = 0.5 * (ring + np.roll(ring, -1, axis=0))[rng.integers(0, len(ring), m)]
    x0[::7], y0[::7] = mid[::7, 0], mid[::7, 1]
    x1, y1 = x0 + size[:, 0], y0 + size[:, 1]
    inside, apart = boxes_vs_convex(hp, extent, x0, x1, y0, y1, 1e-12)
    boxes = shapely.box(x0, y0, x1, y1)
    grown = shapely.buffer(poly, 1e-9, join_style="mitre")
    shrunk = shapely.buffer(poly, -1e-9, join_style="mitre")
    # within round-off of the edges the two may differ; beyond it they agree
    assert np.all(inside <= shapely.covers(grown, boxes))
    assert np.all(shapely.covers(shrunk, boxes) <= inside)
    assert np.all(apart <= ~shapely.intersects(shrunk, boxes))
    assert np.all(~shapely.intersects(grown, boxes) <= apart)
    assert not np.any(inside & apart)
    on = points_in_convex(hp, x0, y0, 1e-12)
    assert np.all(on <= shapely.intersects_xy(grown, x0, y0))
    assert np.all(shapely.intersects_xy(shrunk, x0, y0) <= on)
    assert on[::5].all()  # a vertex is on the outline
