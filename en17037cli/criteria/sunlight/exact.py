"""Sun hours exact by construction: every time the sun's visibility from P can change, then one ray
per interval between consecutive such times (``sunlight.method: exact``).

From P, whether a ray towards the sun leaves through a window of the room and meets no face that
blocks the sun changes only where the sun's apparent path crosses

* the minimum-altitude circle (the sun's elevation equals ``min_altitude_deg``),
* the plane of the window (s . n = 0: the engine casts no ray behind the window),
* the image of an edge (a, b) of a face that blocks the sun or of a window face of the room: a
  great-circle arc, where f(t) = m . s(t) changes sign, m = (a - P) x (b - P) / |...|, and the
  crossing direction lies on the arc between a - P and b - P.

Each such function is sampled along a cubic Hermite interpolant of the SPA's sun vectors
(:class:`SunSpline`, knots every :data:`KNOT_S`; its error is below 1e-8 rad) and every root is
bracketed with a bound on the second derivative of the interpolant (:func:`root_brackets`): a
piece of width w whose end values have one sign and exceed K w^2 / 8 holds no root; a piece with a
sign change and |slope| > K w holds exactly one, which bisection locates to ``tolerance_s``; any
other piece is split until it is narrower than the tolerance and then both its ends are taken.
Between two consecutive candidate times of a day visibility is constant, so one ray at the
midpoint decides it (the engine's own sun rays, :class:`~.visibility.SunVisibility`).

Faces are culled first (:func:`~.culling.cull_triangles`): only those whose image from P reaches the band of
sun directions of the period (declinations, minimum altitude), lies in front of the window's plane
and inside the pyramid from P over one of the room's windows can lie between P and the sun; each
test is a bound on the face's spherical triangle, so no face that can occlude is dropped.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.sunlight.culling import ANGLE_SLACK, cull_triangles, spherical_extent, triangle_edges, window_pyramid
from en17037cli.criteria.sunlight.solar_position import direction_vectors
from en17037cli.geometry import turn

#: Spacing of the SPA knots of the sun's path [s]: the Hermite interpolant's error is about
#: (omega h)^4 / 384 = 1e-8 rad at 600 s (omega = 7.3e-5 rad/s), 1e-4 s of the sun's motion.
KNOT_S = 600.0
#: Pieces a root bracket too wide to decide is split into, per round.
SPLIT = 8
#: Sun's angular speed about the pole [rad/s] times 1.5: bounds d2(elevation)/dt2 and the sun's
#: movement during a bracket (apparent solar rate 7.27e-5 rad/s; refraction adds well under 50 %).
OMEGA_BOUND = 1.5 * 2 * np.pi / 86164.0


class SunSpline:
    """Cubic Hermite interpolant of the SPA's apparent sun vectors over [t_start, t_end].

    Knots every :data:`KNOT_S` seconds; derivatives at the knots by fourth-order central
    differences of the knots (one SPA call for everything). Vectors are in the model frame.

    Parameters
    ----------
    sun_path : callable, (n,) unix times [s] -> (elevation, azimuth) (n,) [deg]
    t_start, t_end : float [s]; true_north_deg : float [deg]
    """

    def __init__(self, sun_path, t_start: float, t_end: float, true_north_deg: float):
        n = int(np.ceil((t_end - t_start) / KNOT_S)) + 1
        self.t0, self.h = t_start - 2 * KNOT_S, KNOT_S
        t = self.t0 + self.h * np.arange(n + 4)  # two extra knots each side for the differences
        elev, azim = sun_path(t)
        self.elev = elev
        s = direction_vectors(elev, azim, true_north_deg)
        ds = np.zeros_like(s)
        ds[2:-2] = (-s[4:] + 8 * s[3:-1] - 8 * s[1:-3] + s[:-4]) / (12 * self.h)
        ds[:2], ds[-2:] = (s[2:4] - s[0:2]) / (2 * self.h), (s[-2:] - s[-4:-2]) / (2 * self.h)
        self.s, self.ds = s, ds
        # second derivative of each piece at its two ends: the largest |s''| on the piece (linear in it)
        h = self.h
        p0, p1, m0, m1 = s[:-1], s[1:], ds[:-1] * h, ds[1:] * h
        a2 = (-6 * p0 - 4 * m0 + 6 * p1 - 2 * m1) / h**2  # s'' at the start of the piece
        b2 = (6 * p0 + 2 * m0 - 6 * p1 + 4 * m1) / h**2   # s'' at its end
        self.curvature = np.maximum(np.linalg.norm(a2, axis=1), np.linalg.norm(b2, axis=1))  # (n+3,) [1/s^2]

    def piece(self, t: np.ndarray) -> np.ndarray:
        """Index of the knot interval holding each time (n,)."""
        return np.clip(np.floor((np.asarray(t) - self.t0) / self.h).astype(np.int64), 0, len(self.s) - 2)

    def __call__(self, t: np.ndarray, k: np.ndarray | None = None) -> np.ndarray:
        """Sun vectors (n, 3) at unix times ``t`` (n,) [s] (not renormalised), on pieces ``k``."""
        t = np.asarray(t, dtype=float)
        k = self.piece(t) if k is None else k
        x = (t - (self.t0 + k * self.h)) / self.h
        x2, x3 = x * x, x * x * x
        h00, h10, h01, h11 = 2 * x3 - 3 * x2 + 1, x3 - 2 * x2 + x, -2 * x3 + 3 * x2, x3 - x2
        return (h00[:, None] * self.s[k] + (h10 * self.h)[:, None] * self.ds[k] + h01[:, None] * self.s[k + 1]
                + (h11 * self.h)[:, None] * self.ds[k + 1])


def root_brackets(values, curvature, key: np.ndarray, a: np.ndarray, b: np.ndarray, tolerance_s: float, piece_s: float,
                  piece_of=None, origin: float = 0.0):
    """Every root of functions f_key on [a, b], each in a bracket at most ``tolerance_s`` wide.

    Parameters
    ----------
    values : callable (key (n,), t (n,) [s], piece (n,)) -> (n,) f_key(t)
    curvature : callable (key (n,), piece (n,)) -> (n,) bound on |f''| over the piece [1/s^2]
    key : (q,) int, which function each domain belongs to; a, b : (q,) float [s]
    piece_s : width of the first pieces [s] (aligned with ``piece_of``'s grid if given)
    piece_of : callable t -> piece index (the bounds of ``curvature`` hold per piece), or None
    origin : float [s], a boundary of the first pieces (the knots of ``piece_of``'s grid)

    Returns
    -------
    key : (r,) int; lo, hi : (r,) float [s], brackets; simple : (r,) bool, True where the bracket
        holds exactly one sign change of f (False: an undecided piece narrower than the tolerance)
    """
    grid0 = origin + np.floor((a - origin) / piece_s) * piece_s
    n = np.maximum(np.ceil((b - grid0) / piece_s).astype(np.int64), 1)
    item = np.repeat(np.arange(len(a)), n)
    j = np.arange(len(item)) - np.repeat(np.cumsum(n) - n, n)
    lo = np.maximum(grid0[item] + j * piece_s, a[item])
    hi = np.minimum(grid0[item] + (j + 1) * piece_s, b[item])
    ok = hi > lo
    kk, lo, hi = key[item[ok]], lo[ok], hi[ok]
    pc = piece_of(0.5 * (lo + hi)) if piece_of is not None else np.zeros(len(lo), np.int64)
    out_k, out_lo, out_hi, out_simple = [key[:0]], [a[:0]], [a[:0]], [np.zeros(0, bool)]
    while len(lo):  # rounds of splitting: each shrinks the pieces SPLIT-fold, so ~log8(piece/tolerance) rounds
        flo, fhi = values(kk, lo, pc), values(kk, hi, pc)
        w = hi - lo
        curv = curvature(kk, pc)
        change = (flo <= 0) != (fhi <= 0)
        simple = change & (np.abs(fhi - flo) > curv * w * w)  # |f'| > 0 on the piece: one root
        none = ~change & (np.minimum(np.abs(flo), np.abs(fhi)) > curv * w * w / 8)
        narrow = ~simple & ~none & (w <= tolerance_s)
        for sel, is_simple in ((simple, True), (narrow, False)):
            out_k.append(kk[sel])
            out_lo.append(lo[sel])
            out_hi.append(hi[sel])
            out_simple.append(np.full(int(sel.sum()), is_simple))
        split = ~simple & ~none & ~narrow
        kk, lo, w, pc = kk[split], lo[split], w[split], pc[split]
        step = w / SPLIT
        kk, pc = np.repeat(kk, SPLIT), np.repeat(pc, SPLIT)
        lo = np.repeat(lo, SPLIT) + np.tile(np.arange(SPLIT), len(step)) * np.repeat(step, SPLIT)
        hi = lo + np.repeat(step, SPLIT)
    rk, rlo, rhi, rs = (np.concatenate(x) for x in (out_k, out_lo, out_hi, out_simple))
    # bisect the simple brackets to the tolerance
    s = np.flatnonzero(rs)
    blo, bhi, bk = rlo[s], rhi[s], rk[s]
    bpc = piece_of(0.5 * (blo + bhi)) if piece_of is not None else np.zeros(len(s), np.int64)
    f_lo = values(bk, blo, bpc) <= 0
    while len(s) and np.max(bhi - blo) > tolerance_s:
        mid = 0.5 * (blo + bhi)
        same = (values(bk, mid, bpc) <= 0) == f_lo
        blo, bhi = np.where(same, mid, blo), np.where(same, bhi, mid)
    rlo[s], rhi[s] = blo, bhi
    return rk, rlo, rhi, rs


def pole_vector(latitude_deg: float, true_north_deg: float) -> np.ndarray:
    """Unit vector (3,) to the celestial pole above the horizon's north (model frame): the axis of the
    sun's daily circles."""
    return direction_vectors(np.array([abs(latitude_deg)]), np.array([0.0 if latitude_deg >= 0 else 180.0]), true_north_deg)[0]


def _min_altitude_roots(spline: SunSpline, sun_path, t0: np.ndarray, t1: np.ndarray, min_alt: float, tolerance_s: float):
    """Brackets of the times the SPA's apparent elevation crosses ``min_alt`` [deg], every day.

    Elevation at the knots comes from the spline's SPA call; elsewhere from the SPA itself. The
    function searched is sin(elevation) - sin(min_alt), the vertical component of the sun vector,
    whose second derivative is bounded by :data:`OMEGA_BOUND` squared (a point on a circle turning
    at the sun's rate, refraction included) at any elevation.
    """
    knot_t = spline.t0 + spline.h * np.arange(len(spline.elev))

    def values(_key, t, pc):
        out = np.empty(len(t))
        at_lo = np.abs(t - knot_t[pc]) < 1e-6
        at_hi = np.abs(t - knot_t[np.minimum(pc + 1, len(knot_t) - 1)]) < 1e-6
        out[at_lo] = spline.elev[pc[at_lo]]
        out[at_hi] = spline.elev[np.minimum(pc[at_hi] + 1, len(knot_t) - 1)]
        rest = ~(at_lo | at_hi)
        if rest.any():
            out[rest] = sun_path(t[rest])[0]
        return np.sin(np.radians(out)) - np.sin(np.radians(min_alt))

    curv = OMEGA_BOUND**2  # on sin(elevation), the vertical component of the sun vector: |s''| ~ omega^2 cos(dec)
    days = np.arange(len(t0))
    return root_brackets(values, lambda k, pc: np.full(len(k), curv), days, t0, t1, tolerance_s, spline.h,
                         spline.piece, origin=spline.t0)


def exact_intervals(visibility, spline: SunSpline, sun_path, scene, room, index: int, t0: np.ndarray, t1: np.ndarray,
                    settings, latitude: float):
    """Visible intervals of each day for point P number ``index`` of ``visibility``, exact to the
    tolerance, and a bound on each day's error.

    Parameters
    ----------
    visibility : :class:`~.visibility.SunVisibility` holding the room's points P
    spline : :class:`SunSpline` over the period; sun_path : SPA (elevation, azimuth) at unix times
    scene, room : the scene and the room (its windows and face groups)
    t0, t1 : (d,) float, each day's start and end [s]

    Returns
    -------
    intervals : list (per day) of (k, 2) float [s]; error_s : (d,) float, bound on each day's error [s]
    """
    from en17037cli.criteria.sunlight.visibility import SunVisibility

    tol = settings.tolerance_s
    p, n = visibility.points[index], visibility.normals[index]
    one = SunVisibility(visibility.engine, p[None, :], n[None, :], visibility.window_group, visibility.loc, settings,
                        visibility.north, visibility.sun_path)
    nd = len(t0)
    # 1. the minimum-altitude crossings, and each day's span above it (a knot margin of 1 deg: between
    # knots the elevation rises above the knots' by at most OMEGA_BOUND^2 h^2 / 8 = 0.03 deg)
    ak, alo, ahi, asimple = _min_altitude_roots(spline, sun_path, t0, t1, settings.min_altitude_deg, tol)
    knot_t = spline.t0 + spline.h * np.arange(len(spline.elev))
    high = spline.elev >= settings.min_altitude_deg - 1.0
    day_of_knot = np.searchsorted(t0, knot_t, side="right") - 1
    inday = (day_of_knot >= 0) & (day_of_knot < nd) & (knot_t < t1[np.clip(day_of_knot, 0, nd - 1)])
    sel = high & inday
    a = np.full(nd, np.inf)
    b = np.full(nd, -np.inf)
    np.minimum.at(a, day_of_knot[sel], knot_t[sel] - spline.h)
    np.maximum.at(b, day_of_knot[sel], knot_t[sel] + spline.h)
    a, b = np.maximum(a, t0), np.minimum(b, t1)
    up_days = np.flatnonzero(b > a)
    # 2. the faces that can occlude, their edges, and the window's plane
    pole = pole_vector(latitude, visibility.north)
    sdec = spline.s[sel] @ pole
    sin_dec = (float(sdec.min()), float(sdec.max())) if len(sdec) else (1.0, -1.0)
    tri = scene.triangles
    engine = visibility.engine
    faces = np.concatenate([engine.faces("sun"), engine.faces(visibility.window_group)])
    kept = cull_triangles(scene.vertices, tri, faces, p, n, window_pyramid(p, room.windows), pole, sin_dec,
                          float(np.sin(np.radians(settings.min_altitude_deg))))
    edges = triangle_edges(tri, kept)
    u, v = scene.vertices[edges[:, 0]] - p, scene.vertices[edges[:, 1]] - p
    m = np.cross(u, v)
    mn = np.linalg.norm(m, axis=1)
    good = mn > 1e-12 * np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1)
    u, v, m = u[good], v[good], m[good] / mn[good, None]
    u /= np.linalg.norm(u, axis=1)[:, None]
    v /= np.linalg.norm(v, axis=1)[:, None]
    normals = np.concatenate([n[None, :], m])  # key 0: the window's plane; keys 1..: the edges' great circles
    # each edge's band of declinations, against each day's: the (edge, day) pairs to search
    uv = np.stack([u, v, u], axis=1)
    elo, ehi = spherical_extent(uv, pole)  # an arc is a degenerate spherical triangle
    dlo = np.full(nd, np.inf)
    dhi = np.full(nd, -np.inf)
    dk = day_of_knot[sel]
    np.minimum.at(dlo, dk, sdec)
    np.maximum.at(dhi, dk, sdec)
    slack = OMEGA_BOUND * spline.h  # the path between knots strays from the knots' band by less
    pair = (ehi[:, None] >= dlo[None, up_days] - slack) & (elo[:, None] <= dhi[None, up_days] + slack)
    ei, di = np.nonzero(pair)
    ea, eb = _hour_angle_windows(spline, pole, u[ei], v[ei], a[up_days[di]], b[up_days[di]])
    key = np.concatenate([np.zeros(len(up_days), np.int64), np.tile(ei + 1, TURNS)])
    lo_dom = np.concatenate([a[up_days], ea.T.ravel()])
    hi_dom = np.concatenate([b[up_days], eb.T.ravel()])
    keep = hi_dom > lo_dom
    key, lo_dom, hi_dom = key[keep], lo_dom[keep], hi_dom[keep]

    def values(k, t, pc):
        return np.einsum("ij,ij->i", spline(t, pc), normals[k])

    rk, rlo, rhi, rsimple = root_brackets(values, lambda k, pc: spline.curvature[pc], key, lo_dom, hi_dom, tol, spline.h,
                                          spline.piece, origin=spline.t0)
    # 3. keep an edge's crossings where the sun is on the arc (with the slack of its bracket)
    mid = 0.5 * (rlo + rhi)
    s = spline(mid)
    s /= np.linalg.norm(s, axis=1)[:, None]
    e = rk - 1
    on = rk == 0
    is_edge = ~on
    ee = e[is_edge]
    slack_arc = ANGLE_SLACK + OMEGA_BOUND * (rhi - rlo)[is_edge]
    c1 = np.einsum("ij,ij->i", np.cross(u[ee], s[is_edge]), m[ee]) >= -slack_arc
    c2 = np.einsum("ij,ij->i", np.cross(s[is_edge], v[ee]), m[ee]) >= -slack_arc
    on[is_edge] = c1 & c2
    rlo, rhi, rsimple = rlo[on], rhi[on], rsimple[on]
    # 4. candidate times and what each adds to the error if it bounds an interval
    lo_all = np.concatenate([alo, rlo])
    hi_all = np.concatenate([ahi, rhi])
    simple = np.concatenate([asimple, rsimple])
    t_c = np.concatenate([0.5 * (lo_all + hi_all)[simple], lo_all[~simple], hi_all[~simple], t0, t1])
    err_c = np.concatenate([0.5 * (hi_all - lo_all)[simple], (hi_all - lo_all)[~simple], (hi_all - lo_all)[~simple],
                            np.zeros(2 * nd)])
    d_c = np.concatenate([np.searchsorted(t0, t_c[:-2 * nd], side="right") - 1, np.arange(nd), np.arange(nd)])
    d_c = np.clip(d_c, 0, nd - 1)
    t_c = np.clip(t_c, t0[d_c], t1[d_c])
    order = np.lexsort((t_c, d_c))
    t_c, err_c, d_c = t_c[order], err_c[order], d_c[order]
    # 5. one ray per interval between consecutive candidates of a day
    same = (d_c[1:] == d_c[:-1]) & (t_c[1:] > t_c[:-1])
    i0 = np.flatnonzero(same)
    tm = 0.5 * (t_c[i0] + t_c[i0 + 1])
    seen = np.zeros(len(i0), bool)
    if len(i0):
        seen = _seen(one, spline, sun_path, tm, settings.min_altitude_deg)
    return _merge(t_c, err_c, d_c, i0, seen, nd)


#: Slack [s] on each edge's time window from its hour angles: covers the linear interpolation of the
#: sun's hour angle between knots (its rate varies by well under 1 % within a knot interval).
HOUR_ANGLE_SLACK_S = 120.0
#: Turns of the sun's hour angle tried per (edge, day): the first whose window can reach the day, and
#: the next two (a day spans less than one turn, so no later turn reaches it).
TURNS = 3


def _hour_angle_windows(spline: SunSpline, pole: np.ndarray, u: np.ndarray, v: np.ndarray, a: np.ndarray, b: np.ndarray):
    """The times within [a, b] (one day each) when the sun's hour angle lies within that of the arc
    from ``u`` to ``v`` (q, 3): outside them the sun cannot cross the arc.

    Along a great circle that misses the pole the hour angle is monotonic, and an arc shorter than
    180 deg spans less than 180 deg of it: the arc's hour angles are the short way between its
    ends'. The sun's hour angle increases through the day, so the window is where it lies in that
    range (up to two windows a day, where the range spans the day's end), widened by
    :data:`HOUR_ANGLE_SLACK_S`.

    Returns
    -------
    lo, hi : (q, TURNS) float [s], the windows (empty where hi <= lo)
    """
    e1 = np.array([0.0, 0.0, 1.0]) - pole[2] * pole
    e1 = e1 / np.linalg.norm(e1) if np.linalg.norm(e1) > 1e-9 else np.cross(pole, [1.0, 0.0, 0.0])
    e2 = np.cross(pole, e1)
    knot_t = spline.t0 + spline.h * np.arange(len(spline.s))
    hk = np.unwrap(np.arctan2(spline.s @ e2, spline.s @ e1))
    if hk[-1] < hk[0]:  # the sun's hour angle increases with time
        e2, hk = -e2, -hk
    hk = np.maximum.accumulate(hk)  # refraction's switch at the horizon may dent it; interp needs it rising
    hu, hv = np.arctan2(u @ e2, u @ e1), np.arctan2(v @ e2, v @ e1)
    d = turn(hu, hv)
    lo_h, w = hu + np.minimum(d, 0.0), np.abs(d)
    ha = np.interp(a, knot_t, hk)
    k0 = np.ceil((ha - w - lo_h - 2 * OMEGA_BOUND * HOUR_ANGLE_SLACK_S) / (2 * np.pi))
    out_lo, out_hi = np.empty((len(u), TURNS)), np.empty((len(u), TURNS))
    for j in range(TURNS):  # the turns of the hour angle that can meet a day (a day spans less than one)
        start = lo_h + 2 * np.pi * (k0 + j)
        t_lo = np.interp(start, hk, knot_t) - HOUR_ANGLE_SLACK_S
        t_hi = np.interp(start + w, hk, knot_t) + HOUR_ANGLE_SLACK_S
        out_lo[:, j], out_hi[:, j] = np.maximum(t_lo, a), np.minimum(t_hi, b)
    return out_lo, out_hi


#: Below this apparent elevation [deg] the spline may be off by the SPA's switch of its refraction
#: formula at the horizon (-0.83 deg; the knots' differences reach two knots, 20 min, beyond it):
#: midpoints there take their elevation from the SPA itself.
SPLINE_MIN_ELEVATION_DEG = 10.0


def _seen(one, spline: SunSpline, sun_path, tm: np.ndarray, min_alt: float) -> np.ndarray:
    """Visibility at the midpoints ``tm``: directions from the spline; the elevation too, but from
    the SPA itself where the spline gives less than :data:`SPLINE_MIN_ELEVATION_DEG` and is within
    1 deg of ``min_alt``."""
    d = spline(tm)
    d /= np.linalg.norm(d, axis=1)[:, None]
    elev = np.degrees(np.arcsin(np.clip(d[:, 2], -1, 1)))
    near = (elev < SPLINE_MIN_ELEVATION_DEG) & (np.abs(elev - min_alt) < 1.0)
    if near.any():
        elev[near] = sun_path(tm[near])[0]
    up = elev >= min_alt
    seen = np.zeros(len(tm), bool)
    if up.any():
        seen = one.seen_along(d, up)
    return seen


def _merge(t_c, err_c, d_c, i0, seen, nd):
    """Per day, the visible intervals between consecutive candidates merged, and the error bound."""
    vi = i0[seen]
    # a run of visible intervals continues where the next visible interval starts where this one ends
    if len(vi):
        start_new = np.ones(len(vi), bool)
        start_new[1:] = ~((t_c[vi[1:]] == t_c[vi[:-1] + 1]) & (d_c[vi[1:]] == d_c[vi[:-1]]))
        end_new = np.ones(len(vi), bool)
        end_new[:-1] = start_new[1:]
        s_idx, e_idx = vi[start_new], vi[end_new] + 1
    else:
        s_idx = e_idx = np.zeros(0, np.int64)
    err = np.bincount(d_c[s_idx], err_c[s_idx], nd) + np.bincount(d_c[e_idx], err_c[e_idx], nd)
    day = d_c[s_idx]
    iv = np.column_stack([t_c[s_idx], t_c[e_idx]])
    bounds = np.searchsorted(day, np.arange(nd + 1))
    intervals = [iv[bounds[k]:bounds[k + 1]] for k in range(nd)]  # one view per day (report data)
    return intervals, err


def union_intervals(per_point: list, errors: list, nd: int):
    """The union over points P of each day's intervals (the room sees the sun when any P does), and
    the sum of the points' error bounds. ``per_point``: per point, per day, (n, 2) unix times [s]."""
    iv = np.concatenate([x[k] for x in per_point for k in range(nd)]) if per_point else np.zeros((0, 2))
    day = np.concatenate([np.full(len(x[k]), k) for x in per_point for k in range(nd)]) if per_point else np.zeros(0, int)
    iv = iv.reshape(-1, 2)
    order = np.lexsort((iv[:, 0], day))  # by day, then start
    iv, day = iv[order], day[order]
    # an interval starts a new merged one where its day changes or it begins after every earlier
    # interval of its day has ended (running maximum of the ends; the days' times are disjoint)
    reach = np.maximum.accumulate(iv[:, 1]) if len(iv) else iv[:, 1]
    new = np.ones(len(iv), bool)
    new[1:] = (day[1:] != day[:-1]) | (iv[1:, 0] > reach[:-1])
    group = np.cumsum(new) - 1
    starts = iv[new, 0]
    ends = np.full(len(starts), -np.inf)
    np.maximum.at(ends, group, iv[:, 1])
    gday = day[new]
    bounds = np.searchsorted(gday, np.arange(nd + 1))
    merged = np.column_stack([starts, ends])
    intervals = [merged[bounds[k]:bounds[k + 1]] for k in range(nd)]  # one view per day (report data)
    return intervals, np.sum(errors, axis=0) if errors else np.zeros(nd)
