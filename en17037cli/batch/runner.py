"""The batch as a whole: every run on an executor (:func:`run_batch`: in this process, a local
process pool or a Dask cluster, :func:`make_executor`), each run's report folder written as it
finishes, then the summary (:func:`write_summary`) and the JUnit XML (:func:`run`)."""
from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from en17037cli.batch.plan import RunSpec
from en17037cli.batch.worker import Failed, Finished, Part, Split, assess_rooms, clear_sessions, finish_run, init_worker, open_run
from en17037cli.errors import InputError, internal_message
from en17037cli.raytrace import available_cores
from en17037cli.report.summary import RunRecord

#: The batch's own files in its folder.
SUMMARY_FILES = ("summary.csv", "summary.json")


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


def make_executor(jobs: int | None = None, scheduler: str | None = None, processes: bool = True,
                  cleanup: Callable[[], None] = clear_sessions):
    """The executor of a batch: in this process for one job, a local process pool for more, or a
    Dask cluster (``scheduler``: an address, or ``local`` for a LocalCluster of ``jobs`` workers).
    Each worker's ray engine gets ``cores // jobs`` threads; ``cleanup`` empties the caches an
    in-process or Dask run leaves in its workers (the batch's sessions, the screen's contexts)."""
    from en17037cli.scale import InlineExecutor, PoolExecutor

    cores = available_cores()
    jobs = jobs or cores
    threads = max(1, cores // jobs)
    if scheduler is not None:
        from en17037cli.scale.dask import DaskExecutor

        return DaskExecutor(scheduler, jobs=jobs, threads_per_worker=threads, processes=processes, cleanup=cleanup)
    if jobs == 1:
        return InlineExecutor(cleanup=cleanup)
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
