"""The report's pictures, drawn from a run's results: which picture each room gets, its file name and
caption. Traces nothing: the values come from the criteria's results and illustrations
(:meth:`~en17037cli.criteria.base.Criterion.illustrate`), the drawing from :mod:`.pictures`.

Per room: for each eye height, plan maps of the horizontal sight angle, the outside distance, the
layers seen and the view level (points near a threshold ringed); the hours of sunlight per day of
the period; per window with a point P, the fisheye with the sun's paths. File names are stable
(``figures/<room>-...png``), so two runs of the same inputs give the same names and bytes.
"""
from __future__ import annotations

import re
import signal
from dataclasses import dataclass

import numpy as np

from en17037cli.criteria.base import room_thresholds
from en17037cli.pipeline import RunResult

#: Sub-folder of the report folder holding the PNG files.
FIGURES_DIR = "figures"

#: Plan-map kinds in the order they are shown, with their captions.
MAP_KINDS = {"sight_angle": "horizontal sight angle", "distance": "outside distance", "layers": "layers seen",
             "level": "view level"}


@dataclass(frozen=True)
class Figure:
    """One picture: its file name in the report folder, the room and section it belongs to, a
    caption, the PNG bytes (report.md, figures/) and the SVG (report.html: vector, text as text)."""

    name: str
    room: str
    section: str  # "view", "sunlight", "daylight" or "glare"
    caption: str
    png: bytes
    svg: bytes = b""
    print_: bool = True  # printed with report.html (False: on screen only)


def room_slug(index: int, name: str) -> str:
    """A file-name stem for a room: its position and a lower-case ASCII form of its name."""
    s = re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")[:40]
    return f"{index + 1:02d}-{s or 'room'}"


def _layer_mask(visible: dict) -> np.ndarray:
    from en17037cli.report.pictures.colours import GROUND, LANDSCAPE, SKY

    return (visible["sky"] * SKY + visible["landscape"] * LANDSCAPE + visible["ground"] * GROUND).astype(float)


@dataclass(frozen=True)
class Job:
    """One picture to draw: its :class:`Figure` fields and the drawing call (a function of
    :mod:`en17037cli.report.pictures` by name, with plain arguments), so any process can draw it."""

    name: str
    room: str
    section: str
    caption: str
    draw: str  # "plan_map" | "hours_chart" | "fisheye"
    args: tuple
    kwargs: dict
    print_: bool = True


def draw(job: Job) -> Figure:
    """Draw one job into a :class:`Figure`."""
    from en17037cli.report import pictures

    png, svg = getattr(pictures, job.draw)(*job.args, **job.kwargs, fmt="both")
    return Figure(job.name, job.room, job.section, job.caption, png, svg, job.print_)


#: View criterion (as results name them) -> the plan-map kind that shows it.
CRITERION_MAP = {"horizontal_sight_angle": "sight_angle", "outside_distance": "distance", "layers": "layers"}


def limiting_map(level_by_criterion: dict) -> str:
    """The map kind of the view criterion that limits an eye height's level: the lowest level, the
    first of sight angle, distance, layers on a tie (the order the standard lists them)."""
    crit = min(CRITERION_MAP, key=lambda c: level_by_criterion.get(c, 99))
    return CRITERION_MAP[crit]


def view_jobs(result: RunResult, i: int, slug: str) -> list[Job]:
    """The plan maps of room ``i``: four per eye height; the level map and the map of what limits
    the level are printed with report.html, the other two are on screen only (``print_``). Where
    the layers cannot be judged (a model without landscape) only the sight angle and distance maps,
    both printed: the layers were not traced and no point has a level."""
    r = result.rooms[i]
    res, plan = r.assessed("view"), r.illustrations.get("view")
    if res is None or plan is None:
        return []
    th = result.project.thresholds
    out = []
    for e in res.eye_heights:
        v = e.values
        if v is None or not len(v):
            continue
        xy = result.scene.to_world(e.points_local)[:, :2]
        values = {"sight_angle": (v.sight.angle_deg, th.horizontal_sight_angle_deg.as_dict()),
                  "distance": (v.distance_m, th.outside_distance_m.as_dict()),
                  "layers": (_layer_mask(v.visible), None), "level": (v.level.astype(float), None)}
        limiting = limiting_map(e.level_by_criterion)
        kinds = MAP_KINDS
        if res.layers_unassessable is not None:  # no landscape: no layers (not traced) and no level to map
            kinds = {k: w for k, w in MAP_KINDS.items() if k in ("sight_angle", "distance")}
        for kind, words in kinds.items():
            vals, thresholds = values[kind]
            title = f"{r.room.name}: {words}, eye height {e.eye_height_m:g} m"
            out.append(Job(f"{FIGURES_DIR}/{slug}-view-{e.eye_height_m:g}m-{kind.replace('_', '-')}.png", r.room.name, "view",
                           title, "plan_map", (xy, vals),
                           {"kind": kind, "thresholds": thresholds, "floor": plan.floor, "utilised": plan.utilised,
                            "windows": plan.windows, "true_north_deg": plan.true_north_deg, "near": v.near,
                            "spacing_m": plan.spacing_m, "title": title},
                           print_=kind in ("level", limiting) or res.layers_unassessable is not None))
    return out


