"""Clause 5.4 under the choices the standard leaves open, for ``en17037 study sensitivity``: where the
critical positions are (distance from the facade, eye height, view directions), the usage time, and
the DGP's own open settings (low-light correction, glare-source threshold, sky subdivision).

Each value is assessed again on the same scene and ray engine; the glare scene's octree is compiled
once and shared, and the reference check and the point-in-time checks (which do not move the level)
are left out of the variants.
"""
from __future__ import annotations

import dataclasses

from en17037cli.criteria.glare.report import glare_score
from en17037cli.project.glare_settings import clock_hours, usage_days

#: The values tried (``study sensitivity``'s ranges; a project's ``sensitivity.ranges`` replaces them).
GLARE_RANGES: dict[str, tuple] = {
    "glare.facade_distance_m": (0.5, 2.0),
    "glare.eye_height_m": (1.7,),
    "glare.directions": (("towards",), ("parallel",)),
    "glare.usage": ("07:00-17:00", "09:00-19:00", "all days"),
    "glare.low_light_correction": (True,),
    "glare.source_threshold_cd_m2": (1000.0, 4000.0),
    "glare.sky_subdivision": (2,),
}
#: How the tables and charts name each choice.
GLARE_LABELS = {"glare.facade_distance_m": "distance from the facade", "glare.eye_height_m": "eye height (glare)",
                "glare.directions": "view directions", "glare.usage": "usage time",
                "glare.low_light_correction": "low-light correction", "glare.source_threshold_cd_m2": "glare-source threshold",
                "glare.sky_subdivision": "sky subdivision (glare)"}


def variant(settings, key: str, value):
    """The glare settings with one choice set to ``value``, or None where that is the project's own
    (or where it does not apply: positions listed in the project file have no distance or height)."""
    field = key.split(".", 1)[1]
    if field in ("facade_distance_m", "eye_height_m", "directions") and settings.positions is not None:
        return None
    if field == "usage":
        if value == "all days":
            new = {"usage_days": usage_days("all")}
        else:
            start, end = value.split("-")
            new = {"usage_start_h": clock_hours(start), "usage_end_h": clock_hours(end)}
    elif field == "directions":
        new = {"directions": tuple(value)}
    else:
        new = {field: value}
    if all(getattr(settings, k) == v for k, v in new.items()):
        return None
    return dataclasses.replace(settings, **new)


def glare_outcomes(project, scene, engine, ranges: dict, log=print) -> tuple[list[tuple[str, str, str, int, float]], float]:
    """(room, choice, value, level, score) of the project's own glare settings (choice ``default``)
    and of each value of :data:`GLARE_RANGES` (or ``ranges``'s glare keys); and the time of the
    project's own settings [s] (the scene compiled for every variant included)."""
    import time

    from en17037cli.criteria import CRITERIA, Context
    from en17037cli.errors import NotAssessable

    c = CRITERIA["glare"]
    base = dataclasses.replace(project.glare, times=(), reference=dataclasses.replace(project.glare.reference, hours=0))
    shared: dict = {}

    def run(settings) -> dict:
        ctx = Context(dataclasses.replace(project, glare=settings), scene, engine)
        for key in ("glare_octrees", "glare_patch_octree", "glare_weather"):  # the scene compiled once for every variant
            if key in shared:
                ctx.cache[key] = shared[key]
        out = {}
        for room in scene.rooms:
            if room.problem is not None:
                continue
            try:
                res = c.assess(ctx, room, c.plan(ctx, room))
            except NotAssessable:
                continue
            if res.level is not None and res.worst is not None:
                out[room.name] = (res.level, glare_score(res.views[res.worst].dgp_5pct, settings.limits())["value"])
        for key in ("glare_octrees", "glare_patch_octree", "glare_weather"):
            shared.setdefault(key, ctx.cache.get(key))
        return out

    if project.glare.weather is None:
        return [], 0.0
    t0 = time.perf_counter()
    rows = [(name, "default", "project", lv, sc) for name, (lv, sc) in run(base).items()]
    base_s = time.perf_counter() - t0
    log(f"  glare with the project's own settings: {base_s:.2f} s")
    for key in GLARE_RANGES:
        for value in ranges.get(key, GLARE_RANGES[key]):
            settings = variant(base, key, tuple(value) if isinstance(value, list) else value)
            if settings is None:
                continue
            t = time.perf_counter()
            text = "+".join(value) if isinstance(value, (tuple, list)) else (f"{value:g}" if isinstance(value, float) else str(value))
            rows += [(name, key, text, lv, sc) for name, (lv, sc) in run(settings).items()]
            log(f"  {key} = {text}: {time.perf_counter() - t:.2f} s")
    return rows, base_s
