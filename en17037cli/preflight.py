"""Checks before any result: what ``validate`` reports and what ``check`` finds before its criteria run.

Both commands call :func:`preflight` (after the run's budget, :mod:`en17037cli.budget`: see
:func:`en17037cli.pipeline.before_criteria`), so ``validate`` says what ``check`` will say, in the
same words: input errors (exit 2) for contradictions in the project file (each criterion finds
its own: :meth:`~en17037cli.criteria.base.Criterion.check_inputs`); warnings for windows no ray
can leave through; and, per room and criterion, why it cannot be assessed.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from en17037cli.criteria import CRITERIA, Context
from en17037cli.dwellings import group_dwellings
from en17037cli.geometry import window_axes
from en17037cli.project.settings import Project
from en17037cli.raytrace import RayEngine
from en17037cli.scene.model import WINDOW, Scene, room_window_group
from en17037cli.scene.windows import describe_part, glazing_grid


@dataclass
class Preflight:
    """What was found before the criteria run.

    warnings : one line each, for the report and ``validate``
    unassessable : criterion -> room name -> reason found without a ray
    dwellings : the rooms grouped into dwellings (see :mod:`en17037cli.dwellings`)
    """

    warnings: list[str] = field(default_factory=list)
    dwellings: list = field(default_factory=list)
    unassessable: dict[str, dict[str, str]] = field(default_factory=dict)


def windows_without_a_way_out(scene: Scene, engine: RayEngine) -> list[str]:
    """Warnings for windows through which no ray from the room leaves: rays from 0.3, 1 and 2 m
    inside the room, straight and at 30 degrees, through points spread over the glazing.

    What stops them is told apart (:func:`blocked_within_wall`): an opaque face within the wall's
    thickness of the glass (a wall the file does not cut for the window, which the scene's cut did
    not recognise) withholds the room's verdict: a FAIL of 0 h there would rest on a modelling
    error; the window is listed with the quarantined elements. An obstruction farther out (a
    neighbour's wall) is a legitimate 0 h: the warning says what it is and how far it lies."""
    from en17037cli.criteria.view.rays import BLOCKED, ViewRays

    view_rays = ViewRays(engine, scene)
    out = []
    tilt = np.radians(30.0)
    for room in scene.rooms:
        for w in room.windows:  # a few rays per window
            n = np.asarray(w.normal, float)
            a, up = window_axes(n)
            targets = glazing_grid(w, 3)
            dirs = np.array([n, np.cos(tilt) * n + np.sin(tilt) * a, np.cos(tilt) * n - np.sin(tilt) * a,
                             np.cos(tilt) * n + np.sin(tilt) * up, np.cos(tilt) * n - np.sin(tilt) * up])
            o = (targets[:, None, None, :] - np.array([0.3, 1.0, 2.0])[None, :, None, None] * dirs[None, None, :, :]).reshape(-1, 3)
            d = np.broadcast_to(dirs[None, None], (len(targets), 3, 5, 3)).reshape(-1, 3)
            cls = view_rays.through_windows(room_window_group(room), o, np.ascontiguousarray(d))[0]
            if not len(cls) or not np.all(cls == BLOCKED):
                continue
            first = f"room '{room.name}', window '{w.name}': no ray from the room leaves through it"
            wall = blocked_within_wall(scene, engine, w, targets)
            if wall is not None:
                out.append(f"{first} (an opaque face lies between the room and the glazing, or beyond it: a wall with no "
                           "opening cut?); it adds no view and no sun")
                out.append(withhold_blocked(scene, room, w, *wall))
                continue
            face, dist = first_hit_past(scene, engine, targets + 1e-3 * n, n, frame_parts(scene, w, 1.0, np.inf))
            hit = face[np.isfinite(dist)]
            what = describe_part(scene.parts[int(scene.part[np.bincount(hit).argmax()])]) if len(hit) else None
            where = (f"the nearest opaque face straight beyond its glazing, on {what}, lies {float(np.median(dist)):.1f} m out"
                     if what and np.isfinite(np.median(dist)) else "what stops the rays lies beyond its wall's thickness")
            out.append(f"{first}: {where} (an obstruction, not a wall left uncut); it adds no view and no sun as drawn")
    return out


def blocked_within_wall(scene: Scene, engine: RayEngine, w, points: np.ndarray) -> tuple[float, str, object] | None:
    """(distance [m], 'beyond' or 'in front of', the part hit most) where the straight rays from the glazing
    ``points`` (its outward normal, and back into the room) meet an opaque face within the wall's
    thickness of the glass: the host's depth on that side + 5 cm where the model names the host,
    at most :data:`~en17037cli.scene.uncut.WALL_DEPTH_M` (that alone where it names none); the
    median over the points. The window's own frame, sash or glazing bars are looked past where they
    do not cover its glazing (:func:`frame_parts`). None elsewhere."""
    from en17037cli.scene.hosts import host_depths
    from en17037cli.scene.uncut import WALL_DEPTH_M

    n = np.asarray(w.normal, float)
    depths = host_depths(scene, w) if w.host else None
    limits = (WALL_DEPTH_M, WALL_DEPTH_M) if depths is None else \
        (min(depths[0] + 0.05, WALL_DEPTH_M), min(depths[1] + 0.05, WALL_DEPTH_M))
    for sign, limit, side in ((1.0, limits[0], "beyond"), (-1.0, limits[1], "in front of")):
        face, dist = first_hit_past(scene, engine, points + sign * 1e-3 * n, sign * n, frame_parts(scene, w, sign, limit))
        t = float(np.median(dist)) + 1e-3
        if t <= limit:
            hit = face[np.isfinite(dist)]
            return t, side, scene.parts[int(scene.part[np.bincount(hit).argmax()])]
    return None


#: An opaque part of a window's own element covering at least this share of its glazing, seen
#: along the glazing's normal, is a panel over it (a shutter, an opaque sash) and can stop every
#: ray; less (a frame around the glass, a sash over its rim, glazing bars) covers only what it
#: overlaps.
SHUTTER_SHARE = 0.5


def own_cover(scene: Scene, w, sign: float, limit: float) -> float:
    """Share [-] of window ``w``'s glazing covered, seen along its normal, by the opaque faces of its
    own element (:func:`~en17037cli.scene.windows.own_parts`) lying on the ``sign`` side of its
    plane (+1 outward) within ``limit`` [m]: those faces and the glazing projected on the glazing's
    plane, the area of the union of the first inside the union of the second over the second's."""
    import shapely

    from en17037cli.scene.windows import own_parts

    mine = own_parts(scene.parts, w)
    faces = np.flatnonzero(mine[scene.part] & (scene.layer != WINDOW))
    if len(faces) == 0:
        return 0.0
    n = np.asarray(w.normal, float)
    tri = scene.vertices[scene.triangles[faces]]
    depth = sign * ((tri.mean(axis=1) - w.centroid) @ n)
    tri = tri[(depth > 0) & (depth <= limit)]
    if len(tri) == 0:
        return 0.0
    a, up = window_axes(n)
    plane = lambda t: shapely.union_all(shapely.make_valid(shapely.polygons(np.stack([t @ a, t @ up], axis=-1))))  # noqa: E731
    glass = plane(w.triangles)
    return float(plane(tri).intersection(glass).area / glass.area) if glass.area > 0 else 0.0


def frame_parts(scene: Scene, w, sign: float, limit: float) -> np.ndarray:
    """(parts,) bool: the parts of ``w``'s own element that rays from its glazing look past on the
    ``sign`` side: all of them where, within ``limit`` [m], they cover less than
    :data:`SHUTTER_SHARE` of it (a frame, a sash over its rim: each hides only what it overlaps,
    and what stops the rays is what lies beyond); none where they cover more (a panel over the pane)."""
    from en17037cli.scene.windows import own_parts

    if w.key is None or own_cover(scene, w, sign, limit) >= SHUTTER_SHARE:
        return np.zeros(len(scene.parts), bool)
    return own_parts(scene.parts, w)


def first_hit_past(scene: Scene, engine: RayEngine, origins: np.ndarray, direction: np.ndarray, past: np.ndarray,
                   steps: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """The first opaque face along ``direction`` (3,) from each of ``origins`` (k, 3) [m] that is not
    on a part ``past`` (parts,) bool marks, and its distance [m] (-1, +inf where none): rays that meet
    such a part go on from just beyond it, at most ``steps`` times (a frame's faces, a sash's)."""
    d = np.broadcast_to(np.asarray(direction, float), origins.shape).copy()
    o = np.array(origins, float)
    face, dist = np.full(len(o), -1, np.int64), np.full(len(o), np.inf)
    gone, live = np.zeros(len(o)), np.arange(len(o))
    for _ in range(steps):
        f, t = engine.first_hit("opaque", o[live], d[live])
        skip = np.isfinite(t) & past[scene.part[np.maximum(f, 0)]]
        face[live[~skip]], dist[live[~skip]] = f[~skip], gone[live[~skip]] + t[~skip]
        step = t[skip] + 1e-4
        live = live[skip]
        o[live] += step[:, None] * d[live]
        gone[live] += step
        if not len(live):
            break
    return face, dist


def withhold_blocked(scene: Scene, room, w, dist: float, side: str, part) -> str:
    """Withhold ``room``'s verdict for its window ``w`` that no ray leaves through because of an
    opaque face ``dist`` [m] ``side`` its glass, of ``part`` (a wall; or the window's own element:
    an opaque panel over what was taken for its pane): list it with the quarantined elements; the
    warning."""
    from en17037cli.scene.model import Quarantined

    element = describe_part(part)
    without = f"to assess the room without this window, add the layer rule {{id: '{w.key}', layer: interior}}"
    if w.key is not None and part.attrs.get("id") == w.key:
        reason = (f"an opaque part of its own element {element} lies {dist:.2f} m {side} its glazing: what was taken for its "
                  "pane is covered by its own panel (a shutter, an opaque sash?), so no ray can pass")
        advice = f"check the window's glass in the file (validate --objects lists its parts); {without}"
    else:
        reason = (f"an opaque face of {element} lies {dist:.2f} m {side} its glazing, within its wall's thickness: the wall "
                  "is not cut for it (no opening), so no ray can pass")
        advice = (f"an export with the opening cut through that wall gives the room its verdict; {without}" if w.key else
                  "cut the opening in that wall, or move the glazing out of it")
    action = "kept as drawn (no ray passes); its room's verdict withheld"
    scene.quarantined.append(Quarantined(f"window '{w.name}'", action, reason, advice, (room.name,)))
    why = f"window '{w.name}' lets no ray through ({reason}); the room is assessed with it as drawn, and no verdict is given"
    room.withheld = why if room.withheld is None else f"{room.withheld}; {why}"
    return f"quarantined: window '{w.name}': {reason}: {action}; room '{room.name}' assessed, no verdict; {advice}"


def layer_warnings(scene: Scene) -> list[str]:
    """Warnings about layers: a model with no ``interior`` face (nothing in the room blocks)."""
    counts = scene.layer_counts()
    return [] if counts["interior"] else ["no face is on the 'interior' layer: walls, reveals and frames will block nothing; "
                                          "check the layer rules"]


def landscape_warnings(project: Project, scene: Scene) -> list[str]:
    """A view check on a model without surroundings, or without any in front of a room's windows,
    cannot judge the layers: say so before it runs."""
    from en17037cli.criteria.view import no_landscape, sparse_surroundings

    if project.view is None:
        return []
    why = no_landscape(scene)
    if why is not None:
        return [f"view: every room NOT ASSESSABLE: {why}"]
    out = []
    for room in scene.rooms:
        why = sparse_surroundings(scene, room, project.view.surroundings_min_share) if room.problem is None else None
        if why is not None:
            out.append(f"view: room '{room.name}' NOT ASSESSABLE: {why}")
    return out


def space_warnings(scene: Scene) -> list[str]:
    """The spaces with windows the check cannot assess (listed by name, with the reason), and a run
    with no room at all: a model whose spaces are all left out is not a pass."""
    left = [lo for lo in scene.left_out if lo.windows]
    out = []
    if left:
        out.append(f"not assessed: {len(left)} space(s) with windows: " +
                   "; ".join(f"'{lo.name}' ({len(lo.windows)} window(s)): {lo.reason}" for lo in left))
    if not scene.rooms:
        out.append("no room to assess: " + (f"every space the project picks is left out ({len(scene.left_out)}: "
                                             f"{scene.left_out[0].reason}, ...)" if scene.left_out else "the project has no room"))
    return out


def preflight(ctx: Context) -> Preflight:
    """Everything the run can find before its criteria: see the module docstring."""
    project, scene = ctx.project, ctx.scene
    pf = Preflight(warnings=layer_warnings(scene) + space_warnings(scene) + landscape_warnings(project, scene) + scene.warnings)
    pf.dwellings = group_dwellings(project.dwellings, scene.rooms, project.path.name)
    for name, c in CRITERIA.items():
        if c.settings(project) is not None:
            pf.unassessable[name] = c.check_inputs(ctx)
    pf.warnings += windows_without_a_way_out(scene, ctx.engine) + requirement_warnings(project)
    return pf


def requirement_warnings(project: Project) -> list[str]:
    """A run that checks nothing, or requires nothing, passes whatever the model: say so."""
    run = [name for name, c in CRITERIA.items() if c.settings(project) is not None]
    if not run:
        return ["no check runs: the project has neither a 'view' nor a 'sunlight' section (add 'view: {}' or "
                "'sunlight: {}' to run one with its defaults)"]
    if all(getattr(spec.requirements, name) == "none" for spec in project.rooms for name in run):
        return [f"no room requires a level of {' or '.join(run)}: the levels are reported, the status passes whatever "
                "they are (set 'requirements')"]
    return []

