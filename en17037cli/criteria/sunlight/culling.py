"""Which faces can lie between a point P and the sun over a period (for the exact sun intervals,
:mod:`.exact`): a conservative cull by bounds on each face's spherical triangle seen from P.

A face is dropped only when its whole image from P misses one of: the half-space in front of the
window's plane, the pyramid from P over one of the room's windows, the band of the period's
declinations, or the sky above the minimum altitude; so no face that can occlude is dropped.
"""
from __future__ import annotations

import numpy as np

from en17037cli.geometry import window_axes

#: Angular slack [rad] of the culling tests and of the arc test (float round-off, interpolant error).
ANGLE_SLACK = 1e-6

def spherical_extent(u: np.ndarray, axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Smallest and largest ``axis . x`` over the spherical triangles with corners ``u`` (T, 3, 3)
    (directions from P, not necessarily unit), ``axis`` (3,) unit.

    The extremes lie at a corner, at the extreme point of an edge's great circle where it falls
    inside the arc, or at +-axis itself where it lies inside the triangle.
    """
    uu = u / np.maximum(np.linalg.norm(u, axis=2, keepdims=True), 1e-300)
    vals = uu @ axis  # (T, 3)
    lo, hi = vals.min(axis=1), vals.max(axis=1)
    inside = []
    for i in range(3):  # the three edges of each triangle
        p, q = uu[:, i], uu[:, (i + 1) % 3]
        m = np.cross(p, q)
        mn = np.linalg.norm(m, axis=1)
        ok = mn > 1e-12
        mh = m / np.maximum(mn, 1e-300)[:, None]
        x = axis[None, :] - (mh @ axis)[:, None] * mh
        xn = np.linalg.norm(x, axis=1)
        x = x / np.maximum(xn, 1e-300)[:, None]
        for sign in (1.0, -1.0):
            xs = sign * x
            on = ok & (xn > 1e-12) & (np.einsum("ij,ij->i", np.cross(p, xs), m) >= 0) & (np.einsum("ij,ij->i", np.cross(xs, q), m) >= 0)
            v = sign * xn
            hi = np.where(on & (v > hi), v, hi)
            lo = np.where(on & (v < lo), v, lo)
        inside.append(np.einsum("ij,j->i", m, axis))
    side = np.stack(inside, axis=1)
    contains = np.all(side >= 0, axis=1) | np.all(side <= 0, axis=1)  # +axis or -axis inside the triangle
    plus = contains & (np.einsum("tij,j->t", uu, axis) > 0)
    hi = np.where(contains & plus, 1.0, hi)
    lo = np.where(contains & ~plus, -1.0, lo)
    return lo, hi


def window_pyramid(p: np.ndarray, windows) -> np.ndarray:
    """Inward normals (w, 4, 3) of the four side planes of the pyramid from ``p`` over each window's
    bounding rectangle in its own plane (the rays that can reach the window lie inside)."""
    out = []
    for w in windows:  # the room's few windows
        a, up = window_axes(w.normal)
        v = w.triangles.reshape(-1, 3)
        sa, su = v @ a, v @ up
        c = w.centroid
        base = c - (c @ a) * a - (c @ up) * up
        corners = [base + x * a + y * up for x, y in ((sa.min(), su.min()), (sa.max(), su.min()),
                                                       (sa.max(), su.max()), (sa.min(), su.max()))]
        g = np.array([np.cross(corners[i] - p, corners[(i + 1) % 4] - p) for i in range(4)])
        g *= np.sign(g @ (c - p))[:, None]
        out.append(g)
    return np.array(out).reshape(-1, 4, 3)


def cull_triangles(vertices: np.ndarray, triangles: np.ndarray, faces: np.ndarray, p: np.ndarray, normal: np.ndarray,
                   pyramids: np.ndarray, pole: np.ndarray, sin_dec: tuple[float, float], sin_min_alt: float) -> np.ndarray:
    """The faces (ids into ``triangles``) that can lie between ``p`` and the sun through a window.

    A face is dropped only when its spherical image from ``p`` certainly misses one of: the half
    space in front of the window's plane, the pyramid over one of the windows (``pyramids``, from
    :func:`window_pyramid`), the sun's band of declinations ``sin_dec`` (sines, about ``pole``) and
    the cap above the minimum altitude.
    """
    if len(faces) == 0:
        return faces
    rel = vertices - p
    dist = np.linalg.norm(rel, axis=1)
    eps = ANGLE_SLACK * dist
    tri = triangles[faces]
    # linear tests per vertex, as bits: a face is outside a plane through p when all three corners are
    front = rel @ normal > -eps
    if len(pyramids) == 0:
        keep = front[tri].any(axis=1)
    else:
        keep = np.zeros(len(faces), bool)
        for g in pyramids:  # one pyramid per window of the room: bit 0 in front, bits 1-4 inside each side
            bits = front.astype(np.uint8)
            for i, gi in enumerate(g):
                bits |= (rel @ (gi / np.linalg.norm(gi)) > -eps).astype(np.uint8) << (i + 1)
            corner = bits[tri]
            keep |= (corner[:, 0] | corner[:, 1] | corner[:, 2]) == 0b11111
    cand, tri = faces[keep], tri[keep]
    if len(cand) == 0:
        return cand
    # a quick bound first: the spherical triangle lies in the cap about its first corner through the
    # farthest corner (a cap under 90 deg is convex), so altitude and declination stay within that
    # radius of the first corner's
    unit = rel / np.maximum(dist, 1e-300)[:, None]
    alt = np.arcsin(np.clip(unit[:, 2], -1, 1))
    dec = np.arcsin(np.clip(unit @ pole, -1, 1))
    u0 = unit[tri[:, 0]]
    chord = np.maximum(np.linalg.norm(unit[tri[:, 1]] - u0, axis=1), np.linalg.norm(unit[tri[:, 2]] - u0, axis=1))
    r = 2 * np.arcsin(np.clip(chord / 2, 0, 1)) + ANGLE_SLACK
    a0, d0 = alt[tri[:, 0]], dec[tri[:, 0]]
    sin_lo, sin_hi = np.arcsin(np.clip(sin_dec[0], -1, 1)), np.arcsin(np.clip(sin_dec[1], -1, 1))
    close = dist[tri].min(axis=1) <= 1e-9
    maybe = close | (r >= np.pi / 2) | ((a0 + r >= np.arcsin(sin_min_alt)) & (d0 + r >= sin_lo) & (d0 - r <= sin_hi))
    cand = cand[maybe]
    if len(cand) == 0:
        return cand
    u = rel[triangles[cand]]
    _, zhi = spherical_extent(u, np.array([0.0, 0.0, 1.0]))
    dlo, dhi = spherical_extent(u, pole)
    ok = (zhi >= sin_min_alt - ANGLE_SLACK) & (dhi >= sin_dec[0] - ANGLE_SLACK) & (dlo <= sin_dec[1] + ANGLE_SLACK)
    return cand[ok]


def triangle_edges(triangles: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """The distinct edges (k, 2) (vertex ids) of ``faces``."""
    t = triangles[faces]
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    e.sort(axis=1)
    return np.unique(e, axis=0) if len(e) else e.reshape(0, 2)
