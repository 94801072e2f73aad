"""The figures at the probes, each by the engine that computes it for rooms.

**The virtual window's half-space.** P lies on the plane of a window flush with the facade, so the
window spans, from P, every direction in front of the facade but those within atan(d / e) of its
plane (d: how far P lies behind the glazing, 1 mm by A.3's rule; e: the distance to the window's
nearest edge, 0.3 m below P for the default window): 0.2 deg. The screen takes the whole
half-space in front of the facade as the window. Its sky component differs by what the sliver
of width delta = 0.2 deg adds: 9 / (7 pi) x the integral of cos(theta) over it, at most
9 / (7 pi) x delta x (pi delta) = (9 / 7) delta^2 = 1.6e-5 (0.0016 % of the unobstructed
horizontal illuminance); the sun there grazes the wall at under 0.2 deg, a minute or two of a day.

* **Sunlight** (5.3): the exact sun hours of the rooms' engine (:func:`~en17037cli.criteria.sunlight.exact.exact_intervals`,
  every time the sun's visibility from P can change, then one ray per interval), with the window
  as that half-space (:class:`HalfSpace`: the window plane's crossing is the only window event)
  and the faces that can block the sun culled per building by the minimum altitude: a face
  farther in plan than (z_top - z_ground) / tan(min altitude) from the building, z_top the tile's
  highest point, is seen below that altitude from every probe of it (exact, not a guess).
* **Vertical sky component**: the daylight criterion's exact sky-component integration
  (:func:`~en17037cli.criteria.daylight.sky_component.sky_component`: the CIE overcast sky,
  Gauss-Legendre cells on the gnomonic grid of the window, split where a sky edge crosses them,
  with a bound) on the facade's plane (cos of the angle to the facade's normal) through an open
  window (transmittance 1) that spans the half-space: one frame for all the probes of a wall's plane.
* **View** (5.2): the view engine's solid angles of sky, landscape and ground through the same
  frame (:func:`~en17037cli.criteria.view.solid_angle.solid_angles`), at the probes' coarser
  resolution (``screen.view_resolution_deg``); the outside distance by the rooms' ``horizontal``
  method (:func:`~en17037cli.criteria.view.distance.horizontal_distance`: over a horizontal fan
  through the window, the distance from the glazing to the first landscape face measured
  perpendicular to it, ground never obstructing, +inf where nothing is met; the median by angle)
  on a fan of rays every :data:`FAN_STEP_DEG` across the half-space, its gap to the neighbouring
  samples as its error.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.daylight.sky_component import SkyTolerance, sky_component
from en17037cli.criteria.sunlight.exact import exact_intervals
from en17037cli.criteria.sunlight.visibility import SunPath, SunVisibility
from en17037cli.criteria.view.distance import horizontal_distance
from en17037cli.criteria.view.frames import RoomGeometry, WindowFrame
from en17037cli.criteria.view.solid_angle import solid_angles
from en17037cli.district.settings import SKY_ABS_TOLERANCE, SKY_REFINE_LEVELS, SKY_REL_TOLERANCE
from en17037cli.geometry import window_axes

#: The window's group name for the sun (the half-space: :class:`HalfSpace`)
WINDOW_GROUP = "virtual window"
#: Half-size of the frame that stands for the half-space [m], seen from 1 mm behind its plane: its
#: edges lie 1e-7 rad from the plane
HALF_SPACE_M = 1.0e4
#: P lies this far behind the virtual window's plane [m] (A.3: on the opening's room-side plane,
#: moved 1 mm into the room, as for rooms: GLAZING_OFFSET_M)
BEHIND_M = 1e-3
#: Angle between the rays of the outside distance's horizontal fan [deg] (180 across the half-space)
FAN_STEP_DEG = 1.0


class HalfSpace:
    """The ray engine as the exact sun hours see it at a probe: the window group is the half-space
    in front of the facade (every ray the sun test casts there, s . n > 0, passes it), and the faces
    that can block the sun are ``sun_faces`` (the building's cull); every query on blocking faces
    goes to the whole tile's engine."""

    def __init__(self, engine, sun_faces: np.ndarray):
        self.engine, self.sun_faces = engine, sun_faces

    def faces(self, name: str) -> np.ndarray:
        return self.sun_faces if name == "sun" else np.zeros(0, np.int64)

    def first_hit(self, name: str, origins, directions):
        if name == WINDOW_GROUP:
            n = len(origins)
            return np.zeros(n, np.int64), np.zeros(n)
        return self.engine.first_hit(name, origins, directions)

    def occluded(self, name: str, origins, directions):
        return self.engine.occluded(name, origins, directions)


class RememberedSunPath(SunPath):
    """The sun's path (:class:`~en17037cli.criteria.sunlight.visibility.SunPath`) remembering every
    array of times it was asked for, short ones too: the exact method searches the minimum-altitude
    crossings of each day with the same times for every probe (their SPA calls were a tenth of a
    probe's time); at most :data:`REMEMBERED` arrays."""

    def __call__(self, t):
        t = np.ascontiguousarray(t, dtype=float)
        key = t.tobytes()
        got = self._memo.get(key)
        if got is None:
            got = super().__call__(t)
            if len(self._memo) < REMEMBERED:
                self._memo[key] = got
        return got


#: Arrays of times a :class:`RememberedSunPath` keeps
REMEMBERED = 4096


class _NoWindows:
    """A room whose window is the half-space: no window pyramid narrows the cull."""

    windows: tuple = ()


class _Faces:
    """Vertices (n, 3) [m, local] and triangles (m, 3) of some faces, as the exact method reads a scene."""

    def __init__(self, vertices: np.ndarray, triangles: np.ndarray):
        self.vertices, self.triangles = vertices, triangles


def sun_faces(ctx, z_ground: float, lo_xy: np.ndarray, hi_xy: np.ndarray) -> np.ndarray:
    """The faces that can block the sun above the minimum altitude from any point of a building
    whose walls stand in the box [lo_xy, hi_xy] [m, local] above z_ground [m, local]: within
    (z_top - z_ground) / tan(min altitude) in plan and reaching above z_ground (module docstring)."""
    reach = max(ctx.z_top - z_ground, 0.0) / np.tan(np.radians(max(ctx.sun.min_altitude_deg, 1e-3))) + 1.0
    near = (np.all(ctx.face_hi[:, :2] >= lo_xy - reach, axis=1) & np.all(ctx.face_lo[:, :2] <= hi_xy + reach, axis=1)
            & (ctx.face_hi[:, 2] > z_ground))
    return ctx.sun_faces[near[ctx.sun_faces]]


def seen_above(ctx, faces: np.ndarray, p: np.ndarray, n: np.ndarray) -> np.ndarray:
    """The faces of ``faces`` that can stand between ``p`` [m, local] and the sun: some corner of
    their box in front of the facade (normal ``n``), and their top above the minimum altitude seen
    from p over the box's nearest point in plan (a bound: no face that can block is dropped)."""
    lo, hi = ctx.face_lo[faces], ctx.face_hi[faces]
    d = np.hypot(np.maximum(np.maximum(lo[:, 0] - p[0], p[0] - hi[:, 0]), 0.0),
                 np.maximum(np.maximum(lo[:, 1] - p[1], p[1] - hi[:, 1]), 0.0))
    high = hi[:, 2] - p[2] >= np.tan(np.radians(ctx.sun.min_altitude_deg)) * d - 1e-6
    front = np.maximum(lo[:, 0] * n[0], hi[:, 0] * n[0]) + np.maximum(lo[:, 1] * n[1], hi[:, 1] * n[1]) \
        + np.maximum(lo[:, 2] * n[2], hi[:, 2] * n[2]) >= p @ n - 1e-6
    return faces[high & front]


def sun_hours(ctx, points: np.ndarray, normals: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Hours of sun [h] (p, d) on each day of the period seen from ``points`` (p, 3) [m, local] facing
    ``normals`` (p, 3), and each day's error bound [h]; the exact method, point by point (each
    vectorised over the sun's path and the faces' edges), over the faces of ``faces`` each can see
    above the minimum altitude (:func:`seen_above`)."""
    nd = len(ctx.t0)
    hours, err = np.zeros((len(points), nd)), np.zeros((len(points), nd))
    # the building's faces as a scene of their own: the exact method's cull looks at every vertex of
    # the scene it is given, so it gets these faces' vertices only (face k of it is faces[k])
    used, tri = np.unique(ctx.triangles[faces], return_inverse=True)
    own = _Faces(ctx.vertices[used], tri.reshape(-1, 3))
    for k in range(len(points)):  # one pass per probe, as the rooms' engine goes point by point
        engine = HalfSpace(ctx.engine, np.searchsorted(faces, seen_above(ctx, faces, points[k], normals[k])))
        vis = SunVisibility(engine, points[k:k + 1], normals[k:k + 1], WINDOW_GROUP, ctx.location, ctx.sun, ctx.north,
                            ctx.sun_path)
        iv, e = exact_intervals(vis, ctx.spline, ctx.sun_path, own, _NoWindows(), 0, ctx.t0, ctx.t1, ctx.sun,
                                float(ctx.location.latitude))
        hours[k] = [float(np.sum(d[:, 1] - d[:, 0])) / 3600.0 for d in iv]
        err[k] = np.asarray(e) / 3600.0
    return hours, err


def half_space(origin: np.ndarray, normal: np.ndarray, group: str = WINDOW_GROUP, upper: bool = False) -> RoomGeometry:
    """A room whose one window is the half-space in front of a facade: a square of half-size
    :data:`HALF_SPACE_M` in the plane through ``origin`` [m, local] facing ``normal`` (horizontal),
    no frame; with ``upper``, its upper half only (the directions above the horizon of points at
    ``origin``'s height: where the sky is)."""
    u, v = window_axes(np.asarray(normal, float))
    s = HALF_SPACE_M
    y0 = 0.0 if upper else -s
    tri2 = np.array([[[-s, y0], [s, y0], [s, s]], [[-s, y0], [s, s], [-s, s]]])
    empty = np.zeros((0, 2, 3))
    frame = WindowFrame(0, "virtual window", np.asarray(origin, float), u, v, np.asarray(normal, float), tri2, -s, s, y0, s,
                        True, np.zeros(0, np.int64), frame_xys=np.zeros((0, 3)), frame_x=np.zeros((0, 2)),
                        frame_y=np.zeros((0, 2)), frame_edges=empty, frame_edge_opposite=empty)
    return RoomGeometry([frame], np.zeros(1, np.int64), np.zeros((0, 3, 3)), np.zeros(0, np.int64), group)


def outside_distance(ctx, rg: RoomGeometry, points: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Outside distance [m] (p,) of ``points`` [m, local] by the ``horizontal`` method over a fan of
    horizontal rays every :data:`FAN_STEP_DEG` across the half-space in front of the facade (ray j
    at angle phi_j = -90 + (j + 1/2) step deg from the normal, weight step), and its gap [m]."""
    k = int(round(180.0 / FAN_STEP_DEG))
    phi = np.radians(-90.0 + (np.arange(k) + 0.5) * 180.0 / k)
    h = np.array([normal[0], normal[1], 0.0])
    h /= np.linalg.norm(h)
    u = np.array([-h[1], h[0], 0.0])
    d = np.cos(phi)[:, None] * h + np.sin(phi)[:, None] * u  # (k, 3)
    p = len(points)
    pidx = np.repeat(np.arange(p), k)
    dirs = np.tile(d, (p, 1))
    face, t = ctx.engine.first_hit("opaque", points[pidx], dirs)
    glass = BEHIND_M / np.maximum(dirs @ np.asarray(normal, float), 1e-12)
    traced = (np.zeros(len(pidx), np.int64), face, t, glass)
    weight = np.full(len(pidx), np.radians(180.0 / k))
    return horizontal_distance(ctx.view_rays, rg, points, pidx, dirs, np.ones(len(pidx), bool), traced, weight, p,
                               ctx.view.distance_statistic)


def plane_figures(ctx, points: np.ndarray, normal: np.ndarray, sky_resolution_deg: float):
    """The vertical sky component and the view at probes ``points`` (p, 3) [m, local] of one wall
    plane facing ``normal`` (3,), through the half-space frame :data:`BEHIND_M` in front of them.

    Returns
    -------
    vsc, vsc_bound : (p,) [-]; solid : :class:`~en17037cli.criteria.view.results.SolidAngles`;
    distance, gap : (p,) [m] (:func:`outside_distance`)
    """
    n = np.asarray(normal, float)
    rg = half_space(points[0] + BEHIND_M * n, n)
    tol = SkyTolerance(resolution_deg=sky_resolution_deg, refine_levels=SKY_REFINE_LEVELS, rel_tolerance=SKY_REL_TOLERANCE,
                       abs_tolerance=SKY_ABS_TOLERANCE, frame_depth_m=0.0)
    sc = np.zeros(len(points)), np.zeros(len(points))
    for z in np.unique(points[:, 2]):  # the sky lies above each point's horizon: its upper quarter-space, per height
        at = np.flatnonzero(points[:, 2] == z)
        up = sky_component(ctx.view_rays, half_space(points[at[0]] + BEHIND_M * n, n, upper=True), points[at], np.ones(1),
                           tol, normal=n)
        sc[0][at], sc[1][at] = up.value, up.bound
    solid = solid_angles(ctx.view_rays, rg, points, ctx.view, parallel=True)
    dist, gap = outside_distance(ctx, rg, points, n)
    return sc[0], sc[1], solid, dist, gap
