"""A worker's part of a screen: its context built once (:func:`context`), then buildings at a time
(:func:`screen_buildings`): their probes placed, the shared walls left out, each figure computed.

The context is the whole city model and the project's other files as one ray engine, in a local
frame whose origin the run fixes (:class:`Spec`), so that every worker traces the same float32
scene and a probe's figures do not depend on which worker, or with which other buildings, it is
screened. Workers keep one context (:data:`MAX_CONTEXTS`) for every task of the run.

**Shared walls.** A probe gets no figures where its wall is shared with a neighbour (or another
part of its building): where a face lies within ``shared_wall_tolerance_m`` (t) in front of P, or
the point t in front of P lies inside a solid (the first face straight above it is seen from
behind: city solids face outwards, CityJSON 2.0 §3.2, CityGML's GML rules). A ring drawn the wrong
way round (the point t behind P outside, the point in front inside) has its normal turned first.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

import numpy as np

from en17037cli.district.figures import RememberedSunPath, plane_figures, sun_faces, sun_hours
from en17037cli.district.probes import PROBE_OFFSET_M, Probes, place_probes

#: Contexts a worker keeps (the run's one)
MAX_CONTEXTS = 1
_CONTEXTS: dict = {}
_LOCK = threading.Lock()
_RUN = threading.Lock()


@dataclass(frozen=True)
class Spec:
    """What a worker needs for a run, as plain data: the project (path and ``--set`` overrides), the
    local origin [m, the model's CRS] and the site the run resolved (latitude, longitude [deg],
    true north [deg clockwise from +Y])."""

    project: str
    overrides: tuple
    origin: tuple
    latitude: float
    longitude: float
    north_deg: float


@dataclass
class Context:
    """The run's scene and engines in a worker (local frame = world - origin)."""

    vertices: np.ndarray
    triangles: np.ndarray
    layer: np.ndarray
    engine: object
    view_rays: object
    settings: object
    location: object
    north: float
    sun_path: object
    spline: object
    dates: list
    t0: np.ndarray
    t1: np.ndarray
    face_lo: np.ndarray
    face_hi: np.ndarray
    sun_faces: np.ndarray
    z_top: float
    origin: np.ndarray
    notes: list = field(default_factory=list)

    @property
    def sun(self):
        return self.settings.sun

    @property
    def view(self):
        return self.settings.view


def build_context(spec: Spec) -> Context:
    """Read the project's files into one ray engine (:func:`~en17037cli.scene.load.load_geometry`:
    the city model whole, the other files as context) and the sun's path over the period."""
    from dataclasses import replace
    from pathlib import Path

    from en17037cli.batch.worker import worker_threads
    from en17037cli.criteria.sunlight.exact import SunSpline
    from en17037cli.criteria.sunlight.intervals import day_bounds
    from en17037cli.criteria.view.rays import ViewRays
    from en17037cli.district.settings import screen_settings
    from en17037cli.io import is_context
    from en17037cli.project import load_project
    from en17037cli.raytrace import RayEngine
    from en17037cli.scene.load import load_geometry
    from en17037cli.scene.model import LANDSCAPE, WINDOW

    project = load_project(Path(spec.project), list(spec.overrides))
    settings = screen_settings(project)
    # the city models whole: the probes' own buildings and what they see must be in the scene (the
    # context radius, made for a building's windows, would cut the tile round another file)
    files = tuple(replace(f, context_radius_m=float("inf")) if is_context(f.path) else f for f in project.model.files)
    g = load_geometry(replace(project.model, files=files), project.path.name)
    origin = np.asarray(spec.origin, dtype=float)
    v = g.vertices - origin
    opaque = g.layer != WINDOW
    engine = RayEngine(v, g.triangles, {"opaque": opaque, "sun": opaque & g.obstructs_sun, "landscape": g.layer == LANDSCAPE},
                       threads=worker_threads())  # the worker's share of the cores
    tri = v[g.triangles]
    loc = replace(project.location, latitude=spec.latitude, longitude=spec.longitude)
    sun = settings.sun
    dates, t0, t1 = day_bounds(sun.year, sun.period_start, sun.period_end, loc.timezone)
    path = RememberedSunPath(loc, sun)
    spline = SunSpline(path, float(t0[0]), float(t1[-1]), spec.north_deg)
    scene_like = type("Layers", (), {"layer": g.layer})()
    return Context(vertices=v, triangles=g.triangles, layer=g.layer, engine=engine, view_rays=ViewRays(engine, scene_like),
                   settings=settings, location=loc, north=spec.north_deg, sun_path=path, spline=spline, dates=dates, t0=t0,
                   t1=t1, face_lo=tri.min(axis=1), face_hi=tri.max(axis=1),
                   sun_faces=np.flatnonzero(opaque & g.obstructs_sun), z_top=float(v[:, 2].max()) if len(v) else 0.0,
                   origin=origin, notes=[*g.notes, *g.warnings])


