"""Mutation tests (issue 39): the daylight criterion's light paths, gather rounds, exact sky component
and climate-based parts (``criteria/daylight/``: transport, gather, sky_component, climate) with
stand-in ray engines and Radiance calls, against hand values, closed forms and brute force.

Stand-in random generators return fixed numbers where a sample must be worked by hand (0.5: the
centre of each stratum). Tolerances: 1e-12 on sums of a few terms; a midpoint rule in the window's
gnomonic angles against one over its area, 2e-4 relative (both O(h^2); 6e-5 measured).
"""
from __future__ import annotations

import math
from statistics import NormalDist
from types import SimpleNamespace

import numpy as np
import pytest

from en17037cli.criteria.daylight import climate, gather, patches, transport
from en17037cli.criteria.daylight import sky_component as scm
from en17037cli.criteria.daylight.sky import glass_reflectance, glass_transmittance
from en17037cli.scene.model import INTERIOR, WINDOW

Z995 = NormalDist().inv_cdf(0.995)
#: The engine's one-pass variance (mean of squares less the squared mean) loses the last digits of a
#: spread near 0: an interval of 2e-10 on a constant sample (measured).
ONE_PASS = 1e-8


class Fixed:
    """A stand-in random generator: every draw is ``value`` (or the next of ``values``, in turn)."""

    def __init__(self, *values):
        self.values, self.k = values, 0

    def random(self, size=None):
        v = self.values[self.k % len(self.values)]
        self.k += 1
        return np.full(size, v) if size is not None else v


# --- sky_component.py -----------------------------------------------------------------------------


def test_rect_solid_angle_closed_form():
    # the rectangle [0, a] x [0, b] at distance 1 seen from a corner's normal: atan(a b / sqrt(1 + a^2 + b^2))
    a, b = 0.7, 1.3
    G = np.array([[0.0, math.atan(a), 0.0, math.atan(b)]])
    assert scm._rect_solid_angle(G)[0] == pytest.approx(math.atan(a * b / math.sqrt(1 + a * a + b * b)), rel=1e-12)


def test_within_budget_by_hand():
    pt = np.array([0, 0, 1, 1, 1])
    own = np.array([0.25, 0.125, 0.125, 0.03, 0.5])
    budget = np.array([0.375, 0.5])
    # point 0: 0.375 in all fits its budget exactly; point 1: 0.655 does not, so each must fit 0.25 x 0.5 / 3 = 0.042
    assert scm._within_budget(pt, own, budget).tolist() == [True, True, False, True, False]


AXES = np.array([[[1.0, 0.0, 0.0], [0.0, 0.6, 0.8], [0.0, -0.8, 0.6]]])  # u, v, n: a pane tilted back 37 deg


def _g(d, c, tv, normal):
    """The integrand per steradian: CIE luminance x cos(theta) x the pane's transmittance, 0 below the horizon."""
    up = d[..., 2]
    cos_t = np.maximum(d @ normal, 0.0)
    return np.where(up > 0, (1 + 2 * up) / 3 * cos_t * glass_transmittance(c, tv), 0.0)


