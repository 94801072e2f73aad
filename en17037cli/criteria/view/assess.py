"""The view of a room: every viewpoint's quantities, levels and error estimates, then the room's levels."""
from __future__ import annotations

from collections.abc import Callable

import numpy as np

from en17037cli import standard
from en17037cli.criteria.view.decide import go_on, level_bounds, visibility_bounds
from en17037cli.criteria.view.frames import RoomGeometry, room_geometry
from en17037cli.criteria.view.gnomonic import patches
from en17037cli.criteria.view.rays import ViewRays
from en17037cli.criteria.view.results import LAYER_NAMES, EyeHeightResult, SolidAngles, ViewPoints, ViewResult, concat
from en17037cli.criteria.view.sight_angle import horizontal
from en17037cli.criteria.view.solid_angle import Integration
from en17037cli.project.settings import ViewSettings
from en17037cli.scene.model import Room, Scene
from en17037cli.standard import Thresholds

#: Base cells per chunk of viewpoints of the sight angle (bounds memory; each chunk is vectorised).
CELLS_PER_CHUNK = 300_000
#: Base cells per task of the solid angles: the tasks run on the engine's threads, one per thread;
#: small enough that their arrays (a few MB) are reused by the allocator instead of being mapped
#: afresh from the system (page faults cost as much as the arithmetic on arrays of 100 MB), large
#: enough that numpy's per-call overhead stays small (docs/performance.md).
CELLS_PER_TASK = 40_000


#: Viewpoints whose patches are made at once when sizing chunks (bounds memory for frames with many vertices).
SIZING_BLOCK = 1024


def cells_per_point(rg: RoomGeometry, points: np.ndarray, settings: ViewSettings) -> np.ndarray:
    """Base cells of each viewpoint [-]: uniform lines and frame lines of each window's grid, multiplied,
    plus one per frame edge of each window it sees (their images are traced per viewpoint)."""
    out = np.zeros(len(points))
    edges = np.array([0 if f.frame_edges is None else len(f.frame_edges) for f in rg.frames], dtype=float)
    for a in range(0, len(points), SIZING_BLOCK):  # blocks of points: bounded memory
        P = patches(rg, points[a:a + SIZING_BLOCK], np.radians(settings.angular_resolution_deg), with_edges=False)
        fa = np.bincount(P.frame_pt[0], minlength=len(P))
        fb = np.bincount(P.frame_pt[1], minlength=len(P))
        out[a:a + SIZING_BLOCK] = np.bincount(P.pt, (P.na + fa) * (P.nb + fb) + edges[P.win], len(points[a:a + SIZING_BLOCK]))
    return out


def chunks(rg: RoomGeometry, points: np.ndarray, settings: ViewSettings, cells: int = CELLS_PER_CHUNK) -> list[slice]:
    """Slices of ``points`` holding at most about ``cells`` base cells each."""
    cum = np.cumsum(cells_per_point(rg, points, settings))
    cuts = [0]
    while cuts[-1] < len(points):
        nxt = int(np.searchsorted(cum, (cum[cuts[-1] - 1] if cuts[-1] else 0) + cells, side="right"))
        cuts.append(min(max(nxt, cuts[-1] + 1), len(points)))
    return [slice(a, b) for a, b in zip(cuts[:-1], cuts[1:])]


def no_solid_angles(n: int) -> SolidAngles:
    """The solid angles of ``n`` points that were not traced (NaN: reported as null), for a view
    whose layers cannot be judged (a model without landscape) when the outside distance does not
    come from them either."""
    nan = np.full(n, np.nan)
    return SolidAngles(sr={k: nan for k in LAYER_NAMES}, err_sr={k: nan for k in LAYER_NAMES}, glazing_sr=nan,
                       cells=np.zeros(n, int))


def refined_solid_angles(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, settings: ViewSettings,
                         progress: Callable[[int], None] | None = None) -> SolidAngles:
    """The solid angles of one eye height's viewpoints, refined level by level as ``view.refine``
    says (:func:`~en17037cli.criteria.view.decide.go_on`): the points in small tasks on the engine's
    threads, each task's :class:`~en17037cli.criteria.view.solid_angle.Integration` tracing its own
    rays; between levels the decision over every point of the eye height (a room's level is
    decided by all of them)."""
    tasks = chunks(rg, points, settings, CELLS_PER_TASK)
    engine = view_rays.engine
    engine.prepare(["opaque"] if len(rg.frames) == 1 else ["opaque", rg.group])  # not by two threads at once

    def start(sl):
        it = Integration(view_rays, rg, points[sl], settings, parallel=False)
        return it, it.measure()

    parts, measures = [], []
    for sl, (it, m) in zip(tasks, engine.map_tasks(start, tasks)):
        parts.append(it)
        measures.append(m)
        if progress:
            progress(sl.stop - sl.start)
    while True:
        m = concat(measures)
        go = go_on(m, settings)
        if not go.any():
            break
        list(engine.map_tasks(lambda k, go=go: parts[k].advance(go[tasks[k]]), range(len(parts))))
        measures = list(engine.map_tasks(lambda k: parts[k].measure(), range(len(parts))))
    out = concat([it.result() for it in parts])
    surely, possibly = visibility_bounds(m, settings.layer_threshold_sr)
    lo, hi = level_bounds(surely, possibly)
    out.decided = lo == hi
    out.undecided = {k: possibly[k] & ~surely[k] for k in LAYER_NAMES}
    return out


