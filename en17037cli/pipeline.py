"""Running a project: project settings -> scene -> criteria -> a typed result the reports format.

A run reads the scene, holds it to the budget (:mod:`en17037cli.budget`), builds one ray engine,
finds what it can before the criteria (:func:`before_criteria`: the budget, then the preflight and
each criterion's own input checks), then assesses each room with each criterion. Criteria run only
when the project asks for them (and ``only`` allows); the ray engine's acceleration structures are
built once per run (a :class:`Session`) and shared by every criterion and room.
"""
from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

from en17037cli import standard
from en17037cli.budget import ANNOUNCE_S, MAX_POINTS, Cost, check_budget, estimate_seconds, reading_note
from en17037cli.criteria import CRITERIA, Context, Criterion, Unassessed
from en17037cli.dwellings import Dwelling
from en17037cli.errors import NotAssessable
from en17037cli.preflight import Preflight, preflight
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
    """One room and the result of each criterion: a typed result, an :class:`Unassessed`, or None
    (not run and not required)."""

    room: Room
    results: dict[str, object]
    #: wall time of each criterion on the room [s] (for the batch summary and JUnit, not report.json)
    time_s: dict[str, float] = field(default_factory=dict)
    illustrations: dict[str, object] = field(default_factory=dict)  # criterion -> picture data, when asked

    def assessed(self, criterion: str):
        """The criterion's typed result, or None where it did not assess the room."""
        r = self.results.get(criterion)
        return None if r is None or isinstance(r, Unassessed) else r

    def level(self, criterion: str) -> str | None:
        r = self.assessed(criterion)
        if r is None or CRITERIA[criterion].unassessable(r) is not None or self.room.withheld is not None:
            return None
        return standard.level_name(CRITERIA[criterion].level(r))

    def level_without_withheld(self, criterion: str) -> str | None:
        """The level computed for a room whose verdict is withheld (:attr:`Room.withheld`): a lower
        bound, reached without its quarantined windows; None elsewhere."""
        r = self.assessed(criterion)
        if self.room.withheld is None or r is None or CRITERIA[criterion].unassessable(r) is not None:
            return None
        return standard.level_name(CRITERIA[criterion].level(r))

    def required(self, criterion: str) -> str:
        return CRITERIA[criterion].required(self.room)

    def status(self, criterion: str) -> str | None:
        """``pass``, ``fail``, ``not_assessed``, ``not_assessable``, or None (not run, not required)."""
        r = self.results.get(criterion)
        if isinstance(r, Unassessed):
            return r.status
        if r is not None and (CRITERIA[criterion].unassessable(r) is not None or self.room.withheld is not None):
            return "not_assessable"
        level = self.level(criterion)
        return None if level is None else standard.status(level, self.required(criterion))


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
    warnings: list[str] = field(default_factory=list)
    dwellings: list[DwellingResult] = field(default_factory=list)
    timer: Timer = field(default_factory=Timer)


@dataclass
class DwellingResult:
    """The sunlight rule of one dwelling (EN 17037 clause 5.3, per ``requirements.sunlight_rooms``).

    status : ``pass``, ``fail``, or None where none of its rooms requires sunlight
    room : the main room that satisfies the rule (the sunniest that passes), else the best main
        room (most hours on its assessed day) and ``shortfall_h`` [h] below its required level
    """

    dwelling: Dwelling
    status: str | None
    room: str | None
    hours: float | None
    required: str | None
    shortfall_h: float | None


