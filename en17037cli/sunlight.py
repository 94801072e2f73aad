"""Exposure-to-sunlight engine (EN 17037 clause 5.3, Annex A.3).

For each room: point P per window, then for every day of the period the intervals during which
the sun is seen from P (through any window of the room), exact to ``tolerance_s``:

1. sample every ``timestep_min`` from local midnight to local midnight;
2. the sun is *seen* when its apparent altitude is at least ``min_altitude_deg``, it lies in
   front of the window plane, the ray from P towards it crosses a window face of the room, and
   no face that obstructs the sun lies anywhere on that ray (interior faces, reveals, frames,
   context; faces with ``obstructs_sun: false`` are left out);
3. every change of visibility between two samples is located by bisection to ``tolerance_s``.

An interval shorter than the timestep can fall between two samples and be missed: that limit is
reported beside the error estimate (the sum of the remaining bisection half-brackets).
"""
from __future__ import annotations

import datetime as dt
import zoneinfo

import numpy as np

from en17037cli import standard
from en17037cli.errors import InputError
from en17037cli.geometry import window_axes
from en17037cli.raytrace import GLAZING_OFFSET_M, room_window_group
from en17037cli.sun.position import direction_vectors, solar_position

#: Start of the reveal search, outside the glazing plane [m], and the lateral step beyond a jamb [m].
REVEAL_PROBE_OUTSIDE_M = 0.01
REVEAL_PROBE_BEYOND_JAMB_M = 0.02


def reveal_depth(engine, start: np.ndarray, normal: np.ndarray, axis: np.ndarray, half_width: float, max_depth: float) -> float:
    """Depth of the room-side plane of the opening behind the glazing plane [m].

    Probes start just outside the glazing plane, 2 cm beyond each jamb (inside the wall, if it
    has thickness), and run inwards along -normal through the interior faces; the deepest face
    parallel to the window (|cos| > 0.9) crossed within ``max_depth`` is the wall's inner face.
    Zero where the wall has no thickness or no wall flanks the window.

    Parameters
    ----------
    start : (3,) point on the glazing plane at the horizontal centre [m]
    normal, axis : (3,) outward normal and horizontal width axis (unit)
    half_width, max_depth : float [m]
    """
    off = half_width + REVEAL_PROBE_BEYOND_JAMB_M
    origins = np.array([start + off * axis, start - off * axis]) + REVEAL_PROBE_OUTSIDE_M * normal
    dirs = np.tile(-normal, (2, 1))
    travelled = np.zeros(2)
    deepest = 0.0
    scene = engine.scene
    for _ in range(4):  # a few crossings: outer face, inner face, beyond
        face, t = engine.first_hit("interior", origins, dirs)
        hit = face >= 0
        if not hit.any():
            break
        v = scene.vertices[scene.triangles[np.maximum(face, 0)]]  # the two faces hit, not the whole scene
        fn = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
        cos = np.abs(fn @ normal) / np.maximum(np.linalg.norm(fn, axis=1), 1e-30)
        depth = travelled + np.where(hit, t, np.inf) - REVEAL_PROBE_OUTSIDE_M
        ok = hit & (cos > 0.9) & (depth <= max_depth)
        if ok.any():
            deepest = max(deepest, float(depth[ok].max()))
        step = np.where(hit, t, 0) + 1e-4
        origins = origins + step[:, None] * dirs
        travelled = travelled + step
        if not np.any(hit & (depth <= max_depth)):
            break
    return max(deepest, 0.0)


def point_p(engine, room, window, cfg: dict) -> tuple[np.ndarray, float, list]:
    """Point P of a window (local frame) by EN 17037 Annex A.3, its reveal depth [m] and notes.

    On the room-side plane of the opening (see :func:`reveal_depth`), at the horizontal centre of
    the window, at height max(floor + 1.2 m, sill + 0.3 m).
    """
    n = window.normal
    a, up = window_axes(n)
    verts = window.triangles.reshape(-1, 3)
    s = verts @ a
    c = window.centroid
    centre = c + (0.5 * (s.min() + s.max()) - c @ a) * a
    z_p = max(room.floor_z + standard.SUN_POINT_MIN_ABOVE_FLOOR_M, window.sill_z + standard.SUN_POINT_MIN_ABOVE_SILL_M)
    if z_p > window.head_z + 1e-9:
        raise InputError(
            f"room '{room.name}', window '{window.name}': point P at max(floor + 1.2 m, sill + 0.3 m) = "
            f"{z_p - room.floor_z:.3f} m above the floor lies above the window head ({window.head_z - room.floor_z:.3f} m); "
            "give rooms[].sun_points explicitly")
    if abs(up[2]) > 1e-9:
        q = centre + ((z_p - centre[2]) / up[2]) * up
    else:
        q = centre
    depth = reveal_depth(engine, q, n, a, 0.5 * (s.max() - s.min()), cfg["max_reveal_depth_m"])
    notes = []
    if depth < GLAZING_OFFSET_M:  # no reveal, or only the wall's own plane found again through round-off
        depth = 0.0
    if depth > 0:
        p = q - depth * n
    else:
        p = q - GLAZING_OFFSET_M * n
        notes.append(f"room '{room.name}', window '{window.name}': P lies on the glazing plane (no reveal found) and was moved {GLAZING_OFFSET_M * 1000:.0f} mm into the room")
    return p, depth, notes


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


