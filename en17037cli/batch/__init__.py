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
or on a Dask cluster; a worker's ray engine gets its share of the cores (:func:`worker_threads`).

The parts: what a batch runs (:mod:`~en17037cli.batch.plan`: variants, run specs), what a worker
does with a run (:mod:`~en17037cli.batch.worker`) and the batch as a whole, on an executor
(:mod:`~en17037cli.batch.runner`); their public names are here.
"""
from __future__ import annotations

from en17037cli.batch.plan import ROOMS_PER_TASK, RunSpec, Variant, load_variants, plan_runs
from en17037cli.batch.runner import check_batch_folder, make_executor, run, run_batch, write_summary
from en17037cli.batch.worker import BUILDS, assess_rooms, clear_sessions, finish_run, open_run, worker_threads

__all__ = ["BUILDS", "ROOMS_PER_TASK", "RunSpec", "Variant", "assess_rooms", "check_batch_folder", "clear_sessions",
           "finish_run", "load_variants", "make_executor", "open_run", "plan_runs", "run", "run_batch", "worker_threads",
           "write_summary"]
