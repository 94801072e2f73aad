"""``en17037 study``: studies of the numerical settings (convergence, sensitivity), not checks."""
from __future__ import annotations

from pathlib import Path

import click

from en17037cli.commands.errors import guard
from en17037cli.commands.options import KindValue, project_argument, set_option


@click.group()
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