def sunlight_jobs(result: RunResult, i: int, slug: str) -> list[Job]:
    """The hours chart of room ``i`` and the fisheye of each of its windows with a point P."""
    r = result.rooms[i]
    res = r.assessed("sunlight")
    if res is None:
        return []
    th = result.project.thresholds.sunlight_hours.as_dict()
    settings = result.project.sunlight
    per_window = None
    if res.window_hours is not None and len(r.room.windows) > 1:
        per_window = {w.name: res.window_hours[k] for k, w in enumerate(r.room.windows) if np.isfinite(res.window_hours[k]).any()}
    title = f"{r.room.name}: hours of sunlight per day"
    out = [Job(f"{FIGURES_DIR}/{slug}-sunlight-hours.png", r.room.name, "sunlight", title, "hours_chart",
               (res.dates, res.hours), {"thresholds": th, "assessed_index": res.assessed_index, "per_window": per_window,
                                        "title": title})]
    for k, f in enumerate(r.illustrations.get("sunlight") or ()):
        paths = [{"label": p.label, "azimuth_deg": p.azimuth_deg, "altitude_deg": p.altitude_deg, "visible": p.visible,
                  "hour_marks": p.hour_marks} for p in f.paths]
        title = f"{r.room.name}: from point P of window '{f.window}'"
        out.append(Job(f"{FIGURES_DIR}/{slug}-sunlight-fisheye-{k + 1}.png", r.room.name, "sunlight", title, "fisheye",
                       (f.image,), {"sun_paths": paths, "min_altitude_deg": settings.min_altitude_deg if settings else 0.0,
                                    "view_azimuth_deg": f.view_azimuth_deg, "title": title}))
    return out


def daylight_jobs(result: RunResult, i: int, slug: str) -> list[Job]:
    """The daylight map of room ``i``: its daylight factor (method 1, the D_T of each level marked) or
    its share of the daylight hours reaching the target illuminance of the level measured to (method 2,
    50 % marked); points within their error of a threshold ringed."""
    r = result.rooms[i]
    res, plan = r.assessed("daylight"), r.illustrations.get("daylight")
    if res is None or plan is None or not len(res.points_local):
        return []
    from en17037cli import standard

    xy = result.scene.to_world(res.points_local)[:, :2]
    th_room = room_thresholds(result.project, r.room)  # a practice's targets per room kind, or the project's
    et = th_room.daylight_target_lx.as_dict()
    if res.daylight_factor_pct is not None:
        dt = {k: round(100.0 * v / res.median_diffuse_lx, 2) for k, v in et.items()}
        etm = th_room.daylight_minimum_target_lx.as_dict()
        lines = [100.0 * v / res.median_diffuse_lx for v in [*et.values(), *etm.values()] if v > 0]
        near = np.any([np.abs(res.daylight_factor_pct - t) <= res.daylight_factor_err_pct for t in lines], axis=0)
        kind, vals, th, words = "daylight_factor", res.daylight_factor_pct, dt, "daylight factor"
    else:
        level = standard.LEVELS[standard.target_level(res.level, r.required("daylight"))]
        lx = et[level]
        vals, err = res.share_of_hours[lx], res.share_of_hours_err[lx]
        near = np.abs(vals - 0.5) <= err
        kind, th, words = "share_of_hours", {"minimum": 0.5, "medium": 0.5, "high": 0.5}, f"share of hours >= {lx:g} lx"
    title = f"{r.room.name}: {words}"
    return [Job(f"{FIGURES_DIR}/{slug}-daylight-{kind.replace('_', '-')}.png", r.room.name, "daylight", title, "plan_map",
                (xy, vals), {"kind": kind, "thresholds": th, "floor": plan.floor, "utilised": plan.utilised,
                             "windows": plan.windows, "true_north_deg": plan.true_north_deg, "near": near,
                             "spacing_m": plan.spacing_m, "title": title})]


