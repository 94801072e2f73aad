"""Benchmark section ``pictures`` of benchmarks/bench.py: the CPU time of each picture of the client
report by kind, and per room of the seed office.

The seed office is checked once in this process (``pictures=True``) and each of its picture jobs
(:func:`en17037cli.report.figures.figure_jobs`) is drawn ``repeat`` times as PNG, as SVG and as
both (what a report draws); the figure is the median CPU time (``time.process_time``: it holds on a
machine shared with other work) of one drawing [ms]. The first picture of a process also pays for
imports and fonts: that is measured in a fresh interpreter (``first_picture_ms``: import of the
drawing code and one plan map, CPU).

``--against REV`` measures a commit of this repository the same way (its ``en17037cli`` exported
with ``git archive`` into a temporary folder) and prints both, before and after.

Usage: ``python benchmarks/bench.py --only pictures``, or ``python benchmarks/bench_pictures.py
[--repeat N] [--against REV]`` from the repository. Never a timed test: the figures are printed.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SEED = ROOT / "sample_projects" / "seed-office" / "project.yaml"

COLUMNS = ["kind", "count", "png_ms", "svg_ms", "both_ms"]

#: Run in a child process with the code under test on its path: prints the rows as JSON.
_MEASURE = r"""
import json, statistics, sys, time
t0 = time.process_time()
from en17037cli.report.figures import draw, figure_jobs
from en17037cli.report import pictures
from en17037cli.pipeline import run
from en17037cli.project import load_project
seed, repeat = sys.argv[1], int(sys.argv[2])
result = run(load_project(seed, []), pictures=True)
jobs = figure_jobs(result)
t1 = time.process_time()
draw(next(j for j in jobs if j.draw == "plan_map"))
first = time.process_time() - t1
def cpu(job, fmt):
    f = getattr(pictures, job.draw)
    times = []
    for _ in range(repeat):
        t = time.process_time()
        f(*job.args, **job.kwargs, fmt=fmt)
        times.append(time.process_time() - t)
    return 1000.0 * statistics.median(times)
rows = {}
for job in jobs:
    kind = job.draw if job.draw != "plan_map" else "plan_map " + job.kwargs["kind"]
    r = rows.setdefault(kind, {"kind": kind, "count": 0, "png_ms": [], "svg_ms": [], "both_ms": []})
    r["count"] += 1
    for fmt in ("png", "svg", "both"):
        r[fmt + "_ms"].append(cpu(job, fmt))
out = [{**r, **{k: statistics.mean(r[k]) for k in ("png_ms", "svg_ms", "both_ms")}} for r in rows.values()]
per_room = sum(r["both_ms"] * r["count"] for r in out) / max(len(result.rooms), 1)
out.append({"kind": "per room (seed office)", "count": len(jobs) // max(len(result.rooms), 1), "both_ms": per_room})
print(json.dumps({"rows": out, "first_picture_ms": 1000.0 * first}))
"""


def picture_cpu(repeat: int = 20, tree: Path | None = None) -> dict:
    """CPU per picture by kind [ms] on the seed office, the code of ``tree`` (default this checkout)."""
    env = dict(os.environ, PYTHONPATH=str(tree or ROOT), EN17037_THREADS=os.environ.get("EN17037_THREADS", "2"))
    # run from the tree measured: "python -c" puts the working folder first on the path
    done = subprocess.run([sys.executable, "-c", _MEASURE, str(SEED), str(repeat)], capture_output=True, text=True, check=True,
                          env=env, cwd=tree or ROOT)
    return json.loads(done.stdout.strip().splitlines()[-1])


def first_picture(tree: Path | None = None, repeat: int = 3) -> float:
    """CPU of a fresh interpreter's first plan map [ms]: imports, fonts and the drawing (median of ``repeat``)."""
    code = ("import time, numpy as np; t = time.process_time()\n"
            "from en17037cli.report.pictures import plan_map\n"
            "f = [[0, 0], [4, 0], [4, 3], [0, 3]]\n"
            "plan_map([[1, 1], [2, 1]], [1, 2], kind='level', thresholds=None, floor=f, utilised=None, windows=[[[1, 3], [3, 3]]],"
            " true_north_deg=0.0, fmt='both')\n"
            "print(1000 * (time.process_time() - t))")
    env = dict(os.environ, PYTHONPATH=str(tree or ROOT))
    return statistics.median(float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                                                  env=env, cwd=tree or ROOT).stdout) for _ in range(repeat))


def export(rev: str, directory: Path) -> Path:
    """The package of commit ``rev`` exported into ``directory`` (``git archive``)."""
    data = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "en17037cli"], capture_output=True, check=True).stdout
    tar = directory / "src.tar"
    tar.write_bytes(data)
    with tarfile.open(tar) as t:
        t.extractall(directory, filter="data")
    return directory


def pictures_cpu(repeat: int = 20, against: str | None = None) -> dict:
    """The rows of this checkout (and of ``against``, a commit, if given)."""
    out = {"after": picture_cpu(repeat), "after_first_ms": first_picture()}
    if against:
        with tempfile.TemporaryDirectory() as tmp:
            tree = export(against, Path(tmp))
            out["before"] = picture_cpu(repeat, tree)
            out["before_first_ms"] = first_picture(tree)
            out["against"] = against
    return out


def print_pictures(res: dict, table) -> None:
    """Print the rows with ``table(title, rows, columns)`` (bench.py's table)."""
    for key in ("before", "after"):
        if key in res:
            label = f"{res['against']} (before)" if key == "before" else "this checkout"
            table(f"CPU per picture of the seed office's report, {label} [ms] (first picture of a process, imports included: "
                  f"{res[key + '_first_ms']:.0f} ms)", res[key]["rows"], COLUMNS)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python benchmarks/bench_pictures.py", description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=20, help="drawings of each picture (median kept)")
    ap.add_argument("--against", help="a commit to measure as well (before)")
    args = ap.parse_args(argv)
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from bench import _table

    t = time.perf_counter()
    res = pictures_cpu(args.repeat, args.against)
    print_pictures(res, _table)
    print(f"({time.perf_counter() - t:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
