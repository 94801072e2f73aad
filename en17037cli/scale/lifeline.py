"""Worker processes end with the process that started them.

A check or a batch killed from outside (a CI job's time limit sends SIGTERM, then SIGKILL) runs
no cleanup, and a worker blocked on its queue or pipe waits forever: each holds a copy of the
other end (a forked picture worker inherits its parent's end of its own pipe; a pool worker
holds the writer of the queue it reads; a forkserver's child the pipe that would tell the server
its parent is gone). They were left running, orphaned. Every worker the package starts (the
picture workers, the batch's process pool, a local Dask cluster's workers) calls
:func:`end_with_parent` first thing:

* on Linux the kernel ends it (``prctl(PR_SET_PDEATHSIG, SIGKILL)``, via ctypes) when the process
  that forked it ends, for a worker forked by the run itself from its main thread (the picture
  workers; prctl(2): the signal follows the death of the forking *thread*, so it is not used for
  workers started from other threads or from a forkserver);
* everywhere, a daemon thread waits on the run's process (a pidfd on Linux 5.3+, else a check
  every :data:`POLL_S`) and ends the worker when it has ended.

A local Dask cluster's workers are spawned by their nannies, which live in the run's process;
Dask ends a worker whose nanny is gone (its own parent pipe), which the tests check. Radiance's
programs get the kernel's signal (:func:`program_ends_with_me`).
"""
from __future__ import annotations

import os
import select
import signal
import sys
import threading
import time

#: prctl(2) option: the signal this process gets when the thread that forked it ends (linux/prctl.h)
PR_SET_PDEATHSIG = 1
#: Where no pidfd can be waited on: how often the worker checks that the run is still there [s]
POLL_S = 0.5
#: The exit status of a worker whose run has ended (128 + SIGKILL, as the kernel's own would be)
ORPHAN_EXIT = 128 + signal.SIGKILL


def kernel_ends_me() -> bool:
    """Ask the kernel for SIGKILL when the thread that forked this process ends (Linux; False elsewhere
    or where prctl is not to be had)."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def program_ends_with_me():
    """A ``preexec_fn`` for :mod:`subprocess`: the program started (Radiance's ``rtrace``) gets
    SIGKILL when the thread that starts it ends (Linux), or None elsewhere. ``prctl`` is looked up
    here, in the parent: the child between fork and exec only calls it (no dlopen, no lock)."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        import ctypes

        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    sig = int(signal.SIGKILL)
    return lambda: prctl(PR_SET_PDEATHSIG, sig, 0, 0, 0)


def _alive(pid: int) -> bool:
    """Whether process ``pid`` is still running (not ended, not a zombie waiting to be reaped)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            return f.read().rsplit(b")", 1)[1].split()[0] != b"Z"
    except OSError:
        return True  # no /proc (macOS): os.kill said it is there


def _watch(pid: int) -> None:
    """Block until process ``pid`` ends, then end this one."""
    try:
        fd = os.pidfd_open(pid)  # Linux 5.3+: readable once the process has ended
    except (AttributeError, OSError):
        fd = None
    if fd is not None:
        select.select([fd], [], [])
    else:
        while _alive(pid):
            time.sleep(POLL_S)
    os._exit(ORPHAN_EXIT)


def end_with_parent(run_pid: int, kernel: bool = False) -> None:
    """In a worker: end this process when process ``run_pid`` (the run that started it) ends.

    Parameters
    ----------
    run_pid : the run's process id, taken by the run before it started the worker
    kernel : also ask the kernel (:func:`kernel_ends_me`): only for a worker forked by ``run_pid``
        itself from a thread that lives as long as the run (its main thread)
    """
    if kernel and os.getppid() == run_pid:
        kernel_ends_me()
    if not _alive(run_pid) or (kernel and os.getppid() != run_pid):  # it ended before the worker got here
        os._exit(ORPHAN_EXIT)
    threading.Thread(target=_watch, args=(run_pid,), name="en17037-lifeline", daemon=True).start()


def start_worker(run_pid: int, initializer, *initargs) -> None:
    """A process pool's initializer: :func:`end_with_parent`, then the pool's own ``initializer``."""
    end_with_parent(run_pid)
    if initializer is not None:
        initializer(*initargs)