def _dense(G, tv, normal, n=300):
    """The cell's integral by an n x n midpoint rule in (alpha, beta), written out."""
    a = G[0] + (np.arange(n) + 0.5) * (G[1] - G[0]) / n
    b = G[2] + (np.arange(n) + 0.5) * (G[3] - G[2]) / n
    X, Y = np.meshgrid(np.tan(a), np.tan(b), indexing="ij")
    s = np.sqrt(1 + X * X + Y * Y)
    d = (X[..., None] * AXES[0, 0] + Y[..., None] * AXES[0, 1] + AXES[0, 2]) / s[..., None]
    f = _g(d, 1 / s, tv, normal) * (1 + X * X) * (1 + Y * Y) / s**3
    return f.sum() * (G[1] - G[0]) * (G[3] - G[2]) / n / n, f[n // 2, n // 2]


@pytest.mark.parametrize("tv", [1.0, 0.7])
@pytest.mark.parametrize("normal", [(0.0, 0.0, 1.0), (0.0, -0.6, 0.8)])
def test_cell_integrals_against_a_dense_midpoint_rule(tv, normal):
    r = math.radians
    G = np.array([[r(-10), r(-8), r(5), r(7)], [r(20), r(25), r(-20), r(-12)], [r(-3), r(3), r(-50), r(-40)]])
    nrm = np.asarray(normal)
    value, qerr, gmin, gmax = scm.cell_integrals(np.repeat(AXES, 3, 0), np.full(3, tv), G, normal, extremes=True)
    for k in range(3):
        want, _ = _dense(G[k], tv, nrm)
        # 3 x 3 Gauss on a smooth cell agrees with 300^2 midpoints to their O(h^2) (1e-6); the third cell
        # lies below the horizon (beta < -36.9 deg): nothing
        assert value[k] == pytest.approx(want, rel=1e-5, abs=1e-15)
        # the error estimate: the difference from the midpoint rule (the centre node), the engine's
        # transmittance interpolated in a table (within 1e-6 of the formula)
        a, b = 0.5 * (G[k, 0] + G[k, 1]), 0.5 * (G[k, 2] + G[k, 3])
        X, Y = math.tan(a), math.tan(b)
        s = math.sqrt(1 + X * X + Y * Y)
        d = (X * AXES[0, 0] + Y * AXES[0, 1] + AXES[0, 2]) / s
        centre = _g(d, 1 / s, tv, nrm) * (1 + X * X) * (1 + Y * Y) / s**3 * (G[k, 1] - G[k, 0]) * (G[k, 3] - G[k, 2])
        assert qerr[k] == pytest.approx(abs(value[k] - centre), abs=1e-5 * value[k] + 1e-15)
    # the integrand's extremes at the 3 x 3 Gauss nodes (+-sqrt(3/5) of the half-widths)
    x = np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
    a = 0.5 * (G[0, 0] + G[0, 1]) + 0.5 * (G[0, 1] - G[0, 0]) * x
    b = 0.5 * (G[0, 2] + G[0, 3]) + 0.5 * (G[0, 3] - G[0, 2]) * x
    X, Y = np.meshgrid(np.tan(a), np.tan(b), indexing="ij")
    s = np.sqrt(1 + X * X + Y * Y)
    g = _g((X[..., None] * AXES[0, 0] + Y[..., None] * AXES[0, 1] + AXES[0, 2]) / s[..., None], 1 / s, tv, nrm)
    assert gmin[0] == pytest.approx(g.min(), rel=1e-6) and gmax[0] == pytest.approx(g.max(), rel=1e-6)
    assert value[2] == qerr[2] == gmin[2] == gmax[2] == 0.0  # below the horizon


def test_window_transmittance_is_area_weighted():
    tris = np.array([[(0, 0, 0), (1, 0, 0), (0, 0, 1)], [(1, 0, 0), (4, 0, 0), (1, 0, 2)], [(0, 1, 0), (2, 1, 0), (0, 1, 1)]], float)
    scene = SimpleNamespace(vertices=tris.reshape(-1, 3), triangles=np.arange(9).reshape(3, 3), layer=np.full(3, WINDOW),
                            rooms=[], optics=np.array([[np.nan, 0.5], [np.nan, np.nan], [np.nan, 0.2]]))
    room = SimpleNamespace(windows=[SimpleNamespace(face_ids=[0, 1]), SimpleNamespace(face_ids=[2])])
    # window 1: 0.5 on 0.5 m2 and the default 0.7 on 3 m2
    refl = {"floor": 0.2, "walls": 0.5, "ceiling": 0.7, "landscape": 0.3, "ground": 0.1}
    assert scm.window_transmittance(scene, room, refl, 0.7).tolist() == pytest.approx([(0.25 + 2.1) / 3.5, 0.2], rel=1e-12)


# --- gather.py ------------------------------------------------------------------------------------


def test_cosine_directions_at_the_strata_centres_by_hand():
    frame = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    d = gather.cosine_directions(2, 3, Fixed(0.5), frame)
    assert d.shape == (2, 9, 3)
    # the concentric map sends the square's ring of 8 centres (+-2/3, 0) to the circle of radius 2/3 at
    # 45 deg steps (counter-clockwise from the +a axis), the centre to the pole; lifted by z = sqrt(1 - r^2)
    ab = [(a, b) for a in (-2 / 3, 0.0, 2 / 3) for b in (-2 / 3, 0.0, 2 / 3)]
    for k, (a, b) in enumerate(ab):
        r = max(abs(a), abs(b))
        phi = math.atan2(b, a)
        local = (r * math.cos(phi), r * math.sin(phi), math.sqrt(1 - r * r))
        assert d[0, k] == pytest.approx([-local[1], local[0], local[2]], abs=1e-12)
    assert np.array_equal(d[0], d[1])


def test_cosine_directions_are_cosine_weighted():
    d = gather.cosine_directions(1, 64, np.random.default_rng(1), np.eye(3))[0]
    assert np.allclose(np.linalg.norm(d, axis=1), 1.0)
    # E[cos] = 2/3 and E[cos^2] = 1/2 over the cosine-weighted hemisphere; stratified: 4096 samples agree to 1e-3
    assert d[:, 2].mean() == pytest.approx(2 / 3, abs=1e-3) and (d[:, 2] ** 2).mean() == pytest.approx(0.5, abs=1e-3)
    assert abs(d[:, 0].mean()) < 1e-3 and abs(d[:, 1].mean()) < 1e-3


def test_sampling_frame_by_hand():
    assert gather.sampling_frame([0.0, -2.0, 0.0]).tolist() == [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    assert np.allclose(gather.sampling_frame([3.0, 4.0, 5.0]), [[0.6, 0.8, 0], [-0.8, 0.6, 0], [0, 0, 1]])
    assert gather.sampling_frame([0.0, 0.0, 1.0]).tolist() == [[1, 0, 0], [0, 1, 0], [0, 0, 1]]


def test_reflected_rounds_and_intervals(monkeypatch):
    """Four points: a steady value (done after the first round), a noisy one (rounds of as many rays again
    until twice its count passes max_rays: 256, 512, 1041, 2065), one whose every ray sees only sky
    straight through the glass (no lit sample: traced to the end, its interval the Poisson bound
    6 / N) and one whose transmitted paths end short of the sky (nothing taken out)."""
    seen = {k: [] for k in range(4)}

    def trace(octree, o, d, args):
        assert octree == "oct" and args == gather.rtrace_args(s)
        k = o[:, 0].astype(int)
        value = np.select([k == 0, k == 1, k == 2], [np.full(len(k), 0.1), 0.2 + 0.2 * np.sign(d[:, 0]), np.ones(len(k))],
                          0.05 + 0.01 * d[:, 1])
        through = np.where(k >= 2, 1.0, 0.5)
        dist = np.where(k == 3, 0.98e10, np.where(k == 2, 0.99e10, 5.0))
        for i in range(4):
            seen[i].extend((value - np.where((dist >= 0.99e10) & (d[:, 2] > 0), through, 0.0))[k == i])
        return value * math.pi, through * math.pi, dist

    monkeypatch.setattr(gather.radiance, "trace", trace)
    s = gather.GatherSettings()
    pts = np.array([[0.0, 0, 0], [1.0, 0, 0], [2.0, 0, 0], [3.0, 0, 0]])
    r = gather.reflected("oct", pts, math.pi * math.pi, s, np.eye(3))
    assert r.rays.tolist() == [256, 2065, 2065, 256]
    for k in range(4):
        y = np.array(seen[k])  # sky_lx = pi^2: each sample is pi / sky_lx x pi (value - through)
        mean, half = y.mean(), Z995 * math.sqrt(y.var(ddof=1) / len(y))
        lit = int((y > 0).sum())
        if lit < 30 and lit < len(y):
            half = max(half, (3 * math.sqrt(lit + 1) + 3) / len(y))
        assert r.value[k] == pytest.approx(mean, rel=1e-12, abs=1e-15) and r.error[k] == pytest.approx(half, rel=1e-9, abs=ONE_PASS)
    assert r.error[2] == pytest.approx(6 / 2065) and r.value[2] == 0.0
    empty = gather.reflected("oct", np.zeros((0, 3)), 1.0, s, np.eye(3))
    assert len(empty.value) == 0 and len(empty.error) == 0 and len(empty.rays) == 0


def test_reflected_paths_rounds_thresholds_and_requests(monkeypatch):
    """Points: 0 steady, with requests answered by Radiance (0.5 x 0.1 each); 1 noisy but far from every
    threshold (known 0.5 + 0.2): done after a round; 2 noisy and on one (0.2): traced to the end; 3 dark
    (nothing lit, nothing touched): done at once."""
    sky_lx = 7.0
    samples = {k: [] for k in range(4)}
    S = SimpleNamespace(window_rays=4)

    def trace_paths(S_, o, d, window_rays, seed):
        assert S_ is S and window_rays == 4
        k = o[:, 0].astype(int)
        y = np.select([k == 0, k == 3], [0.05 + 0.001 * d[:, 0], np.zeros(len(k))], 0.2 + 0.2 * np.sign(d[:, 0]))
        req = transport.Requests()
        mine = np.flatnonzero(k == 0)
        req.add(o[mine], d[mine], np.full(len(mine), 0.5), mine)
        for i in range(4):
            samples[i].extend((y + np.where(k == 0, 0.05, 0.0))[k == i])
        return y, req, k != 3

    def trace(octree, o, d, args, processes):
        assert processes == 3
        return np.full(len(o), 0.1 * sky_lx), None, None

    monkeypatch.setattr(transport, "trace_paths", trace_paths)
    monkeypatch.setattr(gather.radiance, "trace", trace)
    s = gather.GatherSettings(window_rays=4)
    pts = np.array([[0.0, 0, 0], [1.0, 0, 0], [2.0, 0, 0], [3.0, 0, 0]])
    known = (np.array([0.0, 0.5, 0.0, 0.0]), np.zeros(4))
    r = gather.reflected_paths(S, "oct", pts, sky_lx, s, np.eye(3), processes=3, known=known, thresholds=(0.03, 0.2))
    assert r.rays.tolist() == [256, 256, 2065, 256]
    for k in range(4):
        y = np.array(samples[k])
        mean, half = y.mean(), Z995 * math.sqrt(y.var(ddof=1) / len(y))
        assert r.value[k] == pytest.approx(mean, rel=1e-12, abs=1e-15) and r.error[k] == pytest.approx(half, rel=1e-9, abs=ONE_PASS)
    assert r.value[0] == pytest.approx(0.1, abs=1e-3)
    # without thresholds the noisy point 1 is traced to the end too
    for v in samples.values():
        v.clear()
    r = gather.reflected_paths(S, "oct", pts, sky_lx, s, np.eye(3), processes=3, known=known)
    assert r.rays.tolist() == [256, 2065, 2065, 256]


def test_result_intervals_by_hand():
    # 4 samples 1, 2, 3, 6: mean 3, s^2 = 14 / 3; lit 4 of 4 (< 30): at least (3 sqrt(5) + 3) / 4
    total, sq = np.array([12.0, 12.0, 0.0]), np.array([50.0, 50.0, 0.0])
    count, lit = np.array([4.0, 4.0, 4.0]), np.array([4.0, 40.0, 0.0])
    r = gather._result(total, sq, count, lit)
    assert r.value.tolist() == [3.0, 3.0, 0.0] and r.rays.tolist() == [4, 4, 4]
    half = Z995 * math.sqrt(14 / 3 / 4)
    assert r.error.tolist() == pytest.approx([max(half, (3 * math.sqrt(5) + 3) / 4), half, 0.0], rel=1e-12)


# --- transport.py ---------------------------------------------------------------------------------


def test_requests_keep_what_carries_weight():
    r = transport.Requests()
    assert [a.shape for a in r.arrays()] == [(0, 3), (0, 3), (0,), (0,)]
    assert [a.shape for a in r.arrays("sky")] == [(0, 3), (0,), (0,)]
    o, d = np.arange(9.0).reshape(3, 3), -np.arange(9.0).reshape(3, 3)
    r.add(o, d, np.array([0.5, 0.0, 2.0]), np.array([7, 8, 9]))
    r.add(o[:1], d[:1], np.array([1.0]), np.array([4]))
    r.add_sky(d, np.array([0.0, 0.25, 0.0]), np.array([1, 2, 3]))
    oo, dd, w, path = r.arrays()
    assert oo.tolist() == [o[0].tolist(), o[2].tolist(), o[0].tolist()] and dd.tolist() == [d[0].tolist(), d[2].tolist(), d[0].tolist()]
    assert w.tolist() == [0.5, 2.0, 1.0] and path.tolist() == [7, 9, 4]
    sd, sw, sp = r.arrays("sky")
    assert sd.tolist() == [d[1].tolist()] and sw.tolist() == [0.25] and sp.tolist() == [2]


class _Hits:
    """A stand-in ray engine whose first hits per group are given."""

    def __init__(self, **groups):
        self.groups, self.added = groups, {}

    def add_group(self, name, mask):
        self.added[name] = mask

    def first_hit(self, group, o, d):
        return self.groups[group]

    def restart_offset(self, p):
        return np.full(len(p), 1e-6)


def test_scene_hits_tell_opaque_room_glazing_and_other_glazing():
    tris = np.array([[(0, 0, 0), (1, 0, 0), (0, 1, 0)]] * 8, float)
    layer = np.array([INTERIOR] * 5 + [WINDOW] * 3)
    scene = SimpleNamespace(vertices=tris.reshape(-1, 3), triangles=np.arange(24).reshape(8, 3), layer=layer)
    room = SimpleNamespace(index=2, windows=[SimpleNamespace(face_ids=np.array([5]))])
    inf = np.inf
    e = _Hits(opaque=(np.array([3, 3, -1, 3, -1]), np.array([2.0, 2.0, inf, 2.0, inf])),
              daylight_windows=(np.array([-1, 5, 6, 5, -1]), np.array([inf, 1.0, 1.0, 3.0, inf])))
    S = transport.Scene(e, scene, room, np.zeros(8), np.ones(8), [], window_rays=3)
    assert e.added["daylight_windows"].tolist() == (layer == WINDOW).tolist() and S.room_group == "windows of room 2"
    assert S.room_window.tolist() == [False] * 5 + [True, False, False] and S.window_rays == 3
    assert np.allclose(S.normals, [0, 0, 1])
    kind, face, t = S.hits(np.zeros((5, 3)), np.zeros((5, 3)))
    # opaque; the room's glazing first; another room's glazing; opaque before the glazing; nothing
    assert kind.tolist() == [1, 2, 3, 1, 0] and face.tolist() == [3, 5, 6, 3, -1] and t.tolist() == [2.0, 1.0, 1.0, 2.0, inf]


def test_frame_and_cosine_directions_about_a_normal_by_hand():
    f = transport._frame(np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]))
    assert f[0].tolist() == [[0, 0, 1], [0, -1, 0], [1, 0, 0]] and f[1].tolist() == [[0, 1, 0], [-1, 0, 0], [0, 0, 1]]
    n = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    d = transport.cosine_about(n, Fixed(0.25, 0.125))  # u = 0.25, v = 0.125: r = 0.5 at 45 deg, z = sqrt(0.75)
    h = 0.5 * math.sqrt(0.5)
    assert np.allclose(d, [[-h, h, math.sqrt(0.75)]] * 2, rtol=0, atol=1e-12)
    m = np.random.default_rng(2).normal(size=(20000, 3))
    m /= np.linalg.norm(m, axis=1)[:, None]
    c = np.einsum("ij,ij->i", transport.cosine_about(m, np.random.default_rng(3)), m)
    # cosine-weighted about each normal: E[cos] = 2/3, E[cos^2] = 1/2 (20 000 samples: 1 % of 1/sqrt(18) ~ 0.005)
    assert c.min() >= 0 and c.mean() == pytest.approx(2 / 3, abs=0.005) and (c * c).mean() == pytest.approx(0.5, abs=0.005)


