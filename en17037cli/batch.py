"""Batch runs: many project files, or a project times a variants file, on a pool of workers.

A **run** is one project file with one variant's ``--set`` overrides. Each run writes its own
report folder under the batch's folder (the same files ``check`` writes, byte-identical apart from
timings) and gives one row per room and criterion to the batch's summary
(:mod:`en17037cli.report.summary`). A run that fails (bad input, internal error) is recorded with
its message and does not stop the others; the batch's exit code is the worst of its runs.

**Unit of work.** A worker opens a run (:func:`open_run`): it builds the run's scene, ray engine
and preflight once (a :class:`~en17037cli.pipeline.Session`, cached per worker) and, for a project
of at most ``rooms_per_task`` rooms, assesses every room and returns the reports. A larger project
comes back as its room names; its rooms go out in groups (:func:`assess_rooms`), each worker
building the project's session once and reusing it for every group it is given, and one worker
joins the groups (:func:`finish_run`) into the report a single process would write. Which worker
assesses which room changes nothing: a room's result depends only on the project and the room.
Executors (:mod:`en17037cli.scale`) run these functions in this process, on a local process pool
or on a Dask cluster.

**Threads.** A worker's ray engine gets the worker's share of the cores: ``cores // jobs`` on the
local pool and on ``--scheduler local`` (see :func:`worker_threads`).
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import sys
import threading
import uuid
from collections import Counter, OrderedDict
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from en17037cli.errors import InputError, internal_message
from en17037cli.pipeline import RoomAssessment, Session, Timer
from en17037cli.preflight import MAX_POINTS
from en17037cli.raytrace import THREADS_ENV, available_cores
from en17037cli.report.summary import RunRecord, room_rows

#: A project with at most this many rooms is one unit of work; a larger one goes out in groups of
#: this many rooms (small enough to spread a building over the workers, large enough that sending
#: a group costs little next to assessing it).
ROOMS_PER_TASK = 8
#: Sessions (scene and ray engine of a run) a worker keeps for reuse; older ones are closed.
MAX_SESSIONS = 2
#: Variants files larger than this are not parsed [bytes].
MAX_VARIANTS_BYTES = 1024 * 1024
#: What a variant may be called: it names a folder.
VARIANT_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")
#: The batch's own files in its folder.
SUMMARY_FILES = ("summary.csv", "summary.json")


# --- variants ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class Variant:
    """A named set of ``--set`` overrides (``key.path=value``) applied to a project."""

    name: str
    overrides: tuple[str, ...] = ()


def _override(key, value) -> str:
    """``key=value`` with the value written as YAML flow (JSON is YAML), read back as it was."""
    return f"{key}={json.dumps(value, ensure_ascii=False)}"


def load_variants(path: Path) -> list[Variant]:
    """Read a variants file: a YAML list of ``{name: NAME, set: {key.path: value, ...}}`` (``set``
    may also be a list of ``key.path=value`` strings, or left out for the project as it is).

    Raises :class:`InputError` naming the file, the item and what to do.
    """
    from en17037cli.project.yaml12 import parse_yaml_or_fail

    where = f"--variants {path}"
    try:
        if path.stat().st_size > MAX_VARIANTS_BYTES:
            raise InputError(f"{where}: over {MAX_VARIANTS_BYTES // 1024} kB; a variants file lists override sets, not geometry")
        text = path.read_bytes().decode("utf-8-sig")
    except FileNotFoundError:
        raise InputError(f"{where}: file not found; give a YAML list of variants (name and set)") from None
    except UnicodeDecodeError as exc:
        raise InputError(f"{where}: not UTF-8 text (byte {exc.start}); save it as UTF-8") from None
    except OSError as exc:
        raise InputError(f"{where}: cannot read it ({exc.strerror})") from None
    doc = parse_yaml_or_fail(text, where)
    if not isinstance(doc, list) or not doc:
        raise InputError(f"{where}: expected a YAML list of variants, e.g. '- {{name: wide, set: {{view.grid_spacing_m: 1}}}}'")
    out, seen = [], set()
    for i, item in enumerate(doc):
        at = f"{where}: [{i}]"
        if not isinstance(item, dict) or set(item) - {"name", "set"}:
            raise InputError(f"{at}: expected a mapping with 'name' and 'set' (and nothing else)")
        name = item.get("name")
        if not isinstance(name, str) or not VARIANT_NAME.match(name):
            raise InputError(f"{at}: name {name!r}: give each variant a name of letters, digits, '.', '_' or '-' "
                             "(it names the variant's report folder)")
        if name in seen:
            raise InputError(f"{at}: name '{name}' is used twice; give each variant its own name")
        seen.add(name)
        sets = item.get("set") or {}
        if isinstance(sets, dict):
            overrides = tuple(_override(k, v) for k, v in sets.items())
        elif isinstance(sets, list) and all(isinstance(s, str) and "=" in s for s in sets):
            overrides = tuple(sets)
        else:
            raise InputError(f"{at} '{name}': set: expected a mapping key.path: value, or a list of 'key.path=value'")
        out.append(Variant(name, overrides))
    return out


# --- runs ---------------------------------------------------------------------------------------

@dataclass(frozen=True)
class RunSpec:
    """One run as a worker receives it (plain data).

    project : the project file as given; path : the same, absolute (what the worker opens)
    folder : the run's report folder, relative to the batch's folder
    overrides : the batch's ``--set`` then the variant's
    batch : the batch's id, so that a worker's cached sessions never serve another batch
    """

    index: int
    project: str
    path: str
    variant: str = ""
    overrides: tuple[str, ...] = ()
    folder: str = ""
    only: str | None = None
    max_points: int = MAX_POINTS
    rooms_per_task: int = ROOMS_PER_TASK
    batch: str = ""

    @property
    def key(self) -> str:
        """What a worker's session cache is keyed by: the project and everything that changes it."""
        raw = json.dumps([self.batch, self.path, list(self.overrides), self.only, self.max_points])
        return hashlib.sha256(raw.encode("utf-8")).hexdigest()


