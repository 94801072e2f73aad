"""The days of the assessed period and, for each, the intervals during which the sun is seen."""
from __future__ import annotations

import datetime as dt
import zoneinfo

import numpy as np

from en17037cli.bisection import bisect_transitions


def day_bounds(year: int, start_mmdd: str, end_mmdd: str, timezone: str):
    """Local dates of the period and each day's start and end as unix time [s] (local midnights).

    Returns
    -------
    dates : list of datetime.date; t0, t1 : (d,) float [s]
    """
    tz = zoneinfo.ZoneInfo(timezone)
    d0 = dt.date.fromisoformat(f"{year}-{start_mmdd}")
    d1 = dt.date.fromisoformat(f"{year}-{end_mmdd}")
    dates = [d0 + dt.timedelta(days=i) for i in range((d1 - d0).days + 1)]  # one step per day, not per time step
    mid = [dt.datetime.combine(d, dt.time(0), tzinfo=tz).timestamp() for d in dates + [dates[-1] + dt.timedelta(days=1)]]
    mid = np.array(mid)
    return dates, mid[:-1], mid[1:]


def visible_intervals(visible, t0: np.ndarray, t1: np.ndarray, step_s: float, tolerance_s: float):
    """Intervals of each day during which ``visible`` holds, exact to ``tolerance_s``.

    Parameters
    ----------
    visible : callable, (n,) unix times [s] -> (n,) bool
    t0, t1 : (d,) float, start and end of each day [s]
    step_s, tolerance_s : float [s]

    Returns
    -------
    intervals : list (per day) of (k, 2) float arrays [s]
    error_s : (d,) float, sum of the remaining half-brackets of the day's transitions [s]
    """
    nd = len(t0)
    k = np.ceil((t1 - t0) / step_s).astype(int)
    kmax = int(k.max())
    steps = np.arange(kmax + 1)
    grid = np.minimum(t0[:, None] + steps[None, :] * step_s, t1[:, None])  # (d, kmax+1), last sample at t1
    valid = steps[None, :] <= k[:, None]
    vis = np.zeros(grid.shape, dtype=bool)
    vis[valid] = visible(grid[valid])
    pair = valid[:, 1:] & valid[:, :-1]
    change = pair & (vis[:, 1:] != vis[:, :-1])
    di, si = np.nonzero(change)
    lo, hi = grid[di, si], grid[di, si + 1]
    s_lo = vis[di, si]
    lo, hi = bisect_transitions(lambda _, t: visible(t), di, lo, hi, s_lo, max_width=2 * tolerance_s)
    x = 0.5 * (lo + hi)
    err = np.bincount(di, 0.5 * (hi - lo), nd)
    intervals = []
    for d in range(nd):  # assembling each day's list of intervals (report data, not maths)
        sel = di == d
        xs, rising = x[sel], ~s_lo[sel]
        out, cur = [], (t0[d] if vis[d, 0] else None)
        for xv, r in zip(xs, rising):
            if r:
                cur = xv
            elif cur is not None:
                out.append((cur, xv))
                cur = None
        if cur is not None:
            out.append((cur, t1[d]))
        intervals.append(np.array(out, dtype=float).reshape(-1, 2))
    return intervals, err
