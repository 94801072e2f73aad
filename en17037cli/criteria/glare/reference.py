"""The reference: evalglare on 180 deg fisheyes rendered by rpict (``-vta``), for the reference check
of the annual method (a few usage hours of the worst view) and for the point-in-time checks.

Reference hours: the usage hours of the worst view whose annual DGP ranks first, at the 95th
percentile (the hour that decides the level), then evenly down to the median, ``reference.hours``
of them; each rendered under that hour's Perez sky (gendaylit of the EPW row's direct normal and
diffuse horizontal irradiance at the hour's middle, the weather file's site and meridian), without
the shading device. Point-in-time checks (``times``): under that hour's Perez sky with a weather
file, else the CIE clear sky with sun (gensky +s) of the location at that moment.
"""
from __future__ import annotations

import numpy as np

from en17037cli import standard
from en17037cli.criteria.glare import engine
from en17037cli.criteria.glare.results import MomentResult, ReferenceHour
from en17037cli.criteria.glare.usage import parse_moment, standard_offset_h, standard_time


def reference_hours(dgp: np.ndarray, k: int, limits: list[float]) -> np.ndarray:
    """Indices of the ``k`` hours the reference check renders, unique, in time order: the hours whose
    annual DGP lies nearest each level's limit (``limits``, the required level's first: where a
    difference would move an hour across the line the 5 % rule counts), then nearest the DGP
    exceeded in 5 % of the hours, then the brightest hour, then evenly down the ranks."""
    n = len(dgp)
    if n == 0 or k <= 0:
        return np.zeros(0, dtype=int)
    targets = [*limits, float(standard.dgp_exceeded(dgp)), float(dgp.max())]
    picked: list[int] = []
    for t in targets:
        free = np.setdiff1d(np.arange(n), picked)
        if len(picked) < k and len(free):
            picked.append(int(free[np.argmin(np.abs(dgp[free] - t))]))
    order = np.argsort(-dgp, kind="stable")
    for q in np.linspace(0.1, 0.9, max(k - len(picked), 0)):  # the rest evenly down the ranks
        i = int(order[int(round(q * (n - 1)))])
        if i not in picked:
            picked.append(i)
    return np.sort(np.array(picked[:k], dtype=int))


def _render(criterion, ctx, octree: str, view, s, name: str):
    """The reference fisheye of ``view`` (rpict), the sun's disc given its energy (:func:`~.engine.sun_corrected`)."""
    octrees = criterion.octrees(ctx)
    r = s.reference
    pic = engine.fisheye(octrees, octree, view.eye, view.direction, r.resolution_px, r.ab, r.ad, r.aa, r.ar, name)
    return engine.sun_corrected(pic, " ".join(engine.view_args(view.eye, view.direction)))[0]


def in_parallel(fn, jobs: list) -> list:
    """``fn(*job)`` for every job on the cores this process may use (each a Radiance program: threads
    only wait for them), results in the jobs' order."""
    from concurrent.futures import ThreadPoolExecutor

    from en17037cli.raytrace import default_threads

    if len(jobs) <= 1:
        return [fn(*j) for j in jobs]
    with ThreadPoolExecutor(max_workers=min(default_threads(), len(jobs))) as pool:
        return list(pool.map(lambda j: fn(*j), jobs))


