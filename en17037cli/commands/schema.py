"""``en17037 schema``: the JSON Schemas of the project file and of report.json."""
from __future__ import annotations

import json

import click


@click.command()
@click.argument("which", type=click.Choice(["project", "report"]))
def schema(which):
    """Print the JSON Schema of the project file or of report.json."""
    from en17037cli.schemas import load_schema

    click.echo(json.dumps(load_schema(which), indent=2))
