"""A screen as a whole: the buildings read and chosen, the site resolved, the work split by
buildings onto an executor (this process, a local process pool on every core, or a Dask cluster),
the results joined and written (:func:`screen`).

The work is split into tasks of ``screen.buildings_per_task`` buildings in file order, the same
whatever the executor, and each worker builds the run's context once (:mod:`~en17037cli.district.compute`):
a probe's figures depend on the project and its building only, so every executor writes the same
bytes (``summary.json``'s timings apart). Memory: the main process holds the walls of the screened
buildings and the probes' figures; each worker one copy of the city as a ray engine.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from en17037cli.district.city import read_buildings
from en17037cli.district.compute import INTERNAL, Spec, clear_contexts, screen_buildings
from en17037cli.district.settings import screen_settings
from en17037cli.errors import InputError


@dataclass
class Screening:
    """What a screen did: its status (``pass`` / ``fail``), counts, where the outputs are, the warnings."""

    status: str
    buildings: int
    left_out: int
    probes: int
    shared: int
    seconds: float
    out: Path
    warnings: list
    failing: list
    internal: int = 0  # buildings the screen failed on by an internal error (exit 3)


def choose(buildings: list, which, where: str, display: str) -> tuple[list, list[str]]:
    """The buildings ``screen.buildings`` names ("*", ids, or a polygon: those whose centre lies in it)."""
    warnings: list[str] = []
    if isinstance(which, str):
        chosen = buildings
    elif isinstance(which, tuple):
        want = set(which)
        chosen = [b for b in buildings if b.id in want]
        missing = sorted(want - {b.id for b in chosen})
        if not chosen:
            raise InputError(f"{where}: screen.buildings: none of the {len(want)} id(s) is a Building of {display} (e.g. "
                             f"'{missing[0]}'); give CityJSON object ids or CityGML gml:ids of Building features, or \"*\"")
        if missing:
            warnings.append(f"{where}: screen.buildings: {len(missing)} id(s) not a Building of {display}, left out: "
                            f"{', '.join(missing[:5])}{' ...' if len(missing) > 5 else ''}")
    else:
        import shapely

        poly = shapely.make_valid(shapely.Polygon(which))
        ok = [b for b in buildings if not b.problem]
        chosen = [b for b in ok if shapely.contains_xy(poly, *b.centre)]
        if not chosen:
            xy = np.array([b.centre for b in ok]).reshape(-1, 2)
            span = (f"its buildings lie in x {xy[:, 0].min():.0f}..{xy[:, 0].max():.0f}, y {xy[:, 1].min():.0f}.."
                    f"{xy[:, 1].max():.0f}" if len(xy) else "it has no building with walls")
            raise InputError(f"{where}: screen.buildings.polygon: selects no building of {display} ({span}); give the "
                             "polygon in the city model's CRS")
    if not chosen:
        raise InputError(f"{where}: model.files[0]: {display} has no Building to screen")
    return chosen, warnings


def site(project, crs: str | None, centre, where: str, display: str) -> tuple[float, float, float, str]:
    """(latitude, longitude, true north, where from) of the run: the project's where it gives them,
    else the city model's CRS at the screened buildings' centre (:func:`~en17037cli.scene.georef.frame_at`)."""
    from en17037cli.scene.city_frame import frame_at

    loc, north = project.location, project.model.true_north_deg
    frame = frame_at(crs, display, float(centre[0]), float(centre[1])) if crs else None
    if loc.latitude is None or loc.longitude is None:
        if crs is None:
            raise InputError(f"{where}: model.files[0] ({display}): the city model names no CRS (no referenceSystem or "
                             "srsName) and the project gives no location.latitude and longitude; give the file's crs key "
                             "(e.g. crs: EPSG:7415) or the location")
        if frame is None:
            raise InputError(f"{where}: model.files[0] ({display}): its CRS {crs} is not a projected CRS that PROJ knows (or "
                             "pyproj is missing: pip install 'en17037cli[citygml]'); give location.latitude and longitude, "
                             "or the file's crs key")
    lat = loc.latitude if loc.latitude is not None else frame.latitude
    lon = loc.longitude if loc.longitude is not None else frame.longitude
    if north is None:
        north = frame.north_deg if frame is not None else 0.0
    source = "the project" if frame is None else frame.source.replace("at the windows", "at the screened buildings' centre")
    return float(lat), float(lon), float(north), source


def make_executor(jobs: int | None, scheduler: str | None, processes: bool = True):
    """This process (one job), a local process pool (``jobs``, default every core) or a Dask cluster:
    the batch's executor (:func:`en17037cli.batch.runner.make_executor`), emptying the screen's contexts."""
    from en17037cli.batch.runner import make_executor as batch_executor

    return batch_executor(jobs, scheduler, processes, cleanup=clear_contexts)


def run_tasks(executor, spec: Spec, chosen: list, per_task: int, log) -> list:
    """Every task's :class:`~en17037cli.district.compute.Screened`, in task order."""
    tasks = [(i, chosen[i:i + per_task]) for i in range(0, len(chosen), per_task)]
    pending = {executor.submit(screen_buildings, spec, group, first): k for k, (first, group) in enumerate(tasks)}
    done: dict = {}
    while pending:
        for handle in executor.wait(pending):
            k = pending.pop(handle)
            done[k] = executor.result(handle)
            if log is not None:
                log(f"[{len(done)}/{len(tasks)}] buildings {tasks[k][0] + 1}-{tasks[k][0] + len(tasks[k][1])} screened")
    return [done[k] for k in range(len(tasks))]


