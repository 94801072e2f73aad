"""Where a batch's work runs: a small executor interface and its local implementations.

An executor runs module-level functions on plain-data arguments (:mod:`en17037cli.batch` submits
them) and hands back their results; the results do not depend on the executor:

* :class:`InlineExecutor`: in this process, one call after another (``--jobs 1``);
* :class:`PoolExecutor`: a local process pool (``--jobs N``);
* :class:`~en17037cli.scale.dask.DaskExecutor`: a Dask distributed cluster (``--scheduler``),
  imported only when asked for (the ``dask`` extra).
"""
from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
from collections.abc import Callable, Iterable
from typing import Any, Protocol


class Executor(Protocol):
    """Runs ``fn(*args)`` somewhere; ``wait`` blocks until at least one handle is done."""

    #: how many calls may run at once (for messages and benchmarks)
    workers: int

    def submit(self, fn: Callable, *args) -> Any: ...

    def wait(self, handles: Iterable) -> list: ...

    def result(self, handle) -> Any: ...

    def close(self) -> None: ...


class InlineExecutor:
    """Runs each call at once, in this process (no pool to start); ``cleanup()`` runs on close."""

    workers = 1

    def __init__(self, cleanup: Callable | None = None):
        self._cleanup = cleanup

    def submit(self, fn: Callable, *args) -> cf.Future:
        fut: cf.Future = cf.Future()
        try:
            fut.set_result(fn(*args))
        except BaseException as exc:  # noqa: BLE001 - handed to the caller through the future
            if isinstance(exc, KeyboardInterrupt | SystemExit):
                raise
            fut.set_exception(exc)
        return fut

    def wait(self, handles: Iterable) -> list:
        return list(handles)

    def result(self, handle: cf.Future) -> Any:
        return handle.result()

    def close(self) -> None:
        if self._cleanup is not None:
            self._cleanup()


def _context():
    """forkserver where the platform has it (workers start from a clean server process, not from a
    copy of the caller and its threads), else spawn."""
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")


class PoolExecutor:
    """A local pool of ``jobs`` worker processes; ``initializer(*initargs)`` runs in each."""

    def __init__(self, jobs: int, initializer: Callable | None = None, initargs: tuple = ()):
        import os

        from en17037cli.scale.lifeline import start_worker

        self.workers = jobs
        # each worker ends with this process, even killed (:mod:`~en17037cli.scale.lifeline`)
        self._pool = cf.ProcessPoolExecutor(max_workers=jobs, mp_context=_context(), initializer=start_worker,
                                            initargs=(os.getpid(), initializer, *initargs))

    def submit(self, fn: Callable, *args) -> cf.Future:
        return self._pool.submit(fn, *args)

    def wait(self, handles: Iterable) -> list:
        return list(cf.wait(list(handles), return_when=cf.FIRST_COMPLETED).done)

    def result(self, handle: cf.Future) -> Any:
        return handle.result()

    def close(self) -> None:
        self._pool.shutdown(wait=True, cancel_futures=True)
