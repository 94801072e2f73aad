"""``en17037``: the command-line interface, click commands over the library only.

Conventions every command follows (add new ones the same way):

- Exit codes: 0 every required level met, 1 a required level missed (or a required check not
  assessed), 2 bad input, 3 internal error, 130 Ctrl-C, 143 SIGTERM.
- **stdout carries results** (the verdict table and status line of ``check``, what ``validate``
  found, the tables of ``compare`` and ``batch``, ``--json`` documents); **stderr carries
  diagnostics** (``error:``, ``warning:`` and ``note:`` lines, progress bars). So
  ``en17037 check p.yaml > log.txt`` keeps the verdict and a script can parse ``--json``.
- Domain errors become one line ``error: ...`` here, in one place (:func:`guard`), and so do usage
  mistakes (naming the command's ``--help``), exit 2. Help (``--help``, or a bare ``en17037``) goes
  to stdout with exit 0.
- Durations for people are written ``5 h 52 min`` (:func:`~en17037cli.report.numbers.fmt_duration`);
  decimal hours appear only in machine fields whose names end in ``_h``.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import click

from en17037cli import __version__
from en17037cli.terminal import annotate, batch_table, comparison_table, list_objects, progress_factory, summary

EXIT_PASS, EXIT_FAIL, EXIT_INPUT, EXIT_INTERNAL = 0, 1, 2, 3


def _fail(message: str, code: int):
    for line in str(message).splitlines() or [""]:
        click.echo(f"error: {line}", err=True)
    sys.exit(code)


def guard(fn):
    """Run ``fn``; turn InputError into exit 2 and anything unexpected into exit 3."""
    from en17037cli.errors import InputError, internal_message

    try:
        return fn()
    except InputError as exc:
        _fail(str(exc), EXIT_INPUT)
    except (SystemExit, KeyboardInterrupt, click.exceptions.Exit):
        raise
    except Exception as exc:  # noqa: BLE001 - the one place internal errors are reported
        _fail(internal_message(exc), EXIT_INTERNAL)


class KindValue(click.ParamType):
    """``KIND=NUMBER`` with KIND from a set, e.g. ``--target angle_deg=0.01``; ``kinds`` is a callable
    so the set can live in a module imported only when the option is used."""

    name = "KIND=VALUE"

    def __init__(self, kinds):
        self.kinds = kinds

    def convert(self, value, param, ctx):
        kinds = self.kinds()
        kind, sep, number = str(value).partition("=")
        if not sep or kind not in kinds:
            self.fail(f"{value}: unknown kind '{kind}'; use one of {', '.join(kinds)}", param, ctx)
        try:
            return kind, float(number)
        except ValueError:
            self.fail(f"{value}: '{number}' is not a number", param, ctx)


def project_argument(fn):
    return click.argument("project_file", type=click.Path(dir_okay=False, path_type=Path))(fn)


def max_points_option(fn):
    return click.option("--max-points", type=click.IntRange(1), default=None,
                        help="Viewpoint budget of a run [default: 100,000]; a larger project stops with exit 2 before any work.")(fn)


def set_option(fn):
    return click.option("--set", "overrides", multiple=True, metavar="KEY.PATH=VALUE",
                        help="Override a project key, e.g. --set view.grid_spacing_m=1 (repeatable); a key with no effect "
                             "under the project's other settings is a warning saying why.")(fn)


class Group(click.Group):
    """click's group: help (and a bare group with no command) on stdout with exit 0; a usage mistake
    as one line ``error: ...`` on stderr naming the command's --help (exit 2), like every other input
    error; Ctrl-C as exit 130."""

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode, **extra)
        try:
            code = super().main(args, prog_name, complete_var, False, **extra)
        except click.exceptions.NoArgsIsHelpError as exc:  # a bare `en17037` (or group): its help, not an error
            click.echo(exc.ctx.get_help())
            sys.exit(EXIT_PASS)
        except click.UsageError as exc:  # one line, like every other input error (click lists choices on several)
            where = f" (see {exc.ctx.command_path} --help)" if exc.ctx is not None else ""
            _fail(" ".join(exc.format_message().split()) + where, EXIT_INPUT)
        except click.ClickException as exc:
            _fail(exc.format_message(), EXIT_INPUT)
        except (click.exceptions.Abort, KeyboardInterrupt):
            click.echo("error: interrupted", err=True)
            sys.exit(130)
        sys.exit(code or 0)


@click.group(cls=Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="en17037")
def cli():
    """Check EN 17037 daylight provision (5.1), view out (5.2), exposure to sunlight (5.3) and protection from glare (5.4) on a 3D model."""


def junit_option(fn):
    return click.option("--junit", type=click.Path(dir_okay=False, path_type=Path), default=None, metavar="FILE",
                        help="Also write JUnit XML: one test case per room and criterion (failure for FAIL, error for "
                             "not assessable / not assessed).")(fn)


@cli.command()
@project_argument
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Report folder [default: en17037-report/<project file stem>/ beside the project file].")
@click.option("--only", type=click.Choice(["view", "sunlight", "daylight", "glare"]), default=None,
              help="Run one check only (a required check left out is NOT ASSESSED and fails).")
@set_option
@max_points_option
@click.option("--baseline", type=click.Path(path_type=Path), default=None, metavar="REPORT",
              help="A report.json (or report folder) of an earlier design: fail (exit 1) only where a level or a status "
                   "got worse, or a new room or criterion fails.")
@junit_option
@click.option("--no-plots", is_flag=True, help="No pictures: report.html and report.md without maps, fisheyes or charts.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bars and no summary.")
@click.option("--json", "as_json", is_flag=True,
              help="Print report.json on stdout instead of the verdict table (for scripts; the reports are written too).")
def check(project_file: Path, out_dir, only, overrides, max_points, baseline, junit, no_plots, quiet, as_json):
    """Run the checks of PROJECT_FILE and write the reports."""
    from en17037cli import pipeline
    from en17037cli.preflight import MAX_POINTS
    from en17037cli.project import load_project
    from en17037cli.report.document import build_report
    from en17037cli.report.figures import pictures_available, render_figures
    from en17037cli.report.folder import check_file, check_folder, default_folder
    from en17037cli.report.write import WRITERS, write_reports

    out = out_dir or default_folder(project_file)

    def run():
        before = None
        if baseline is not None:
            from en17037cli.compare import load_report

            before = load_report(baseline, "--baseline")
        if junit is not None:
            check_file(junit, "--junit")
        project = load_project(project_file, list(overrides))
        check_folder(out, project.path, WRITERS)  # before any work: a folder we may not write stops here
        plots = not no_plots and pictures_available()
        painters = _painters() if plots else None
        try:
            tty = sys.stderr.isatty()
            bar, progress = progress_factory(not quiet and tty, lines=not quiet and not as_json and not tty)
            notify = None if quiet else (lambda line: click.echo(f"note: {line}", err=True))
            if bar is not None:
                with bar:
                    result = pipeline.run(project, only, progress, max_points or MAX_POINTS, pictures=plots, notify=notify)
            else:
                result = pipeline.run(project, only, progress, max_points=max_points or MAX_POINTS, pictures=plots,
                                      notify=notify)
            figures = render_figures(result, painters) if plots else []
        finally:
            if painters is not None:
                painters.close()
        if not no_plots and not plots:
            result.warnings.append("no pictures: they need matplotlib (pip install 'en17037cli[plot]'); "
                                   "report.html and report.md are written without them")
        report = build_report(result)
        write_reports(report, out, project.path, figures)
        comparison = None
        if before is not None:
            from en17037cli.compare import compare_reports

            comparison = compare_reports(before, report, str(baseline), str(out / "report.json"))
        record = _check_record(project_file, out, report, result, comparison)
        if junit is not None:
            from en17037cli.report.folder import write_file
            from en17037cli.report.junit import junit_xml

            write_file(junit, junit_xml([record]).encode("utf-8"), "--junit")
        return report, comparison, record

    _exit_on_sigterm()
    report, comparison, record = guard(run)
    annotate([record])
    if as_json:
        from en17037cli.report.write import report_json

        click.echo(report_json(report), nl=False)
    elif not quiet:
        summary(report, out)
        if comparison is not None:
            comparison_table(comparison)
    if comparison is not None:
        sys.exit(comparison.exit_code)
    sys.exit(EXIT_PASS if report["status"] == "pass" else EXIT_FAIL)


def _painters():
    """Worker processes (up to one per core, at most 4; more than one only for many pictures) that
    load matplotlib while the run traces rays and then draw the pictures (:class:`~en17037cli.report.figures.Painters`); None where processes
    cannot be forked (the pictures are then drawn in this process)."""
    import os

    from en17037cli.report.figures import Painters

    try:
        return Painters(max(1, min(4, os.cpu_count() or 1)))
    except (OSError, ValueError, ImportError):
        return None


def _check_record(project_file: Path, out: Path, report: dict, result, comparison):
    """The run of ``check`` as a :class:`~en17037cli.report.summary.RunRecord` (for JUnit and annotations)."""
    from en17037cli.compare import regressed_pairs
    from en17037cli.report.summary import RunRecord, room_rows

    times = {r.room.name: r.time_s for r in result.rooms}
    code = EXIT_PASS if report["status"] == "pass" else EXIT_FAIL
    if comparison is not None:
        code = comparison.exit_code
    return RunRecord(project=str(project_file), report_dir=str(out), exit_code=code, rows=room_rows(report, times),
                     status=report["status"], counts=report["summary"], warnings=list(report["warnings"]),
                     time_s=report["timings_s"]["total"],
                     regressions=None if comparison is None else regressed_pairs(comparison))


def _exit_on_sigterm():
    """SIGTERM ends the run like Ctrl-C does: cleanup runs, exit code 143 (128 + 15)."""
    import signal

    def handler(signum, frame):
        click.echo("error: terminated", err=True)
        sys.exit(128 + signum)

    signal.signal(signal.SIGTERM, handler)


@cli.command()
@project_argument
@set_option
@max_points_option
@click.option("--objects", is_flag=True, help="Also list every object (part) of the model with its layer and faces.")
@click.option("--json", "as_json", is_flag=True, help="Print the findings as one JSON document on stdout (for scripts).")
@click.option("--plan", "plan_dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Draw each storey's plan as read into this folder: walls cut at eye height, each room's floor, "
                   "windows, viewpoints and points P (one PNG per floor level; needs matplotlib).")
def validate(project_file: Path, overrides, max_points, objects, as_json, plan_dir):
    """Check PROJECT_FILE and its geometry as `check` would, without running the criteria.

    Prints faces per layer, each room's floor, ceiling and the windows that bound it (and why),
    rooms and windows that cannot be assessed, and warnings.
    """
    from en17037cli.criteria import Context
    from en17037cli.preflight import MAX_POINTS, preflight
    from en17037cli.project import load_project
    from en17037cli.raytrace import RayEngine
    from en17037cli.scene import build_scene

    def run():
        project = load_project(project_file, list(overrides))
        scene = build_scene(project)
        with RayEngine(scene.vertices, scene.triangles, scene.ray_groups()) as engine:
            ctx = Context(project, scene, engine)
            pf = preflight(ctx, max_points or MAX_POINTS)
            if plan_dir is not None:
                from en17037cli.plan_pictures import draw_understood

                plans.extend(draw_understood(ctx, plan_dir))
            return project, scene, pf

    plans: list[str] = []
    project, scene, pf = guard(run)
    if as_json:
        from en17037cli.report.validation import validation_document

        click.echo(json.dumps(validation_document(project_file, project, scene, pf, max_points or MAX_POINTS), indent=2,
                              ensure_ascii=False))
        return
    click.echo(f"{project_file}: valid")
    click.echo("faces per layer: " + ", ".join(f"{k} {v}" for k, v in scene.layer_counts().items()))
    for display, line in scene.read:  # what each reader read and left out
        click.echo(f"read {display}: {line}")
    from en17037cli.scene.site import bearing_label, location_lines

    for line in location_lines(project, scene):  # where the run takes the site and north from
        click.echo(line)
    if pf.points:
        click.echo(f"estimated cost: {pf.points:,} viewpoints, {pf.cells:,.0f} sampling cells (budget {max_points or MAX_POINTS:,} viewpoints)")
    bounding = set()
    storey = None
    for room in scene.rooms:
        if room.storey and room.storey != storey:
            storey = room.storey
            click.echo(f"storey '{storey}':")
        if room.problem:
            click.echo(f"room '{room.name}': NOT ASSESSABLE: {room.problem}")
            continue
        z0 = room.floor_z + scene.origin[2]
        click.echo(f"room '{room.name}': floor {room.floor.area:.2f} m² at z {z0:.3f} m ({room.floor_source}), ceiling at "
                   f"z {room.ceiling_z + scene.origin[2]:.3f} m ({room.ceiling_source}), {len(room.windows)} window(s)")
        for w in room.windows:
            bounding.add(w.name)
            n = ", ".join(f"{round(c, 4) + 0.0:.4f}" for c in w.normal)  # + 0.0: no "-0.0000"
            click.echo(f"  window '{w.name}': {w.area_m2:.3f} m², outward normal ({n}), {len(w.face_ids)} faces; "
                       f"bounds the room: {room.window_reasons[w.name]}; {bearing_label(w.normal, scene.true_north_deg)}")
        for crit, rooms in pf.unassessable.items():
            if room.name in rooms:
                click.echo(f"  {crit}: NOT ASSESSABLE: {rooms[room.name]}")
    from en17037cli.scene.spaces import windows_in_no_room

    for lo in scene.left_out:
        click.echo(f"space '{lo.name}': not a room of the check: {lo.reason}"
                   + (f" ({len(lo.windows)} window(s): NOT ASSESSED)" if lo.windows else ""))
    for name, why in windows_in_no_room(scene):
        click.echo(f"window '{name}': in no room: {why}")
    for display, label, why in scene.windows_left_out:
        click.echo(f"window {label} ({display}): not a window of the check: {why}")
    if project.dwellings is not None:
        for d in pf.dwellings:
            main = "" if d.main_rooms == d.rooms else f" (main: {', '.join(d.main_rooms)})"
            click.echo(f"dwelling '{d.name}' ({d.source}): {', '.join(d.rooms)}{main}")
    for note in pf.warnings:  # diagnostics: stderr
        click.echo(f"warning: {note}", err=True)
    for note in scene.notes:
        click.echo(f"note: {note}", err=True)
    for path in plans:
        click.echo(f"plan as read: {path}")
    if objects:
        list_objects(scene)


@cli.group()
def study():
    """Studies of the numerical settings (not checks)."""


def _target_kinds():
    from en17037cli.studies.convergence import TARGETS

    return tuple(TARGETS)


@study.command()
@project_argument
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path), required=True,
              help="Folder for convergence.csv and convergence.png.")
@click.option("--ladder", "ladders", multiple=True, metavar="KNOB",
              help="Run only this ladder, e.g. view.angular_resolution_deg (repeatable) [default: all].")
@click.option("--target", "targets", multiple=True,
              type=KindValue(_target_kinds),
              help="Error target: angle_deg, solid_angle_sr, distance_m, sun_time_s, share_pp, daylight_factor_pct, share_of_hours (repeatable).")
@click.option("--points", "max_points", type=click.IntRange(1), default=None,
              help="Use at most this many viewpoints per room and eye height (spread evenly).")
@set_option
def convergence(project_file: Path, out_dir: Path, ladders, targets, max_points, overrides):
    """Error against run time for ladders of resolutions; cheapest setting within the targets."""
    from rich.console import Console
    from rich.table import Table

    from en17037cli.errors import InputError
    from en17037cli.studies import convergence as st

    def run():
        chosen = st.LADDERS
        if ladders:
            known = {lad.knob: lad for lad in st.LADDERS}
            bad = [k for k in ladders if k not in known]
            if bad:
                raise InputError(f"--ladder {bad[0]}: unknown; use one of {', '.join(known)}")
            chosen = tuple(known[k] for k in ladders)
        return st.convergence(project_file, out_dir, chosen, dict(targets), overrides, max_points,
                              log=lambda m: click.echo(m, err=True))

    res = guard(run)
    console = Console(width=max(Console().width, 120))
    table = Table(title=f"Convergence of {project_file}")
    for col in ("knob", "value", "quantity", "max error", "estimate", "over est.", "target", "unit", "ok", "time s", "rays"):
        table.add_column(col, justify="right")
    for r in res["rows"]:
        table.add_row(r["ladder"], st.fmt_value(r["value"]), r["quantity"], f"{r['error']:.3g}", f"{r['estimate']:.3g}",
                      "-" if r["over_estimate"] < 0 else str(r["over_estimate"]), f"{r['target']:g}", st.UNITS.get(r["kind"], ""),
                      "yes" if r["within_target"] else "no", f"{r['wall_s']:.3f}", str(r["rays"]))
    console.print(table)
    for (knob, q), p in res["orders"].items():
        console.print(f"observed order of {q} in {knob}: " + ("at round-off or too few rungs" if p != p else f"{p:.2f}"))
    ladders_run = {lad.knob: lad for lad in st.LADDERS}
    for knob, v in res["cheapest"].items():
        console.print(f"cheapest {knob} within the targets: " + ("none of the rungs" if v is None else
                                                                  "--set " + st.rung_settings(ladders_run[knob], v).replace(", ", " --set ")))
    console.print(f"wrote {out_dir / 'convergence.csv'}" + (f" and {res['png']}" if res["png"] else
                                                             " (install matplotlib for convergence.png)"))


@study.command()
@project_argument
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path), required=True,
              help="Folder for sensitivity.csv, sensitivity.json, sensitivity.html and the tornado charts.")
@set_option
def sensitivity(project_file: Path, out_dir: Path, overrides):
    """How each verdict moves with the choices the standard leaves open (one at a time)."""
    from rich.console import Console
    from rich.table import Table

    from en17037cli.studies import sensitivity as st

    res = guard(lambda: st.sensitivity(project_file, out_dir, overrides, log=lambda m: click.echo(m, err=True)))
    console = Console(width=max(Console().width, 120))
    table = Table(title=f"Sensitivity of {project_file}")
    for col in ("room", "check", "required", "level", "lowest", "highest", "moved by", "verdict"):
        table.add_column(col)
    for r in res["rooms"]:
        table.add_row(r["room"], r["check"], r["required"], r["level"], r["lowest"], r["highest"], ", ".join(r["moved_by"]) or "-",
                      r["verdict"])
    console.print(table)
    c = res["cost"]
    console.print(f"cost: {c['total_s']:.1f} s, {c['ratio']:.1f} x the check with the project's own settings ({c['base_s']:.1f} s); "
                  f"wrote {out_dir / 'sensitivity.csv'}, sensitivity.json, sensitivity.html")


@cli.command()
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
@click.option("--only", type=click.Choice(["view", "sunlight", "daylight", "glare"]), default=None,
              help="Run one check only (a required check left out is NOT ASSESSED and fails).")
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
    from en17037cli.preflight import MAX_POINTS
    from en17037cli.report.folder import check_file

    def prepare():
        chosen = b.load_variants(variants) if variants is not None else None
        specs = b.plan_runs([str(p) for p in projects], chosen, tuple(overrides), only, max_points or MAX_POINTS,
                            rooms_per_task or b.ROOMS_PER_TASK)
        b.check_batch_folder(out_dir)
        if junit is not None:
            check_file(junit, "--junit")
        return specs

    _exit_on_sigterm()
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


@cli.command()
@click.argument("before", type=click.Path(path_type=Path))
@click.argument("after", type=click.Path(path_type=Path))
@click.option("--format", "fmt", type=click.Choice(["text", "md", "json"]), default="text", show_default=True,
              help="md: a Markdown table for a pull-request comment; json: for scripts.")
@click.option("--json", "as_json", is_flag=True, help="Same as --format json.")
@click.option("--all", "everything", is_flag=True, help="List the unchanged rooms and criteria too.")
def compare(before: Path, after: Path, fmt, everything, as_json):
    """What changed from BEFORE to AFTER (report.json files or report folders), room by room.

    Exit 1 when a level or a status got worse (or a new room or criterion fails), 0 otherwise.
    """
    from en17037cli.compare import compare_reports, comparison_json, comparison_markdown, load_report

    c = guard(lambda: compare_reports(load_report(before, "BEFORE"), load_report(after, "AFTER"), str(before), str(after)))
    if as_json:
        fmt = "json"
    if fmt == "md":
        click.echo(comparison_markdown(c, everything), nl=False)
    elif fmt == "json":
        click.echo(comparison_json(c), nl=False)
    else:
        comparison_table(c, everything=everything)
    sys.exit(c.exit_code)


@cli.command()
@click.argument("which", type=click.Choice(["project", "report"]))
def schema(which):
    """Print the JSON Schema of the project file or of report.json."""
    from en17037cli.schemas import load_schema

    click.echo(json.dumps(load_schema(which), indent=2))


def main():
    cli(prog_name="en17037")
