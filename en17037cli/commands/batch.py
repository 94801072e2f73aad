"""``en17037 batch``: many projects (or a project times its variants) and one summary."""
from __future__ import annotations

import sys
from pathlib import Path

import click

from en17037cli.commands.errors import exit_on_sigterm, guard
from en17037cli.commands.options import junit_option, max_points_option, only_option, set_option
from en17037cli.terminal import annotate, batch_table


@click.command()
@click.argument("projects", nargs=-1, required=True, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--variants", type=click.Path(dir_okay=False, path_type=Path), default=None, metavar="FILE",
              help="YAML list of named override sets ({name: wide, set: {key.path: value}}): each project runs once per variant.")
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path), default=Path("en17037-batch"),
              show_default=True, help="Folder of the summary (summary.csv, summary.json) and of each run's report folder.")
@click.option("--jobs", "-j", type=click.IntRange(1), default=None,
              help="Worker processes (with --scheduler local: workers) [default: the cores]; each ray engine gets cores // jobs threads.")
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="Run on a Dask cluster: its scheduler's address (tcp://host:8786), or 'local' for a LocalCluster "
                   "(needs the dask extra).")
@only_option
@set_option
@max_points_option
@click.option("--rooms-per-task", type=click.IntRange(1), default=None, metavar="N",
              help="A project of more rooms is spread over the workers in groups of N rooms [default: 8].")
@junit_option
@click.option("--quiet", "-q", is_flag=True, help="No progress lines and no table.")
def batch(projects, variants, out_dir: Path, jobs, scheduler, only, overrides, max_points, rooms_per_task, junit, quiet):
    """Check many PROJECTS (or each project once per variant) and write one summary.

    Each run writes its own report folder under --out; summary.csv and summary.json hold one row
    per room and criterion of every run. A run that fails (bad input, internal error) is recorded
    with its message and the others go on; the exit code is the worst of the runs.
    """
    from en17037cli import batch as b
    from en17037cli.budget import MAX_POINTS
    from en17037cli.report.folder import check_file

    def prepare():
        chosen = b.load_variants(variants) if variants is not None else None
        specs = b.plan_runs([str(p) for p in projects], chosen, tuple(overrides), only, max_points or MAX_POINTS,
                            rooms_per_task or b.ROOMS_PER_TASK)
        b.check_batch_folder(out_dir)
        if junit is not None:
            check_file(junit, "--junit")
        return specs

    exit_on_sigterm()
    specs = guard(prepare)
    n = len(specs)
    finished = []

    def progress(rec):
        finished.append(rec)
        if not quiet:
            what = {0: "PASS", 1: "FAIL", 2: "BAD INPUT", 3: "INTERNAL ERROR"}[rec.exit_code]
            click.echo(f"[{len(finished)}/{n}] {rec.label}: {what}", err=True)

    records = guard(lambda: b.run(specs, out_dir, jobs, scheduler, junit, on_done=progress))
    annotate(records)
    if not quiet:
        batch_table(records, out_dir)
    from en17037cli.report.summary import worst_exit_code

    sys.exit(worst_exit_code(records))
