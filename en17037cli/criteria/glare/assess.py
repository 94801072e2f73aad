"""Clause 5.4 for one room: the annual method at each view, the shading device, the level, the
shading a failing room needs, the reference check and the point-in-time checks."""
from __future__ import annotations

import time

import numpy as np

from en17037cli import standard
from en17037cli.criteria.glare import engine
from en17037cli.criteria.glare.annual import Climate, ViewModel, eye_rays, sun_through_glazing
from en17037cli.criteria.glare.results import GlareResult, ViewResult

#: Shading transmittances tried to find the one a failing room needs (control: glare).
TRANSMITTANCES = (0.7, 0.5, 0.35, 0.25, 0.18, 0.12, 0.08, 0.05, 0.03, 0.02, 0.01, 0.005)
#: Student's t at 97.5 % for 1..63 degrees of freedom (2 to 64 replicates), the first few; beyond, 2.0.
T975 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306, 9: 2.262, 10: 2.228}


def mean_and_error(values: np.ndarray) -> tuple[float, float]:
    """Mean of replicates (last axis) and the half-width of its 95 % interval, t s / sqrt(n)."""
    v = np.asarray(values, dtype=float)
    n = v.shape[-1]
    return float(v.mean(axis=-1)), float(T975.get(n - 1, 2.0) * v.std(axis=-1, ddof=1) / np.sqrt(n))


def deployed(dgp_unshaded: np.ndarray, limit: float, control: str) -> np.ndarray:
    """Hours the movable device is down: those over ``limit`` (control ``glare``) or every hour."""
    return np.ones(dgp_unshaded.shape, dtype=bool) if control == "always" else dgp_unshaded > limit


