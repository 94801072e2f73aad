"""Benchmark of the facade screen (issue 45): ``en17037 screen`` on a real tile of about 1,000
buildings, every facade probed at 3 m storeys and 3 m spacing, whole process: wall time, CPU time
(user and system of the process and its workers, sampled: on a shared machine the wall time
follows the other load, the CPU time much less), time per probe, peak memory of the process
and its workers together; on a local process pool of 1 and 2
workers and on a Dask LocalCluster of 1, 2 and 4 workers, with the ratio of each time to the
one-worker time. Goals: under 10 minutes on 2 cores, under 4 GB; twice the workers, close to half
the time.

Nothing is downloaded here. The tile's path comes from the argument or ``EN17037_DISTRICT_TILE``;
without one the benchmark says so and stops (exit 0). The tile used in docs/district.md: The
Hague's 3D model, tile 01 (844 LoD2 buildings, CityGML 2.0, EPSG:28992), as converted in the
cityjson/specs repository's history (``example-datasets/DenHaag/DenHaag_01.zip``, git blob
58a84d3; from https://data.overheid.nl/data/dataset/ngr-3d-model-den-haag): unzip it and give
``DenHaag_01.xml`` a ``.gml`` ending. Any CityJSON or CityGML tile in a projected CRS will do.

Usage: ``python benchmarks/bench_district.py [TILE] [--runs pool1,pool2,dask1,dask2,dask4] [--box X0 Y0 X1 Y1]
[--keep DIR] [--out bench_district.json]`` (``--box``: screen the buildings whose centre lies in that
rectangle of the tile's CRS, the rest as context; ``--keep``: the last run's outputs are kept there).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ENV = "EN17037_DISTRICT_TILE"
RUNS = {"pool1": ["-j", "1"], "pool2": ["-j", "2"], "dask1": ["--scheduler", "local", "-j", "1"],
        "dask2": ["--scheduler", "local", "-j", "2"], "dask4": ["--scheduler", "local", "-j", "4"]}


def watch(pid: int, stop: threading.Event, out: dict) -> None:
    """Sample the process ``pid`` and its descendants every 0.2 s: the peak of their summed resident
    memory [MB] and, per process, the last CPU time seen (user + system [s]), summed at the end."""
    import psutil

    peak, cpu = 0, {}
    try:
        root = psutil.Process(pid)
    except psutil.NoSuchProcess:
        return
    while not stop.is_set():
        total = 0
        try:
            procs = [root, *root.children(recursive=True)]
        except psutil.NoSuchProcess:
            break
        for p in procs:
            try:
                total += p.memory_info().rss
                t = p.cpu_times()
                cpu[p.pid] = t.user + t.system
            except psutil.NoSuchProcess:
                pass
        peak = max(peak, total)
        stop.wait(0.2)
    out["peak_mb"], out["cpu_s"] = peak / 2**20, sum(cpu.values())


def project(folder: Path, tile: Path, box=None) -> Path:
    p = folder / "project.yaml"
    which = "\"*\"" if box is None else json.dumps({"polygon": [[box[0], box[1]], [box[2], box[1]], [box[2], box[3]],
                                                                [box[0], box[3]]]})
    p.write_text(f"version: 1\nname: district benchmark\nmodel: {{files: [{{path: {json.dumps(str(tile.resolve()))}}}]}}\n"
                 f"location: {{timezone: Europe/Amsterdam}}\nscreen: {{buildings: {which}, storey_height_m: 3.0, spacing_m: 3.0}}\n"
                 "sunlight: {}\n")
    return p


def run(p: Path, out: Path, args: list) -> dict:
    """One whole ``en17037 screen`` in a child process: wall time, peak memory, the summary's counts."""
    cmd = [sys.executable, "-m", "en17037cli", "screen", str(p), "--out", str(out), "-q", *args]
    tic = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    stop, seen = threading.Event(), {}
    watcher = threading.Thread(target=watch, args=(proc.pid, stop, seen))
    watcher.start()
    stdout, stderr = proc.communicate()
    wall = time.perf_counter() - tic
    stop.set()
    watcher.join()
    if proc.returncode not in (0, 1):
        raise SystemExit(f"screen failed ({proc.returncode}): {stderr.strip()[-500:]}")
    info = json.loads((out / "summary.json").read_text())
    n = info["counts"]["probes"]
    return {"args": " ".join(args), "wall_s": round(wall, 1), "cpu_s": round(seen.get("cpu_s", float("nan")), 1), "probes": n,
            "buildings": info["counts"]["buildings"],
            "per_probe_ms": round(1000 * wall / max(n, 1), 2), "peak_mb": round(seen.get("peak_mb", float("nan"))),
            "parts_s": {k: v for k, v in info["timings_s"].items() if k in ("probes", "sunlight", "sky_and_view")}}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("tile", nargs="?", default=os.environ.get(ENV))
    ap.add_argument("--runs", default="pool2,pool1,dask1,dask2,dask4")
    ap.add_argument("--out", default=None)
    ap.add_argument("--box", nargs=4, type=float, default=None)
    ap.add_argument("--keep", default=None)
    a = ap.parse_args(argv)
    if not a.tile or not Path(a.tile).is_file():
        print(f"bench_district: no tile (give its path or set {ENV}; see this file's docstring for where to get one): skipped")
        return 0
    with open("/proc/loadavg") as fh:
        load = fh.read().split()[:3]
    print(f"tile {a.tile}; load average before: {' '.join(load)}; cores {os.cpu_count()}")
    rows = []
    with tempfile.TemporaryDirectory(prefix="en17037-district-") as tmp:
        p = project(Path(tmp), Path(a.tile), a.box)
        for name in a.runs.split(","):
            where = Path(a.keep) if a.keep else Path(tmp) / name
            r = run(p, where, RUNS[name])
            r["run"] = name
            rows.append(r)
            print(f"{name:6s} {r['wall_s']:8.1f} s wall {r['cpu_s']:8.1f} s CPU  {r['per_probe_ms']:7.2f} ms/probe  {r['peak_mb']:6.0f} MB  "
                  f"{r['probes']} probes, {r['buildings']} buildings  parts {r['parts_s']}", flush=True)
    base = {k[:4]: r["wall_s"] for r in rows for k in [r["run"]] if k.endswith("1")}
    for r in rows:
        one = base.get(r["run"][:4])
        if one:
            r["time_vs_one_worker"] = round(r["wall_s"] / one, 3)
            print(f"{r['run']:6s} time / one worker's: {r['time_vs_one_worker']:.3f}")
    with open("/proc/loadavg") as fh:
        print(f"load average after: {' '.join(fh.read().split()[:3])}")
    if a.out:
        Path(a.out).write_text(json.dumps({"tile": a.tile, "load_before": load, "runs": rows}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
