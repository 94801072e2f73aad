"""The reflected components of the daylight factor (externally and internally reflected light): the
rounds of samples per point and their intervals, for the light paths of :mod:`.transport`
(:func:`reflected_paths`, what the criterion uses) and for a gather on Radiance alone
(:func:`reflected`, kept as an independent cross-check: docs/daylight.md), which this docstring
describes; the rules of the rounds and intervals are the same.

The illuminance of a horizontal point is E = ∫ L(ω) cos θ dω over its upper hemisphere. Cosine-
weighted directions make each sample an estimate of it: E ≈ π mean(L(ω_k)). Each direction is
traced by ``rtrace`` (:func:`~.radiance.trace`) in the scene lit by the CIE overcast sky
(:func:`~.radiance.cie_overcast_sky_text`); Radiance follows the light back through any number
of diffuse bounces (ambient sampling with Russian roulette: no bias from a bounce limit or a
weight cut-off) and through the glazing (its transmission and its reflection). What a ray sees
straight through the glazing of the sky (the transmitted part ``x`` of a ray whose transmitted path
ends on the sky above the horizon) is the sky component, which :mod:`.sky_component` integrates
exactly; it is taken out of that ray's value, leaving the light reflected by the glazing. The rest
is the externally reflected component (ground, obstructions, the facade beyond the glass) and the
internally reflected one (the room's surfaces), both lit by every path Radiance finds:

    R(p) = π / N Σ_k (v_k − x_k [the transmitted path of ray k ends on the sky above the horizon])

Directions: an n x n grid of strata of the unit square, one jittered sample in each, mapped to the
disc by Shirley and Chiu's concentric map and lifted to the hemisphere (a cosine-weighted
stratified sample), in a frame turned with the room's first window so that moving or rotating the
model does not change the sample. Seeded: the same inputs give the same numbers.

Error: the samples are independent (each ray's own random walk), so s / sqrt(N) with s their
standard deviation bounds the standard error of the mean from above for the stratified sample (the
spread between strata is counted as if it were noise); the interval is z(0.995) s / sqrt(N), a 99 %
interval, so that at least 95 % of a plane's points are covered, not only on average. Adaptive:
after a first round of ``rays`` directions per point, a point whose interval is wider than
max(``rel_tolerance`` R, ``abs_tolerance``), or fewer of whose samples than :data:`MIN_LIT` saw
any reflected light, gets as many new directions again (a new stratified round), until it is within
or has ``max_rays``; a point left with fewer lit samples than that gets an interval of at least
Y_MAX (3 sqrt(k + 1) + 3) / N (k lit of N: a Poisson 99.5 % upper bound on k, each at the largest
value a sample can take, :data:`Y_MAX`): 0 lit samples of 4096 is at most 0.15 % D.

References: P. Shirley, K. Chiu (1997), A low distortion map between disk and square, J. Graphics
Tools 2(3); G. Ward (1994), The RADIANCE lighting simulation and rendering system, SIGGRAPH
(``-lr 0``: Russian roulette, rtrace(1)); J. Arvo, D. Kirk (1990), Particle transport and image
synthesis (roulette is unbiased).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.criteria.daylight import radiance

#: Two-sided 99 % quantile of the normal distribution (the intervals of the reflected part).
Z995 = 2.5758293035489004
#: A transmitted path at least this long ended on the sky or the ground's glow [m] (Radiance's FHUGE is 1e10).
SKY_DISTANCE_M = 0.99e10
#: Seed of the first round's jitter (each round and point draws its own stream from it).
SEED = 17037
#: A point's interval is trusted once at least this many of its samples saw reflected light: with
#: fewer (a dark room lit by one bright surface, whose light a ray finds rarely), the samples' spread
#: says little about the mean's, so more rays are traced (up to ``max_rays``).
MIN_LIT = 30
#: The largest value one sample can take [-]: a surface's luminance times π over the unobstructed
#: horizontal illuminance, its reflectance (at most 1) times its illuminance relative to the
#: unobstructed sky's (at most 1 under an overcast sky for any surface a room sees).
Y_MAX = 1.0


@dataclass(frozen=True)
class GatherSettings:
    """How the reflected part is sampled (``daylight.radiance``).

    rays : directions per point in the first round (a square number: n x n strata)
    max_rays : at most this many per point
    rel_tolerance, abs_tolerance : a point is done once the half-width of its 99 % interval is within
        max(rel_tolerance x R, abs_tolerance); abs_tolerance as a fraction of the unobstructed
        horizontal illuminance (1e-4: 0.01 % D)
    ab : Radiance's limit of diffuse bounces (with Russian roulette below the weight ``lw``)
    ad : hemisphere samples Radiance takes at each diffuse hit (1: one path per ray)
    lw : weight below which Russian roulette decides whether a path goes on
    window_rays : directions per window a path's bounce sends through the glazing (next-event
        estimation, :mod:`.transport`)
    """

    rays: int = 256
    max_rays: int = 4096
    rel_tolerance: float = 0.05
    abs_tolerance: float = 1e-4
    ab: int = 100
    ad: int = 1
    lw: float = 0.05
    window_rays: int = 1


@dataclass
class Reflected:
    """Per point: ``value`` [-] (fraction of the unobstructed horizontal illuminance), ``error`` [-]
    (half-width of its 99 % interval), ``rays`` traced from it; ``traced``: rays in all."""

    value: np.ndarray
    error: np.ndarray
    rays: np.ndarray


def rtrace_args(s: GatherSettings) -> list[str]:  # pragma: no mutate block
    """rtrace options of the gather: no ambient cache (each value its own estimate), Russian roulette
    (``-lr 0``: paths end at random below the weight ``lw``, unbiased), correlated sampling in one
    process (``-u- -n 1``: the same rays give the same numbers)."""
    return ["-n", "1", "-u-", "-ab", str(s.ab), "-ad", str(s.ad), "-as", "0", "-aa", "0", "-lw", f"{s.lw:g}", "-lr", "0"]


def cosine_directions(m: int, n: int, rng: np.random.Generator, frame: np.ndarray) -> np.ndarray:
    """(m, n², 3) unit directions: for each of m points, one jittered sample in each of n x n strata
    of the unit square, mapped by the concentric map to the disc and lifted to the hemisphere about
    ``frame[2]`` (z = sqrt(1 - x² - y²)): cosine-weighted, stratified.

    Parameters
    ----------
    frame : (3, 3) orthonormal rows x, y, z
    """
    i, j = np.divmod(np.arange(n * n), n)
    a = 2.0 * (i[None] + rng.random((m, n * n))) / n - 1.0
    b = 2.0 * (j[None] + rng.random((m, n * n))) / n - 1.0
    first = np.abs(a) > np.abs(b)
    r = np.where(first, a, b)
    with np.errstate(divide="ignore", invalid="ignore"):
        phi = np.where(first, 0.25 * np.pi * b / a, 0.5 * np.pi - 0.25 * np.pi * a / b)
    phi = np.nan_to_num(phi)
    x, y = r * np.cos(phi), r * np.sin(phi)
    z = np.sqrt(np.maximum(0.0, 1.0 - x * x - y * y))
    return x[..., None] * frame[0] + y[..., None] * frame[1] + z[..., None] * frame[2]


def sampling_frame(window_normal) -> np.ndarray:
    """The gather's frame: z up, x the horizontal part of the room's first window's outward normal
    (or +x where it has none: a roof light)."""
    n = np.asarray(window_normal, float)
    x = np.array([n[0], n[1], 0.0])
    x = x / np.linalg.norm(x) if np.linalg.norm(x) > 1e-9 else np.array([1.0, 0.0, 0.0])
    z = np.array([0.0, 0.0, 1.0])
    return np.stack([x, np.cross(z, x), z])


def reflected(octree, points: np.ndarray, sky_lx: float, s: GatherSettings, frame: np.ndarray) -> Reflected:
    """The reflected part of the daylight factor at horizontal ``points`` (p, 3) [m, local] (see the
    module docstring): ``octree`` holds the scene under the CIE overcast sky giving ``sky_lx`` [lx]
    on an unobstructed horizontal plane.
    """
    p = len(points)
    total, sq, count, lit = np.zeros(p), np.zeros(p), np.zeros(p), np.zeros(p)
    if not p:
        return Reflected(total, total.copy(), count.astype(int))
    todo = np.arange(p)
    n = max(1, int(round(np.sqrt(min(s.rays, s.max_rays)))))
    rnd = 0
    args = rtrace_args(s)
    while len(todo):  # a few rounds; each one rtrace call for every point still to do
        rng = np.random.default_rng([SEED, rnd])
        d = cosine_directions(len(todo), n, rng, frame)
        k = n * n
        dirs = d.reshape(-1, 3)
        value, through, dist = radiance.trace(octree, np.repeat(points[todo], k, axis=0), dirs, args)
        sky = (dist >= SKY_DISTANCE_M) & (dirs[:, 2] > 0)
        y = (np.pi / sky_lx) * (value - np.where(sky, through, 0.0))  # each an estimate of R [-]
        y = y.reshape(len(todo), k)
        total[todo] += y.sum(axis=1)
        sq[todo] += (y * y).sum(axis=1)
        count[todo] += k
        lit[todo] += (y > 0).sum(axis=1)
        mean, half = _interval(total[todo], sq[todo], count[todo])
        done = ((half <= np.maximum(s.rel_tolerance * np.abs(mean), s.abs_tolerance)) & ((lit[todo] >= MIN_LIT) | (lit[todo] == count[todo]))
                | (2 * count[todo] > s.max_rays))
        todo = todo[~done]
        n = int(round(np.sqrt(count[todo].max()))) if len(todo) else n  # as many again: n x n new strata
        rnd += 1
    mean, half = _interval(total, sq, count)
    # few lit samples: at least what a Poisson 99.5 % upper bound on their count allows, at Y_MAX each
    few = (lit < MIN_LIT) & (lit < count)
    half = np.where(few, np.maximum(half, Y_MAX * (3.0 * np.sqrt(lit + 1.0) + 3.0) / count), half)
    return Reflected(mean, half, count.astype(int))


def reflected_paths(S, octree, points: np.ndarray, sky_lx: float, s: GatherSettings, frame: np.ndarray,
                    processes: int = 1, known=None, thresholds=()) -> Reflected:
    """The reflected part at horizontal ``points`` (p, 3) [m, local] by light paths with next-event
    estimation through the room's windows (:mod:`.transport`: ``S`` its scene), the luminance of what
    is outside from Radiance (``octree``: the scene under the CIE overcast sky giving ``sky_lx`` on
    an unobstructed horizontal plane). Rounds, intervals and their rules as :func:`reflected`'s,
    with one path per direction; and a point is also done once its daylight factor, ``known`` =
    (value, bound) (p,) [-] (the sky component) plus the reflected part, lies farther than their
    errors from every one of ``thresholds`` [-] (D_T and D_TM of each level): more paths would not
    move it across one. ``known`` may also be a function giving that pair, called once after the first
    round's paths (the sky component computed meanwhile in another thread: the same numbers)."""
    from en17037cli.criteria.daylight.transport import trace_paths

    p = len(points)
    total, sq, count, lit = np.zeros(p), np.zeros(p), np.zeros(p), np.zeros(p)
    if not p:
        return Reflected(total, total.copy(), count.astype(int))
    todo = np.arange(p)
    n = max(1, int(round(np.sqrt(min(s.rays, s.max_rays)))))
    rnd = 0
    args = rtrace_args(s)
    while len(todo):  # a few rounds; each one rtrace call for every point still to do
        rng = np.random.default_rng([SEED, rnd])
        k = n * n
        dirs = cosine_directions(len(todo), n, rng, frame).reshape(-1, 3)
        y, req, touched = trace_paths(S, np.repeat(points[todo], k, axis=0), dirs, S.window_rays, [SEED, rnd, 1])
        o, d, w, path = req.arrays()
        if len(o):
            value, _, _ = radiance.trace(octree, o, d, args, processes)
            y += np.bincount(path, w * value / sky_lx, len(y))
        y = y.reshape(len(todo), k)
        total[todo] += y.sum(axis=1)
        sq[todo] += (y * y).sum(axis=1)
        count[todo] += k
        lit[todo] += touched.reshape(len(todo), k).sum(axis=1)
        mean, half = _interval(total[todo], sq[todo], count[todo])
        trusted = (lit[todo] >= MIN_LIT) | (lit[todo] == 0)
        precise = half <= np.maximum(s.rel_tolerance * np.abs(mean), s.abs_tolerance)
        if known is not None and len(thresholds):
            if callable(known):  # the sky component, once it is there
                known = known()
            d, e = known[0][todo] + mean, known[1][todo] + half
            precise |= np.all(np.abs(d[:, None] - np.asarray(thresholds)[None]) > e[:, None], axis=1)
        done = (precise & trusted) | (2 * count[todo] > s.max_rays)
        todo = todo[~done]
        n = int(round(np.sqrt(count[todo].max()))) if len(todo) else n
        rnd += 1
    return _result(total, sq, count, lit)


def _interval(total, sq, count) -> tuple[np.ndarray, np.ndarray]:
    """Mean and 99 % half-interval z(0.995) s / sqrt(N) of samples from their sums ``total``, sums of
    squares ``sq`` and counts ``count`` (s: the unbiased standard deviation; see the module docstring)."""
    mean = total / count
    var = np.maximum(sq / count - mean * mean, 0.0) * count / np.maximum(count - 1, 1)
    return mean, Z995 * np.sqrt(var / count)


def _result(total, sq, count, lit) -> Reflected:
    """Means and 99 % intervals of the samples' sums (see the module docstring)."""
    mean, half = _interval(total, sq, count)
    few = (lit < MIN_LIT) & (lit > 0)
    half = np.where(few, np.maximum(half, Y_MAX * (3.0 * np.sqrt(lit + 1.0) + 3.0) / count), half)
    return Reflected(mean, half, count.astype(int))
