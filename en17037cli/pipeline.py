"""Running a project: project settings -> scene -> criteria -> a typed result the reports format.

Criteria run only when the project asks for them (and ``only`` allows); the ray engine's
acceleration structures are built once per run and shared by every criterion and room.
"""
from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

from en17037cli import standard
from en17037cli.criteria import CRITERIA, Context
from en17037cli.project.settings import Project
from en17037cli.raytrace import RayEngine
from en17037cli.scene import build_scene
from en17037cli.scene.model import Room, Scene

#: progress(total, label) -> advance(n): how the CLI draws progress bars
Progress = Callable[[int, str], Callable[[int], None]]


class Timer:
    """Wall time per stage [s]."""

    def __init__(self):
        self.t: dict[str, float] = {}
        self._start = time.perf_counter()

    def stage(self, name: str) -> None:
        now = time.perf_counter()
        self.t[name] = self.t.get(name, 0.0) + now - self._start
        self._start = now


@dataclass
class RoomResult:
    """One room and the result of each criterion that ran (None where it did not)."""

    room: Room
    results: dict[str, object]

    def level(self, criterion: str) -> str | None:
        r = self.results.get(criterion)
        return None if r is None else standard.level_name(CRITERIA[criterion].level(r))

    def required(self, criterion: str) -> str:
        return CRITERIA[criterion].required(self.room)


@dataclass
class RunResult:
    """Everything a run found: the scene, per-room results, the verdict, what ran and what it cost."""

    project: Project
    scene: Scene
    rooms: list[RoomResult]
    status: str
    checks_run: list[str]
    rays_traced: int
    context: Context
    timer: Timer = field(default_factory=Timer)


def overall_status(rooms: list[RoomResult], requirements) -> str:
    """``pass`` when every required level is met by the checks that ran.

    View: every room. Sunlight: every room or at least one, by ``requirements.sunlight_rooms``
    (:func:`~en17037cli.standard.sunlight_rooms_pass`).
    """
    ok = True
    sun_ok = []
    for r in rooms:
        view, sun = r.level("view"), r.level("sunlight")
        if view is not None:
            ok &= standard.passes(view, r.required("view"))
        if sun is not None:
            sun_ok.append(standard.passes(sun, r.required("sunlight")))
    ok &= standard.sunlight_rooms_pass(sun_ok, requirements.sunlight_rooms)
    return "pass" if ok else "fail"


def run(project: Project, only: str | None = None, progress: Progress | None = None) -> RunResult:
    """Run the checks of ``project``.

    Parameters
    ----------
    only : a criterion name (``view``, ``sunlight``), or None for every criterion the project asks for
    progress : optional progress-bar factory (see :data:`Progress`)
    """
    timer = Timer()
    scene = build_scene(project)
    timer.stage("load")
    chosen = [c for name, c in CRITERIA.items() if c.settings(project) is not None and only in (None, name)]
    results: dict[str, dict[str, object]] = {}
    with RayEngine(scene.vertices, scene.triangles, scene.ray_groups()) as engine:
        ctx = Context(project, scene, engine)
        groups = [g for c in chosen for g in c.ray_groups(scene)]
        engine.prepare(list(dict.fromkeys(groups)))  # built once, shared by every criterion and room
        timer.stage("build")
        for c in chosen:
            plans = {room.name: c.plan(ctx, room) for room in scene.rooms}
            advance = progress(sum(c.size(p) for p in plans.values()), c.name) if progress else None
            results[c.name] = {room.name: c.assess(ctx, room, plans[room.name], advance) for room in scene.rooms}
            timer.stage(c.name)
    rooms = [RoomResult(room, {name: results.get(name, {}).get(room.name) for name in CRITERIA}) for room in scene.rooms]
    return RunResult(project=project, scene=scene, rooms=rooms, status=overall_status(rooms, project.requirements),
                     checks_run=[c.name for c in chosen], rays_traced=engine.rays_traced, timer=timer, context=ctx)
