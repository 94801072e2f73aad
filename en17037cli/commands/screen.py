"""``en17037 screen``: every facade of a city model probed for sunlight, sky and view (docs/district.md)."""
from __future__ import annotations

import sys
from pathlib import Path

import click

from en17037cli.commands.errors import EXIT_INTERNAL, exit_on_sigterm, guard
from en17037cli.commands.options import project_argument, set_option


@click.command()
@project_argument
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Folder of the outputs (probes.csv, probes.geojson, buildings.csv, the city model with the results, "
                   "report.html, summary.json) [default: en17037-screen/<project file name>/ beside the project file].")
@click.option("--jobs", "-j", type=click.IntRange(1), default=None,
              help="Worker processes (with --scheduler local: workers) [default: the cores]; each ray engine gets cores // jobs threads.")
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="Run on a Dask cluster: its scheduler's address (tcp://host:8786), or 'local' for a LocalCluster "
                   "(needs the dask extra; the workers need the project and model files at the same paths).")
@set_option
@click.option("--quiet", "-q", is_flag=True, help="No progress lines.")
def screen(project_file: Path, out_dir, jobs, scheduler, overrides, quiet):
    """Probe every wall of the buildings of a city model (the project's screen: section) for sunlight
    (5.3), the vertical sky component and the view (5.2), and write where planners look.

    Exit code 0 where every screened building has some facade reaching the sunlight level the
    project requires (requirements.sunlight), 1 where one has none, 2 for bad input, 3 for an
    internal error.
    """
    from en17037cli.district.run import screen as run

    exit_on_sigterm()
    out = out_dir or project_file.parent / "en17037-screen" / project_file.stem
    log = None if quiet else (lambda line: click.echo(line, err=True))
    res = guard(lambda: run(project_file, out, tuple(overrides), jobs, scheduler, log=log))
    for w in res.warnings:
        click.echo(f"warning: {w}", err=True)
    per = 1000 * res.seconds / max(res.probes, 1)
    click.echo(f"screened {res.buildings - res.left_out} of {res.buildings} buildings ({res.left_out} left out): {res.probes} "
               f"probes, {res.shared} more on shared walls left out; {res.seconds:.1f} s, {per:.1f} ms per probe")
    failing = f"; {len(res.failing)} building(s) with no facade reaching the required sunlight" if res.failing else ""
    click.echo(f"status: {res.status.upper()}{failing}; outputs in {res.out}")
    if res.internal:  # the outputs stand for the others; a building the screen itself failed on is no pass
        click.echo(f"error: {res.internal} building(s) could not be screened by an internal error (the warnings name "
                   "them); please report it with this project", err=True)
        sys.exit(EXIT_INTERNAL)
    sys.exit(0 if res.status == "pass" else 1)
