"""Profile: ``python benchmarks/profiling.py`` (or ``make profile``) prints the top functions of
``en17037 check`` on the seed office without its daylight section and on the paper's grid.

Each check runs in this process under cProfile with a CPU-time clock (``time.process_time``), so
the shares hold on a machine shared with other work; with one ray-tracing thread
(``EN17037_THREADS=1``), so that the work the engine's threads do (Embree and the numpy around
the rays) is seen by the profiler, which follows the main thread only. Pictures are drawn in this
process too (no drawing workers). Imports are part of the first check's profile.

Usage: ``python benchmarks/profiling.py [--only seed|paper ...] [--project FILE ...] [--top N]
[--sort tottime|cumulative] [--save DIR]`` from the repository (it needs ``sample_projects/``);
``--project`` profiles other project files instead (a real export's).
"""
from __future__ import annotations

import argparse
import cProfile
import io
import os
import pstats
import sys
import tempfile
import time
from pathlib import Path

from goals import seed_without_daylight  # benchmarks/goals.py: the same project the goals time

ROOT = Path(__file__).resolve().parent.parent
PAPER = ROOT / "sample_projects" / "seed-office" / "project-paper-grid.yaml"


def profile_check(project: Path, out: Path, pictures: bool = True) -> tuple[cProfile.Profile, float, float]:
    """``en17037 check project`` in this process under cProfile (CPU clock): the profile, its CPU
    time [s] and wall time [s]."""
    from en17037cli import cli as cli_module
    from en17037cli.cli import cli

    cli_module._painters = lambda: None  # the pictures are drawn in this process, seen by the profiler
    args = ["check", str(project), "--quiet", "--out", str(out)] + ([] if pictures else ["--no-plots"])
    prof = cProfile.Profile(time.process_time)
    c0, w0 = time.process_time(), time.perf_counter()
    prof.enable()
    try:
        cli.main(args, standalone_mode=False)
    except SystemExit:
        pass
    finally:
        prof.disable()
    return prof, time.process_time() - c0, time.perf_counter() - w0


def _print(prof: cProfile.Profile, title: str, cpu: float, wall: float, top: int, sorts: list[str]) -> None:
    print(f"\n=== {title}: {cpu:.2f} s CPU ({wall:.2f} s wall) under cProfile, one ray-tracing thread ===")
    for key in sorts:
        buf = io.StringIO()
        st = pstats.Stats(prof, stream=buf)
        st.sort_stats(key).print_stats(top)
        text = buf.getvalue()
        body = text[text.find("   ncalls"):] if "   ncalls" in text else text
        print(f"--- top {top} by {key} ---")
        print(body.replace(str(ROOT) + "/", "").replace(sys.prefix + "/", "").rstrip())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python benchmarks/profiling.py", description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="+", choices=("seed", "paper"), default=["seed", "paper"])
    ap.add_argument("--project", nargs="+", type=Path, default=[], help="profile these project files instead")
    ap.add_argument("--top", type=int, default=25, help="functions listed per table (default 25)")
    ap.add_argument("--sort", nargs="+", choices=("tottime", "cumulative"), default=["tottime", "cumulative"])
    ap.add_argument("--save", type=Path, default=None, help="also write each profile (.prof) into this folder")
    args = ap.parse_args(argv)
    os.environ["EN17037_THREADS"] = "1"
    with tempfile.TemporaryDirectory() as tmp:
        jobs = [(p.stem, str(p), p.resolve()) for p in args.project]
        if "seed" in args.only and not args.project:
            jobs.append(("seed", "seed office, view and sunlight (no daylight section)", seed_without_daylight(Path(tmp))))
        if "paper" in args.only and not args.project:
            jobs.append(("paper", "paper's grid (project-paper-grid.yaml, 2,800 viewpoints)", PAPER))
        for key, title, project in jobs:
            prof, cpu, wall = profile_check(project, Path(tmp) / f"out-{key}")
            if args.save is not None:
                args.save.mkdir(parents=True, exist_ok=True)
                prof.dump_stats(str(args.save / f"{key}.prof"))
            _print(prof, title, cpu, wall, args.top, args.sort)
    return 0


if __name__ == "__main__":
    sys.exit(main())
