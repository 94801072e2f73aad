"""What a run may cost and how long it will take, for the pipeline: the viewpoint budget a run is
held to before any work (:func:`check_budget`, ``--max-points``) and the rough estimate of its
time that a long run announces (:func:`estimate_seconds`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.criteria.view.viewpoints import grid_lines, grid_tolerance
from en17037cli.errors import InputError
from en17037cli.project.settings import Project
from en17037cli.scene.model import Scene

#: Default budget: viewpoints of a run (all rooms and eye heights). A viewpoint's results take
#: about 10 kB in memory and in report.json, so this keeps a check within about 2 GB.
MAX_POINTS = 100_000
#: Sampling cells per viewpoint the budget allows on average (the seed office needs about 9,000).
CELLS_PER_POINT = 20_000


#: Rough costs for the estimate shown before a long run (CPU seconds on one core of this project's
#: 2-core test machine, fitted on the corpus of real exports, docs/performance.md): a sampling cell
#: of the view's solid angles traced, a viewpoint whose solid angles are not traced (no landscape),
#: a point P's day-by-day sun, a daylight grid point. The run's own bar then shows the time left.
SECONDS_PER_CELL = 8e-6
SECONDS_PER_VIEWPOINT = 1e-3
SECONDS_PER_POINT_P = 0.3
SECONDS_PER_DAYLIGHT_POINT = 0.02
#: A run estimated to take longer than this says so before its work [s].
ANNOUNCE_S = 10.0
#: Model files larger than this together are announced before they are read [bytes] ...
LARGE_MODEL_BYTES = 5_000_000
#: ... with about this many seconds a megabyte (ifcopenshell's tessellation of a Revit IFC, 2 cores).
READ_SECONDS_PER_MB = 2.5


@dataclass
class Cost:
    """The estimated size of a run: viewpoints and sampling cells of the view (all rooms and eye heights)."""

    points: int = 0
    cells: float = 0.0


def estimate_room_points(room, settings) -> int:
    """Viewpoints of a room before making them: explicit points, or the grid over the floor's
    minimum rotated rectangle at each eye height (what the grid allocates)."""
    import shapely

    if room.spec.view_points is not None:
        return len(room.spec.view_points)
    if room.floor.is_empty:
        return 0
    rect = np.asarray(shapely.minimum_rotated_rectangle(room.floor).exterior.coords)[:3]
    sides = np.linalg.norm(np.diff(rect, axis=0), axis=1)
    s = settings.grid_spacing_m
    per_height = np.prod(grid_lines(sides, s, grid_tolerance(sides.max(), s)).astype(float))
    return int(min(per_height * len(settings.eye_heights_m), 1e15))


def estimate_cells_per_point(room, settings) -> float:
    """Sampling cells of one viewpoint: the windows' solid angle seen from the floor's centroid at
    the first eye height [sr] over the cell size [sr]. An estimate, for the budget only."""
    if room.floor.is_empty or not room.windows:
        return 0.0
    c = np.array([room.floor.centroid.x, room.floor.centroid.y, room.floor_z + settings.eye_heights_m[0]])
    omega = sum(min(2 * np.pi, w.area_m2 * abs(np.dot(w.normal, (w.centroid - c))) / max(np.linalg.norm(w.centroid - c), 0.1) ** 3)
                for w in room.windows)
    return omega / np.radians(settings.angular_resolution_deg) ** 2


def check_budget(project: Project, scene: Scene, max_points: int) -> Cost:
    """Raise :class:`InputError` when the run's estimated viewpoints or cells exceed the budget
    (``--max-points`` raises it); return them."""
    where = project.path.name
    points, cells = 0, 0.0
    if project.view is not None:
        for room in scene.rooms:  # one estimate per room
            n = estimate_room_points(room, project.view)
            c = n * estimate_cells_per_point(room, project.view)
            points, cells = points + n, cells + c
            if points > max_points or cells > max_points * CELLS_PER_POINT:
                raise InputError(
                    f"{where}: rooms[{room.spec.index}] '{room.name}': about {n:,.0f} viewpoints and {c:,.0f} sampling cells, "
                    f"over the budget of {max_points:,} viewpoints ({max_points * CELLS_PER_POINT:,.0f} cells) a run may have; "
                    "check the floor's units and view.grid_spacing_m / view.angular_resolution_deg, or raise --max-points")
    return Cost(points, cells)


def estimate_seconds(project: Project, scene: Scene, cost: Cost) -> dict[str, float]:
    """A rough estimate of each criterion's time [s] from the run's counts (viewpoints and
    sampling cells, points P, daylight grid points) and :data:`SECONDS_PER_CELL` and the other
    rough costs: shown before a long run, never a budget."""
    from en17037cli.criteria.view import no_landscape

    out: dict[str, float] = {}
    if project.view is not None:
        traced = no_landscape(scene) is None
        out["view"] = cost.cells * SECONDS_PER_CELL if traced else cost.points * SECONDS_PER_VIEWPOINT
    if project.sunlight is not None:
        out["sunlight"] = SECONDS_PER_POINT_P * sum(len(r.windows) for r in scene.rooms if r.problem is None)
    if getattr(project, "daylight", None) is not None:
        import shapely

        area = sum(shapely.area(r.floor) for r in scene.rooms if r.problem is None)
        out["daylight"] = SECONDS_PER_DAYLIGHT_POINT * area / project.daylight.grid_spacing_m ** 2
    return out


def reading_note(project: Project) -> str | None:
    """What a run says before it reads large model files (over :data:`LARGE_MODEL_BYTES` together):
    how long the reading will take, about; None for smaller ones."""
    size = sum(f.path.stat().st_size for f in project.model.files if f.path.is_file())
    if size <= LARGE_MODEL_BYTES:
        return None
    return (f"reading {len(project.model.files)} model file(s), {size / 1e6:.0f} MB: about "
            f"{size / 1e6 * READ_SECONDS_PER_MB:.0f} s before the checks start")