def assess_dwelling(d: Dwelling, rooms: dict[str, RoomResult], rule: str, thresholds) -> DwellingResult:
    """Whether a dwelling meets the sunlight rule: ``any`` of its main rooms, or ``all`` its rooms."""
    judged = list(d.main_rooms) if rule == "any" else list(d.rooms)
    statuses = {n: rooms[n].status("sunlight") for n in judged}
    required = [n for n in judged if statuses[n] is not None]
    if not required:
        return DwellingResult(d, None, None, None, None, None)
    ok = standard.sunlight_rooms_pass([statuses[n] == "pass" for n in required], rule)
    hours = {n: float(r.hours[r.assessed_index]) for n in required if (r := rooms[n].assessed("sunlight")) is not None}
    passing = [n for n in required if statuses[n] == "pass"]
    if rule == "any":
        pool = passing if ok else list(hours)
        room = max(pool, key=lambda n: hours.get(n, -1.0)) if pool else required[0]
    else:  # 'all': the room that limits the dwelling
        failing = [n for n in required if statuses[n] != "pass"]
        pool = failing or list(hours)
        room = min(pool, key=lambda n: hours.get(n, -1.0)) if pool else required[0]
    need = rooms[room].required("sunlight")
    h = hours.get(room)
    short = None
    if not ok and h is not None and need != "none":
        short = max(getattr(thresholds.sunlight_hours, need) - h, 0.0)
    return DwellingResult(d, "pass" if ok else "fail", room, h, need, short)


def overall_status(rooms: list[RoomResult], dwellings: list[DwellingResult], required: tuple[str, ...] = (),
                   spaces_left_out: int = 0) -> str:
    """``pass`` when every required level is met: view, daylight and glare in every room, sunlight in
    every dwelling. A required criterion that did not assess a room (not assessed, not assessable) does
    not meet its requirement. Never a pass on nothing: each criterion in ``required`` (the project
    asks a level of it) must have assessed at least one room, and no space of the model with a
    window may have been left out (``spaces_left_out``: a space the project picked that opens onto
    a window but could not be made a room)."""
    ok = all(r.status(c) in (None, "pass") for r in rooms for c in ("view", "daylight", "glare"))
    ok &= all(d.status in (None, "pass") for d in dwellings)
    ok &= all(any(r.status(c) in ("pass", "fail") for r in rooms) for c in required)
    ok &= spaces_left_out == 0
    return "pass" if ok else "fail"


def required_criteria(project: Project) -> tuple[str, ...]:
    """The criteria of which some room entry of the project asks a level."""
    return tuple(c for c in CRITERIA if any(getattr(spec.requirements, c) != "none" for spec in project.rooms))


def _unrun(project: Project, only: str | None):
    """The results of the criteria that do not run: ``not_assessed`` where a room requires them."""
    out: dict[str, dict[str, object]] = {}
    for name, c in CRITERIA.items():
        if c.settings(project) is not None and only in (None, name):
            continue
        reason = f"the project has no '{name}' section" if c.settings(project) is None else f"--only {only} left it out"
        out[name] = {}
        for spec in project.rooms:
            required = getattr(spec.requirements, name)
            if required != "none":
                out[name][spec.name] = Unassessed("not_assessed", reason)
    return out


def _assess(c: Criterion, ctx: Context, room: Room, plan, advance):
    if room.problem is not None:
        return Unassessed("not_assessable", room.problem)
    if isinstance(plan, Unassessed):
        return plan
    try:
        return c.assess(ctx, room, plan, advance)
    except NotAssessable as exc:
        return Unassessed("not_assessable", str(exc))


def _plan(c: Criterion, ctx: Context, room: Room):
    if room.problem is not None:
        return None
    try:
        return c.plan(ctx, room)
    except NotAssessable as exc:
        return Unassessed("not_assessable", str(exc))


def before_criteria(ctx: Context, max_points: int = MAX_POINTS) -> tuple[Cost, Preflight]:
    """What a run finds before its criteria, in order: its size against the budget (an input error
    over it, before any ray: :func:`~en17037cli.budget.check_budget`), then the preflight (warnings,
    dwellings, each criterion's input checks, the windows no ray leaves through:
    :func:`~en17037cli.preflight.preflight`). ``check`` (a :class:`Session`) and ``validate`` both
    call it, so ``validate`` says what ``check`` will say."""
    cost = check_budget(ctx.project, ctx.scene, max_points)
    return cost, preflight(ctx)


