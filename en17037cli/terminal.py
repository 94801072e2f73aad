"""What ``en17037`` shows on the terminal: the tables of check, batch and compare, progress bars,
the object list of validate, and GitHub Actions annotations (rich and click; no computation)."""
from __future__ import annotations

from pathlib import Path

import click


def stderr_console():
    from rich.console import Console

    return Console(stderr=True)


#: Progress lines on a non-interactive stderr (a CI log): at most one every this many seconds, and
#: only once a criterion has run this long [s].
LINE_EVERY_S = 15.0


def progress_factory(enabled: bool, lines: bool = False):
    """A ``progress(total, label) -> advance(n)`` callable: rich bars with the time left on an
    interactive stderr (``enabled``), plain lines every :data:`LINE_EVERY_S` on another (``lines``:
    a CI log sees a long run move), or (None, None)."""
    if not enabled and not lines:
        return None, None
    if not enabled:
        return None, _progress_lines
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

    bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                   TextColumn("left"), TimeRemainingColumn(), console=stderr_console(), transient=True)

    def progress(total: int, label: str):
        task = bar.add_task(label, total=total)
        return lambda n: bar.advance(task, n)

    return bar, progress


def _progress_lines(total: int, label: str):
    """Plain progress lines on stderr: ``view: 40% (1,200 of 3,000), 1 min 20 s, about 2 min left``."""
    import time

    def fmt(seconds: float) -> str:
        if not seconds == seconds:
            return "?"
        return f"{seconds:.0f} s" if seconds < 120 else f"{seconds // 60:.0f} min {seconds % 60:02.0f} s"

    start = time.perf_counter()
    state = {"done": 0, "said": start}

    def advance(n: int) -> None:
        state["done"] += n
        now = time.perf_counter()
        if now - state["said"] < LINE_EVERY_S or now - start < LINE_EVERY_S or total <= 0:
            return
        state["said"] = now
        f = min(state["done"] / total, 1.0)
        left = (now - start) * (1 - f) / f if f > 0 else float("nan")
        click.echo(f"{label}: {100 * f:.0f}% ({state['done']:,} of {total:,}), {fmt(now - start)}, about {fmt(left)} left",
                   err=True)

    return advance


def annotate(records) -> None:
    """GitHub Actions annotations (``::error ...``) on stdout, when running in GitHub Actions."""
    import os

    if os.environ.get("GITHUB_ACTIONS") == "true":
        from en17037cli.report.junit import github_annotations

        for line in github_annotations(records):
            click.echo(line)


def stdout_console():
    from rich.console import Console

    return Console()


def summary(report: dict, out: Path):
    """The verdict table and the status line on stdout (results); warnings on stderr (diagnostics)."""
    from rich.table import Table

    from en17037cli.report.labels import STATUS_LABEL
    from en17037cli.report.numbers import fmt_duration

    table = Table(title=f"EN 17037: {report['project']['name']}")
    for col in ("room", "check", "reached", "required", "result"):
        table.add_column(col)
    for room in report["rooms"]:
        for name, key in (("daylight", "daylight"), ("view out", "view"), ("sunlight", "sunlight"), ("glare", "glare")):
            r = room.get(key)
            if r:
                extra = ""
                if key == "sunlight" and r["status"] in ("pass", "fail"):
                    extra = f" ({fmt_duration(r['hours_h'])} on {r['assessed_date']})"
                if key == "daylight" and r["status"] in ("pass", "fail"):
                    extra = f" ({daylight_words(r)})"
                if key == "glare" and r["status"] in ("pass", "fail"):
                    extra = f" (DGP {r['dgp_5pct']:.2f} in 5 % of {r['usage_hours']} h)"
                table.add_row(room["name"], name + extra, r["level"] or "-", r["required"], STATUS_LABEL[r["status"]])
    console = stdout_console()
    console.print(table)
    for line in why_lines(report):
        click.echo(line)
    s = report["summary"]
    if s["dwellings_sunlight_required"] > 1:
        console.print(f"{s['dwellings_sunlight_pass']} of {s['dwellings_sunlight_required']} dwellings pass sunlight; "
                      f"{s['rooms_view_pass']} of {s['rooms_view_required']} rooms pass view")
    for w in report["warnings"]:
        click.echo(f"warning: {w}", err=True)
    # one whole line, never wrapped: scripts and people grep it
    click.echo(f"status: {report['status'].upper()}; reports in {out}/ (report.html, report.md, report.json and the CSVs)")