def glare_jobs(result: RunResult, i: int, slug: str) -> list[Job]:
    """Room ``i``'s map of critical positions, the hourly DGP of its worst view and the fisheye of
    each point-in-time check (:mod:`en17037cli.criteria.glare.pictures`)."""
    from en17037cli.criteria.glare.pictures import glare_jobs as jobs

    return [Job(*j) for j in jobs(result, i, slug, FIGURES_DIR)]


def figure_jobs(result: RunResult) -> list[Job]:
    """Every picture of a run (a run made with ``pictures=True``), room by room, as jobs."""
    out = []
    for i, r in enumerate(result.rooms):
        slug = room_slug(i, r.room.name)
        out += view_jobs(result, i, slug) + sunlight_jobs(result, i, slug) + daylight_jobs(result, i, slug)
        out += glare_jobs(result, i, slug)
    return out


def pictures_available() -> bool:
    """Whether matplotlib (the ``plot`` extra) is installed: without it a run writes no pictures."""
    import importlib.util

    return importlib.util.find_spec("matplotlib") is not None


def render_figures(result: RunResult, pool=None) -> list[Figure]:
    """Every picture of a run, drawn here or by ``pool`` (a :class:`Painters`); the time goes to the
    run's ``figures`` stage."""
    jobs = figure_jobs(result)
    out = pool.draw(jobs) if pool is not None else [draw(j) for j in jobs]
    result.timer.stage("figures")
    return out


_SIGNALS = (signal.SIGINT, signal.SIGTERM)


#: Jobs per extra drawing process: a run with more pictures than this forks more workers once
#: its rays are traced (each new worker first imports matplotlib, about 0.3 s).
JOBS_PER_EXTRA_WORKER = 16


class Painters:
    """Worker processes that draw the pictures. One is forked before the run and imports matplotlib
    and loads its font while the run traces rays in the parent; a run with many pictures (a
    building) forks up to ``workers - 1`` more when they are sent (forking them earlier would slow
    the tracing they share the cores with). The jobs are dealt out in turn; the figures come back
    in the jobs' order, byte-identical to drawing them in the parent. The workers ignore Ctrl-C and
    are ended by :meth:`close`, so an interrupted run leaves nothing behind."""

    def __init__(self, workers: int = 1):
        import os

        self._pid = os.getpid()
        self._max = max(1, workers)
        self._workers: list = []
        self._start()

    def _start(self) -> None:
        import multiprocessing

        ctx = multiprocessing.get_context("fork")
        conn, child = ctx.Pipe()
        proc = ctx.Process(target=_paint, args=(child, self._pid), name="en17037-pictures", daemon=True)
        self._workers.append((conn, proc))
        # The child is forked with SIGINT and SIGTERM blocked and unblocks them once its own handlers
        # are set: a signal arriving in between must not run the parent's handler in the child.
        old = signal.pthread_sigmask(signal.SIG_BLOCK, _SIGNALS)
        try:
            proc.start()
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)
        child.close()

    def draw(self, jobs: list[Job]) -> list[Figure]:
        while len(self._workers) < min(self._max, 1 + len(jobs) // JOBS_PER_EXTRA_WORKER):
            self._start()
        n = len(self._workers)
        for k, (conn, _) in enumerate(self._workers):
            conn.send(jobs[k::n])
        out: list = [None] * len(jobs)
        for k, (conn, _) in enumerate(self._workers):
            got = conn.recv()
            if isinstance(got, BaseException):
                raise got
            out[k::n] = got
        return out

    def close(self) -> None:
        import contextlib
        import os

        if os.getpid() != self._pid:  # a forked copy of the process that started the workers
            return
        for conn, proc in self._workers:
            with contextlib.suppress(OSError):
                conn.close()
            if proc.is_alive():
                proc.terminate()
        for _, proc in self._workers:
            proc.join(timeout=5)


def _paint(conn, run_pid: int) -> None:
    """The worker of :class:`Painters`: warm up, draw one batch of jobs, send the figures back; it
    ends with the run, even a run killed from outside (:mod:`~en17037cli.scale.lifeline`: it holds
    a copy of the run's end of its pipe, so its ``recv`` would wait for ever)."""
    from en17037cli.report.pictures.raster import warm_up
    from en17037cli.scale.lifeline import end_with_parent

    end_with_parent(run_pid, kernel=True)

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent handles Ctrl-C and ends this process
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, _SIGNALS)  # blocked by Painters() around the fork
    warm_up()
    try:
        jobs = conn.recv()
    except (EOFError, OSError):
        return
    try:
        out: object = [draw(j) for j in jobs]
    except Exception as exc:  # noqa: BLE001 - sent back and raised in the parent
        out = exc
    conn.send(out)