@dataclass
class RoomAssessment:
    """What assessing one room produced: each chosen criterion's result, its wall time [s] and the
    rays it traced. Plain data, so that a batch worker can send it to another process."""

    results: dict[str, object] = field(default_factory=dict)
    time_s: dict[str, float] = field(default_factory=dict)
    rays: int = 0


class Session:
    """A project opened for assessment: its scene, its ray engine with the acceleration structures
    built, and the preflight, ready to assess any of its rooms.

    :func:`run` opens one and assesses every room. A batch worker (:mod:`en17037cli.batch`) opens
    one per project and reuses it for each group of rooms it is given; the assessments of every
    room, from however many sessions of the same project, give the same :class:`RunResult` as
    :func:`run` (a room's result depends on nothing but the project and the room).

    Parameters
    ----------
    only : a criterion name (``view``, ``sunlight``), or None for every criterion the project asks for
    max_points : the viewpoint budget (see :func:`~en17037cli.budget.check_budget`)
    threads : ray-tracing threads (see :class:`~en17037cli.raytrace.RayEngine`)

    Raises :class:`~en17037cli.errors.InputError` for bad input, before any criterion. Use as a
    context manager, or call :meth:`close`, to stop the engine's threads.
    """

    def __init__(self, project: Project, only: str | None = None, max_points: int = MAX_POINTS,
                 threads: int | None = None):
        self.project, self.only = project, only
        self.timer = Timer()
        self.scene = build_scene(project)
        self.timer.stage("load")
        self.chosen = [c for name, c in CRITERIA.items() if c.settings(project) is not None and only in (None, name)]
        self.engine = RayEngine(self.scene.vertices, self.scene.triangles, self.scene.ray_groups(), threads=threads)
        try:
            self.context = Context(project, self.scene, self.engine)
            self.cost, self.checks = before_criteria(self.context, max_points)  # input errors stop the run here, before any criterion
            groups = [g for c in self.chosen for g in c.ray_groups(self.scene)]
            self.engine.prepare(list(dict.fromkeys(groups)))  # built once, shared by every criterion and room
        except BaseException:
            self.engine.close(wait=False)
            raise
        self.preflight_rays = self.engine.rays_traced
        self.timer.stage("build")
        self._rooms = {room.name: room for room in self.scene.rooms}

    def __enter__(self) -> Session:
        return self

    def __exit__(self, exc_type, *exc) -> None:
        self.close(wait=exc_type is None)

    def close(self, wait: bool = True) -> None:
        """End the engine's threads (``wait``: for the chunks they trace; not when an exception ends the run)."""
        self.engine.close(wait)

    @property
    def room_names(self) -> list[str]:
        """The project's rooms, in report order."""
        return [room.name for room in self.scene.rooms]

    def assess(self, rooms: list[str] | None = None, progress: Progress | None = None) -> dict[str, RoomAssessment]:
        """Assess ``rooms`` (names; default every room, in report order) with each chosen criterion.

        The filter is how a batch spreads one project over several workers: each assesses a part
        of its rooms and :meth:`result` joins them.
        """
        names = self.room_names if rooms is None else list(rooms)
        unknown = [n for n in names if n not in self._rooms]
        if unknown:
            raise KeyError(f"no room named {unknown[0]!r} in {self.project.path.name}")
        out = {n: RoomAssessment() for n in names}
        ctx, engine = self.context, self.engine
        for c in self.chosen:
            plans = {}
            for n in names:
                rays = engine.rays_traced
                plans[n] = _plan(c, ctx, self._rooms[n])
                out[n].rays += engine.rays_traced - rays
            size = sum(c.size(p) for p in plans.values() if p is not None and not isinstance(p, Unassessed))
            advance = progress(size, c.name) if progress else None
            for n in names:
                t, rays = time.perf_counter(), engine.rays_traced
                out[n].results[c.name] = _assess(c, ctx, self._rooms[n], plans[n], advance)
                out[n].time_s[c.name] = time.perf_counter() - t
                out[n].rays += engine.rays_traced - rays
            self.timer.stage(c.name)
        return out

    def illustrate(self, result: RunResult) -> None:
        """What the report's pictures need of each assessed room (:meth:`Criterion.illustrate`), into
        ``RoomResult.illustrations``; traced now, while the engine is open, and not counted in
        ``rays_traced`` (the pictures are not part of the check)."""
        for r in result.rooms:
            for c in self.chosen:
                res = r.assessed(c.name)
                if res is not None:
                    r.illustrations[c.name] = c.illustrate(self.context, r.room, res)
        self.timer.stage("pictures")

    def result(self, assessed: dict[str, RoomAssessment], timer: Timer | None = None) -> RunResult:
        """The run's result from the assessments of every room of the project (from this session or
        others of the same project), the dwellings judged and the verdict; ``timer`` defaults to
        this session's."""
        unrun = _unrun(self.project, self.only)
        chosen = [c.name for c in self.chosen]
        rooms = []
        for room in self.scene.rooms:
            a = assessed[room.name]
            results = {name: a.results.get(name) if name in chosen else unrun.get(name, {}).get(room.name) for name in CRITERIA}
            rooms.append(RoomResult(room, results, dict(a.time_s)))
        by_name = {r.room.name: r for r in rooms}
        project = self.project
        dwellings = [assess_dwelling(d, by_name, project.requirements.sunlight_rooms, project.thresholds)
                     for d in self.checks.dwellings]
        rays = self.preflight_rays + sum(a.rays for a in assessed.values())
        left = sum(1 for lo in self.scene.left_out if lo.windows)
        status = overall_status(rooms, dwellings, required_criteria(project), left)
        return RunResult(project=project, scene=self.scene, rooms=rooms, status=status,
                         dwellings=dwellings, checks_run=chosen, rays_traced=rays, context=self.context,
                         warnings=self.checks.warnings, timer=timer or self.timer)