WIN = SimpleNamespace(origin=np.zeros(3), u=np.array([1.0, 0.0, 0.0]), v=np.array([0.0, 0.0, 1.0]), n=np.array([0.0, -1.0, 0.0]),
                      xmin=-1.0, xmax=1.0, ymin=1.0, ymax=2.0)  # 2 x 1 m in the plane y = 0, room at y > 0


class _Window:
    """What window_estimate asks of the scene: every ray towards -y reaches the room's pane (face 0, tv),
    then the sky, but where it crosses the pane at x > 0 when ``half`` (an obstruction: face 9)."""

    def __init__(self, tv, half=False):
        self.frames, self.tv, self.half = [WIN], np.array([tv]), half
        self.normals = np.array([[0.0, -1.0, 0.0]])
        self.engine = self

    def hits(self, o, d):
        t = o[:, 1] / -d[:, 1]
        return np.where(d[:, 1] < 0, 2, 0), np.zeros(len(o), int), t

    def restart_offset(self, p):
        return np.full(len(p), 1e-6)

    def first_hit(self, group, g, d):
        assert group == "opaque"
        return np.where(self.half & (g[:, 0] > 0), 9, -1), np.zeros(len(g))


def _through_window(p, nv, tv, part, n=500, lum=True):
    """9 / (7 pi) x the integral of [L(g)] cos(theta_v) tau(i) over the pane's part x < 0 (-1), x > 0 (+1) or
    whole (0): the midpoint rule over its area, d omega = cos(i) dA / r^2."""
    x0, x1 = {-1: (-1.0, 0.0), 1: (0.0, 1.0), 0: (-1.0, 1.0)}[part]
    xs, zs = x0 + (np.arange(n) + 0.5) * (x1 - x0) / n, 1.0 + (np.arange(n) + 0.5) / n
    X, Z = np.meshgrid(xs, zs)
    r = np.stack([X - p[0], -np.full_like(X, p[1]), Z - p[2]], axis=-1)
    dist = np.linalg.norm(r, axis=-1)
    d = r / dist[..., None]
    cos_i = -d[..., 1]
    w = np.maximum(d @ nv, 0.0) * glass_transmittance(cos_i, tv) * cos_i / dist**2 * (x1 - x0) / n / n
    if lum:
        w = w * (1 + 2 * d[..., 2]) / 3 * 9 / (7 * math.pi)
    return float(w.sum())


