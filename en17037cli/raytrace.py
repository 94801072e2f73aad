"""Ray engine: Embree scenes per face group, queried in float32 chunks on all cores.

Embree has no ray masks and no tnear in embreex, so transparency is handled with one scene per
group of faces (``window``, ``interior``, ``outdoor`` = landscape + ground, ``landscape``,
``sun`` = every opaque face that blocks the sun). Each is built on first use and shared by every
check and room of the run. Geometry arrives already shifted to a local origin in float64
(:mod:`en17037cli.scene`), so the float32 cast loses nothing that matters near the rooms.
"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from en17037cli.geometry import check_shape
from en17037cli.scene import GROUND, INTERIOR, LANDSCAPE, WINDOW

#: A point lying on a glazing plane is moved this far into the room before rays start from it [m].
GLAZING_OFFSET_M = 1e-3

#: Rays per embreex call; large enough to amortise the call, small enough to share two cores.
CHUNK = 1 << 16

GROUPS = {
    "window": lambda s: s.layer == WINDOW,
    "interior": lambda s: s.layer == INTERIOR,
    "outdoor": lambda s: (s.layer == LANDSCAPE) | (s.layer == GROUND),
    "landscape": lambda s: s.layer == LANDSCAPE,
    "sun": lambda s: (s.layer != WINDOW) & s.obstructs_sun,
}


class RayEngine:
    """First-hit and occlusion queries against groups of a :class:`~en17037cli.scene.Scene`.

    Parameters
    ----------
    scene : Scene
    threads : int, optional
        Worker threads (embreex releases the GIL); default: the machine's cores.
    """

    def __init__(self, scene, threads: int | None = None):
        self.scene = scene
        self.threads = max(1, threads or os.cpu_count() or 1)
        self._groups: dict = {}
        self.rays_traced = 0
        self._pool = ThreadPoolExecutor(self.threads) if self.threads > 1 else None

    def close(self):
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None

    def _group(self, name: str):
        """(embree scene or None, face ids of the group) built on first use."""
        if name not in self._groups:
            from embreex import rtcore_scene as rtcs
            from embreex.mesh_construction import TriangleMesh

            faces = np.flatnonzero(GROUPS[name](self.scene))
            if len(faces) == 0:
                self._groups[name] = (None, faces)
            else:
                es = rtcs.EmbreeScene()
                tris = self.scene.vertices[self.scene.triangles[faces]].astype(np.float32)
                TriangleMesh(es, tris)
                self._groups[name] = (es, faces)
        return self._groups[name]

    def _map(self, fn, n: int):
        bounds = [(a, min(a + CHUNK, n)) for a in range(0, n, CHUNK)]
        if self._pool is None or len(bounds) == 1:
            return [fn(a, b) for a, b in bounds]
        return list(self._pool.map(lambda ab: fn(*ab), bounds))

    def first_hit(self, group: str, origins, directions) -> tuple[np.ndarray, np.ndarray]:
        """Nearest hit of each ray with the faces of ``group``.

        Parameters
        ----------
        origins : (n, 3) float [m], local frame
        directions : (n, 3) float, unit vectors

        Returns
        -------
        face : (n,) int, index into ``scene.triangles`` (-1 where nothing is hit)
        distance : (n,) float64 [m] along the ray (+inf where nothing is hit)
        """
        origins = check_shape("origins", origins, (None, 3))
        directions = check_shape("directions", directions, (len(origins), 3))
        n = len(origins)
        face = np.full(n, -1, dtype=np.int64)
        dist = np.full(n, np.inf)
        es, faces = self._group(group)
        if es is None or n == 0:
            return face, dist
        o32 = np.ascontiguousarray(origins, dtype=np.float32)
        d32 = np.ascontiguousarray(directions, dtype=np.float32)

        def run(a, b):
            r = es.run(o32[a:b], d32[a:b], output=1)
            hit = r["primID"] >= 0
            face[a:b] = np.where(hit, faces[np.maximum(r["primID"], 0)], -1)
            dist[a:b] = np.where(hit, r["tfar"].astype(np.float64), np.inf)

        self._map(run, n)
        self.rays_traced += n
        return face, dist

    def occluded(self, group: str, origins, directions) -> np.ndarray:
        """Whether each ray hits any face of ``group`` (an occlusion query, cheaper than a first hit).

        Returns
        -------
        (n,) bool
        """
        origins = check_shape("origins", origins, (None, 3))
        directions = check_shape("directions", directions, (len(origins), 3))
        n = len(origins)
        out = np.zeros(n, dtype=bool)
        es, _ = self._group(group)
        if es is None or n == 0:
            return out
        o32 = np.ascontiguousarray(origins, dtype=np.float32)
        d32 = np.ascontiguousarray(directions, dtype=np.float32)

        def run(a, b):
            out[a:b] = es.run(o32[a:b], d32[a:b], query="OCCLUDED") != -1

        self._map(run, n)
        self.rays_traced += n
        return out

    def layer_of(self, face: np.ndarray) -> np.ndarray:
        """Layer code of each face index (-1 where face is -1)."""
        return np.where(face >= 0, self.scene.layer[np.maximum(face, 0)], -1)


#: Classes of a direction seen from inside a room.
BLOCKED, SKY, LANDSCAPE_HIT, GROUND_HIT = 0, 1, 2, 3


def trace_through_windows(engine: RayEngine, origins, directions):
    """Where each ray from inside a room goes: through which window and onto which layer.

    A ray *leaves through a window* when it reaches a window face before any opaque face and
    the first opaque face beyond the glazing is not ``interior`` (outer reveals, frames and the
    room's own walls block). Beyond the glazing it hits ``landscape``, ``ground``, or nothing:
    sky when it points upwards, ground when it leaves the model below the horizon.

    Parameters
    ----------
    origins : (n, 3) float [m]; directions : (n, 3) unit

    Returns
    -------
    cls : (n,) int8, BLOCKED / SKY / LANDSCAPE_HIT / GROUND_HIT
    window_face : (n,) int, the window face crossed (-1 if blocked)
    outside_distance : (n,) float [m] along the ray to the outdoor hit (+inf if none)
    glass_distance : (n,) float [m] along the ray to the window face (+inf if blocked)
    """
    n = len(origins)
    cls = np.zeros(n, dtype=np.int8)
    wface = np.full(n, -1, dtype=np.int64)
    odist = np.full(n, np.inf)
    gdist = np.full(n, np.inf)
    f_g, t_g = engine.first_hit("window", origins, directions)
    cand = np.flatnonzero(f_g >= 0)
    if len(cand) == 0:
        return cls, wface, odist, gdist
    o, d = origins[cand], directions[cand]
    _, t_i = engine.first_hit("interior", o, d)
    before = t_g[cand] < t_i
    cand, o, d, t_i = cand[before], o[before], d[before], t_i[before]
    f_o, t_o = engine.first_hit("outdoor", o, d)
    ok = (t_g[cand] < t_o) & (t_i >= t_o)  # no outdoor face before the glass; no interior face before the outdoor hit
    cand, d, f_o, t_o = cand[ok], d[ok], f_o[ok], t_o[ok]
    layer = engine.layer_of(f_o)
    cls[cand] = np.where(layer == LANDSCAPE, LANDSCAPE_HIT,
                         np.where(layer == GROUND, GROUND_HIT, np.where(d[:, 2] < 0, GROUND_HIT, SKY)))
    wface[cand] = f_g[cand]
    odist[cand] = t_o
    gdist[cand] = t_g[cand]
    return cls, wface, odist, gdist
