"""Light paths for the reflected components: the room's interreflection traced here on the ray
engine, with the light that comes in through the glazing taken at every bounce (next-event
estimation), and what is seen outside through the glazing by Radiance.

A path starts at a point p of the reference plane in a cosine-weighted direction (stratified over
the paths of a point, as :func:`~.gather.cosine_directions`). Where it meets an opaque face v of
reflectance ρ (the layer rule's, else the kind's default, :func:`~.radiance.face_optics`):

* it adds W ρ E_w(v): E_w, the illuminance of v straight through the room's windows, estimated by
  ``per_window`` directions per window, stratified over the window's gnomonic rectangle as v sees it
  (weight: the cell's exact solid angle x cos θ_v); a direction whose first hit is the room's
  glazing brings τ(i) L from beyond it: the CIE sky by its formula where nothing is hit above the
  horizon, else what Radiance sees from the glass outwards (obstructions, the ground, the
  facade, the ground's glow below the horizon: a request, :class:`Requests`);
* it goes on with probability ρ (Russian roulette, the weight W unchanged) in a new cosine-weighted
  direction about v's normal;

where it meets the room's glazing it goes on as the glass reflects it (W x ρ_g(i)), its transmitted
part being what the windows' next-event estimates count (for p: the sky component, exact
elsewhere, and the light from outside, a request from p itself); where it meets glazing of
another room, or nothing, what Radiance sees along it ends it (a request). The point's estimate of
the reflected illuminance over the unobstructed horizontal one is the sum over its paths / their number:

    R(p) = 1/N Σ_paths Σ_vertices W ρ_v E_w(v) / E_h  +  the requests' values

Every term is a Monte Carlo estimate with no bias (roulette: Arvo and Kirk 1990; next-event
estimation: the rendering equation split by the directions that leave through the glazing, Kajiya
1986): the paths are independent, so their spread gives each point's interval (:mod:`.gather`).

Where Radiance comes in: the luminance of what is outside (sky-lit obstructions and ground, with
their own interreflections, ``rtrace`` with Russian roulette). Inside, the surfaces are grey and
Lambertian as the Radiance scene's ``plastic`` (no specular part) and the glazing Radiance's
``glass`` (:func:`~.sky.glass_transmittance`, :func:`~.sky.glass_reflectance`): the same physics, traced
where the light through the windows can be aimed at, which Radiance's own ambient sampling cannot
(it finds a window by chance, so that one lit wall in a dark room took thousands of rays a point).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from en17037cli.criteria.daylight.sky import OPEN_TV, cie_overcast_luminance, glass_reflectance, glass_transmittance

#: Unobstructed horizontal illuminance of the CIE overcast sky over its zenith luminance: 7 π / 9.
UNOBSTRUCTED = 7.0 * np.pi / 9.0
#: A path is followed until Russian roulette ends it, at most this many bounces (the chance of a path
#: surviving that long is ρ^1000: 1e-46 in a room of reflectance 0.9; a cap of 24 left 2 % of the
#: light of a room of 0.85 out).
MAX_BOUNCES = 1000


@dataclass
class Requests:
    """Rays whose luminance Radiance gives (``origin``, ``direction``), each adding ``weight`` x
    luminance / E_h to path ``path``; ``sky``: the next-event samples that reached the sky, kept for
    method 2 (``direction``, ``weight`` x luminance of the sky in that direction / E_h, path)."""

    origin: list = field(default_factory=list)
    direction: list = field(default_factory=list)
    weight: list = field(default_factory=list)
    path: list = field(default_factory=list)
    sky_direction: list = field(default_factory=list)
    sky_weight: list = field(default_factory=list)
    sky_path: list = field(default_factory=list)

    def add(self, o, d, w, path):
        keep = w > 0
        self.origin.append(o[keep])
        self.direction.append(d[keep])
        self.weight.append(w[keep])
        self.path.append(path[keep])

    def add_sky(self, d, w, path):
        keep = w > 0
        self.sky_direction.append(d[keep])
        self.sky_weight.append(w[keep])
        self.sky_path.append(path[keep])

    def arrays(self, kind: str = "outside"):
        """The requests (``outside``) or the sky samples (``sky``) as arrays."""
        cols = (self.origin, self.direction, self.weight, self.path) if kind == "outside" else \
            (self.sky_direction, self.sky_weight, self.sky_path)
        shapes = ((0, 3), (0, 3), (0,), (0,)) if kind == "outside" else ((0, 3), (0,), (0,))
        return tuple(np.concatenate(c) if c else np.zeros(s) for c, s in zip(cols, shapes))


class Scene:
    """What the paths need of the scene: the ray engine with the room's windows and every window as
    groups, per face its reflectance, transmittance and normal, per room window its frame."""

    def __init__(self, engine, scene, room, rho: np.ndarray, tv: np.ndarray, frames: list, window_rays: int = 1):
        from en17037cli.geometry import triangle_normals
        from en17037cli.scene.model import WINDOW, room_window_group

        self.engine, self.room_group = engine, room_window_group(room)
        engine.add_group("daylight_windows", scene.layer == WINDOW)
        self.rho, self.tv = rho, tv
        self.normals, _ = triangle_normals(scene.vertices[scene.triangles])
        self.room_window = np.zeros(len(scene.triangles), bool)
        for w in room.windows:
            self.room_window[w.face_ids] = True
        self.frames = frames
        self.window_rays = window_rays

    def hits(self, o, d):
        """First hits: (kind, face, distance): kind 0 nothing, 1 opaque, 2 the room's glazing, 3 other glazing."""
        e = self.engine
        f_o, t_o = e.first_hit("opaque", o, d)
        f_w, t_w = e.first_hit("daylight_windows", o, d)
        glass = (f_w >= 0) & (t_w < t_o)
        kind = np.where(glass, np.where(self.room_window[np.maximum(f_w, 0)], 2, 3), np.where(f_o >= 0, 1, 0))
        return kind, np.where(glass, f_w, f_o), np.where(glass, t_w, t_o)