@pytest.mark.parametrize("tv", [1.0, 0.7])
def test_window_estimate_against_the_integral_over_the_pane(tv):
    v = np.array([[0.0, 2.0, 0.5], [0.0, 1.5, 1.0], [0.3, -0.5, 1.0]])  # the last behind the pane's plane
    nv = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [0.0, 1.0, 0.0]])
    req = transport.Requests()
    out = transport.window_estimate(_Window(tv), v, nv, np.array([2.0, 0.5, 1.0]), np.array([4, 7, 8]), 3600, Fixed(0.5), req)
    # 60 x 60 strata centres: the midpoint rule in the gnomonic angles
    want = [2.0 * _through_window(v[0], nv[0], tv, 0), 0.5 * _through_window(v[1], nv[1], tv, 0), 0.0]
    assert out.tolist() == pytest.approx(want, rel=2e-4)
    o, d, w, path = req.arrays()
    assert len(w) == 0  # everything reached the sky
    sd, sw, sp = req.arrays("sky")
    assert sp.tolist() == [4] * 3600 + [7] * 3600 and np.all(sd[:, 1] < 0)
    assert sw[sp == 4].sum() == pytest.approx(2.0 * _through_window(v[0], nv[0], tv, 0, lum=False), rel=2e-4)


def test_window_estimate_sends_what_is_obstructed_to_radiance():
    v, nv = np.array([[0.0, 2.0, 0.5]]), np.array([[0.0, 0.0, 1.0]])
    req = transport.Requests()
    out = transport.window_estimate(_Window(0.7, half=True), v, nv, np.ones(1), np.array([3]), 3600, Fixed(0.5), req)
    assert out[0] == pytest.approx(_through_window(v[0], nv[0], 0.7, -1), rel=2e-4)
    o, d, w, path = req.arrays()
    assert path.tolist() == [3] * 1800 and np.all(o[:, 0] > 0)
    assert np.allclose(o[:, 1], d[:, 1] * 1e-6)  # on the pane, moved on by the restart offset
    assert w.sum() == pytest.approx(_through_window(v[0], nv[0], 0.7, 1, lum=False), rel=2e-4)
    req = transport.Requests()
    out = transport.window_estimate(_Window(0.7, half=True), v, nv, np.ones(1), np.array([3]), 3600, Fixed(0.5), req, sky_too=False)
    assert out.tolist() == [0.0] and len(req.arrays("sky")[0]) == 0 and len(req.arrays()[0]) == 1800


