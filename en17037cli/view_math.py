"""Maths behind the view engine: viewpoint grids, solid-angle cells, weighted statistics.

No ray is traced here; :mod:`en17037cli.view` calls these functions.
"""
from __future__ import annotations

import numpy as np

from en17037cli.geometry import triangle_solid_angle, unit


def grid_points(utilised, spacing_m: float) -> np.ndarray:
    """Grid of points over a polygon, aligned with its minimum-area bounding rectangle.

    The grid is centred on the rectangle and symmetric, so rotating or mirroring the model
    moves the grid with it. If no grid point falls inside (spacing larger than the area), the
    polygon's centroid (or a point surely inside it) is used.

    Parameters
    ----------
    utilised : shapely Polygon, local xy [m]
    spacing_m : float [m]

    Returns
    -------
    (n, 2) float [m]
    """
    import shapely

    if utilised.is_empty or utilised.area <= 0:
        return np.zeros((0, 2))
    rect = np.asarray(shapely.minimum_rotated_rectangle(utilised).exterior.coords)[:4]
    centre = rect.mean(axis=0)
    e1, e2 = rect[1] - rect[0], rect[2] - rect[1]
    l1, l2 = np.linalg.norm(e1), np.linalg.norm(e2)
    e1, e2 = e1 / max(l1, 1e-12), e2 / max(l2, 1e-12)
    n1, n2 = int(np.floor(l1 / spacing_m + 1e-9)) + 1, int(np.floor(l2 / spacing_m + 1e-9)) + 1
    a = (np.arange(n1) - (n1 - 1) / 2) * spacing_m
    b = (np.arange(n2) - (n2 - 1) / 2) * spacing_m
    A, B = np.meshgrid(a, b, indexing="ij")
    pts = centre + A.reshape(-1, 1) * e1 + B.reshape(-1, 1) * e2
    inside = shapely.contains_xy(utilised.buffer(1e-9), pts[:, 0], pts[:, 1])
    pts = pts[inside]
    if len(pts) == 0:
        c = utilised.centroid
        p = c if utilised.contains(c) else utilised.representative_point()
        pts = np.array([[p.x, p.y]])
    order = np.lexsort((np.round(pts[:, 1], 9), np.round(pts[:, 0], 9)))
    return pts[order]


