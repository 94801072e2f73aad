"""``en17037 compare``: what changed between two reports, room by room."""
from __future__ import annotations

import sys
from pathlib import Path

import click

from en17037cli.commands.errors import guard
from en17037cli.terminal import comparison_table


@click.command()
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