class _Glass:
    """Paths from z = 0 upwards: a pane at z = 1 (face 0, tv) reflects them; above it nothing."""

    def __init__(self, tv):
        self.tv, self.rho, self.frames, self.window_rays = np.array([tv]), np.zeros(1), [], 1
        self.normals = np.array([[0.0, 0.0, -1.0]])
        self.engine = self

    def hits(self, o, d):
        below = (o[:, 2] < 0.5) & (d[:, 2] > 0)
        t = np.where(below, (1.0 - o[:, 2]) / np.where(below, d[:, 2], 1.0), np.inf)
        return np.where(below, 2, 0), np.where(below, 0, -1), t

    def restart_offset(self, p):
        return np.full(len(p), 1e-6)


@pytest.mark.parametrize("tv", [0.7, 1.0])
def test_paths_reflected_by_the_glass_then_lost(tv):
    d = np.array([[0.0, 0.6, 0.8], [0.6, 0.0, 0.8], [0.0, 0.0, 1.0]])
    total, req, touched = transport.trace_paths(_Glass(tv), np.zeros((3, 3)), d.copy(), 1, 5)
    o, dd, w, path = req.arrays()
    assert total.tolist() == [0.0, 0.0, 0.0]
    if tv >= 1.0:  # an open opening reflects nothing: the paths end
        assert len(w) == 0 and touched.tolist() == [False] * 3
        return
    # each path comes back down mirrored, weight pi rho_g(cos i), and is lost (a request: what Radiance sees)
    assert path.tolist() == [0, 1, 2] and touched.tolist() == [True] * 3
    assert np.allclose(dd, d * [1, 1, -1], rtol=0, atol=1e-12)
    assert o[:, 2].tolist() == pytest.approx([1 - 0.8e-6, 1 - 0.8e-6, 1 - 1e-6], abs=1e-12)
    assert w.tolist() == pytest.approx((math.pi * glass_reflectance(d[:, 2], tv)).tolist(), rel=1e-12)


class _Room:
    """Paths from z = 0: a floor-to-ceiling box of faces 0 (black) and 1 (reflectance rho) overhead at
    z = 1 for x < 0 and x >= 0; nothing else, no window."""

    def __init__(self, rho):
        self.tv, self.rho, self.frames, self.window_rays = np.ones(2), np.array([0.0, rho]), [], 1
        self.normals = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, -1.0]])
        self.engine = self

    def hits(self, o, d):
        up = (o[:, 2] < 0.5) & (d[:, 2] > 0)
        t = np.where(up, (1.0 - o[:, 2]) / np.where(up, d[:, 2], 1.0), np.inf)
        x = o[:, 0] + t * d[:, 0]
        return np.where(up, 1, 0), np.where(up, (x >= 0).astype(int), -1), t

    def restart_offset(self, p):
        return np.full(len(p), 1e-6)


def test_paths_end_on_black_and_leave_a_white_ceiling():
    d = np.array([[-0.6, 0.0, 0.8], [0.6, 0.0, 0.8]])
    total, req, touched = transport.trace_paths(_Room(1.0), np.zeros((2, 3)), d.copy(), 1, 5)
    o, dd, w, path = req.arrays()
    # the black face ends its path untouched; the white one sends it on (roulette keeps it: rho 1), downwards
    # about the face's normal, from where it finds nothing: a request of weight pi from just under the face
    assert touched.tolist() == [False, True] and path.tolist() == [1] and w.tolist() == [pytest.approx(math.pi)]
    assert dd[0, 2] < 0 and o[0].tolist() == pytest.approx([0.75, 0.0, 1.0 - 1e-6], abs=1e-12)
    assert total.tolist() == [0.0, 0.0]


# --- climate.py -----------------------------------------------------------------------------------


