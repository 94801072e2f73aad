"""The data of ``validate --plan``: each room's floor, windows, viewpoints and points P as the
criteria would take them, and the walls of each storey's plan, handed to the drawing
(:mod:`en17037cli.report.pictures.understood`)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from en17037cli.errors import InputError, NotAssessable


def draw_understood(ctx, out_dir: Path) -> list[str]:
    """Draw every storey of ``ctx.scene``'s rooms into ``out_dir``; returns the paths written."""
    import shapely

    from en17037cli.criteria.sunlight.point_p import point_p
    from en17037cli.criteria.view.viewpoints import viewpoints
    from en17037cli.scene.section import plan_of

    try:
        from en17037cli.report.pictures.understood import RoomDrawing, draw_storeys, window_trace
    except ImportError as exc:  # matplotlib missing
        raise InputError(f"--plan: drawing needs matplotlib: pip install 'en17037cli[plot]' ({exc})") from exc
    scene, project = ctx.scene, ctx.project
    o = scene.origin
    rooms, walls = [], {}
    for room in scene.rooms:
        if room.problem:
            continue
        level = round(float(room.floor_z + o[2]), 3)
        if level not in walls:
            walls[level] = shapely.affinity.translate(plan_of(scene, room.floor_z).walls, o[0], o[1])
        d = RoomDrawing(room.name, level, shapely.affinity.translate(room.floor, o[0], o[1]),
                        [window_trace(w, o) for w in room.windows])
        if project.view is not None:
            try:
                groups, _ = viewpoints(scene, room, project.view)
                if groups:
                    d.viewpoints = groups[0][1][:, :2] + o[:2]
            except NotAssessable:
                pass
        if project.sunlight is not None:
            ps = []
            for w in room.windows:
                try:
                    ps.append(point_p(ctx.engine, scene, room, w, project.sunlight)[0][:2] + o[:2])
                except NotAssessable:
                    continue
            d.points_p = np.array(ps).reshape(-1, 2)
        rooms.append(d)
    return [str(p) for p in draw_storeys(walls, rooms, Path(out_dir), project.name)]
