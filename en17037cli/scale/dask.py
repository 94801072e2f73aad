"""A batch on a Dask distributed cluster (``batch --scheduler ADDRESS``, or ``local``).

Needs the ``dask`` extra (``pip install 'en17037cli[dask]'``); the workers need en17037cli, the
same version, and the project and model files at the same paths (a shared file system): they open
them, the client writes the reports. ``local`` starts a LocalCluster of ``jobs`` worker processes,
each with ``cores // jobs`` threads, which its ray engine uses (see :func:`en17037cli.batch.worker_threads`);
on a cluster of your own, start the workers with ``--nthreads`` their share of the cores, or set
``EN17037_THREADS`` in their environment, and unset ``MALLOC_TRIM_THRESHOLD_`` in their Dask config
(``distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_: null``; see below).
"""
from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

from en17037cli.errors import InputError

#: How long to wait for a scheduler [s].
CONNECT_TIMEOUT_S = 20


def _distributed():
    try:
        import distributed
    except ImportError:
        raise InputError("--scheduler: needs Dask (dask[distributed]); install it with pip install 'en17037cli[dask]', "
                         "or leave --scheduler out to use the local process pool") from None
    return distributed


class DaskExecutor:
    """Submits calls to a Dask cluster: ``address`` of a running scheduler, or ``local`` for a
    LocalCluster of ``jobs`` workers (``processes=False``: threads of this process, for tests)."""

    def __init__(self, address: str, jobs: int = 1, threads_per_worker: int = 1, processes: bool = True,
                 cleanup: Callable | None = None):
        distributed = _distributed()
        self._cluster = None
        self._cleanup = cleanup
        if address == "local":
            import dask

            # Dask's nannies set MALLOC_TRIM_THRESHOLD_ in their workers, which stops glibc from
            # raising its mmap threshold: every array over 128 kB is then mapped and unmapped. On 36
            # rooms of the IFC block that took 8.6 s of system time instead of 1.3 s and about a
            # quarter more wall time. Our workers keep glibc's default.
            with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}):
                self._cluster = distributed.LocalCluster(n_workers=jobs, threads_per_worker=threads_per_worker,
                                                         processes=processes, dashboard_address=None)
            self.client = distributed.Client(self._cluster)
        else:
            try:
                self.client = distributed.Client(address, timeout=CONNECT_TIMEOUT_S)
            except (OSError, TimeoutError, ValueError) as exc:
                raise InputError(f"--scheduler {address}: cannot reach a Dask scheduler there ({exc}); check the address "
                                 "(tcp://host:8786) or use --scheduler local") from None
        self.workers = max(1, len(self.client.scheduler_info().get("workers", {})))

    def submit(self, fn: Callable, *args) -> Any:
        return self.client.submit(fn, *args, pure=False)

    def wait(self, handles: Iterable) -> list:
        from distributed import wait

        return list(wait(list(handles), return_when="FIRST_COMPLETED").done)

    def result(self, handle) -> Any:
        return handle.result()

    def close(self) -> None:
        try:
            if self._cleanup is not None:
                self.client.run(self._cleanup)  # free the workers' cached scenes and engines
        finally:
            self.client.close()
            if self._cluster is not None:
                self._cluster.close()