def test_equal_weights_by_hand():
    o, d = np.arange(12.0).reshape(4, 3), -np.arange(12.0).reshape(4, 3)
    w = np.array([0.5, 1.0, 2.5, 0.2])  # W0 = 1.05: w / W0 = 0.48, 0.95, 2.38, 0.19
    oo, dd, w0, pt = climate._equal_weights(o, d, w, np.array([1, 0, 1, 0]),
                                                 SimpleNamespace(random=lambda n: np.array([0.5, 0.5, 0.5, 0.1])[:n]))
    # copies: 0 (0.48 < 0.5), 1 (0.95 > 0.5), 2 (0.38 < 0.5 left over), 1 (0.19 > 0.1); sorted by point, stably
    assert w0 == pytest.approx(1.05) and pt.tolist() == [0, 0, 1, 1]
    assert oo.tolist() == [o[1].tolist(), o[3].tolist(), o[2].tolist(), o[2].tolist()] and dd.tolist() == (-oo).tolist()
    # equal weights: one copy each; sorted by point, each point's requests in their order (stable)
    o = np.arange(600.0).reshape(200, 3)
    oo, _, _, pt = climate._equal_weights(o, o, np.ones(200), np.arange(200) % 2, np.random.default_rng(0))
    assert oo[:, 0].tolist() == [6.0 * k for k in range(100)] + [6.0 * k + 3 for k in range(100)]
    rng = np.random.default_rng(4)
    w = rng.random(20000) ** 3
    _, _, w0, pt = climate._equal_weights(np.zeros((20000, 3)), np.zeros((20000, 3)), w, np.zeros(20000, int), rng)
    # unbiased: the copies times W0 carry the weights' sum (Poisson-like spread: 1 % of it)
    assert len(pt) * w0 == pytest.approx(w.sum(), rel=0.01)


def test_sink_point_by_hand():
    scene = SimpleNamespace(vertices=np.array([[-2.0, 1.0, 3.0], [4.0, 5.0, -1.0], [0.0, 0.0, 0.0]]))
    assert climate.sink_point(scene).tolist() == [1.0, 2.5, -11.0]


def _epw(year):
    days = np.arange(np.datetime64(f"{year}-01-01"), np.datetime64(f"{year + 1}-01-01"))
    month = days.astype("datetime64[M]").astype(int) % 12 + 1
    day = (days - days.astype("datetime64[M]")).astype(int) + 1
    return SimpleNamespace(month=np.repeat(month, 24), day=np.repeat(day, 24), hour=np.tile(np.arange(1, 25), len(days)),
                           tz_hours=1.0, latitude=52.0, longitude=4.36, elevation_m=0.0)


@pytest.mark.parametrize("year", [2025, 2024])
def test_sun_directions_at_the_middle_of_each_hour_against_pvlib(year, monkeypatch):
    import datetime as dt
    import time

    from oracles import sun_position

    monkeypatch.setenv("TZ", "America/New_York")  # the machine's own time zone does not enter
    time.tzset()

    w = _epw(year)
    hours = np.array([12, 24 * 59 + 10, 24 * 200 + 14, len(w.hour) - 12])
    north = 30.0
    got = climate.sun_directions(w, hours, north)
    t = [dt.datetime(year, int(w.month[h]), int(w.day[h]), tzinfo=dt.UTC).timestamp() + (w.hour[h] - 0.5 - 1.0) * 3600
         for h in hours]
    el, az = sun_position(np.array(t), 52.0, 4.36, refraction=False)
    e, a = np.radians(el), np.radians(az + north)
    want = np.column_stack([np.sin(a) * np.cos(e), np.cos(a) * np.cos(e), np.sin(e)])
    monkeypatch.delenv("TZ")
    time.tzset()
    assert np.abs(got - want).max() < 1e-6  # the two SPAs agree to 1e-5 deg (docs/mutation.md)


def test_direct_sun_by_hand(monkeypatch):
    from en17037cli.criteria.view.rays import SKY

    class VR:  # rays with d_x > 0 leave through face 0 (window 1), d_x < -0.5 or from x > 1 and d_y > 0.8 are blocked,
        def __init__(self, engine, scene):  # the others through face 2 (window 0)
            assert engine == "engine" and scene is ctx.scene

        def through_windows(self, group, o, d):
            assert group == "windows of room 0" and o.shape == d.shape
            blocked = (d[:, 0] < -0.5) | ((o[:, 0] > 1.0) & (d[:, 1] > 0.8))
            return np.where(blocked, 0, SKY), np.where(blocked, -1, np.where(d[:, 0] > 0, 0, 2)), None, None, None

    monkeypatch.setattr(climate, "ViewRays", VR)
    room = SimpleNamespace(index=0, windows=[SimpleNamespace(face_ids=[1, 2, 3], normal=np.array([0.0, -1.0, 0.0])),
                                             SimpleNamespace(face_ids=[0], normal=np.array([1.0, 0.0, 0.0]))])
    ctx = SimpleNamespace(engine="engine", scene=SimpleNamespace(triangles=np.zeros((10, 3))))
    h = 1300  # more hours than two blocks of 512; the hours under the horizon or without sun among the first
    az = np.linspace(0, 40 * np.pi, h)
    el = np.where((np.arange(h) % 7 == 3) & (np.arange(h) < 100), -0.1, 0.4)
    sun_dir = np.column_stack([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)])
    sun_lx = np.where((np.arange(h) % 11 == 5) & (np.arange(h) < 100), 0.0, 50000.0 + np.arange(h))
    sun_lx[200] = 0.5
    tv = np.array([0.7, 0.9])
    pts = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    out = climate.direct_sun(ctx, room, pts, tv, sun_lx, sun_dir)
    x = sun_dir[:, 0]
    tau = np.where(x > 0, glass_transmittance(np.abs(x), 0.9), glass_transmittance(np.abs(sun_dir[:, 1]), 0.7))
    want = np.where((x >= -0.5) & (sun_dir[:, 2] > 0), sun_lx * sun_dir[:, 2] * tau, 0.0)
    assert out.shape == (2, h) and np.allclose(out[0], want, rtol=1e-12, atol=0)
    assert np.allclose(out[1], np.where(sun_dir[:, 1] > 0.8, 0.0, want), rtol=1e-12, atol=0) and out[0, 200] > 0
    assert climate.direct_sun(ctx, room, np.zeros((0, 3)), tv, sun_lx, sun_dir).shape == (0, h)
    assert not climate.direct_sun(ctx, room, pts, tv, np.zeros(h), sun_dir).any()