def assess_points(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, settings: ViewSettings,
                  thresholds: Thresholds, progress: Callable[[int], None] | None = None,
                  solid: SolidAngles | None = None, layers: bool = True) -> ViewPoints | None:
    """Every per-point quantity, level and error estimate for one set of viewpoints (vectorised).

    Parameters
    ----------
    points : (p, 3) float [m], local frame
    solid : the solid angles of these same points from an earlier run whose solid-angle settings
        were the same (the sensitivity study's distance statistics): not traced again
    layers : False where the layers cannot be judged (a model without landscape): the solid angles
        are not traced unless the outside distance is measured with them (NaN, reported as null);
        they are most of a view's cost (SampleHouse4: 27 of 28 s)

    Returns
    -------
    ViewPoints, or None without points
    """
    if solid is None and not layers and settings.distance_method == "horizontal":
        solid = no_solid_angles(len(points))
    if len(points) == 0:
        return None
    # chunks bound memory; each is vectorised, and a point's values do not depend on its chunk
    sight = [horizontal(view_rays, rg, points[sl], settings) for sl in chunks(rg, points, settings)]
    if solid is None:
        solid = refined_solid_angles(view_rays, rg, points, settings, progress)
    elif progress:
        progress(len(points))
    sa, hz = solid, concat(sight)
    src = hz if settings.distance_method == "horizontal" else sa
    dist, gap = src.distance_m, src.distance_gap_m
    thr = settings.layer_threshold_sr
    visible = {k: standard.layer_visible(sa.sr[k], thr) for k in LAYER_NAMES}
    lv = {
        "horizontal_sight_angle": standard.level_from_value(hz.angle_deg, thresholds.horizontal_sight_angle_deg),
        "outside_distance": standard.level_from_value(np.where(np.isnan(dist), -np.inf, dist), thresholds.outside_distance_m),
        "layers": standard.level_from_layers(visible["sky"], visible["landscape"], visible["ground"]),
    }
    # near a threshold: within its error bound of one (sight angle, distance), or a layer whose
    # interval still holds the layer threshold (whether it is visible is not decided)
    layers_near = (np.any([sa.undecided[k] for k in LAYER_NAMES], axis=0) if sa.undecided is not None else
                   np.any([standard.near_threshold(sa.sr[k], sa.err_sr[k], [thr]) for k in LAYER_NAMES], axis=0))
    near = (
        standard.near_threshold(hz.angle_deg, hz.angle_err_deg, thresholds.horizontal_sight_angle_deg)
        | standard.near_threshold(dist, gap, thresholds.outside_distance_m)
        | layers_near
    )
    return ViewPoints(solid=sa, sight=hz, distance_m=dist, distance_gap_m=gap, visible=visible, level_by_criterion=lv,
                      level=standard.point_view_level(*lv.values()), near=near)


def assess_room(view_rays: ViewRays, scene: Scene, room: Room, settings: ViewSettings, thresholds: Thresholds,
                groups: tuple[list, list], progress: Callable[[int], None] | None = None,
                reuse: ViewResult | None = None, layers: bool = True) -> ViewResult:
    """View result of one room: per eye height, per point values, shares and levels.

    Parameters
    ----------
    groups : the room's :func:`~en17037cli.criteria.view.viewpoints.viewpoints` (made by the caller,
        which sizes a progress bar with them)
    reuse : an earlier result of the room with the same viewpoints and solid-angle settings: its
        solid angles are taken, not traced (the caller vouches for the settings)
    layers : False where the layers cannot be judged (:func:`assess_points`)
    """
    rg = room_geometry(scene, room, settings.frame_depth_m)
    planned, notes = groups
    eye = []
    for h, pts in planned:  # one pass per eye height (two by default)
        old = next((e.values for e in (reuse.eye_heights if reuse else ())
                    if e.values is not None and e.points_local.shape == pts.shape and np.array_equal(e.points_local, pts)), None)
        values = assess_points(view_rays, rg, pts, settings, thresholds, progress, None if old is None else old.solid,
                               layers)
        levels, share = {}, {}
        for crit in standard.VIEW_CRITERIA:
            levels[crit], share[crit] = standard.room_level([] if values is None else values.level_by_criterion[crit],
                                                            settings.area_fraction)
        _, share["view"] = standard.room_level([] if values is None else values.level, settings.area_fraction)
        eye.append(EyeHeightResult(eye_height_m=h, points_local=pts, values=values, level=standard.view_level(levels.values()),
                                   level_by_criterion=levels, share_by_level=share))
    return ViewResult(eye_heights=eye, level=standard.view_level(e.level for e in eye), notes=notes)
