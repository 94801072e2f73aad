"""The pipeline behind ``en17037 check``: project -> scene -> engines -> report data.

Engines run only for the checks the project asks for; the ray engine's acceleration structures
are built once per run and shared by every check and room.
"""
from __future__ import annotations

import time

from en17037cli import standard, sunlight, view
from en17037cli.raytrace import RayEngine, room_window_group
from en17037cli.scene import build_scene


class Timer:
    """Wall time per stage [s]."""

    def __init__(self):
        self.t = {}
        self._start = time.perf_counter()

    def stage(self, name: str):
        now = time.perf_counter()
        self.t[name] = self.t.get(name, 0.0) + now - self._start
        self._start = now


def run_check(project, only: str | None = None, progress=None) -> dict:
    """Run the checks of ``project``; return the data the report writer formats.

    Parameters
    ----------
    project : Project
    only : ``"view"`` | ``"sunlight"`` | None
    progress : callable(total: int, label: str) -> callable(advance: int), optional
    """
    timer = Timer()
    cfg = project.config
    scene = build_scene(project)
    timer.stage("load")
    engine = RayEngine(scene)
    run_view = "view" in cfg and only in (None, "view")
    run_sun = "sunlight" in cfg and only in (None, "sunlight")
    rooms = []
    try:
        # the acceleration structures the checks will query, built once and shared by every room
        engine.prepare([room_window_group(r) for r in scene.rooms] + (["opaque"] if run_view else [])
                       + (["interior", "sun"] if run_sun else []))
        timer.stage("build")
        view_results = {}
        if run_view:
            planned = {r.name: view.viewpoints(scene, r, cfg["view"], project.view_points.get(r.name)) for r in scene.rooms}
            total = sum(len(p) for groups, _ in planned.values() for _, p in groups)
            advance = progress(total, "view") if progress else None
            for room in scene.rooms:  # one pass per room
                view_results[room.name] = view.assess_room(engine, scene, room, cfg["view"], cfg["thresholds"],
                                                           progress=advance, planned=planned[room.name])
            timer.stage("view")
        sun_results = {}
        if run_sun:
            advance = progress(len(scene.rooms), "sunlight") if progress else None
            for room in scene.rooms:
                sun_results[room.name] = sunlight.assess_room(engine, scene, room, cfg["sunlight"], cfg["location"],
                                                              cfg["thresholds"], room.config.get("sun_points"))
                if advance:
                    advance(1)
            timer.stage("sunlight")
    finally:
        engine.close()
    for room in scene.rooms:
        req = {**cfg["requirements"], **room.config.get("requirements", {})}
        rooms.append({"room": room, "view": view_results.get(room.name), "sunlight": sun_results.get(room.name),
                      "required": req})
    status = overall_status(rooms, cfg["requirements"])
    return {"scene": scene, "rooms": rooms, "status": status, "timer": timer, "rays_traced": engine.rays_traced,
            "ran": {"view": run_view, "sunlight": run_sun}}


def overall_status(rooms: list, requirements: dict) -> str:
    """``pass`` when every required level is met by the checks that ran.

    View: every room. Sunlight: every room (``sunlight_rooms: all``) or at least one (``any``;
    EN 17037 clause 5.3 asks it of at least one habitable room of a dwelling).
    """
    ok = True
    sun_ok = []
    for r in rooms:
        if r["view"] is not None:
            ok &= standard.passes(standard.level_name(r["view"]["level"]), r["required"]["view"])
        if r["sunlight"] is not None:
            sun_ok.append(standard.passes(standard.level_name(r["sunlight"]["level"]), r["required"]["sunlight"]))
    if sun_ok:
        ok &= all(sun_ok) if requirements["sunlight_rooms"] == "all" else any(sun_ok)
    return "pass" if ok else "fail"
