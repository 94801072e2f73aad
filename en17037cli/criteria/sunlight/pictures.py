"""What the report draws of the sunlight criterion, traced here: per window, the fisheye from point P
and the sun's paths on the period's first, assessed and last day.

The report's drawing functions (:mod:`en17037cli.report.pictures`) trace nothing; this module
gives them the classes of every fisheye pixel (rays from P through the room's windows, classified
like the view criterion's rays) and the sun's positions with what P sees of them.
"""
from __future__ import annotations

import datetime as dt
import math
import zoneinfo
from dataclasses import dataclass, field

import numpy as np

from en17037cli.criteria.sunlight.intervals import day_bounds
from en17037cli.criteria.sunlight.results import SunlightResult
from en17037cli.criteria.sunlight.visibility import SunPath, SunVisibility
from en17037cli.criteria.view.rays import ViewRays
from en17037cli.geometry.fisheye import fisheye_directions
from en17037cli.project.settings import Location, SunSettings
from en17037cli.raytrace import RayEngine
from en17037cli.scene.model import Room, Scene, room_window_group

#: Fisheye raster traced per window [px per side]: the drawn circle's diameter
#: (:data:`en17037cli.report.pictures.FISHEYE_RADIUS_PX` x 2), one ray per drawn pixel.
FISHEYE_PIXELS = 320
#: Spacing of the sun-path samples drawn [s].
PATH_STEP_S = 120.0


@dataclass
class SunPathDay:
    """The sun on one day as drawn: positions every :data:`PATH_STEP_S` and whether P sees it.

    azimuth_deg, altitude_deg : (t,) [deg], clockwise from true north / above the horizon
    visible : (t,) bool, seen from P through this window
    hour_marks : (azimuth [deg], altitude [deg], "HH:00") at each full local hour with the sun up
    """

    label: str
    date: dt.date
    azimuth_deg: np.ndarray
    altitude_deg: np.ndarray
    visible: np.ndarray
    hour_marks: list = field(default_factory=list)


@dataclass
class WindowFisheye:
    """One window's fisheye from its point P.

    image : (N, N) int8, -1 outside the 180 deg circle, 0 blocked or interior, 1 sky,
        2 landscape, 3 ground (:mod:`en17037cli.criteria.view.rays` classes), row 0 at the top
    view_azimuth_deg : [deg] clockwise from true north, the window's outward normal
    """

    window: str
    image: np.ndarray
    view_azimuth_deg: float
    paths: list[SunPathDay]


def view_azimuth_deg(normal, true_north_deg: float) -> float:
    """Azimuth [deg, clockwise from true north, in [0, 360)] of a window's outward normal (model
    frame, true north ``true_north_deg`` clockwise from +Y)."""
    return (math.degrees(math.atan2(normal[0], normal[1])) - true_north_deg) % 360.0


def fisheye_classes(engine: RayEngine, scene: Scene, room: Room, p: np.ndarray, view_az: float,
                    n: int = FISHEYE_PIXELS) -> np.ndarray:
    """(n, n) int8 classes of an equidistant fisheye from ``p`` (local [m]) looking at ``view_az``
    [deg]: one ray per pixel through the room's windows (:meth:`ViewRays.through_windows`)."""
    dirs, inside = fisheye_directions(n, view_az, scene.true_north_deg)
    d = dirs[inside]
    cls, *_ = ViewRays(engine, scene).through_windows(room_window_group(room), np.broadcast_to(p, d.shape).copy(), d)
    image = np.full((n, n), -1, dtype=np.int8)
    image[inside] = cls
    return image


def sun_path_day(label: str, date: dt.date, t0: float, t1: float, sun: SunPath, seen: SunVisibility,
                 tz: zoneinfo.ZoneInfo) -> SunPathDay:
    """The sun from ``t0`` to ``t1`` [unix s] every :data:`PATH_STEP_S`, with full-hour marks."""
    t = np.arange(t0, t1 + 0.5 * PATH_STEP_S, PATH_STEP_S)
    alt, az = sun(t)
    vis = seen(t)
    hours = np.arange(math.ceil(t0 / 3600.0) * 3600.0, t1, 3600.0)
    h_alt, h_az = sun(hours)
    marks = [(float(a), float(e), dt.datetime.fromtimestamp(h, tz).strftime("%H:%M"))
             for a, e, h in zip(h_az, h_alt, hours) if e > 0]
    return SunPathDay(label, date, az, alt, vis, marks)


def window_fisheyes(engine: RayEngine, scene: Scene, room: Room, res: SunlightResult, settings: SunSettings,
                    location: Location, sun: SunPath) -> list[WindowFisheye]:
    """The fisheye of every window of the room with a point P, and the sun on the period's first,
    assessed and last day (each once)."""
    tz = zoneinfo.ZoneInfo(location.timezone)
    dates, t0, t1 = day_bounds(settings.year, settings.period_start, settings.period_end, location.timezone)
    days: dict[int, list[str]] = {}
    for k, label in ((0, "first day"), (res.assessed_index, "assessed"), (len(dates) - 1, "last day")):
        days.setdefault(k, []).append(label)
    out = []
    for i, w in enumerate(room.windows):  # one fisheye per window
        if res.window_problems and res.window_problems[i]:
            continue
        p = res.points_local[i]
        az = view_azimuth_deg(w.normal, scene.true_north_deg)
        seen = SunVisibility(engine, p[None, :], np.asarray(w.normal)[None, :], room_window_group(room), location, settings,
                             scene.true_north_deg, sun)
        paths = [sun_path_day(f"{dates[k].day} {dates[k].strftime('%b')} ({', '.join(labels)})", dates[k], t0[k], t1[k], sun,
                              seen, tz) for k, labels in sorted(days.items())]
        out.append(WindowFisheye(w.name, fisheye_classes(engine, scene, room, p, az), az, paths))
    return out