def screen(project_file: Path, out: Path, overrides=(), jobs: int | None = None, scheduler: str | None = None,
           processes: bool = True, log=None) -> Screening:
    """Screen the project's city model (module docstring) and write the outputs into ``out``."""
    from en17037cli.district.outputs import outputs
    from en17037cli.project import load_project
    from en17037cli.report.folder import check_folder, commit

    tic = time.perf_counter()
    project = load_project(project_file, list(overrides))
    where = project.path.name
    settings = screen_settings(project)
    f0 = project.model.files[0]
    if f0.transform is not None:
        raise InputError(f"{where}: model.files[0].transform: the screened city model stays in its own CRS (its outputs are "
                         "in it); remove the transform, and place the other files in the city model's CRS instead")
    from en17037cli.district.citymodel import written_name

    names = ("probes.csv", "probes.geojson", "buildings.csv", "summary.json", "report.html", written_name(f0.path))
    check_folder(out, project.path, names)
    buildings, crs = read_buildings(f0.path, f0.lod, f0.exclude, f0.crs)
    chosen, warnings = choose(buildings, settings.buildings, where, f0.display)
    warnings += [f"{f0.display}: building '{b.id}' left out: {b.problem}" for b in chosen if b.problem]
    good = [b for b in chosen if not b.problem]
    centre = np.mean([b.centre for b in good], axis=0) if good else np.zeros(2)
    lat, lon, north, source = site(project, crs, centre, where, f0.display)
    z0 = min((b.z_ground for b in good), default=0.0)
    spec = Spec(str(project.path), tuple(overrides), (float(round(centre[0])), float(round(centre[1])), float(round(z0))),
                lat, lon, north)
    executor = make_executor(jobs, scheduler, processes)
    try:
        parts = run_tasks(executor, spec, chosen, settings.buildings_per_task, log)
    finally:
        executor.close()
    problems = {bi: why for q in parts for bi, why in q.problems}
    warnings += [f"{f0.display}: building '{chosen[bi].id}' left out: {why}" for bi, why in sorted(problems.items())]
    files, info = outputs(project, settings, f0, crs, chosen, parts, problems, (lat, lon, north, source), warnings,
                          time.perf_counter() - tic, executor.workers)
    commit(out, project.path, files)
    probes = sum(len(q.probes) for q in parts)
    return Screening(info["status"], len(chosen), len(problems) + sum(1 for b in chosen if b.problem), probes,
                     sum(sum(q.shared.values()) for q in parts), time.perf_counter() - tic, out, warnings, info["failing"],
                     sum(1 for why in problems.values() if why.startswith(INTERNAL)))