def run(project: Project, only: str | None = None, progress: Progress | None = None,
        max_points: int = MAX_POINTS, threads: int | None = None, pictures: bool = False,
        notify: Callable[[str], None] | None = None) -> RunResult:
    """Run the checks of ``project``: open a :class:`Session` and assess every room.

    Parameters
    ----------
    only : a criterion name (``view``, ``sunlight``), or None for every criterion the project asks for
    progress : optional progress-bar factory (see :data:`Progress`)
    max_points : the viewpoint budget (see :func:`~en17037cli.budget.check_budget`)
    threads : ray-tracing threads [default: ``EN17037_THREADS``, else every core]
    pictures : also trace what the report's pictures need (:meth:`Criterion.illustrate`), stage ``pictures``
    notify : optional ``notify(line)``: told what a long run is about to do (a large model read, the
        estimated time of the criteria: :func:`~en17037cli.budget.estimate_seconds`)
    """
    if notify is not None and (note := reading_note(project)) is not None:
        notify(note)
    with Session(project, only, max_points, threads) as session:
        if notify is not None:
            est = estimate_seconds(project, session.scene, session.cost)
            chosen = {c.name for c in session.chosen}
            total = sum(v for k, v in est.items() if k in chosen)
            if total > ANNOUNCE_S:
                parts = ", ".join(f"{k} ~{v:.0f} s" for k, v in est.items() if k in chosen)
                n = len(session.scene.rooms)
                notify(f"{n} room{'s' * (n != 1)}, {session.cost.points:,} viewpoints, "
                       f"{session.cost.cells / 1e6:,.1f} M view cells: about {total:.0f} s of work ({parts}; a rough "
                       "estimate, the progress shows the time left)")
        result = session.result(session.assess(progress=progress))
        if pictures:
            session.illustrate(result)
        return result
