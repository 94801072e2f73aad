"""Ray engine: first-hit and occlusion queries against named groups of faces, in float32 chunks on all cores.

Embree has no ray masks and no tnear in embreex, so transparency is handled by the caller with
one group (one Embree scene) per set of faces it needs: the pipeline registers ``opaque``,
``interior``, ``landscape``, ``sun`` and one group per room's windows (see
:meth:`~en17037cli.scene.model.Scene.face_groups`). Each group is built on first use (or by
:meth:`RayEngine.prepare`) and shared by every check and room of a run; groups with identical
faces share one scene. The engine knows nothing of layers or rooms.

Geometry arrives already shifted to a local origin in float64 (:mod:`en17037cli.scene`), so the
float32 cast loses nothing that matters near the rooms (see trimesh/ray/ray_pyembree.py).
"""
from __future__ import annotations

import os
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from en17037cli.geometry import check_shape

#: Environment variable that sets the default thread count of every engine (a batch worker's share
#: of the cores, or a CI runner's): a positive whole number.
THREADS_ENV = "EN17037_THREADS"

#: Rays per embreex call; large enough to amortise the call, small enough to share two cores.
CHUNK = 1 << 15

#: Smallest distance a ray restarts beyond a surface it hit [m] ...
MIN_RESTART_OFFSET_M = 1e-4
#: ... and, far from the local origin, this many float32 units of the point's largest coordinate.
RESTART_OFFSET_ULPS = 16


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the system tells, else every core)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def default_threads() -> int:
    """Threads of an engine given none: :data:`THREADS_ENV` where set, else :func:`available_cores`."""
    raw = os.environ.get(THREADS_ENV, "").strip()
    if not raw:
        return available_cores()
    if not raw.isdigit() or int(raw) < 1:
        from en17037cli.errors import InputError

        raise InputError(f"{THREADS_ENV}={raw}: not a positive whole number; unset it or give the ray-tracing threads, e.g. 2")
    return int(raw)


#: Embree's enums (embree4/rtcore_geometry.h, rtcore_buffer.h, rtcore_common.h).
_RTC_GEOMETRY_TYPE_TRIANGLE, _RTC_BUFFER_TYPE_INDEX, _RTC_BUFFER_TYPE_VERTEX = 0, 0, 1
_RTC_FORMAT_UINT3, _RTC_FORMAT_FLOAT3 = 0x5003, 0x9003

_EMBREE: list = []  # [ctypes library or None, offsets of (scene pointer, device object) in an EmbreeScene], found once


def _embree_c():
    """Embree's C library as embreex loaded it (ctypes), and where an ``EmbreeScene`` keeps its
    ``RTCScene``; None where any check of that layout fails."""
    if _EMBREE:
        return _EMBREE[0]
    _EMBREE.append(None)
    try:
        import ctypes
        import glob
        import sys

        import embreex
        from embreex import rtcore as rtc
        from embreex import rtcore_scene as rtcs

        libs = sorted(glob.glob(os.path.join(os.path.dirname(os.path.dirname(embreex.__file__)), "embreex.libs", "libembree4*.so*")))
        if len(libs) != 1:
            return None
        lib = ctypes.CDLL(libs[0])  # the same copy the extension loaded (same path)
        vp = ctypes.c_void_p
        for name, res, args in (("rtcGetSceneDevice", vp, [vp]), ("rtcReleaseDevice", None, [vp]),
                                ("rtcNewGeometry", vp, [vp, ctypes.c_int]),
                                ("rtcSetNewGeometryBuffer", vp, [vp, ctypes.c_int, ctypes.c_uint, ctypes.c_int, ctypes.c_size_t,
                                                                  ctypes.c_size_t]),
                                ("rtcCommitGeometry", None, [vp]), ("rtcAttachGeometry", ctypes.c_uint, [vp, vp]),
                                ("rtcReleaseGeometry", None, [vp])):
            fn = getattr(lib, name)
            fn.restype, fn.argtypes = res, args
        # Cython's layout of EmbreeScene (rtcore_scene.pxd): object header, RTCScene scene_i,
        # int is_committed, EmbreeDevice device; and of EmbreeDevice: header, RTCDevice device.
        # Every field is checked against what it must hold before the scene pointer is used.
        head = object.__basicsize__
        dev = rtc.EmbreeDevice()
        es = rtcs.EmbreeScene(dev)
        if sys.getsizeof(es) < head + 24 or sys.getsizeof(dev) < head + 8:
            return None
        if vp.from_address(id(es) + head + 16).value != id(dev):
            return None
        es.is_committed = 12345
        ok = ctypes.c_int.from_address(id(es) + head + 8).value == 12345
        es.is_committed = 0
        scene = vp.from_address(id(es) + head).value
        device = vp.from_address(id(dev) + head).value
        if not ok or not scene or not device:
            return None
        got = lib.rtcGetSceneDevice(scene)  # retains the device
        lib.rtcReleaseDevice(got)
        if got != device:
            return None
        _EMBREE[0] = (lib, head)
    except Exception:  # any surprise: embreex's own (slower) constructor
        return None
    return _EMBREE[0]


