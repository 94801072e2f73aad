"""Worker processes end with the run that started them (issue 35): a check killed from outside (a
CI job's time limit: SIGTERM, then SIGKILL) left a worker running, orphaned. Each kind of worker
the package starts is started in a subprocess, which is then killed with SIGKILL (no cleanup
runs); no worker may survive it. Linux only (/proc, the kernel's parent-death signal)."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")

ROOT = Path(__file__).resolve().parents[1]
#: How long the workers get to notice [s]: the kernel's signal is immediate and a pidfd wait wakes
#: at once; generous for a loaded 2-core machine, never reached when they do end.
GRACE_S = 20.0


def running(pid: int) -> bool:
    """Whether ``pid`` is a live process (a zombie, ended and not yet reaped, is not)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_bytes()
    except OSError:
        return False
    return stat.rsplit(b")", 1)[1].split()[0] != b"Z"


def children(pid: int) -> set[int]:
    """Every descendant of ``pid`` now, from /proc."""
    parent = {}
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                parent[int(d.name)] = int((d / "stat").read_bytes().rsplit(b")", 1)[1].split()[1])
            except (OSError, ValueError, IndexError):
                continue
    out, todo = set(), [pid]
    while todo:
        p = todo.pop()
        kids = {c for c, pp in parent.items() if pp == p}
        todo += list(kids - out)
        out |= kids
    return out


def survivors(pids: set[int]) -> set[int]:
    deadline = time.monotonic() + GRACE_S
    while time.monotonic() < deadline:
        alive = {p for p in pids if running(p)}
        if not alive:
            return set()
        time.sleep(0.1)
    return alive


def kill_and_wait(proc: subprocess.Popen, pids: set[int]) -> set[int]:
    assert pids, "the run started no worker"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    return survivors(pids)


SCRIPT = textwrap.dedent("""
    import os, sys, time

    def main():
        kind = sys.argv[1]
        if kind == "pictures":
            from en17037cli.report.figures import Painters
            painters = Painters(2)
            painters._start()  # a second one, as a run with many pictures forks
        elif kind == "pool":
            from en17037cli.batch import make_executor
            ex = make_executor(2)
            print(*{f.result() for f in [ex.submit(os.getpid) for _ in range(4)]}, flush=True)
        else:
            from en17037cli.batch import make_executor
            ex = make_executor(2, "local")
            ex.client.run(os.getpid)
        print("ready", flush=True)
        time.sleep(600)

    if __name__ == "__main__":
        main()
""")


@pytest.mark.parametrize("kind", ["pictures", "pool", "dask"])
def test_workers_end_when_their_run_is_killed(tmp_path, kind):
    """Before: a picture worker (blocked in recv on a pipe whose other end it holds itself) and a
    pool worker (blocked on its queue), with the forkserver it came from, stayed running."""
    if kind == "dask":
        pytest.importorskip("distributed")
    script = tmp_path / "run.py"
    script.write_text(SCRIPT)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, str(script), kind], stdout=subprocess.PIPE, text=True, env=env, cwd=tmp_path)
    try:
        for line in proc.stdout:  # until the workers are up
            if line.strip() == "ready":
                break
        pids = children(proc.pid)
    except BaseException:
        proc.kill()
        raise
    assert not kill_and_wait(proc, pids), f"{kind}: workers still running after their run was killed"


def test_a_check_killed_from_outside_leaves_no_process(tmp_path):
    """The case of the issue: ``en17037 check`` killed with SIGKILL while it runs (its picture
    worker forked and waiting): nothing of it remains."""
    project = ROOT / "sample_projects" / "synthetic-street" / "project.yaml"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-m", "en17037cli", "check", str(project), "--out", str(tmp_path / "r")],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    pids: set[int] = set()
    deadline = time.monotonic() + 60
    while not pids and proc.poll() is None and time.monotonic() < deadline:
        pids = children(proc.pid)
        time.sleep(0.05)
    if proc.poll() is not None:
        pytest.fail("the check ended before it started its picture worker")
    assert not kill_and_wait(proc, pids)
