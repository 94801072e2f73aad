"""Arguments, options and parameter types that several commands share, as decorators."""
from __future__ import annotations

from pathlib import Path

import click


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


def only_option(fn):
    return click.option("--only", type=click.Choice(["view", "sunlight", "daylight", "glare"]), default=None,
                        help="Run one check only (a required check left out is NOT ASSESSED and fails).")(fn)


def junit_option(fn):
    return click.option("--junit", type=click.Path(dir_okay=False, path_type=Path), default=None, metavar="FILE",
                        help="Also write JUnit XML: one test case per room and criterion (failure for FAIL, error for "
                             "not assessable / not assessed).")(fn)