class SunVisibility:
    """Visibility of the sun from the P points of one room, vectorised over times."""

    def __init__(self, engine, points: np.ndarray, normals: np.ndarray, window_group: str, location: dict,
                 cfg: dict, true_north_deg: float):
        self.engine, self.points, self.normals = engine, points, normals
        self.window_group = window_group
        self.loc, self.cfg, self.north = location, cfg, true_north_deg
        self.calls = 0

    def __call__(self, t: np.ndarray) -> np.ndarray:
        """(n,) bool: the sun is seen from P through a window of the room at unix times ``t`` [s]."""
        self.calls += 1
        c = self.cfg
        elev, azim = solar_position(t, self.loc["latitude"], self.loc["longitude"], self.loc.get("elevation_m", 0.0),
                                    c["pressure_mbar"], c["temperature_c"], refraction=c["refraction"])
        up = elev >= c["min_altitude_deg"]
        seen = np.zeros(len(t), dtype=bool)
        if not up.any():
            return seen
        d = direction_vectors(elev, azim, self.north)
        for p, n in zip(self.points, self.normals):  # one pass per window of the room
            cand = np.flatnonzero(up & ~seen & (d @ n > 0))  # no ray below the altitude or behind the window
            if len(cand) == 0:
                continue
            o = np.broadcast_to(p, (len(cand), 3))
            face, _ = self.engine.first_hit(self.window_group, o, d[cand])
            cand = cand[face >= 0]
            if len(cand) == 0:
                continue
            blocked = self.engine.occluded("sun", np.broadcast_to(p, (len(cand), 3)), d[cand])
            seen[cand[~blocked]] = True
        return seen


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
    while len(lo) and np.max(hi - lo) > 2 * tolerance_s:  # bisection, all transitions at once
        mid = 0.5 * (lo + hi)
        vm = visible(mid)
        same = vm == s_lo
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
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


def assess_room(engine, scene, room, cfg: dict, location: dict, thresholds: dict, explicit=None) -> dict:
    """Sunlight result of one room: P per window, every day's hours and intervals, assessed date and level."""
    notes = []
    if explicit is not None:
        if len(explicit) != len(room.windows):
            names = ", ".join(f"'{w.name}'" for w in room.windows)
            raise InputError(f"room '{room.name}': sun_points has {len(explicit)} points for {len(room.windows)} windows ({names}); give one per window, in that order")
        pts = scene.to_local(np.asarray(explicit, dtype=float))
        depths = [None] * len(pts)
        notes.append(f"room '{room.name}': point P given explicitly (rooms[].sun_points)")
    else:
        res = [point_p(engine, room, w, cfg) for w in room.windows]  # one per window
        pts = np.array([r[0] for r in res])
        depths = [r[1] for r in res]
        for r in res:
            notes.extend(r[2])
    normals = np.array([w.normal for w in room.windows])
    vis = SunVisibility(engine, pts, normals, room_window_group(room), location, cfg, scene.true_north_deg)
    dates, t0, t1 = day_bounds(cfg["year"], cfg["period"]["start"], cfg["period"]["end"], location["timezone"])
    step = cfg["timestep_min"] * 60.0
    intervals, err_s = visible_intervals(vis, t0, t1, step, cfg["tolerance_s"])
    hours = np.array([float(np.sum(iv[:, 1] - iv[:, 0])) / 3600.0 for iv in intervals])
    if cfg["date"] == "worst":
        k = int(np.argmin(hours))  # argmin/argmax return the first: ties go to the earliest day
    elif cfg["date"] == "best":
        k = int(np.argmax(hours))
    else:
        k = [d.strftime("%m-%d") for d in dates].index(cfg["date"])
    err_h = err_s / 3600.0
    level = int(standard.level_from_value([hours[k]], thresholds["sunlight_hours"])[0])
    near = bool(standard.near_threshold([hours[k]], [err_h[k]], thresholds["sunlight_hours"])[0])
    return {
        "points_local": pts, "reveal_depths_m": depths, "dates": dates, "hours": hours, "intervals": intervals,
        "error_h": err_h, "assessed_index": k, "level": level, "near_threshold": near, "notes": notes,
        "timestep_s": step,
    }
