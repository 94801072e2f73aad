"""EN 17037 clause 5.4, Protection from glare: the daylight glare probability (DGP) at the critical
positions of a room, exceeded in at most 5 % of the usage hours, with Radiance through pyradiance.

* the positions and view directions: :mod:`.positions`; the usage hours: :mod:`.usage`
* the DGP, the position index, the glass: :mod:`.dgp`; the Radiance runs: :mod:`.engine` (the
  scene by the daylight criterion's writer)
* the annual method (daylight coefficients, the sun apart, clause 5.3's sun visibility):
  :mod:`.annual`; per room, the shading device and the transmittance a room needs: :mod:`.assess`
* the reference (evalglare on rpict fisheyes) and the point-in-time checks: :mod:`.reference`
* the report section and the CSVs: :mod:`.report`; the pictures: :mod:`.pictures`

pyradiance is imported only when a project has a ``glare`` section and the check runs.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.base import Context, Criterion
from en17037cli.criteria.glare.results import GlareResult
from en17037cli.project.glare_settings import GlareSettings
from en17037cli.project.settings import Project
from en17037cli.scene.model import room_window_group


class GlareCriterion(Criterion):
    name = "glare"
    title = "protection from glare (5.4)"

    def settings(self, project: Project) -> GlareSettings | None:
        return project.glare

    def _settings(self, ctx: Context) -> GlareSettings:
        if ctx.project.glare is None:
            raise ValueError("the glare criterion runs only on projects with a glare section")
        return ctx.project.glare

    def ray_groups(self, scene):
        return [room_window_group(r) for r in scene.rooms] + ["sun"]

    def check_inputs(self, ctx: Context) -> dict[str, str]:
        from en17037cli.criteria.daylight.radiance import binpath
        from en17037cli.errors import InputError

        try:
            binpath()  # the extra is installed, or an input error saying how
        except InputError:
            raise InputError("glare: the glare check needs Radiance through pyradiance: pip install 'en17037cli[daylight]'; "
                             "or remove the glare section") from None
        self.weather(ctx)  # the weather file reads
        return self.unplannable(ctx)

    def plan(self, ctx: Context, room):
        from en17037cli.criteria.glare.positions import room_views

        plans = ctx.cache.setdefault("glare_plans", {})
        if room.name not in plans:
            plans[room.name] = room_views(ctx.scene, room, self._settings(ctx), ctx.cache)
        return plans[room.name]

    def size(self, plan) -> int:
        return len(plan)

    def weather(self, ctx: Context):
        s = self._settings(ctx)
        if s.weather is None:
            return None
        if "glare_weather" not in ctx.cache:
            from en17037cli.weather.epw import read_epw

            ctx.cache["glare_weather"] = read_epw(s.weather, f"{ctx.project.path.name}: glare.weather")
        return ctx.cache["glare_weather"]

    def octrees(self, ctx: Context):
        """The glare scene compiled once per run (:class:`~.engine.Octrees`)."""
        if "glare_octrees" not in ctx.cache:
            from en17037cli.criteria.daylight import radiance
            from en17037cli.criteria.glare import engine

            s = self._settings(ctx)
            text = radiance.scene_text(engine.glare_scene(ctx.scene), dict(s.reflectance), s.glazing_transmittance)
            ctx.cache["glare_octrees"] = engine.Octrees(text)
        return ctx.cache["glare_octrees"]

    def patch_octree(self, ctx: Context) -> str:
        """The scene with the unit sky and ground hemispheres the coefficients are binned from."""
        if "glare_patch_octree" not in ctx.cache:
            from en17037cli.criteria.glare import engine

            ctx.cache["glare_patch_octree"] = self.octrees(ctx).with_sky(engine.PATCH_SKY, "patches")
        return ctx.cache["glare_patch_octree"]

    def climate(self, ctx: Context):
        """The usage hours, their skies and the sun, once per run (:func:`~.annual.climate`)."""
        if "glare_climate" not in ctx.cache:
            from en17037cli.criteria.glare.annual import climate

            ctx.cache["glare_climate"] = climate(self.weather(ctx), ctx.scene.location, self._settings(ctx),
                                                 ctx.scene.true_north_deg, ctx.project.sunlight)
        return ctx.cache["glare_climate"]

    def window_tn(self, ctx: Context, room) -> np.ndarray:
        """Radiance glass transmissivity of each window of the room (1: an open opening)."""
        from en17037cli.criteria.daylight import radiance

        if "glare_optics" not in ctx.cache:
            s = self._settings(ctx)
            ctx.cache["glare_optics"] = radiance.face_optics(ctx.scene, dict(s.reflectance), s.glazing_transmittance)[1]
        value = ctx.cache["glare_optics"]
        tv = np.array([value[w.face_ids[0]] for w in room.windows], dtype=float)
        return np.where(tv >= radiance.OPEN_TV, 1.0, radiance.glass_transmissivity(tv))

    def assess(self, ctx: Context, room, plan, progress=None) -> GlareResult:
        from en17037cli.criteria.glare.assess import assess_room

        res = assess_room(self, ctx, room, plan, self.required(room))
        if progress:
            progress(len(plan))
        return res

    def level(self, result: GlareResult) -> int:
        return 0 if result.level is None else result.level

    def unassessable(self, result: GlareResult) -> str | None:
        return result.unassessable

    def report(self, ctx: Context, room, result: GlareResult) -> dict:
        from en17037cli.criteria.glare.report import glare_section

        return glare_section(ctx.scene, result, self.required(room), self._settings(ctx))

    def illustrate(self, ctx: Context, room, result: GlareResult):
        from typing import cast

        from en17037cli.criteria.view.pictures import room_plan
        from en17037cli.project.settings import ViewSettings

        return room_plan(ctx.scene, room, cast(ViewSettings, _AsView(0.5, 0.5)))  # the plan's outline and windows only


class _AsView:
    """What :func:`~en17037cli.criteria.view.pictures.room_plan` reads of view settings."""

    def __init__(self, wall_margin_m: float, grid_spacing_m: float):
        self.wall_margin_m, self.grid_spacing_m = wall_margin_m, grid_spacing_m