def _folders(projects: list[str]) -> list[str]:
    """A report folder name per project file: its stem where the stems differ, else its path from
    the files' common folder: the folder alone where every file has the same name
    (``a/project.yaml``, ``b/project.yaml`` -> ``a``, ``b``), else without the suffix."""
    paths = [Path(p).resolve() for p in projects]
    stems = [p.stem for p in paths]
    if len(set(stems)) == len(stems):
        return stems
    common = Path(os.path.commonpath([p.parent for p in paths]))
    parents = [p.parent.relative_to(common).as_posix() for p in paths]
    if len({p.name for p in paths}) == 1 and "." not in parents:
        return parents
    return [p.relative_to(common).with_suffix("").as_posix() for p in paths]


def plan_runs(projects: list[str], variants: list[Variant] | None = None, overrides: tuple[str, ...] = (),
              only: str | None = None, max_points: int = MAX_POINTS, rooms_per_task: int = ROOMS_PER_TASK) -> list[RunSpec]:
    """Every run of a batch: each project file, times each variant where a variants file is given,
    in that order. Raises :class:`InputError` for a project file given twice."""
    seen: dict[Path, str] = {}
    for p in projects:
        r = Path(p).resolve()
        if r in seen:
            raise InputError(f"{p}: given twice (also as {seen[r]}); give each project file once, use --variants for variants")
        seen[r] = p
    batch = uuid.uuid4().hex
    specs: list[RunSpec] = []
    for project, folder in zip(projects, _folders(projects)):
        for v in variants or [Variant("")]:
            specs.append(RunSpec(index=len(specs), project=str(project), path=str(Path(project).resolve()), variant=v.name,
                                 overrides=tuple(overrides) + v.overrides, folder=f"{folder}/{v.name}" if v.name else folder,
                                 only=only, max_points=max_points, rooms_per_task=rooms_per_task, batch=batch))
    return specs


# --- what a worker does -----------------------------------------------------------------------

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


# --- the batch ----------------------------------------------------------------------------------

def _failed(spec: RunSpec, code: int, message: str) -> RunRecord:
    """The record of a run that stopped; its message names the project file as it was given."""
    return RunRecord(project=spec.project, variant=spec.variant, report_dir="", exit_code=code,
                     message=message.replace(spec.path, spec.project))


def check_batch_folder(out: Path) -> None:
    """Raise :class:`InputError` unless the batch may write its summary into ``out``: not another
    project's report folder, no summary there that another tool or user wrote."""
    from en17037cli.report.folder import check_folder, read_manifest

    manifest = read_manifest(out)
    owner = out / "summary.json"
    if manifest is not None and manifest.get("project") != str(owner.resolve()):
        raise InputError(f"--out {out}: it is the report folder of {manifest.get('project')}; choose another folder for the batch")
    check_folder(out, owner, SUMMARY_FILES)


