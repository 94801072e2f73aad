"""Whether the sun is seen from the points P of a room, at given times."""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.sunlight.solar_position import direction_vectors, solar_position
from en17037cli.project.settings import Location, SunSettings
from en17037cli.raytrace import RayEngine

#: Times per call of the SPA (its nutation terms make (63, n) float arrays: 25 MB at this size).
SPA_CHUNK = 50_000


#: Time arrays at least this long are remembered by :class:`SunPath` (the sampling grid, the same
#: for every room of a run); the bisection's short arrays are computed afresh.
MEMO_MIN_TIMES = 256


class SunPath:
    """The sun's apparent elevation and azimuth [deg] at unix times [s] for one site and one
    set of sunlight settings (NREL SPA, :func:`~.solar_position.solar_position`), shared by the
    rooms of a run: the sampling grid of the period is computed once, not once per room."""

    def __init__(self, location: Location, settings: SunSettings):
        self.loc, self.settings = location, settings
        self._memo: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def __call__(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(elevation, azimuth) (n,) [deg] at unix times ``t`` (n,) [s]."""
        t = np.ascontiguousarray(t, dtype=float)
        key = t.tobytes() if len(t) >= MEMO_MIN_TIMES else None
        if key is not None and key in self._memo:
            return self._memo[key]
        c = self.settings
        elev, azim = np.empty(len(t)), np.empty(len(t))
        for a in range(0, len(t), SPA_CHUNK):  # the SPA's periodic terms take (63, n) arrays: bounded memory
            b = a + SPA_CHUNK
            elev[a:b], azim[a:b] = solar_position(t[a:b], self.loc.latitude, self.loc.longitude, self.loc.elevation_m,
                                                  c.pressure_mbar, c.temperature_c, refraction=c.refraction)
        if key is not None:
            self._memo[key] = (elev, azim)
        return elev, azim


class SunVisibility:
    """Visibility of the sun from the P points of one room, vectorised over times."""

    def __init__(self, engine: RayEngine, points: np.ndarray, normals: np.ndarray, window_group: str, location: Location,
                 settings: SunSettings, true_north_deg: float, sun_path: SunPath | None = None):
        self.engine, self.points, self.normals = engine, points, normals
        self.window_group = window_group
        self.loc, self.settings, self.north = location, settings, true_north_deg
        self.sun_path = sun_path or SunPath(location, settings)

    def __call__(self, t: np.ndarray) -> np.ndarray:
        """(n,) bool: the sun is seen from P through a window of the room at unix times ``t`` [s]."""
        c = self.settings
        elev, azim = self.sun_path(t)
        up = elev >= c.min_altitude_deg
        seen = np.zeros(len(t), dtype=bool)
        if not up.any():
            return seen
        return self.seen_along(direction_vectors(elev, azim, self.north), up)

    def seen_along(self, d: np.ndarray, up: np.ndarray) -> np.ndarray:
        """(n,) bool: the sun is seen from P along unit directions ``d`` (n, 3) where ``up`` (n,) (above
        the minimum altitude): a ray in front of a window's plane that leaves through a window of the
        room and meets no face that blocks the sun."""
        seen = np.zeros(len(d), dtype=bool)
        for p, n in zip(self.points, self.normals):  # one pass per window of the room
            cand = np.flatnonzero(up & ~seen & (d @ n > 0))  # no ray below the altitude or behind the window
            if len(cand) == 0:
                continue
            o = np.broadcast_to(p, (len(cand), 3))
            face, _ = self.engine.first_hit(self.window_group, o, d[cand])
            cand = cand[face >= 0]
            if len(cand) == 0:
                continue
            blocked = self.engine.occluded("sun", np.broadcast_to(p, (len(cand), 3)), d[cand])
            seen[cand[~blocked]] = True
        return seen