def add_triangles(es, tri32: np.ndarray) -> bool:
    """Add triangles ``tri32`` (m, 3, 3) float32 [m] to embreex scene ``es`` as one Embree geometry,
    filling Embree's vertex and index buffers with numpy (as embreex's ``TriangleMesh`` lays them
    out, 3 vertices per triangle, so hits and primitive ids are the same); False when Embree's C
    library cannot be reached (then call ``TriangleMesh``).

    embreex's ``TriangleMesh`` copies every coordinate through a Python-level index of an untyped
    array (about 1.2 s per million triangles); this is a copy of a contiguous block.
    """
    found = _embree_c()
    if found is None:
        return False
    import ctypes

    lib, head = found
    m = len(tri32)
    scene = ctypes.c_void_p.from_address(id(es) + head).value
    device = lib.rtcGetSceneDevice(scene)
    lib.rtcReleaseDevice(device)  # the scene holds it
    geom = lib.rtcNewGeometry(device, _RTC_GEOMETRY_TYPE_TRIANGLE)
    pv = lib.rtcSetNewGeometryBuffer(geom, _RTC_BUFFER_TYPE_VERTEX, 0, _RTC_FORMAT_FLOAT3, 16, 3 * m)
    pi = lib.rtcSetNewGeometryBuffer(geom, _RTC_BUFFER_TYPE_INDEX, 0, _RTC_FORMAT_UINT3, 12, m)
    if not pv or not pi:
        lib.rtcReleaseGeometry(geom)
        return False
    vbuf = np.ctypeslib.as_array((ctypes.c_float * (12 * m)).from_address(pv)).reshape(3 * m, 4)
    vbuf[:, :3] = tri32.reshape(3 * m, 3)
    vbuf[:, 3] = 0.0
    np.ctypeslib.as_array((ctypes.c_uint32 * (3 * m)).from_address(pi))[:] = np.arange(3 * m, dtype=np.uint32)
    lib.rtcCommitGeometry(geom)
    lib.rtcAttachGeometry(scene, geom)
    lib.rtcReleaseGeometry(geom)
    return True


