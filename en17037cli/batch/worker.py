"""What a batch's worker does with a run: open it (:func:`open_run`: its scene, ray engine and
preflight once, a :class:`~en17037cli.pipeline.Session` cached per worker), assess a small project
whole or a group of a large one's rooms (:func:`assess_rooms`), and join the groups into the run's
report files (:func:`finish_run`). Every result is plain data (:class:`Finished`, :class:`Split`,
:class:`Part`, :class:`Failed`), so that it can come back from another process.

**Threads.** A worker's ray engine gets the worker's share of the cores: ``cores // jobs`` on the
local pool and on ``--scheduler local`` (see :func:`worker_threads`).
"""
from __future__ import annotations

import os
import sys
import threading
from collections import Counter, OrderedDict
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from en17037cli.batch.plan import RunSpec
from en17037cli.errors import InputError, internal_message
from en17037cli.pipeline import RoomAssessment, Session, Timer
from en17037cli.raytrace import THREADS_ENV
from en17037cli.report.summary import RunRecord, room_rows

#: Sessions (scene and ray engine of a run) a worker keeps for reuse; older ones are closed.
MAX_SESSIONS = 2


@dataclass
class Failed:
    """A run that stopped: exit code 2 (bad input) or 3 (internal error), and the message."""

    code: int
    message: str


@dataclass
class Split:
    """A run too large for one unit of work: its rooms, in report order."""

    rooms: list[str]


@dataclass
class Part:
    """The assessments of a group of rooms."""

    rooms: dict[str, RoomAssessment]


@dataclass
class Finished:
    """A run's report files (name -> bytes) and its record for the summary."""

    files: dict[str, bytes]
    record: RunRecord


#: (worker, run key) -> session, oldest first; a worker's lock is held while it uses its sessions.
_SESSIONS: OrderedDict[tuple[str, str], tuple[Session, dict]] = OrderedDict()
_LOCKS: dict[str, threading.Lock] = {}
_GUARD = threading.Lock()
#: (worker, run key) -> sessions built: what the tests read to see each worker build a run once.
BUILDS: Counter[tuple[str, str]] = Counter()
#: Ray-engine threads of this process's worker, set by the local pool's initializer.
_THREADS: list[int | None] = [None]


def init_worker(threads: int | None) -> None:
    """Initializer of a local pool's processes: the ray engine's threads (the worker's share of the cores)."""
    _THREADS[0] = threads


def _dask_worker():
    if "distributed" not in sys.modules:
        return None
    from distributed import get_worker

    try:
        return get_worker()
    except ValueError:  # not inside a Dask task
        return None


def worker_threads() -> int | None:
    """Ray-engine threads of a worker: the local pool's share (``cores // jobs``); else
    ``EN17037_THREADS`` where set; else a Dask worker's own thread count (its share of the cores:
    ``--scheduler local`` gives each ``cores // jobs``); else None (every core)."""
    if _THREADS[0]:
        return _THREADS[0]
    if os.environ.get(THREADS_ENV):
        return None  # the engine reads it
    worker = _dask_worker()
    return None if worker is None else int(worker.state.nthreads)


def clear_sessions() -> None:
    """Close and forget every cached session of this process (after a batch, on each Dask worker)."""
    with _GUARD:
        sessions = [s for s, _ in _SESSIONS.values()]
        _SESSIONS.clear()
    for s in sessions:
        s.close()


@contextmanager
def _session(spec: RunSpec) -> Iterator[tuple[Session, dict]]:
    """The worker's session of ``spec`` (built on first use), and its record of load and build
    times; the worker runs one task at a time on its sessions (its ray engine has the threads)."""
    worker = _dask_worker()
    wid = "process" if worker is None else str(worker.address)
    with _GUARD:
        lock = _LOCKS.setdefault(wid, threading.Lock())
    with lock:
        key = (wid, spec.key)
        with _GUARD:
            entry = _SESSIONS.get(key)
            if entry is not None:
                _SESSIONS.move_to_end(key)
        if entry is None:
            from en17037cli.project import load_project

            project = load_project(spec.path, list(spec.overrides))
            session = Session(project, spec.only, spec.max_points, threads=worker_threads())
            entry = (session, dict(session.timer.t))
            with _GUARD:
                BUILDS[key] += 1
                _SESSIONS[key] = entry
                mine = [k for k in _SESSIONS if k[0] == wid]
                old = [_SESSIONS.pop(k)[0] for k in mine[:-MAX_SESSIONS]]
            for s in old:
                s.close()
        yield entry


def _caught(fn: Callable[[], object]):
    """``fn()``, or :class:`Failed` with exit code 2 for bad input and 3 for anything else."""
    try:
        return fn()
    except InputError as exc:
        return Failed(2, str(exc))
    except Exception as exc:  # noqa: BLE001 - a run's internal error is recorded, the batch goes on
        return Failed(3, internal_message(exc))


def _finish(spec: RunSpec, session: Session, assessed: dict[str, RoomAssessment], timer: Timer) -> Finished:
    from en17037cli.report.document import build_report
    from en17037cli.report.write import WRITERS

    report = build_report(session.result(assessed, timer))
    files = {name: writer(report).encode("utf-8") for name, writer in WRITERS.items()}
    rows = room_rows(report, {name: a.time_s for name, a in assessed.items()})
    record = RunRecord(project=spec.project, variant=spec.variant, report_dir=spec.folder,
                       exit_code=0 if report["status"] == "pass" else 1, rows=rows, status=report["status"],
                       counts=report["summary"], warnings=list(report["warnings"]), time_s=report["timings_s"]["total"])
    return Finished(files, record)


def open_run(spec: RunSpec) -> Finished | Split | Failed:
    """Open a run on this worker: assess a small project whole, or return a large one's rooms."""
    def work():
        with _session(spec) as (session, _):
            names = session.room_names
            if len(names) > spec.rooms_per_task:
                return Split(names)
            return _finish(spec, session, session.assess(), session.timer)

    return _caught(work)


def assess_rooms(spec: RunSpec, rooms: list[str]) -> Part | Failed:
    """Assess a group of a run's rooms with this worker's session of the run."""
    def work():
        with _session(spec) as (session, _):
            return Part(session.assess(rooms))

    return _caught(work)


def finish_run(spec: RunSpec, parts: list[Part]) -> Finished | Failed:
    """Join the groups of a run's rooms into its reports (on any worker: its session of the run)."""
    def work():
        with _session(spec) as (session, built):
            assessed: dict[str, RoomAssessment] = {}
            for p in parts:
                assessed.update(p.rooms)
            timer = Timer()
            timer.t = {**built}
            for a in assessed.values():
                for crit, t in a.time_s.items():
                    timer.t[crit] = timer.t.get(crit, 0.0) + t
            return _finish(spec, session, assessed, timer)

    return _caught(work)
