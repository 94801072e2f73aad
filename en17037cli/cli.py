"""``en17037``: the command-line interface, a thin layer over :mod:`en17037cli.check`.

Exit codes: 0 every required level met, 1 a required level missed, 2 bad input, 3 internal error.
Domain errors become one-line messages here, in one place.
"""
from __future__ import annotations

import json
import sys
import traceback
from pathlib import Path

import click

from en17037cli import __version__

EXIT_PASS, EXIT_FAIL, EXIT_INPUT, EXIT_INTERNAL = 0, 1, 2, 3


def _stderr_console():
    from rich.console import Console

    return Console(stderr=True)


def _progress_factory(enabled: bool):
    """A ``progress(total, label) -> advance(n)`` callable drawing rich bars on stderr, or None."""
    if not enabled:
        return None, None
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                   console=_stderr_console(), transient=True)

    def progress(total: int, label: str):
        task = bar.add_task(label, total=total)
        return lambda n: bar.advance(task, n)

    return bar, progress


def _fail(message: str, code: int):
    for line in str(message).splitlines() or [""]:
        click.echo(f"error: {line}", err=True)
    sys.exit(code)


def _guard(fn):
    """Run ``fn``; turn InputError into exit 2 and anything unexpected into exit 3."""
    from en17037cli.errors import InputError

    try:
        return fn()
    except InputError as exc:
        _fail(str(exc), EXIT_INPUT)
    except (SystemExit, KeyboardInterrupt):
        raise
    except click.exceptions.Exit:
        raise
    except Exception as exc:  # noqa: BLE001 - the one place internal errors are reported
        tb = traceback.format_exc(limit=-3).strip().splitlines()
        _fail(f"internal error ({type(exc).__name__}: {exc}); please report it with this project. {tb[-1] if tb else ''}", EXIT_INTERNAL)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="en17037")
def cli():
    """Check EN 17037 View out (5.2) and Exposure to sunlight (5.3) on a 3D model."""


@cli.command()
@click.argument("project_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Report folder [default: en17037-report/ beside the project file].")
@click.option("--only", type=click.Choice(["view", "sunlight"]), default=None, help="Run one check only.")
@click.option("--set", "overrides", multiple=True, metavar="KEY.PATH=VALUE",
              help="Override a project key, e.g. --set sunlight.timestep_min=1 (repeatable).")
@click.option("--quiet", "-q", is_flag=True, help="No progress bars and no summary.")
def check(project_file: Path, out_dir, only, overrides, quiet):
    """Run the checks of PROJECT_FILE and write the reports."""
    from en17037cli import report as rep
    from en17037cli.check import run_check
    from en17037cli.project import load_project

    out = out_dir or project_file.parent / "en17037-report"

    def run():
        rep.remove_reports(out) if out.is_dir() else None
        project = load_project(project_file, list(overrides))
        bar, progress = _progress_factory(not quiet and sys.stderr.isatty())
        if bar is not None:
            with bar:
                result = run_check(project, only, progress)
        else:
            result = run_check(project, only)
        timer = result["timer"]
        report = rep.build_report(project, result, timer.t)
        timer.stage("report")
        report["timings_s"] = {k: round(v, 3) for k, v in timer.t.items()} | {"total": round(sum(timer.t.values()), 3)}
        rep.write_reports(report, out)
        return report

    report = _guard(run)
    if not quiet:
        _summary(report, out)
    sys.exit(EXIT_PASS if report["status"] == "pass" else EXIT_FAIL)


def _summary(report: dict, out: Path):
    from rich.table import Table

    table = Table(title=f"EN 17037: {report['project']['name']}")
    for col in ("room", "check", "reached", "required", "result"):
        table.add_column(col)
    for room in report["rooms"]:
        for name, key in (("view out", "view"), ("sunlight", "sunlight")):
            r = room[key]
            if r:
                extra = f" ({r['hours']} h on {r['assessed_date']})" if key == "sunlight" else ""
                table.add_row(room["name"], name + extra, r["level"], r["required"], "PASS" if r["status"] == "pass" else "FAIL")
    console = _stderr_console()
    console.print(table)
    console.print(f"status: {report['status'].upper()}; reports in {out}/ (report.md, report.json, view_points.csv, sunlight_days.csv)")


@cli.command()
@click.argument("project_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--set", "overrides", multiple=True, metavar="KEY.PATH=VALUE", help="Override a project key.")
def validate(project_file: Path, overrides):
    """Check PROJECT_FILE and its geometry; print faces per layer and each room's windows."""
    from en17037cli.project import load_project
    from en17037cli.scene import build_scene, layer_counts

    def run():
        project = load_project(project_file, list(overrides))
        return project, build_scene(project)

    project, scene = _guard(run)
    click.echo(f"{project_file}: valid")
    click.echo("faces per layer: " + ", ".join(f"{k} {v}" for k, v in layer_counts(scene).items()))
    for room in scene.rooms:
        click.echo(f"room '{room.name}': floor {room.floor.area:.2f} m² ({room.floor_source}), {len(room.windows)} window(s)")
        for w in room.windows:
            n = ", ".join(f"{c:.4f}" for c in w.normal)
            click.echo(f"  window '{w.name}': {w.area_m2:.3f} m², outward normal ({n}), {len(w.face_ids)} faces")
    for note in scene.warnings + scene.notes:
        click.echo(f"note: {note}")


@cli.command()
@click.argument("which", type=click.Choice(["project", "report"]))
def schema(which):
    """Print the JSON Schema of the project file or of report.json."""
    from en17037cli.project import load_schema

    click.echo(json.dumps(load_schema(which), indent=2))


def main():
    cli(prog_name="en17037")