def test_path_coefficients_bin_the_sky_samples_and_the_requests(monkeypatch):
    """Four paths per point (rays 4: 2 x 2 strata): sky samples put in their patches (gendaymtx's order: the
    ground first), requests of one weight answered per patch by rcontrib (a stand-in), over the paths."""
    mf = 1
    up = patches.patch_directions(mf)

    seeds = []

    def trace_paths(S_, o, d, window_rays, seed):
        assert S_ is S and window_rays == 3 and o.tolist() == [[1.0, 2.0, 3.0]] * 4 + [[4.0, 5.0, 6.0]] * 4
        assert d.shape == (8, 3) and np.allclose(np.linalg.norm(d, axis=1), 1.0) and np.all(d[:, 2] > 0)
        seeds.append((seed, d.copy()))
        req = transport.Requests()
        req.add_sky(up[[1, 1, 50, 145]], np.array([0.5, 0.25, 1.0, 2.0]), np.array([0, 1, 4, 7]))
        req.add(o[[0, 5, 6]], d[[0, 5, 6]], np.full(3, 0.8), np.array([0, 5, 6]))
        return None, req, None

    def record_sums(octree, o, d, point, n, mf_, args, sink, processes):
        assert octree == "oct" and mf_ == mf and args == ["-ab", "1"] and processes == 2 and n == 2
        assert o.tolist() == [[1.0, 2.0, 3.0]] + [[4.0, 5.0, 6.0]] * 2 and np.all(d[:, 2] > 0)
        assert point.tolist() == [0, 1, 1] and sink.tolist() == [9.0, 9.0, 9.0]
        out = np.zeros((n, patches.reinhart_bins(mf)))
        out[0, 3], out[1, 0] = 1.0, 2.0
        return out

    monkeypatch.setattr(transport, "trace_paths", trace_paths)
    monkeypatch.setattr(climate, "_record_sums", record_sums)
    S = SimpleNamespace(window_rays=3, engine=SimpleNamespace(threads=2))
    pts = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
    dc = climate.path_coefficients(S, "oct", pts, mf, 4, 0, ["-ab", "1"], np.eye(3), np.full(3, 9.0))
    want = np.zeros((2, 146))
    want[0, 1] = 0.75 / 4  # paths 0 and 1 of point 0 in the first patch (row 1; patch_directions' row 0 is the ground)
    want[1, 50], want[1, 145] = 1.0 / 4, 2.0 / 4  # paths 4 and 7 of point 1: patch 49 and the zenith cap
    want[0, 3], want[1, 0] = 0.8 / 4, 1.6 / 4
    assert np.allclose(dc, want, rtol=0, atol=1e-15)
    # the same inputs, the same paths; another replicate, other ones
    climate.path_coefficients(S, "oct", pts, mf, 4, 0, ["-ab", "1"], np.eye(3), np.full(3, 9.0))
    climate.path_coefficients(S, "oct", pts, mf, 4, 1, ["-ab", "1"], np.eye(3), np.full(3, 9.0))
    (s0, d0), (s1, d1), (s2, d2) = seeds
    assert s0 is not None and s0 == s1 and np.array_equal(d0, d1) and s2 != s0 and not np.allclose(d2, d0)
    assert climate.path_coefficients(S, "oct", np.zeros((0, 3)), mf, 4, 0, [], np.eye(3), np.zeros(3)).shape == (0, 146)


def _box_engine(triangle=False):
    """The box room of the reference tests (4 x 6 x 3 m, a 2 x 1.4 m south window, the ground outside):
    the ray engine, view rays and room geometry."""
    from en17037cli.criteria.view.frames import RoomGeometry, window_frame
    from en17037cli.criteria.view.rays import ViewRays
    from en17037cli.raytrace import RayEngine
    from en17037cli.samples.box import BoxRoom, box_room_polygons
    from en17037cli.scene.model import Window

    tris, layer = [], []
    for name, quads in box_room_polygons(BoxRoom(building_height=0.0, triangle_window=triangle)).items():
        for q in quads:
            q = np.asarray(q, float)
            for k in range(1, len(q) - 1):  # fan
                tris.append([q[0], q[k], q[k + 1]])
                layer.append(WINDOW if name == "glazing" else INTERIOR)
    tris, layer = np.array(tris), np.array(layer)
    win = np.flatnonzero(layer == WINDOW)
    engine = RayEngine(tris.reshape(-1, 3), np.arange(3 * len(tris)).reshape(-1, 3), {"opaque": layer != WINDOW, "win": win})
    f = window_frame(Window("glazing", 0, win, tris[win], np.array([0.0, -1.0, 0.0]), 0.0), 0)
    wof = np.full(len(tris), -1)
    wof[win] = 0
    return engine, ViewRays(engine, SimpleNamespace(layer=layer)), RoomGeometry([f], wof, tris[win], np.zeros(len(win), int), "win")