def context(spec: Spec) -> Context:
    """This worker's context of the run ``spec``, built on first use."""
    with _LOCK:
        ctx = _CONTEXTS.get(spec)
        if ctx is None:
            for old in list(_CONTEXTS)[:len(_CONTEXTS) + 1 - MAX_CONTEXTS]:
                _CONTEXTS.pop(old).engine.close()
            ctx = _CONTEXTS[spec] = build_context(spec)
        return ctx


def clear_contexts() -> None:
    """Free the worker's contexts (their engines' threads)."""
    with _LOCK:
        while _CONTEXTS:
            _CONTEXTS.popitem()[1].engine.close()


@dataclass
class Screened:
    """What a task gives back: its probes (world frame) and their figures, arrays of one row per
    probe (see :mod:`~en17037cli.district.results`), the probes left out on shared walls, the
    buildings left out and why, and the time spent on each part [s]."""

    probes: Probes
    shared: dict
    hours: np.ndarray
    hours_err: np.ndarray
    vsc: np.ndarray
    vsc_bound: np.ndarray
    sr: dict
    err_sr: dict
    distance_m: np.ndarray
    distance_gap_m: np.ndarray
    problems: list
    seconds: dict


def exposed(ctx: Context, points: np.ndarray, normals: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Which probes stand on a wall that is not shared (module docstring), and their normals
    (turned where the ring is drawn the wrong way round). ``points`` [m, local]."""
    def inside(q):
        f, _ = ctx.engine.first_hit("opaque", q, np.tile([0.0, 0.0, 1.0], (len(q), 1)))
        t = ctx.vertices[ctx.triangles[np.maximum(f, 0)]]
        nz = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])[:, 2]
        return (f >= 0) & (nz > 0)  # seen from below: from inside a solid

    step = max(tol, 2 * PROBE_OFFSET_M)
    front, back = inside(points + step * normals), inside(points - step * normals)
    turned = front & ~back
    normals = np.where(turned[:, None], -normals, normals)
    front = front & ~turned
    f, t = ctx.engine.first_hit("opaque", points + PROBE_OFFSET_M * normals, normals)
    touching = (f >= 0) & (t <= max(tol - PROBE_OFFSET_M, 0.0))
    return ~(front | touching), normals


def _one_building(ctx: Context, b, index: int, seconds: dict) -> tuple:
    """(probes, shared count, figures...) of one building; see :func:`screen_buildings`."""
    st = ctx.settings
    tic = time.perf_counter()
    probes = place_probes([b], st, index)
    pts = probes.point - ctx.origin
    keep, normals = exposed(ctx, pts, probes.normal, st.shared_wall_tolerance_m)
    shared = int(np.count_nonzero(~keep))
    probes = probes.take(keep)
    probes.normal = normals[keep]
    pts = pts[keep] + PROBE_OFFSET_M * probes.normal
    p = len(probes)
    vsc, bound, dist, gap = np.zeros(p), np.zeros(p), np.full(p, np.inf), np.zeros(p)
    sr = {k: np.zeros(p) for k in ("sky", "landscape", "ground")}
    err = {k: np.zeros(p) for k in ("sky", "landscape", "ground")}
    seconds["probes"] += time.perf_counter() - tic
    if p == 0:
        return (probes, shared, *_empty(len(ctx.t0))[2:])
    tic = time.perf_counter()
    lo, hi = pts[:, :2].min(axis=0), pts[:, :2].max(axis=0)
    hours, hours_err = sun_hours(ctx, pts, probes.normal, sun_faces(ctx, b.z_ground - ctx.origin[2], lo, hi))
    seconds["sunlight"] += time.perf_counter() - tic
    tic = time.perf_counter()
    key = probes.wall * 1000 + probes.poly
    for k in np.unique(key):  # one plane per wall polygon: each call vectorised over its probes
        g = np.flatnonzero(key == k)
        vsc[g], bound[g], solid, dist[g], gap[g] = plane_figures(ctx, pts[g], probes.normal[g[0]], st.sky_resolution_deg)
        for name in sr:
            sr[name][g], err[name][g] = solid.sr[name], solid.err_sr[name]
    seconds["sky_and_view"] += time.perf_counter() - tic
    return probes, shared, hours, hours_err, vsc, bound, sr, err, dist, gap


def _empty(nd: int) -> tuple:
    """The figures of no probe (the tuple :func:`_one_building` gives)."""
    z, zi = np.zeros(0), np.zeros(0, np.int64)
    layers = {k: z for k in ("sky", "landscape", "ground")}
    return (Probes(zi, zi, zi, zi, np.zeros((0, 3)), np.zeros((0, 3)), z), 0, np.zeros((0, nd)), np.zeros((0, nd)), z, z,
            layers, dict(layers), z, z)


def screen_buildings(spec: Spec, buildings: list, first: int) -> Screened:
    """Probes and figures of ``buildings`` (their indices in the run counted from ``first``). A
    building whose probes or figures cannot be had (a degenerate wall, an engine's error) is left
    out with why, the others go on."""
    with _RUN:  # one task at a time in a worker: its ray engine has the worker's threads (a Dask worker's nthreads)
        return _screen(spec, buildings, first)


#: How a building's problem begins where the screen itself failed on it (a bug, not the model): the
#: tile goes on, and the command ends with exit 3 once its outputs are written.
INTERNAL = "could not be screened"


def _screen(spec: Spec, buildings: list, first: int) -> Screened:
    from en17037cli.errors import InputError, internal_message

    ctx = context(spec)
    seconds = {"probes": 0.0, "sunlight": 0.0, "sky_and_view": 0.0}
    parts, problems, shared_of = [], [], []
    for i, b in enumerate(buildings):  # the task's few buildings
        try:
            parts.append(_one_building(ctx, b, first + i, seconds))
            shared_of.append(first + i)
        except InputError as exc:
            problems.append((first + i, str(exc)))
        except Exception as exc:  # noqa: BLE001 - one building's failure leaves the tile going, named
            problems.append((first + i, f"{INTERNAL} ({internal_message(exc)})"))
    if not parts:
        parts = [_empty(len(ctx.t0))]
    probes = Probes(*(np.concatenate([getattr(q[0], f) for q in parts])
                      for f in ("building", "wall", "poly", "storey", "point", "normal", "area_m2")))
    cat = lambda j: np.concatenate([q[j] for q in parts])  # noqa: E731
    sr = {k: np.concatenate([q[6][k] for q in parts]) for k in parts[0][6]}
    err = {k: np.concatenate([q[7][k] for q in parts]) for k in parts[0][7]}
    shared = {b: q[1] for b, q in zip(shared_of, parts) if q[1]}
    return Screened(probes, shared, cat(2), cat(3), cat(4), cat(5), sr, err, cat(8), cat(9), problems, seconds)
