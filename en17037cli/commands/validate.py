"""``en17037 validate``: the project and its geometry as ``check`` reads them, without the criteria."""
from __future__ import annotations

import json
from pathlib import Path

import click

from en17037cli.commands.errors import guard
from en17037cli.commands.options import max_points_option, project_argument, set_option
from en17037cli.terminal import list_objects


@click.command()
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
    from en17037cli.budget import MAX_POINTS
    from en17037cli.criteria import Context
    from en17037cli.pipeline import before_criteria
    from en17037cli.project import load_project
    from en17037cli.raytrace import RayEngine
    from en17037cli.scene import build_scene

    def run():
        project = load_project(project_file, list(overrides))
        scene = build_scene(project)
        with RayEngine(scene.vertices, scene.triangles, scene.ray_groups()) as engine:
            ctx = Context(project, scene, engine)
            cost, pf = before_criteria(ctx, max_points or MAX_POINTS)
            if plan_dir is not None:
                from en17037cli.plan_pictures import draw_understood

                plans.extend(draw_understood(ctx, plan_dir))
            return project, scene, cost, pf

    plans: list[str] = []
    project, scene, cost, pf = guard(run)
    if as_json:
        from en17037cli.report.validation import validation_document

        click.echo(json.dumps(validation_document(project_file, project, scene, pf, cost, max_points or MAX_POINTS), indent=2,
                              ensure_ascii=False))
        return
    click.echo(f"{project_file}: valid")
    click.echo("faces per layer: " + ", ".join(f"{k} {v}" for k, v in scene.layer_counts().items()))
    for display, line in scene.read:  # what each reader read and left out
        click.echo(f"read {display}: {line}")
    from en17037cli.report.validation import kind_entry, kind_text
    from en17037cli.scene.site import bearing_label, location_lines

    for line in location_lines(project, scene):  # where the run takes the site and north from
        click.echo(line)
    if cost.points:
        click.echo(f"estimated cost: {cost.points:,} viewpoints, {cost.cells:,.0f} sampling cells (budget {max_points or MAX_POINTS:,} viewpoints)")
    bounding = set()
    storey = None
    for room in scene.rooms:
        if room.storey and room.storey != storey:
            storey = room.storey
            click.echo(f"storey '{storey}':")
        if room.problem:
            click.echo(f"room '{room.name}': NOT ASSESSABLE: {room.problem}")
            click.echo(f"  kind: {kind_text(kind_entry(room))}")
            continue
        z0 = room.floor_z + scene.origin[2]
        click.echo(f"room '{room.name}': floor {room.floor.area:.2f} m² at z {z0:.3f} m ({room.floor_source}), ceiling at "
                   f"z {room.ceiling_z + scene.origin[2]:.3f} m ({room.ceiling_source}), {len(room.windows)} window(s)")
        click.echo(f"  kind: {kind_text(kind_entry(room))}")
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