def angular_size(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Largest angle between the directions to two vertices of each cell [rad].

    Parameters
    ----------
    points : (n, 3) float [m]; cells : (n, 3, 3) float [m]
    """
    d = unit(cells - points[:, None, :])
    c = np.minimum(np.minimum(np.einsum("ij,ij->i", d[:, 0], d[:, 1]), np.einsum("ij,ij->i", d[:, 1], d[:, 2])),
                   np.einsum("ij,ij->i", d[:, 2], d[:, 0]))
    return np.arccos(np.clip(c, -1.0, 1.0))


def split4(cells: np.ndarray) -> np.ndarray:
    """Split triangles into four by their edge midpoints.

    Parameters
    ----------
    cells : (n, 3, 3) float [m]

    Returns
    -------
    (4 n, 3, 3) float; the children of cell i are rows 4 i .. 4 i + 3.
    """
    a, b, c = cells[:, 0], cells[:, 1], cells[:, 2]
    ab, bc, ca = 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)
    kids = np.stack([np.stack([a, ab, ca], 1), np.stack([ab, b, bc], 1),
                     np.stack([ca, bc, c], 1), np.stack([ab, bc, ca], 1)], axis=1)
    return kids.reshape(-1, 3, 3)


def base_cells(points: np.ndarray, point_index: np.ndarray, triangles: np.ndarray, resolution_rad: float):
    """Subdivide window triangles, per viewpoint, until each cell subtends at most ``resolution_rad``.

    The number of cells, hence of rays, scales with the windows' solid angle seen from each
    point, not with the whole sphere.

    Parameters
    ----------
    points : (p, 3) float [m]
    point_index : (n,) int, viewpoint of each starting triangle
    triangles : (n, 3, 3) float [m]
    resolution_rad : float [rad]

    Returns
    -------
    point_index : (m,) int; cells : (m, 3, 3) float [m]
    """
    done_p, done_c = [], []
    pi, cells = point_index, triangles
    for _ in range(40):  # levels, not cells: each halves the cell size
        if len(cells) == 0:
            break
        big = angular_size(points[pi], cells) > resolution_rad
        done_p.append(pi[~big])
        done_c.append(cells[~big])
        pi, cells = np.repeat(pi[big], 4), split4(cells[big])
    done_p.append(pi)
    done_c.append(cells)
    return np.concatenate(done_p), np.concatenate(done_c)


def cell_weights(points: np.ndarray, point_index: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Exact solid angle of each cell seen from its viewpoint [sr] (Van Oosterom and Strackee 1983).

    The cells of a planar window tile it, so their weights add up to its exact solid angle.
    """
    return triangle_solid_angle(points[point_index], cells)


#: Vertex samples are pulled this fraction of the way towards the centroid, so that a sample
#: never lies exactly on a window's own edge (where glazing and wall meet) and the cells along
#: the window outline are not refined for nothing.
VERTEX_INSET = 0.01


def cell_samples(points: np.ndarray, point_index: np.ndarray, cells: np.ndarray):
    """Ray origins and unit directions through each cell's centroid and (nearly) its three vertices.

    Returns
    -------
    origins : (4 m, 3); directions : (4 m, 3); row 4 i is the centroid of cell i.
    """
    centroid = cells.mean(axis=1)[:, None, :]
    corners = cells + VERTEX_INSET * (centroid - cells)
    targets = np.concatenate([centroid, corners], axis=1)  # (m, 4, 3)
    origins = np.repeat(points[point_index], 4, axis=0)
    return origins, unit(targets.reshape(-1, 3) - origins)


def weighted_statistic(values: np.ndarray, weights: np.ndarray, statistic: str):
    """Weighted statistic per row, ignoring zero weights; +inf values are allowed.

    ``median`` and ``pNN`` are lower weighted percentiles: the smallest value v such that the
    weight of values <= v reaches the fraction. ``min`` is the smallest value with positive weight.

    Parameters
    ----------
    values : (p, k) float [m] (NaN allowed where the weight is 0)
    weights : (p, k) float >= 0 (e.g. [deg] or [sr])
    statistic : str, ``median`` | ``min`` | ``mean`` | ``pNN``

    Returns
    -------
    value : (p,) float, NaN where a row has no weight
    gap : (p,) float, largest gap from the value to its neighbouring finite samples (a
        resolution estimate), 0 where the neighbours are equal
    """
    v = np.where(weights > 0, values, np.nan)
    w = np.where(weights > 0, weights, 0.0)
    total = w.sum(axis=1)
    empty = total <= 0
    if statistic == "mean":
        with np.errstate(invalid="ignore", divide="ignore"):
            vv = np.where(w > 0, v, 0.0)
            has_inf = np.any(np.isinf(vv) & (w > 0), axis=1)
            mean = np.where(has_inf, np.inf, (np.where(np.isinf(vv), 0, vv) * w).sum(axis=1) / np.where(empty, 1, total))
        return np.where(empty, np.nan, mean), np.zeros(len(v))
    q = 0.0 if statistic == "min" else (0.5 if statistic == "median" else int(statistic[1:]) / 100.0)
    order = np.argsort(np.where(np.isnan(v), np.inf, v), axis=1, kind="stable")
    vs = np.take_along_axis(v, order, axis=1)
    ws = np.take_along_axis(w, order, axis=1)
    cum = np.cumsum(ws, axis=1)
    target = q * total
    reach = (cum >= target[:, None] * (1 - 1e-12)) & (ws > 0)
    idx = np.argmax(reach, axis=1)
    rows = np.arange(len(v))
    value = np.where(empty, np.nan, vs[rows, idx])
    # neighbouring distinct samples with weight, for a resolution estimate
    pos = np.where(ws > 0, np.arange(vs.shape[1])[None, :], -1)
    prev_idx = np.max(np.where(pos < idx[:, None], pos, -1), axis=1)
    nxt = np.where((pos > idx[:, None]) & (pos >= 0), pos, vs.shape[1])
    next_idx = np.min(nxt, axis=1)
    with np.errstate(invalid="ignore"):
        lo = np.where(prev_idx >= 0, value - vs[rows, np.maximum(prev_idx, 0)], 0.0)
        hi = np.where(next_idx < vs.shape[1], vs[rows, np.minimum(next_idx, vs.shape[1] - 1)] - value, 0.0)
    lo = np.where(np.isfinite(lo), lo, 0.0)
    hi = np.where(np.isfinite(hi), hi, 0.0)
    return value, np.where(empty, np.nan, np.maximum(lo, hi))