def reference_check(criterion, ctx, room, vr, clim, s, required: str) -> list[ReferenceHour]:
    """The annual method's DGP and E_v against evalglare's at the reference hours of one view, the
    hours rendered side by side."""
    w = criterion.weather(ctx)
    octrees = criterion.octrees(ctx)
    g = dict(s.reflectance)["ground"]
    limits = s.limits()
    first = limits.get(required, limits["minimum"])
    order = [first] + [v for v in limits.values() if v != first]
    tag = f"ref{room.index}"

    def one(k: int, h: int) -> ReferenceHour:
        row = int(clim.usage.rows[h])
        sky = engine.sky_text("gendaylit", int(w.month[row]), int(w.day[row]), float(w.hour[row]) - 0.5, w.latitude, w.longitude,
                              15.0 * w.tz_hours, ctx.scene.true_north_deg, g, float(np.nan_to_num(w.dni_wh_m2[row])),
                              float(np.nan_to_num(w.dhi_wh_m2[row])))
        octree = octrees.with_sky(sky, name=f"{tag}-{k}")
        pic = _render(criterion, ctx, octree, vr.view, s, f"{tag}-{k}.hdr")
        d, ev = engine.evalglare(pic)
        octrees.drop(octree)
        return ReferenceHour(str(clim.usage.local_start[h]).replace("T", " "), float(vr.dgp_unshaded[h]), d, float(vr.ev_lx[h]), ev)

    hours = reference_hours(vr.dgp_unshaded, s.reference.hours, order)
    return in_parallel(one, [(k, int(h)) for k, h in enumerate(hours)])


def moment_sky(criterion, ctx, text: str, s) -> tuple[str, str]:
    """(sky description, words) of a point-in-time check (module docstring)."""
    loc = ctx.scene.location
    _, local = parse_moment(text, loc.timezone)
    g = dict(s.reflectance)["ground"]
    north = ctx.scene.true_north_deg
    w = criterion.weather(ctx)
    if w is None:
        mo, d, h = standard_time(local)
        return (engine.sky_text("gensky", mo, d, h, loc.latitude, loc.longitude, 15.0 * standard_offset_h(loc.timezone, local.year),
                                north, g), "CIE clear sky with sun (gensky +s)")
    utc = local.timestamp()
    std = utc / 3600.0 + w.tz_hours  # hours since 1970 in the file's standard time
    import datetime as dt

    st = dt.datetime(1970, 1, 1) + dt.timedelta(hours=std)
    rows = np.flatnonzero((w.month == st.month) & (w.day == st.day) & (w.hour == st.hour + 1))
    if not len(rows):
        raise ValueError(f"glare.times: {text}: the weather file has no row for {st:%m-%d %H}:00")
    row = int(rows[0])
    hour = st.hour + st.minute / 60.0
    return (engine.sky_text("gendaylit", st.month, st.day, hour, w.latitude, w.longitude, 15.0 * w.tz_hours, north, g,
                            float(np.nan_to_num(w.dni_wh_m2[row])), float(np.nan_to_num(w.dhi_wh_m2[row]))),
            f"Perez sky of the weather file's hour (gendaylit, direct normal {w.dni_wh_m2[row]:g} W/m², diffuse horizontal "
            f"{w.dhi_wh_m2[row]:g} W/m²)")


def moments(criterion, ctx, room, views, s) -> list[MomentResult]:
    """The point-in-time checks of a room: DGP and E_v by evalglare at every view and time."""
    out = []
    octrees = criterion.octrees(ctx) if s.times else None
    skies = ctx.cache.setdefault("glare_moment_skies", {})
    for text in s.times:  # a few moments, each rendered once per view
        if text not in skies:
            try:
                sky, words = moment_sky(criterion, ctx, text, s)
            except (ValueError, RuntimeError) as exc:  # the sun below the horizon for gendaylit, a missing row
                skies[text] = (None, f"not evaluated: {exc}")
            else:
                skies[text] = (octrees.with_sky(sky, name=f"moment{len(skies)}"), words)
        octree, words = skies[text]
        if octree is None:
            out += [MomentResult(text, v, words, float("nan"), float("nan")) for v in views]
            continue

        def one(k: int, v, text=text, octree=octree, words=words) -> MomentResult:
            pic = _render(criterion, ctx, octree, v, s, f"moment{room.index}-{k}.hdr")
            d, ev = engine.evalglare(pic)
            return MomentResult(text, v, words, d, ev, engine.luminance_picture(pic))

        out += in_parallel(one, list(enumerate(views)))  # the views rendered side by side
    return out