def series(model: ViewModel, shading, limit: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(replicates, h) DGP with the device where deployed, (replicates, h) without, (h,) deployed."""
    raw = model.dgp()
    if shading is None:
        return raw, raw, np.zeros(raw.shape[1], dtype=bool)
    down = deployed(raw.mean(axis=0), limit, shading.control)
    out = raw.copy()
    hours = np.flatnonzero(down)
    if len(hours):
        out[:, hours] = model.dgp(hours, shading.transmittance, shading.sun_transmittance)
    return out, raw, down


def needed_transmittance(models: list[ViewModel], limit: float, sun_hidden: bool = False) -> float | None:
    """The largest of :data:`TRANSMITTANCES` at which every view keeps its DGP at or below ``limit``
    in all but 5 % of the usage hours with the device down when the unshaded DGP exceeds it: a
    neutral filter (the sun's disc seen through it dimmed alike), or with ``sun_hidden`` a device
    through which the sun's disc is not seen (normal-normal transmittance 0: a blind cut off, a
    fabric without openness); None where even the smallest does not."""
    glare = []
    for m in models:  # the unshaded series and its hours over the limit, once
        raw = m.dgp().mean(axis=0)
        glare.append((m, raw, np.flatnonzero(raw > limit)))
    for t in TRANSMITTANCES:  # a dozen values, each vectorised over the hours of glare
        ok = True
        for m, raw, hours in glare:
            s = raw.copy()
            if len(hours):
                s[hours] = m.dgp(hours, t, 0.0 if sun_hidden else None).mean(axis=0)
            ok &= bool(standard.dgp_exceeded(s) <= limit)
        if ok:
            return t
    return None


def annual_views(ctx, settings, room, views, clim: Climate, octrees, octree: str, window_tn, required: str):  # pragma: no mutate block
    """The :class:`ViewResult` of each view and their models (one ray set and sun per eye)."""
    eyes = {}
    for v in views:
        eyes.setdefault(v.position, v.eye)
    traced = eye_rays(octrees, octree, np.array(list(eyes.values())), settings.view_rays, settings.sky_subdivision,
                      (ctx.engine, room))
    rays = dict(zip(eyes, traced))
    share = {k: sun_through_glazing(ctx.engine, ctx.scene, room, eye, clim, window_tn) for k, eye in eyes.items()}
    r = settings.radiance
    dc = engine.eye_coefficients(octrees, octree, np.array([v.eye for v in views]), np.array([v.direction for v in views]),
                                 settings.sky_subdivision, r.ab, r.ad, r.lw, r.replicates)
    limits = settings.limits()
    limit = limits.get(required, limits["minimum"])
    models, out = [], []
    for i, v in enumerate(views):  # a few views per room, each vectorised over the hours
        m = ViewModel(rays[v.position], dc[:, i], v.direction, clim, share[v.position], settings.source_threshold_cd_m2,
                      settings.low_light_correction)
        s, raw, down = series(m, settings.shading, limit)
        e5 = [float(standard.dgp_exceeded(s[k])) for k in range(len(s))]
        mean = s.mean(axis=0)
        d5 = float(standard.dgp_exceeded(mean))
        _, err = mean_and_error(np.array(e5))
        over = {lim: int(np.count_nonzero(mean > lim)) for lim in sorted(set(limits.values()))}
        out.append(ViewResult(v, mean, raw.mean(axis=0), m.ev.mean(axis=0), m.in_view, down, d5, err, over,
                              int(standard.glare_level(d5, limits))))
        models.append(m)
    return out, models


def assess_room(criterion, ctx, room, views, required: str) -> GlareResult:  # pragma: no mutate block
    """Clause 5.4 for ``room`` at ``views`` (see the package docstring)."""
    from en17037cli.criteria.glare.reference import moments, reference_check

    s = criterion.settings(ctx.project)
    t0 = time.perf_counter()
    octrees = criterion.octrees(ctx)
    method = {"annual": "enhanced simplified DGP from daylight coefficients, the sun apart (docs/glare.md)",
              "source_threshold_cd_m2": s.source_threshold_cd_m2, "low_light_correction": s.low_light_correction,
              "view_rays": s.view_rays, "sky_subdivision": s.sky_subdivision,
              "radiance": {"ab": s.radiance.ab, "ad": s.radiance.ad, "lw": s.radiance.lw, "replicates": s.radiance.replicates}}
    res = GlareResult(views=[], level=None, worst=None, usage_local=np.zeros(0, "datetime64[m]"), usage_hours=0, method=method)
    if s.weather is None:
        res.unassessable = "no weather file: the annual method needs glare.weather (an EPW of the site); the point-in-time checks are reported"
    else:
        clim = criterion.climate(ctx)
        octree = criterion.patch_octree(ctx)
        limits = s.limits()
        res.views, models = annual_views(ctx, s, room, views, clim, octrees, octree, criterion.window_tn(ctx, room), required)
        res.usage_local, res.usage_hours = clim.usage.local_start, len(clim.usage)
        res.level = min(v.level for v in res.views)
        res.worst = int(np.argmax([v.dgp_5pct for v in res.views]))
        res.sun_in_view_hours = int(np.any([v.sun_in_view for v in res.views], axis=0).sum())
        res.time_s["annual"] = time.perf_counter() - t0
        need = standard.level_index(required) if required != "none" else 0
        if res.level < need:
            res.transmittance_needed = needed_transmittance(models, limits[required])
            res.transmittance_needed_sun_hidden = needed_transmittance(models, limits[required], sun_hidden=True)
            res.transmittance_tried = TRANSMITTANCES
        t1 = time.perf_counter()
        if s.reference.hours > 0:
            res.reference = reference_check(criterion, ctx, room, res.views[res.worst], clim, s, required)
        res.reference_s = time.perf_counter() - t1
        if res.reference:  # the level the annual series gives moved by the reference's mean difference
            bias = float(np.mean([h.dgp_evalglare - h.dgp_fast for h in res.reference]))
            res.level_reference = min(int(standard.glare_level(standard.dgp_exceeded(np.clip(v.dgp + bias, 0, 1)), limits))
                                      for v in res.views)
        mc = max(v.dgp_5pct_err for v in res.views)
        ref = max((abs(h.dgp_fast - h.dgp_evalglare) for h in res.reference), default=0.0)
        res.error_dgp = float(np.hypot(mc, ref))
        lim = np.array(list(limits.values()))
        res.near_threshold = bool(any(np.any(np.abs(v.dgp_5pct - lim) <= res.error_dgp) for v in res.views)) and res.error_dgp > 0
    t2 = time.perf_counter()
    res.moments = moments(criterion, ctx, room, views, s)
    res.time_s["moments"] = time.perf_counter() - t2
    return res
