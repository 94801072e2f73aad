"""Ray engine: Embree scenes per face group, queried in float32 chunks on all cores.

Embree has no ray masks and no tnear in embreex, so transparency is handled with one scene per
group of faces: ``opaque`` (every face that is not glazing), ``interior``, ``landscape``,
``sun`` (every opaque face that blocks the sun; the ``opaque`` scene itself when no face is
left out) and one small scene per room holding that room's windows. Each is built on first use
and shared by every check and room of the run. Geometry arrives already shifted to a local origin
in float64 (:mod:`en17037cli.scene`), so the float32 cast loses nothing that matters near the
rooms.
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
CHUNK = 1 << 15

#: Classes of a direction seen from inside a room.
BLOCKED, SKY, LANDSCAPE_HIT, GROUND_HIT = 0, 1, 2, 3

GROUPS = {
    "opaque": lambda s: s.layer != WINDOW,
    "interior": lambda s: s.layer == INTERIOR,
    "landscape": lambda s: s.layer == LANDSCAPE,
    "sun": lambda s: (s.layer != WINDOW) & s.obstructs_sun,
}


def room_window_group(room) -> str:
    """Name of the engine group holding the window faces of ``room`` (one per room, set up by :class:`RayEngine`)."""
    return f"windows of room {room.index}"


class RayEngine:
    """First-hit and occlusion queries against groups of faces of a :class:`~en17037cli.scene.Scene`.

    Parameters
    ----------
    scene : Scene
    threads : int, optional
        Worker threads (embreex's loop runs without the GIL); default: the machine's cores.
    """

    def __init__(self, scene, threads: int | None = None):
        self.scene = scene
        self.threads = max(1, threads or os.cpu_count() or 1)
        self._faces = {name: None for name in GROUPS}
        for room in scene.rooms:
            self._faces[room_window_group(room)] = np.concatenate([w.face_ids for w in room.windows])
        self._groups: dict = {}
        #: class of a ray whose first opaque face beyond the glazing is each face (see outside_class)
        self.face_class = np.select([scene.layer == LANDSCAPE, scene.layer == GROUND], [LANDSCAPE_HIT, GROUND_HIT],
                                    BLOCKED).astype(np.int8)
        self.rays_traced = 0
        self.build_s = 0.0
        self._pool = ThreadPoolExecutor(self.threads) if self.threads > 1 else None

    def close(self):
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None

    def prepare(self, names) -> None:
        """Build the acceleration structures of ``names`` now (otherwise on first use)."""
        for name in names:
            self._group(name)

    def faces(self, name: str) -> np.ndarray:
        """Face ids of group ``name`` (sorted)."""
        f = self._faces[name]
        if f is None:
            f = self._faces[name] = np.flatnonzero(GROUPS[name](self.scene))
        return f

    def _group(self, name: str):
        """(embree scene or None, face ids of the group), built on first use; identical groups share one scene."""
        if name not in self._groups:
            import time

            from embreex import rtcore_scene as rtcs
            from embreex.mesh_construction import TriangleMesh

            t = time.perf_counter()
            faces = self.faces(name)
            twin = next((g for g in self._groups.values() if len(g[1]) == len(faces) and np.array_equal(g[1], faces)), None)
            if twin is not None:
                self._groups[name] = twin
            elif len(faces) == 0:
                self._groups[name] = (None, faces)
            else:
                es = rtcs.EmbreeScene()
                TriangleMesh(es, self.scene.vertices[self.scene.triangles[faces]].astype(np.float32))
                es.run(np.zeros((1, 3), np.float32), np.ones((1, 3), np.float32))  # commit (builds the BVH) now
                self._groups[name] = (es, faces)
            self.build_s += time.perf_counter() - t
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
            prim = r["primID"]
            hit = prim >= 0
            face[a:b] = np.where(hit, faces[np.maximum(prim, 0)], -1)
            dist[a:b] = np.where(hit, r["tfar"], np.inf)

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


def outside_class(engine: RayEngine, face: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Class of rays whose first opaque face beyond the glazing is ``face`` (-1: none).

    ``interior`` beyond the glazing (outer reveals, frames, the building's own walls) blocks;
    ``landscape`` and ``ground`` are seen; a ray that meets nothing is sky when it points upwards
    and ground when it leaves the model below the horizon.

    Returns
    -------
    (n,) int8, BLOCKED / SKY / LANDSCAPE_HIT / GROUND_HIT
    """
    cls = engine.face_class[np.maximum(face, 0)]
    none = face < 0
    cls[none] = np.where(directions[none, 2] < 0, GROUND_HIT, SKY)
    return cls


def trace_through_windows(engine: RayEngine, window_group: str, origins, directions):
    """Where each ray from inside a room goes: through which window and onto which layer.

    A ray *leaves through a window* when it reaches a face of ``window_group`` (the room's
    windows) before any opaque face, and the first opaque face beyond the glazing is not
    ``interior`` (see :func:`outside_class`). Two queries per ray: the room's windows (a scene
    of a few triangles) and the opaque faces.

    Parameters
    ----------
    window_group : str, e.g. :func:`room_window_group` (room)
    origins : (n, 3) float [m]; directions : (n, 3) unit

    Returns
    -------
    cls : (n,) int8, BLOCKED / SKY / LANDSCAPE_HIT / GROUND_HIT
    window_face : (n,) int, the window face crossed (-1 if blocked)
    outside_face : (n,) int, the first opaque face beyond the glazing (-1 if none or blocked)
    outside_distance : (n,) float [m] along the ray to that face (+inf if none)
    glass_distance : (n,) float [m] along the ray to the window face (+inf if blocked)
    """
    n = len(origins)
    cls = np.zeros(n, dtype=np.int8)
    wface = np.full(n, -1, dtype=np.int64)
    oface = np.full(n, -1, dtype=np.int64)
    odist = np.full(n, np.inf)
    gdist = np.full(n, np.inf)
    f_g, t_g = engine.first_hit(window_group, origins, directions)
    cand = np.flatnonzero(f_g >= 0)
    if len(cand) == 0:
        return cls, wface, oface, odist, gdist
    f_o, t_o = engine.first_hit("opaque", origins[cand], directions[cand])
    ok = t_g[cand] < t_o
    cand, f_o, t_o = cand[ok], f_o[ok], t_o[ok]
    c = outside_class(engine, f_o, directions[cand])
    cls[cand] = c
    keep = cand[c != BLOCKED]
    wface[keep] = f_g[keep]
    oface[keep] = f_o[c != BLOCKED]
    odist[keep] = t_o[c != BLOCKED]
    gdist[keep] = t_g[keep]
    return cls, wface, oface, odist, gdist