def write_summary(out: Path, records: list[RunRecord]) -> None:
    """``summary.csv`` and ``summary.json`` into the batch's folder, as one set."""
    from en17037cli.report.folder import commit
    from en17037cli.report.summary import summary_csv, summary_json

    commit(out, out / "summary.json", {"summary.csv": summary_csv(records).encode("utf-8"),
                                       "summary.json": summary_json(records).encode("utf-8")})


def run_batch(specs: list[RunSpec], executor, out: Path, on_done: Callable[[RunRecord], None] | None = None) -> list[RunRecord]:
    """Run every spec on ``executor``, write each run's report folder under ``out`` as it finishes,
    and return the runs' records in the order of ``specs`` (the summary is :func:`write_summary`).

    A run's report folder is checked before any work (a folder this tool may not write fails that
    run with exit code 2); a worker that dies fails its run with exit code 3.
    """
    from en17037cli.report.folder import check_folder, commit
    from en17037cli.report.write import WRITERS

    records: dict[int, RunRecord] = {}
    pending: dict = {}
    parts: dict[int, list] = {}

    def done(spec: RunSpec, rec: RunRecord) -> None:
        records[spec.index] = rec
        if on_done is not None:
            on_done(rec)

    for spec in specs:
        try:
            check_folder(out / spec.folder, Path(spec.path), WRITERS)
        except InputError as exc:
            done(spec, _failed(spec, 2, str(exc)))
            continue
        pending[executor.submit(open_run, spec)] = (spec, -1)
    while pending:
        for handle in executor.wait(pending):
            spec, group = pending.pop(handle)
            try:
                res = executor.result(handle)
            except Exception as exc:  # noqa: BLE001 - the worker died or the result did not come back
                res = Failed(3, internal_message(exc))
            if spec.index in records:
                continue  # the run failed in another group already
            if isinstance(res, Failed):
                done(spec, _failed(spec, res.code, res.message))
            elif isinstance(res, Split):
                groups = [res.rooms[i:i + spec.rooms_per_task] for i in range(0, len(res.rooms), spec.rooms_per_task)]
                parts[spec.index] = [None] * len(groups)
                for i, g in enumerate(groups):
                    pending[executor.submit(assess_rooms, spec, g)] = (spec, i)
            elif isinstance(res, Part):
                got = parts[spec.index]
                got[group] = res
                if all(p is not None for p in got):
                    pending[executor.submit(finish_run, spec, parts.pop(spec.index))] = (spec, -1)
            elif isinstance(res, Finished):
                try:
                    commit(out / spec.folder, Path(spec.path), res.files)
                except InputError as exc:
                    done(spec, _failed(spec, 2, str(exc)))
                    continue
                done(spec, res.record)
    return [records[s.index] for s in specs]


def make_executor(jobs: int | None = None, scheduler: str | None = None, processes: bool = True):
    """The executor of a batch: in this process for one job, a local process pool for more, or a
    Dask cluster (``scheduler``: an address, or ``local`` for a LocalCluster of ``jobs`` workers).
    Each worker's ray engine gets ``cores // jobs`` threads."""
    from en17037cli.scale import InlineExecutor, PoolExecutor

    cores = available_cores()
    jobs = jobs or cores
    threads = max(1, cores // jobs)
    if scheduler is not None:
        from en17037cli.scale.dask import DaskExecutor

        return DaskExecutor(scheduler, jobs=jobs, threads_per_worker=threads, processes=processes, cleanup=clear_sessions)
    if jobs == 1:
        return InlineExecutor(cleanup=clear_sessions)
    return PoolExecutor(jobs, init_worker, (threads,))



def run(specs: list[RunSpec], out: Path, jobs: int | None = None, scheduler: str | None = None, junit: Path | None = None,
        on_done: Callable[[RunRecord], None] | None = None) -> list[RunRecord]:
    """A whole batch: run ``specs`` (see :func:`make_executor`, :func:`run_batch`), then write the
    summary into ``out`` and, with ``junit``, the JUnit XML of every run; return the runs' records."""
    executor = make_executor(jobs, scheduler)
    try:
        records = run_batch(specs, executor, out, on_done)
    finally:
        executor.close()
    write_summary(out, records)
    if junit is not None:
        from en17037cli.report.folder import write_file
        from en17037cli.report.junit import junit_xml

        write_file(junit, junit_xml(records).encode("utf-8"), "--junit")
    return records
