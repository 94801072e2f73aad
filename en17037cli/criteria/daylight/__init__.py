"""EN 17037 clause 5.1, Daylight provision: the reference plane's daylight factor (method 1) or its
hourly illuminance over the daylight hours (method 2), split as the standard's method splits it:

* the sky component (light straight from the sky through the glazing), exact, with a bound:
  :mod:`.sky_component` (the view engine's exact visibility and refinement, the CIE overcast
  luminance and the glazing's angular transmittance of :mod:`.sky`);
* the externally and internally reflected components on Radiance (pyradiance), with a statistical
  interval: :mod:`.gather` (the scene as Radiance geometry and the runs: :mod:`.radiance`);
* method 1: :func:`.assess.daylight_factor_room`; method 2: :mod:`.climate`; the weather:
  :mod:`en17037cli.weather.epw`; per room into :mod:`.results`; report section: :mod:`.report`

pyradiance is imported only when a project has a ``daylight`` section and the check runs.
"""
from __future__ import annotations

import time

import numpy as np

from en17037cli.criteria.base import Context, Criterion, room_thresholds
from en17037cli.criteria.daylight.assess import daylight_factor_room, reference_plane
from en17037cli.criteria.daylight.results import DaylightResult
from en17037cli.errors import InputError
from en17037cli.project.settings import DaylightSettings, Project
from en17037cli.scene.model import room_window_group

#: Horizontal illuminance of the overcast sky the daylight factors are computed under [lx]
#: (any value: D is a ratio; 10 klx keeps Radiance's numbers near 1).
SKY_LX = 10000.0