class RayEngine:
    """First-hit and occlusion queries against named groups of faces.

    Parameters
    ----------
    vertices : (n, 3) float [m], local frame
    triangles : (m, 3) int
    groups : mapping name -> (m,) bool mask or face ids (or a callable returning either)
    threads : int, optional
        Worker threads (embreex's loop runs without the GIL); default: :func:`default_threads`
        (``EN17037_THREADS``, else the cores available). Results do not depend on it.

    Use as a context manager, or call :meth:`close`, to stop the worker threads.
    """

    def __init__(self, vertices: np.ndarray, triangles: np.ndarray, groups: dict | None = None, threads: int | None = None):
        self.vertices = vertices
        self.triangles = triangles
        self.threads = max(1, threads or default_threads())
        self._spec: dict = {}
        self._faces: dict[str, np.ndarray] = {}
        self._groups: dict = {}
        for name, faces in (groups or {}).items():
            self.add_group(name, faces)
        self.rays_traced = 0
        self._count_lock = threading.Lock()
        self._build_lock = threading.RLock()  # a group is built once when two threads ask for it at once
        self._pool = ThreadPoolExecutor(self.threads) if self.threads > 1 else None

    def __enter__(self) -> RayEngine:
        return self

    def __exit__(self, exc_type, *exc) -> None:
        self.close(wait=exc_type is None)

    def close(self, wait: bool = True) -> None:
        """End the threads. Tasks still queued are cancelled (a run interrupted by Ctrl-C or SIGTERM
        while :meth:`map_tasks` had a building's worth of tasks queued waited for all of them, tens
        of seconds: issue 43); ``wait``: for the ones running to finish their chunk (False when an
        exception ends the run: it does not need their answers)."""
        if self._pool is not None:
            self._pool.shutdown(wait=wait, cancel_futures=True)
            self._pool = None

    def add_group(self, name: str, faces: np.ndarray | Callable[[], np.ndarray]) -> None:
        """Register group ``name``: a boolean face mask, face ids, or a callable giving either."""
        self._spec[name] = faces
        self._faces.pop(name, None)
        self._groups.pop(name, None)

    def faces(self, name: str) -> np.ndarray:
        """Face ids of group ``name`` (sorted)."""
        if name not in self._faces:
            f = self._spec[name]
            f = np.asarray(f() if callable(f) else f)
            self._faces[name] = np.flatnonzero(f) if f.dtype == bool else f.astype(np.int64)
        return self._faces[name]

    def prepare(self, names) -> None:
        """Build the acceleration structures of ``names`` now (otherwise on first use)."""
        for name in names:
            self._group(name)

    def _group(self, name: str):
        """(embree scene or None, face ids of the group), built on first use; identical groups share one scene."""
        if name in self._groups:
            return self._groups[name]
        with self._build_lock:
            return self._build_group(name)

    def _build_group(self, name: str):
        if name not in self._groups:
            from embreex import rtcore_scene as rtcs
            from embreex.mesh_construction import TriangleMesh

            faces = self.faces(name)
            twin = next((g for g in self._groups.values() if len(g[1]) == len(faces) and np.array_equal(g[1], faces)), None)
            if twin is not None:
                self._groups[name] = twin
            elif len(faces) == 0:
                self._groups[name] = (None, faces)
            else:
                es = rtcs.EmbreeScene()
                tri32 = self.vertices[self.triangles[faces]].astype(np.float32)
                if not add_triangles(es, tri32):
                    TriangleMesh(es, tri32)
                es.run(np.zeros((1, 3), np.float32), np.ones((1, 3), np.float32))  # commit (builds the BVH) now
                self._groups[name] = (es, faces)
        return self._groups[name]

    def embree_scene(self, name: str):
        """(embreex scene or None, face ids) of group ``name``, built if need be: for benchmarks that
        time raw embreex against this engine on the same scene."""
        return self._group(name)

    def restart_offset(self, points: np.ndarray) -> np.ndarray:
        """Distance [m] to move a ray past a surface it hit at ``points`` (n, 3) [m] before tracing on.

        At least :data:`MIN_RESTART_OFFSET_M`; far from the local origin, :data:`RESTART_OFFSET_ULPS`
        float32 units of the point's largest coordinate, so the offset scales with where the
        float32 ray tracer's round-off is.
        """
        scale = np.abs(np.asarray(points, dtype=float)).max(axis=-1)
        return np.maximum(MIN_RESTART_OFFSET_M, RESTART_OFFSET_ULPS * np.finfo(np.float32).eps * scale)

    def _map(self, fn, n: int, parallel: bool = True):
        bounds = [(a, min(a + CHUNK, n)) for a in range(0, n, CHUNK)]
        if self._pool is None or len(bounds) == 1 or not parallel:
            return [fn(a, b) for a, b in bounds]
        return list(self._pool.map(lambda ab: fn(*ab), bounds))

    def map_chunks(self, fn: Callable[[int, int], object], n: int, parallel: bool = True) -> list:
        """``fn(a, b)`` over the chunks [a, b) of ``n`` rays on the engine's threads (results in order).

        For callers that compute their rays and use the hits per chunk: the maths beside the
        queries (numpy, which releases the GIL on large arrays) then runs on every core too.
        Queries inside ``fn`` go through :meth:`first_hit_chunk` and are counted by the caller
        (:meth:`count_rays`). ``parallel=False``: in the calling thread (a caller already running
        on the engine's threads, :meth:`map_tasks`).
        """
        return self._map(fn, n, parallel)

    def map_tasks(self, fn: Callable[[object], object], items: list) -> Iterator:
        """``fn(item)`` for each of ``items`` on the engine's threads, results in order as they are
        ready (in this thread without a pool). ``fn`` must not use the pool itself: its queries go
        through :meth:`first_hit_chunk`, or :meth:`map_chunks` with ``parallel=False``."""
        if self._pool is None or len(items) <= 1:
            return (fn(x) for x in items)
        return self._pool.map(fn, items)

    def first_hit_chunk(self, group: str, o32: np.ndarray, d32: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`first_hit` of one chunk in the calling thread: contiguous float32 (k, 3) rays,
        at most :data:`CHUNK`; not counted in :attr:`rays_traced`."""
        k = len(o32)
        es, faces = self._group(group)
        if es is None or k == 0:
            return np.full(k, -1, dtype=np.int64), np.full(k, np.inf)
        r = es.run(o32, d32, output=1)
        prim = r["primID"]
        hit = prim >= 0
        return np.where(hit, faces[np.maximum(prim, 0)], -1), np.where(hit, r["tfar"].astype(np.float64), np.inf)

    def count_rays(self, n: int) -> None:
        """Add ``n`` rays traced through :meth:`first_hit_chunk` to :attr:`rays_traced` (from any thread)."""
        with self._count_lock:
            self.rays_traced += n

    def first_hit(self, group: str, origins, directions) -> tuple[np.ndarray, np.ndarray]:
        """Nearest hit of each ray with the faces of ``group``.

        Parameters
        ----------
        origins : (n, 3) float [m], local frame
        directions : (n, 3) float, unit vectors

        Returns
        -------
        face : (n,) int, index into the engine's triangles (-1 where nothing is hit)
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