def _frame(n: np.ndarray) -> np.ndarray:
    """(m, 3, 3) orthonormal frames (x, y, z) with z = n."""
    t = np.where(np.abs(n[:, [0]]) < 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]))
    x = np.cross(n, t)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    return np.stack([x, np.cross(n, x), n], axis=1)


def cosine_about(n: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """One cosine-weighted direction about each unit normal of ``n`` (m, 3) (Malley's method)."""
    u, v = rng.random(len(n)), rng.random(len(n))
    r, phi = np.sqrt(u), 2.0 * np.pi * v
    f = _frame(n)
    return (r * np.cos(phi))[:, None] * f[:, 0] + (r * np.sin(phi))[:, None] * f[:, 1] + np.sqrt(1.0 - u)[:, None] * f[:, 2]


def window_estimate(S: Scene, v: np.ndarray, nv: np.ndarray, weight: np.ndarray, path: np.ndarray, per_window: int,
                    rng: np.random.Generator, req: Requests, sky_too: bool = True) -> np.ndarray:
    """(m,) the part of ``weight`` x E_w(v) / E_h that the sky gives directly (CIE, exact per sample),
    and requests for the rest (see the module docstring). ``sky_too`` False leaves the sky out (at
    the reference plane: its sky component is exact elsewhere)."""
    out = np.zeros(len(v))
    k = max(1, int(round(np.sqrt(per_window))))
    for f in S.frames:  # the room's windows, a few; each vectorised over the vertices
        r = v - f.origin
        dist = -(r @ f.n)
        front = np.flatnonzero(dist > 1e-6)
        if not len(front):
            continue
        x0, y0, dd = r[front] @ f.u, r[front] @ f.v, dist[front]
        a0, a1 = np.arctan((f.xmin - x0) / dd), np.arctan((f.xmax - x0) / dd)
        b0, b1 = np.arctan((f.ymin - y0) / dd), np.arctan((f.ymax - y0) / dd)
        i, j = np.divmod(np.arange(k * k), k)
        A = a0[:, None] + (a1 - a0)[:, None] * (i[None] + rng.random((len(front), k * k))) / k
        B = b0[:, None] + (b1 - b0)[:, None] * (j[None] + rng.random((len(front), k * k))) / k
        X, Y = np.tan(A), np.tan(B)
        s = np.sqrt(1.0 + X * X + Y * Y)
        d = ((X[..., None] * f.u + Y[..., None] * f.v + f.n) / s[..., None]).reshape(-1, 3)
        dw = ((1.0 + X * X) * (1.0 + Y * Y) / s**3 * ((a1 - a0) * (b1 - b0))[:, None] / (k * k)).ravel()
        idx = np.repeat(front, k * k)
        w = weight[idx] * dw * np.maximum(np.einsum("ij,ij->i", d, nv[idx]), 0.0)
        o = v[idx]
        kind, face, t = S.hits(o, d)
        through = np.flatnonzero((kind == 2) & (w > 0))  # straight through the room's glazing
        if not len(through):
            continue
        ft = face[through]
        cos_i = np.abs(np.einsum("ij,ij->i", d[through], S.normals[ft]))
        tau = glass_transmittance(cos_i, S.tv[ft])
        g = o[through] + d[through] * t[through, None]
        g = g + d[through] * S.engine.restart_offset(g)[:, None]
        f_o, _ = S.engine.first_hit("opaque", g, d[through])
        sky = (f_o < 0) & (d[through, 2] > 0)
        wt = w[through] * tau
        if sky_too:
            lum = 9.0 / (7.0 * np.pi) * cie_overcast_luminance(np.arcsin(np.clip(d[through, 2], 0.0, 1.0)))
            np.add.at(out, idx[through], np.where(sky, wt * lum, 0.0))
            req.add_sky(d[through], np.where(sky, wt, 0.0), path[idx[through]])
        req.add(g, d[through], np.where(sky, 0.0, wt), path[idx[through]])
    return out


def trace_paths(S: Scene, points: np.ndarray, dirs: np.ndarray, per_window: int, seed) -> tuple[np.ndarray, Requests, np.ndarray]:
    """Follow one path per row of ``dirs`` (n, 3) from ``points`` (n, 3) (see the module docstring).

    Returns
    -------
    sky : (n,) [-] what each path gathered from the sky straight through the glazing, over E_h
    requests : what Radiance must say (outside luminance along rays), per path
    touched : (n,) bool, the path met a surface that reflects (or light from outside through
        the glazing): its value could be other than 0
    """
    n = len(points)
    rng = np.random.default_rng(seed)
    req = Requests()
    path = np.arange(n)
    total = np.zeros(n)
    # at the point: the light from outside through the glazing (its sky is the sky component)
    up = np.tile([0.0, 0.0, 1.0], (n, 1))
    window_estimate(S, points, up, np.ones(n), path, per_window, rng, req, sky_too=False)
    o, d, w = points.copy(), dirs.copy(), np.ones(n)
    touched = np.zeros(n, bool)
    for _ in range(MAX_BOUNCES):  # bounces: each vectorised over the paths still alive
        if not len(path):
            break
        kind, face, t = S.hits(o, d)
        hit = o + d * np.where(np.isfinite(t), t, 0.0)[:, None]
        end = (kind == 0) | (kind == 3)  # nothing, or another room's glazing: what Radiance sees along it
        req.add(o[end], d[end], np.pi * w[end], path[end])  # π L: the cosine-weighted estimate of what it lights
        touched[path[end]] = True
        glass = np.flatnonzero(kind == 2)
        if len(glass):  # the room's glazing: the glass's reflection goes on
            nrm = S.normals[face[glass]]
            cos_i = np.einsum("ij,ij->i", d[glass], nrm)
            w[glass] *= np.where(S.tv[face[glass]] >= OPEN_TV, 0.0, glass_reflectance(np.abs(cos_i), S.tv[face[glass]]))
            d[glass] = d[glass] - 2.0 * cos_i[:, None] * nrm
            o[glass] = hit[glass] + d[glass] * S.engine.restart_offset(hit[glass])[:, None]
        opq = np.flatnonzero(kind == 1)
        if len(opq):  # a surface: the windows' light on it, then on (with probability ρ)
            nrm = S.normals[face[opq]]
            nrm = np.where((np.einsum("ij,ij->i", nrm, d[opq]) > 0)[:, None], -nrm, nrm)
            rho = S.rho[face[opq]]
            touched[path[opq]] |= rho > 0
            v = hit[opq] + nrm * S.engine.restart_offset(hit[opq])[:, None]
            total += np.bincount(path[opq], window_estimate(S, v, nrm, w[opq] * rho, path[opq], per_window, rng, req), n)
            live = rng.random(len(opq)) < rho
            d[opq] = np.where(live[:, None], cosine_about(nrm, rng), d[opq])
            o[opq] = v
            w[opq] = np.where(live, w[opq], 0.0)
        keep = np.flatnonzero(((kind == 1) | (kind == 2)) & (w > 0))
        path, o, d, w = path[keep], o[keep], d[keep], w[keep]
    o_req, _, _, p_req = req.arrays()
    touched[p_req] = True
    return total, req, touched
