"""Outside distance: weighted statistics of the distances seen through a room's windows.

EN 17037 clause 5.2 asks for the distance from the window to the view's landscape layer without
saying over which directions or how to summarise them; the statistic (``view.distance_statistic``)
and where it is measured (``view.distance_method``) are project parameters.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.view.frames import RoomGeometry
from en17037cli.criteria.view.rays import ViewRays
from en17037cli.scene.model import GROUND, LANDSCAPE


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


def pad_rows(row: np.ndarray, values: np.ndarray, weights: np.ndarray, p: int):
    """Scatter ragged (row, value, weight) triples into (p, kmax) arrays padded with weight 0."""
    order = np.argsort(row, kind="stable")
    row, values, weights = row[order], values[order], weights[order]
    counts = np.bincount(row, minlength=p)
    kmax = max(int(counts.max()) if len(counts) else 0, 1)
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    col = np.arange(len(row)) - start[row]
    V = np.full((p, kmax), np.nan)
    W = np.zeros((p, kmax))
    V[row, col] = values
    W[row, col] = weights
    return V, W


def ragged_statistic(row: np.ndarray, values: np.ndarray, weights: np.ndarray, p: int, statistic: str):
    """:func:`weighted_statistic` of ragged (row, value, weight) triples, for rows 0..p-1."""
    return weighted_statistic(*pad_rows(row, values, weights, p), statistic)


def horizontal_distance(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, pidx: np.ndarray, dirs: np.ndarray,
                        leave: np.ndarray, traced: tuple, weight: np.ndarray, p: int, statistic: str):
    """Outside distance of each point by the ``horizontal`` method, from its horizontal fan.

    Over the fan's leaving directions: the distance from the glazing plane to the first
    ``landscape`` face, measured horizontally and perpendicular to the window (ground never
    obstructs: landscape behind ground is looked for; unobstructed counts as +inf), summarised by
    the weighted ``statistic`` with each sample's angular weight.

    Parameters
    ----------
    points : (p, 3) float [m]; pidx : (s,) int, the point of each fan sample
    dirs : (s, 3) float, unit directions; leave : (s,) bool, the sample leaves through a window
    traced : (window face, outside face, outside distance [m], glass distance [m]) of each sample,
        as :meth:`~en17037cli.criteria.view.rays.ViewRays.through_windows` returns them
    weight : (s,) float [rad], angular length owned by each sample

    Returns
    -------
    distance, gap : (p,) float [m]
    """
    wface, oface, odist, gdist = traced
    idx = np.flatnonzero(leave)
    t_l = np.where(view_rays.layer_of(oface[idx]) == LANDSCAPE, odist[idx], np.inf)
    beyond_ground = np.flatnonzero(view_rays.layer_of(oface[idx]) == GROUND)
    if len(beyond_ground):  # ground never obstructs: look for landscape behind it
        g = idx[beyond_ground]
        t_l[beyond_ground] = view_rays.engine.first_hit("landscape", points[pidx[g]], dirs[g])[1]
    nrm = rg.frame_array("n")[rg.window_of_face[wface[idx]]]
    nh = nrm.copy()
    nh[:, 2] = 0.0
    nh /= np.maximum(np.linalg.norm(nh, axis=1, keepdims=True), 1e-12)
    dist = np.full(len(pidx), np.nan)
    dist[idx] = (t_l - gdist[idx]) * np.einsum("ij,ij->i", dirs[idx], nh)
    return ragged_statistic(pidx, dist, weight, p, statistic)
