"""``en17037 check``: run a project's checks and write its reports."""
from __future__ import annotations

import sys
from pathlib import Path

import click

from en17037cli.commands.errors import EXIT_FAIL, EXIT_PASS, exit_on_sigterm, guard
from en17037cli.commands.options import junit_option, max_points_option, only_option, project_argument, set_option
from en17037cli.terminal import annotate, comparison_table, progress_factory, summary


@click.command()
@project_argument
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Report folder [default: en17037-report/<project file stem>/ beside the project file].")
@only_option
@set_option
@max_points_option
@click.option("--baseline", type=click.Path(path_type=Path), default=None, metavar="REPORT",
              help="A report.json (or report folder) of an earlier design: fail (exit 1) only where a level or a status "
                   "got worse, or a new room or criterion fails.")
@junit_option
@click.option("--bcf", "bcf", type=click.Path(dir_okay=False, path_type=Path), default=None, metavar="FILE",
              help="Also write a BCF 2.1 file: one topic per room and criterion that fails or cannot be assessed, with a "
                   "viewpoint at the point that limits it [default: the project file's report.bcf].")
@click.option("--ifc-out", "ifc_out", type=click.Path(dir_okay=False, path_type=Path), default=None, metavar="FILE",
              help="Also write a copy of the input IFC with the results in a property set EN17037_Results on every room's "
                   "IfcSpace and window [default: the project file's report.ifc].")
@click.option("--no-plots", is_flag=True, help="No pictures: report.html and report.md without maps, fisheyes or charts.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bars and no summary.")
@click.option("--json", "as_json", is_flag=True,
              help="Print report.json on stdout instead of the verdict table (for scripts; the reports are written too).")
def check(project_file: Path, out_dir, only, overrides, max_points, baseline, junit, bcf, ifc_out, no_plots, quiet,
          as_json):
    """Run the checks of PROJECT_FILE and write the reports."""
    from en17037cli import pipeline
    from en17037cli.bim import output_path
    from en17037cli.budget import MAX_POINTS
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
        bcf_path = output_path(project, "bcf", bcf)
        if bcf_path is not None:
            check_file(bcf_path, "--bcf" if bcf is not None else "report.bcf")
        ifc_path = output_path(project, "ifc", ifc_out)
        if ifc_path is not None:
            from en17037cli.bim.frames import require_ifc

            require_ifc(project, "--ifc-out" if ifc_out is not None else "report.ifc")
            check_file(ifc_path, "--ifc-out" if ifc_out is not None else "report.ifc")
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
        if bcf_path is not None:
            from en17037cli.bim.bcf import bcf_for
            from en17037cli.report.folder import write_file

            data, n = bcf_for(result, report, figures)
            write_file(bcf_path, data, "--bcf" if bcf is not None else "report.bcf")
            if not quiet:
                click.echo(f"bcf: {n} topic(s) in {bcf_path}", err=True)
        if ifc_path is not None:
            _write_ifc(result, report, ifc_path, "--ifc-out" if ifc_out is not None else "report.ifc", quiet)
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

    exit_on_sigterm()
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


def _write_ifc(result, report: dict, path: Path, flag: str, quiet: bool) -> None:
    """The IFC file(s) holding the rooms' spaces and windows, with the results (:mod:`en17037cli.bim.ifc_out`):
    ``path`` itself where one file holds them (the usual case), else ``<stem>-<input stem>.ifc`` beside it per file."""
    from en17037cli.bim.frames import ModelFiles
    from en17037cli.bim.ifc_out import ifc_files_with_results, results_ifc
    from en17037cli.report.folder import write_file

    sources = ifc_files_with_results(report)
    if not sources:
        click.echo(f"warning: {flag}: no room or window of the check comes from an IFC file; nothing written", err=True)
        return
    files = ModelFiles(result.project)
    for src in sources:
        target = path if len(sources) == 1 else path.with_name(f"{path.stem}-{Path(src).stem}{path.suffix}")
        write_file(target, results_ifc(result, report, src, files), flag)
        if not quiet:
            click.echo(f"ifc: results of {src} in {target}", err=True)


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