#: Rows of the verdict table explained under it at most; the rest are in report.md and report.html.
WHY_LINES = 12


def why_lines(report: dict) -> list[str]:
    """One line per room and check that did not pass: what limits it and by how much, or why it was
    not assessed (the sentences of report.md), so a terminal run says why without opening a file."""
    from en17037cli.report.verdicts import limit_text

    out = []
    for room in report["rooms"]:
        for key, name in (("daylight", "daylight"), ("view", "view out"), ("sunlight", "sunlight"), ("glare", "glare")):
            r = room.get(key)
            if not r or r["status"] == "pass":
                continue
            why = limit_text(key, r) if r["status"] == "fail" else ""  # starts with what limits: "sight angle: ..."
            status = r["status"].replace("_", " ")
            out.append(f"{room['name']}: {why}" if why else f"{room['name']}: {name} {status}: {r.get('reason') or 'see report.md'}")
    if len(out) > WHY_LINES:
        out = out[:WHY_LINES] + [f"... and {len(out) - WHY_LINES} more: report.md lists every room"]
    return out


def daylight_words(section: dict) -> str:
    """``D median 2.1 %, method 1`` or ``climate-based, hours first``: the daylight row's figure."""
    if section["method"] == "daylight_factor":
        return f"D median {section.get('median_daylight_factor_pct', 0):.2f} %, method 1"
    return f"climate-based, {section['aggregation'].replace('_', ' ')}"


def list_objects(scene):
    """One line per part of the model: file, names, layer, faces (``validate --objects``)."""
    import numpy as np

    from en17037cli.scene.model import LAYERS

    faces = np.bincount(scene.part, minlength=len(scene.parts))
    for i, part in enumerate(scene.parts):
        if not faces[i]:
            continue
        layers = np.unique(scene.layer[scene.part == i])
        names = ", ".join(f"{k}={v}" for k, v in part.attrs.items() if k != "file")
        click.echo(f"object {part.attrs.get('file', '')}: {names or '(no name)'}: layer "
                   f"{'/'.join(LAYERS[c] for c in layers)}, {faces[i]} faces")


def batch_table(records, out: Path) -> None:
    from rich.markup import escape
    from rich.table import Table

    from en17037cli.report.labels import STATUS_LABEL
    from en17037cli.report.numbers import fmt_duration

    table = Table(title="EN 17037 batch")
    for col in ("run", "room", "check", "reached", "required", "result", "hours / share"):
        table.add_column(col)
    for rec in records:
        for row in rec.rows:
            result = STATUS_LABEL[row["status"]]
            if row["verdict"] != row["status"]:
                result += " (dwelling passes)" if row["dwelling_status"] == "pass" else " (not asked)"
            figure = (fmt_duration(row["hours_h"]) if row["hours_h"] is not None else
                      f"{row['share']:.0%}" if row["share"] is not None else "")
            table.add_row(escape(rec.label), escape(row["room"]), row["criterion"], row["level"] or "-", row["required"], result,
                          figure)
    console = stdout_console()
    if table.row_count:
        console.print(table)
    for rec in records:  # whole lines, never wrapped: scripts and people grep them
        if rec.exit_code >= 2:
            for line in rec.message.splitlines():
                click.echo(f"error: {rec.label}: {line}", err=True)
    counts = {code: sum(r.exit_code == code for r in records) for code in range(4)}
    click.echo(f"{len(records)} runs: {counts[0]} pass, {counts[1]} fail, {counts[2]} bad input, {counts[3]} internal error; "
               f"summary in {out}/ (summary.csv, summary.json)")


def comparison_table(c, err: bool = False, everything: bool = False) -> None:
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    from en17037cli.compare import headline, table_rows

    console = Console(stderr=err)
    rows = table_rows(c, everything)
    if rows:
        table = Table(title=escape(f"{c.before} → {c.after}"))
        for col in ("change", "room", "criterion", "level", "status", "figures"):
            table.add_column(col)
        for r in rows:
            table.add_row(*(escape(x) for x in r), style="red" if r[0].startswith(("worse", "added (regression)")) else None)
        console.print(table)
    click.echo(headline(c), err=err)  # one whole line, never wrapped
