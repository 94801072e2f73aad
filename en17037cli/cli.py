"""``en17037``: the command-line interface, click commands over the library only.

The root group :func:`cli` (the console script's :func:`main`) gathers the commands, one module
each under :mod:`en17037cli.commands` (its docstring gives the conventions every command follows:
exit codes, stdout and stderr, errors translated in :mod:`~en17037cli.commands.errors`).
"""
from __future__ import annotations

import click

from en17037cli.commands.batch import batch
from en17037cli.commands.check import check
from en17037cli.commands.compare import compare
from en17037cli.commands.errors import Group
from en17037cli.commands.schema import schema
from en17037cli.commands.screen import screen
from en17037cli.commands.study import study
from en17037cli.commands.validate import validate
from en17037cli.version import __version__


@click.group(cls=Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="en17037")
def cli():
    """Check EN 17037 daylight provision (5.1), view out (5.2), exposure to sunlight (5.3) and protection from glare (5.4) on a 3D model."""


for _command in (check, validate, study, batch, screen, compare, schema):
    cli.add_command(_command)


def main():
    """The console command. SIGTERM ends it like Ctrl-C from its first line on; an interrupted run
    ends as soon as its own cleanup has run (temporary folders removed, picture workers ended),
    without waiting for the engine's threads to finish the chunk they trace
    (:func:`~en17037cli.commands.errors.exit_now`)."""
    from en17037cli.commands.errors import INTERRUPTED, exit_now, exit_on_sigterm

    exit_on_sigterm()
    try:
        cli(prog_name="en17037")
    except SystemExit as exc:
        if exc.code in INTERRUPTED:
            exit_now(exc.code)
        raise