class DaylightCriterion(Criterion):
    name = "daylight"
    title = "daylight provision (5.1)"

    def settings(self, project: Project) -> DaylightSettings | None:
        return project.daylight

    def _settings(self, ctx: Context) -> DaylightSettings:
        if ctx.project.daylight is None:
            raise ValueError("the daylight criterion runs only on projects with a daylight section")
        return ctx.project.daylight

    def ray_groups(self, scene):
        return [room_window_group(r) for r in scene.rooms] + ["opaque"]  # the sky component's visibility

    def check_inputs(self, ctx: Context) -> dict[str, str]:
        from en17037cli.criteria.daylight.radiance import binpath

        binpath()  # the extra is installed, or an input error saying how
        self.median(ctx)  # the weather file reads
        return self.unplannable(ctx)

    def plan(self, ctx: Context, room):
        plans = ctx.cache.setdefault("daylight_plans", {})
        if room.name not in plans:
            plans[room.name] = reference_plane(room, self._settings(ctx))
        return plans[room.name]

    def size(self, plan) -> int:
        return len(plan)

    def weather(self, ctx: Context):
        s = self._settings(ctx)
        if s.weather is None:
            return None
        if "daylight_weather" not in ctx.cache:
            from en17037cli.weather.epw import read_epw

            ctx.cache["daylight_weather"] = read_epw(s.weather, f"{ctx.project.path.name}: daylight.weather")
        return ctx.cache["daylight_weather"]

    def median(self, ctx: Context) -> tuple[float, str]:
        """E_v,d,med [lx] and where it came from."""
        s = self._settings(ctx)
        if s.median_diffuse_lx is not None:
            return s.median_diffuse_lx, "daylight.median_diffuse_lx"
        w = self.weather(ctx)
        if w is None:
            raise InputError(f"{ctx.project.path.name}: daylight: give median_diffuse_lx or weather")
        return w.median_diffuse_lx(), f"median diffuse horizontal illuminance of the 4380 daylight hours of {s.weather_display}"

    def octree(self, ctx: Context, kind: str = "overcast"):
        """The scene with its sky, compiled once per run (``overcast``, ``sky`` patches, ``black``)."""
        key = f"daylight_octree_{kind}"
        if key not in ctx.cache:
            pending = ctx.cache.pop(f"{key}_pending", None)  # started by :meth:`octree_soon`
            ctx.cache[key] = pending.result() if pending is not None else self._build_octree(ctx, kind)
        return ctx.cache[key]

    def octree_soon(self, ctx: Context, kind: str = "overcast") -> None:
        """Start compiling :meth:`octree` in a thread (``oconv`` runs while Python integrates the sky
        component); :meth:`octree` waits for it."""
        key = f"daylight_octree_{kind}"
        if key in ctx.cache or f"{key}_pending" in ctx.cache:
            return
        from concurrent.futures import ThreadPoolExecutor

        pool = ThreadPoolExecutor(1)
        ctx.cache[f"{key}_pending"] = pool.submit(self._build_octree, ctx, kind)
        pool.shutdown(wait=False)

    def _build_octree(self, ctx: Context, kind: str):
        from en17037cli.criteria.daylight import radiance

        s = self._settings(ctx)
        refl = dict(s.reflectance)
        t = time.perf_counter()
        scene = radiance.scene_text(ctx.scene, refl, s.glazing_transmittance, black=kind == "black")
        files = None
        if kind == "overcast":
            sky, files = radiance.cie_overcast_sky_text(SKY_LX, refl["ground"]), radiance.sky_files()
        else:
            from en17037cli.criteria.daylight.climate import patch_sky_text, sink_point

            sky = patch_sky_text(sink_point(ctx.scene))
        octree = radiance.Octree(scene, sky, files=files)
        ctx.cache["daylight_build_s"] = ctx.cache.get("daylight_build_s", 0.0) + time.perf_counter() - t
        return octree

    def sky(self, ctx: Context, room, points, bins=None, nbins: int = 0):
        """The sky component of ``points`` (p, 3) [m, local] through ``room``'s windows (:mod:`.sky_component`;
        ``bins``, ``nbins``: also per sky patch)."""
        from en17037cli.criteria.daylight.sky_component import SkyTolerance, sky_component
        from en17037cli.criteria.view.frames import room_geometry
        from en17037cli.criteria.view.rays import ViewRays

        c = self._settings(ctx).sky_component
        tol = SkyTolerance(c.resolution_deg, c.refine_levels, c.rel_tolerance, c.abs_tolerance_pct / 100.0)
        rg = room_geometry(ctx.scene, room, tol.frame_depth_m)
        return sky_component(ViewRays(ctx.engine, ctx.scene), rg, points, self.window_tv(ctx, room), tol,
                             bins=bins, nbins=nbins)

    def window_tv(self, ctx: Context, room):
        """(windows,) transmittance of each of ``room``'s windows (:func:`.sky_component.window_transmittance`)."""
        from en17037cli.criteria.daylight.sky_component import window_transmittance

        s = self._settings(ctx)
        return window_transmittance(ctx.scene, room, dict(s.reflectance), s.glazing_transmittance)


    def reflected(self, ctx: Context, room, points, sky=None):
        """The reflected components at ``points``: light paths with next-event estimation through the
        room's windows, what is outside from Radiance (:mod:`.transport`, :func:`.gather.reflected_paths`);
        with the points' sky component ``sky`` (or a function giving it), a point stops early once its
        D is clear of every threshold of Table A.1."""
        from en17037cli.criteria.daylight.assess import targets
        from en17037cli.criteria.daylight.gather import reflected_paths, sampling_frame

        median, _ = self.median(ctx)
        et, etm = targets(room_thresholds(ctx.project, room))
        thresholds = sorted({v / median for v in (*et.values(), *etm.values()) if v > 0})  # 0 lx: reached, never flips
        if sky is None or not self._settings(ctx).radiance.stop_clear_of_thresholds:
            known = None
        elif callable(sky):  # computed in another thread meanwhile

            def known():
                sc = sky()
                return sc.value, sc.bound
        else:
            known = (sky.value, sky.bound)
        return reflected_paths(self.paths_scene(ctx, room), self.octree(ctx), points, SKY_LX, self.gather_settings(ctx),
                               sampling_frame(room.windows[0].normal), ctx.engine.threads, known, thresholds)

    def gather_settings(self, ctx: Context):
        from en17037cli.criteria.daylight.gather import GatherSettings

        p = self._settings(ctx).radiance
        return GatherSettings(p.rays, p.max_rays, p.rel_tolerance, p.abs_tolerance_pct / 100.0, p.ab, p.ad, p.lw,
                              p.window_rays)

    def paths_scene(self, ctx: Context, room):
        """The light paths' view of the scene for ``room`` (:class:`.transport.Scene`)."""
        from en17037cli.criteria.daylight import radiance
        from en17037cli.criteria.daylight.transport import Scene
        from en17037cli.criteria.view.frames import window_frame

        s = self._settings(ctx)
        kind, value = radiance.face_optics(ctx.scene, dict(s.reflectance), s.glazing_transmittance)
        rho = np.where(kind == 5, 0.0, value)
        tv = np.where(kind == 5, value, 0.0)
        return Scene(ctx.engine, ctx.scene, room, rho, tv, [window_frame(w, i) for i, w in enumerate(room.windows)],
                     s.radiance.window_rays)

    def assess(self, ctx: Context, room, plan, progress=None) -> DaylightResult:
        s = self._settings(ctx)
        median, source = self.median(ctx)
        p = s.radiance
        params = {"ab": p.ab, "ad": p.ad, "as": p.as_, "lw": p.lw, "rays": p.rays, "max_rays": p.max_rays,
                  "rel_tolerance": p.rel_tolerance, "abs_tolerance_pct": p.abs_tolerance_pct, "window_rays": p.window_rays,
                  "stop_clear_of_thresholds": p.stop_clear_of_thresholds}
        t = time.perf_counter()
        if s.method == "daylight_factor":
            self.octree_soon(ctx)
            # the sky component in a second thread while the first round of light paths runs (its
            # rtrace is a separate program): the reflected part needs the sky component only to stop
            # points early, after that round; the numbers are those of one after the other
            from concurrent.futures import ThreadPoolExecutor

            def timed_sky():
                t0 = time.perf_counter()
                return self.sky(ctx, room, plan), time.perf_counter() - t0

            with ThreadPoolExecutor(1) as pool:
                job = pool.submit(timed_sky)
                refl = self.reflected(ctx, room, plan, lambda: job.result()[0])
                sc, t_sky = job.result()
            res = daylight_factor_room(plan, sc, refl, median, source, room_thresholds(ctx.project, room), params)
            res.radiance["sky_time_s"] = t_sky
        else:
            from en17037cli.criteria.daylight.climate import climate_room

            res = climate_room(self, ctx, room, plan, s, median, source, params)
        res.radiance["time_s"] = time.perf_counter() - t
        if progress:
            progress(len(plan))
        return res

    def illustrate(self, ctx: Context, room, result: DaylightResult):
        from en17037cli.criteria.view.pictures import room_plan

        s = self._settings(ctx)
        plan = room_plan(ctx.scene, room, _AsView(s.wall_margin_m, s.grid_spacing_m))
        return plan

    def level(self, result: DaylightResult) -> int:
        return result.level

    def report(self, ctx: Context, room, result: DaylightResult) -> dict:
        from en17037cli.criteria.daylight.report import daylight_section

        return daylight_section(ctx.scene, result, self.required(room), self._settings(ctx),
                                room_thresholds(ctx.project, room))


class _AsView:
    """What :func:`~en17037cli.criteria.view.pictures.room_plan` reads of view settings, from the daylight grid's."""

    def __init__(self, wall_margin_m: float, grid_spacing_m: float):
        self.wall_margin_m, self.grid_spacing_m = wall_margin_m, grid_spacing_m
