"""EN 17037 clause 5.3, Exposure to sunlight: hours of sun seen from point P on the assessed day.

* point P (Annex A.3): :mod:`.point_p`; the sun: :mod:`.solar_position` (NREL SPA)
* visibility from P: :mod:`.visibility`; the days and their intervals: :mod:`.exact` (``sunlight.method:
  exact``, every time visibility can change, from the geometry) or :mod:`.intervals` (``sampled``)
* per room: :mod:`.assess` into :mod:`.results`; report section: :mod:`.report`
"""
from __future__ import annotations

import zoneinfo

import numpy as np

from en17037cli.criteria.base import Context, Criterion
from en17037cli.criteria.sunlight.assess import assess_room, check_sun_points
from en17037cli.criteria.sunlight.intervals import day_bounds
from en17037cli.criteria.sunlight.pictures import window_fisheyes
from en17037cli.criteria.sunlight.point_p import point_p_height
from en17037cli.criteria.sunlight.report import sunlight_section
from en17037cli.criteria.sunlight.results import SunlightResult
from en17037cli.criteria.sunlight.visibility import SunPath
from en17037cli.errors import InputError, NotAssessable
from en17037cli.project.settings import Location, Project, SunSettings
from en17037cli.scene.model import room_window_group

#: Sun samples of one room (days x samples a day) the sampled method may take.
MAX_SUN_SAMPLES = 20_000_000


class SunlightCriterion(Criterion):
    name = "sunlight"
    title = "exposure to sunlight (5.3)"

    def settings(self, project: Project) -> SunSettings | None:
        return project.sunlight

    def _settings(self, ctx: Context) -> tuple[SunSettings, Location]:
        p, loc = ctx.project, ctx.scene.location  # the project's location, completed from the model (IfcSite)
        if p.sunlight is None or loc is None:
            raise ValueError("the sunlight criterion runs only on projects with sunlight and location sections")
        return p.sunlight, loc

    def ray_groups(self, scene):
        return [room_window_group(r) for r in scene.rooms] + ["interior", "sun"]

    def plan(self, ctx: Context, room):
        return None

    def check_inputs(self, ctx: Context) -> dict[str, str]:
        check_sample_count(ctx.project)
        out = {}
        for room in ctx.scene.rooms:
            if room.problem is not None:
                continue
            check_sun_points(room)
            if room.spec.sun_points is None:
                problems = []
                for w in room.windows:  # the height rule needs no ray
                    try:
                        point_p_height(room, w)
                    except NotAssessable as exc:
                        problems.append(str(exc))
                if len(problems) == len(room.windows):
                    out[room.name] = "no window of the room has a point P: " + "; ".join(problems)
        return out

    def assess(self, ctx: Context, room, plan, progress=None) -> SunlightResult:
        settings, location = self._settings(ctx)
        sun_path = ctx.cache.setdefault("sun_path", SunPath(location, settings))
        result = assess_room(ctx.engine, ctx.scene, room, settings, location, ctx.project.thresholds, sun_path)
        if progress:
            progress(1)
        return result

    def illustrate(self, ctx: Context, room, result: SunlightResult):
        """Per window with a point P: the fisheye and the sun paths (:mod:`.pictures`)."""
        settings, location = self._settings(ctx)
        sun_path = ctx.cache.setdefault("sun_path", SunPath(location, settings))
        return window_fisheyes(ctx.engine, ctx.scene, room, result, settings, location, sun_path)

    def level(self, result: SunlightResult) -> int:
        return result.level

    def report(self, ctx: Context, room, result: SunlightResult) -> dict:
        settings, location = self._settings(ctx)
        return sunlight_section(ctx.scene, room, result, self.required(room), settings, zoneinfo.ZoneInfo(location.timezone),
                                ctx.project.thresholds.sunlight_hours)


def check_sample_count(project: Project) -> None:
    """Raise :class:`InputError` when the sampled method's sun samples of one room (days x samples a
    day) exceed :data:`MAX_SUN_SAMPLES`; the exact method (SPA knots every 10 min) has no such cost."""
    s = project.sunlight
    if s is None or s.method != "sampled":
        return
    days = len(day_bounds(s.year, s.period_start, s.period_end, "UTC")[0])
    samples = days * np.ceil(86400.0 / (s.timestep_min * 60.0))
    if samples > MAX_SUN_SAMPLES:
        raise InputError(f"{project.path.name}: sunlight: {days} days at {s.timestep_min:g} min make {samples:,.0f} sun samples "
                         f"a room, over the {MAX_SUN_SAMPLES:,} a run may have; shorten the period or lengthen timestep_min")