def _unit_radiance(p, split, part, tv, inside=None, n=400):
    """The integral of cos(theta) tau(i) d omega over the window's directions with d_z > split (part 1), at most
    (part 0) or all (None), above the horizon: the midpoint rule over the pane's area (x in [-1, 1], z in [0.8, 2.2])."""
    s, t = (np.arange(n) + 0.5) / n, (np.arange(n) + 0.5) / n
    S, T = np.meshgrid(s, t, indexing="ij")
    X = np.stack([-1.0 + 2.0 * S, np.zeros_like(S), 0.8 + 1.4 * T], axis=-1)
    r = X - p
    dist = np.linalg.norm(r, axis=-1)
    d = r / dist[..., None]
    cos_pane = np.abs(d[..., 1])
    f = np.maximum(d[..., 2], 0.0) * glass_transmittance(cos_pane, tv) * cos_pane / dist**2 * 2.8 / n / n
    keep = np.ones(S.shape, bool) if inside is None else inside(S, T)
    if part is not None:
        keep &= (d[..., 2] > split) == bool(part)
    return float((f * keep).sum())


def test_sky_component_bins_its_nodes_by_direction():
    engine, view_rays, rg = _box_engine()
    pts = np.array([[0.0, 2.0, 0.85], [1.2, 4.5, 0.85]])
    sc = scm.sky_component(view_rays, rg, pts, np.array([0.7]), bins=lambda d: (d[:, 2] > 0.3).astype(int), nbins=2)
    assert sc.patches.shape == (2, 2)
    for k, p in enumerate(pts):
        whole = _unit_radiance(p, 0.3, None, 0.7)
        # the cells are refined until the sky component's bound is within 0.5 % of it: the unit-radiance
        # integral over the same cells to that (1.5e-4 measured); the nodes of a cell the split crosses go to
        # one side or the other: 2 % of a side
        assert sc.patches[k].sum() == pytest.approx(whole, rel=5e-3)
        assert sc.patches[k, 1] == pytest.approx(_unit_radiance(p, 0.3, 1, 0.7), rel=0.02)
        assert sc.patches[k, 0] == pytest.approx(_unit_radiance(p, 0.3, 0, 0.7), rel=0.02)
    none = scm.sky_component(view_rays, rg, pts, np.array([0.7]), bins=lambda d: np.where(d[:, 2] > 0.3, 0, -1), nbins=1)
    assert none.patches[:, 0] == pytest.approx(sc.patches[:, 1], rel=1e-9)
    assert scm.sky_component(view_rays, rg, pts, np.array([0.7])).patches is None
    engine.close()


def test_sky_component_bins_of_a_pane_that_is_not_a_rectangle():
    engine, view_rays, rg = _box_engine(triangle=True)
    pts = np.array([[0.0, 2.0, 0.85]])
    sc = scm.sky_component(view_rays, rg, pts, np.array([1.0]), bins=lambda d: np.zeros(len(d), int), nbins=1)
    want = _unit_radiance(pts[0], 0.0, None, 1.0, inside=lambda s, t: s + t <= 1.0, n=800)
    # cells cut by the hypotenuse weigh their clipped share of the cell's integral: within the sky component's
    # tolerance, 0.5 % (2.2e-3 measured)
    assert sc.patches[0, 0] == pytest.approx(want, rel=5e-3)
    engine.close()


def test_path_coefficients_of_one_ray_per_point(monkeypatch):
    def trace_paths(S, o, d, window_rays, seed):
        assert o.tolist() == [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]  # 1 x 1 strata: one path per point
        req = transport.Requests()
        req.add_sky(patches.patch_directions(1)[[3]], np.array([0.5]), np.array([1]))
        return None, req, None

    monkeypatch.setattr(transport, "trace_paths", trace_paths)
    S = SimpleNamespace(window_rays=1, engine=SimpleNamespace(threads=1))
    dc = climate.path_coefficients(S, "oct", np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]), 1, 1, 0, [], np.eye(3), np.zeros(3))
    assert dc[1, 3] == 0.5 and dc.sum() == 0.5


def test_each_round_draws_from_its_own_fixed_stream(monkeypatch):
    # rounds r = 0, 1, 2, ... draw their directions from default_rng([SEED, r]) (and the paths from
    # [SEED, r, 1]): the same numbers on every run, other numbers in every round
    firsts, path_seeds = [], []
    real = gather.cosine_directions

    def directions(n, m, rng, frame):
        firsts.append(float(rng.random()))
        return real(n, m, rng, frame)

    def trace(octree, o, d, args, processes=1):
        k = np.arange(len(o))
        return 0.3 * (k % 2) + 0.01, np.zeros(len(o)), np.full(len(o), 5.0)  # noisy: rounds to the end

    monkeypatch.setattr(gather, "cosine_directions", directions)
    monkeypatch.setattr(gather.radiance, "trace", trace)
    s = gather.GatherSettings(rays=4, max_rays=40)
    r = gather.reflected("oct", np.zeros((1, 3)), 1.0, s, np.eye(3))
    want = [float(np.random.default_rng([gather.SEED, k]).random()) for k in range(len(firsts))]
    assert len(firsts) >= 3 and firsts == want
    assert r.rays.dtype.kind == "i" and r.rays.tolist() == [4 + 4 + 9 + 16]  # 2 x 33 > 40 ends it

    def trace_paths(S_, o, d, window_rays, seed):
        path_seeds.append(list(seed))
        return 0.3 * (np.arange(len(o)) % 2) + 0.01, transport.Requests(), np.ones(len(o), bool)

    monkeypatch.setattr(transport, "trace_paths", trace_paths)
    firsts.clear()
    r = gather.reflected_paths(SimpleNamespace(window_rays=1), "oct", np.zeros((1, 3)), 1.0, s, np.eye(3))
    assert firsts == want and path_seeds == [[gather.SEED, k, 1] for k in range(len(want))]
    assert r.rays.dtype.kind == "i"


def test_no_points_no_rays():
    s = gather.GatherSettings()
    for r in (gather.reflected("oct", np.zeros((0, 3)), 1.0, s, np.eye(3)),
              gather.reflected_paths(None, "oct", np.zeros((0, 3)), 1.0, s, np.eye(3))):
        assert r.value.shape == (0,) and r.error.shape == (0,) and r.rays.shape == (0,) and r.rays.dtype.kind == "i"
