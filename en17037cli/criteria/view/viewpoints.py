"""Viewpoints of a room: a grid over its utilised area at each eye height, or explicit points."""
from __future__ import annotations

import numpy as np

from en17037cli.errors import NotAssessable
from en17037cli.project.settings import ViewSettings
from en17037cli.scene.model import GLAZING_OFFSET_M, Room, Scene

#: Outline changes smaller than this share of the utilised area's size [-] do not change the grid
#: (:func:`grid_lines`, :func:`grid_points`). A room drawn on round coordinates has sides that are
#: multiples of the spacing, where a bare floor(length / spacing) jumps: the same room given as a
#: rectangle and derived from the model's faces (which comes back a micron smaller) got different
#: grids, 77 and 60 points on a 4 x 6 m room.
GRID_SNAP = 1e-4


def grid_tolerance(size_m: float, spacing_m: float) -> float:
    """The grid's snap distance [m]: :data:`GRID_SNAP` of the larger of the area's size and the
    spacing, and at most a hundredth of the spacing (a very fine grid on a large floor)."""
    return min(GRID_SNAP * max(float(size_m), float(spacing_m)), 0.01 * float(spacing_m))


def grid_lines(length_m, spacing_m: float, tol_m: float) -> np.ndarray:
    """Grid lines along a side of ``length_m`` [m]: floor((length - tol) / spacing) + 1.

    The lines are centred on the side and ``spacing_m`` apart, so they span (n - 1) spacing <=
    length - tol: the outermost lie at least tol / 2 inside the side's ends, never on them. A side
    within ``tol_m`` [m] of a multiple of the spacing, above or below, gets the lines of one
    spacing less than that multiple (a 3 m side at 0.5 m: 6 lines, 0.25 m in from each end)."""
    return np.floor((np.asarray(length_m, dtype=float) - tol_m) / spacing_m).astype(np.int64) + 1


def grid_points(utilised, spacing_m: float, offset: float = 0.0) -> np.ndarray:
    """Grid of points over a polygon, aligned with its minimum-area bounding rectangle.

    The grid is centred on the rectangle and symmetric, so rotating or mirroring the model
    moves the grid with it; ``offset`` shifts it along both axes by that fraction of a cell. If
    no grid point falls inside (spacing larger than the area), the polygon's centroid (or a
    point surely inside it) is used. The count of lines and the points kept do not change under
    a change of the outline smaller than :func:`grid_tolerance` (:func:`grid_lines`; points within a
    quarter of it of the outline are outside, and the rectangle's own sides keep the lines half of
    it away), so a floor given and the same floor derived from the model give the same grid. Points are ordered along the rectangle's axes taken in a canonical way
    (:func:`canonical_axes`), by their grid indices, so the order too does not depend on the
    last bits of the outline.

    Parameters
    ----------
    utilised : shapely Polygon, local xy [m]
    spacing_m : float [m]
    offset : float, fraction of ``spacing_m`` in [0, 1)

    Returns
    -------
    (n, 2) float [m]
    """
    import shapely

    if utilised.is_empty or utilised.area <= 0:
        return np.zeros((0, 2))
    rect = np.asarray(shapely.minimum_rotated_rectangle(utilised).exterior.coords)[:4]
    centre = rect.mean(axis=0)
    e1, e2 = rect[1] - rect[0], rect[2] - rect[1]
    l1, l2 = np.linalg.norm(e1), np.linalg.norm(e2)
    e1, e2 = e1 / max(l1, 1e-12), e2 / max(l2, 1e-12)
    tol = grid_tolerance(max(l1, l2), spacing_m)
    n1, n2 = (int(n) for n in grid_lines([l1, l2], spacing_m, tol))
    a = (np.arange(-1, n1 + 1) - (n1 - 1) / 2 + offset) * spacing_m  # a row more each side: the shifted grid's
    b = (np.arange(-1, n2 + 1) - (n2 - 1) / 2 + offset) * spacing_m  # points that fall inside (none when unshifted)
    A, B = np.meshgrid(a, b, indexing="ij")
    pts = centre + A.reshape(-1, 1) * e1 + B.reshape(-1, 1) * e2
    inside = shapely.contains_xy(utilised.buffer(-0.25 * tol, join_style="mitre"), pts[:, 0], pts[:, 1])
    pts = pts[inside]
    if len(pts) == 0:
        c = utilised.centroid
        p = c if utilised.contains(c) else utilised.representative_point()
        pts = np.array([[p.x, p.y]])
    u, v = canonical_axes(e1, e2, l1, l2, tol)
    rel = pts - centre
    # twice the index along each axis: an integer (grid points sit at whole or half spacings from the centre)
    iu, iv = (np.round(2.0 * (rel @ ax) / spacing_m) for ax in (u, v))
    return pts[np.lexsort((iv, iu))]


def canonical_axes(e1: np.ndarray, e2: np.ndarray, l1: float, l2: float, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """The axes of a rectangle (unit sides ``e1``, ``e2`` of lengths ``l1``, ``l2`` [m]) taken the same
    way whichever corner the rectangle starts at: ``u`` along the longer side (the one nearer the
    x axis where they are within ``tol`` [m] of each other), pointing at an azimuth in [-45, 135)
    deg; ``v`` a quarter turn counterclockwise from it. The choice changes only for a side at
    45 deg (the nearer-axis tie) or at -45 / 135 deg (the direction's), not for the common
    axis-aligned rooms."""
    if abs(l1 - l2) > tol:
        u = e1 if l1 > l2 else e2
    else:
        u = e1 if abs(e1[0]) >= abs(e2[0]) else e2
    ang = np.degrees(np.arctan2(u[1], u[0]))
    if not -45.0 <= ang < 135.0:
        u = -u
    return u, np.array([-u[1], u[0]])


def viewpoints(scene: Scene, room: Room, settings: ViewSettings) -> tuple[list, list]:
    """Viewpoints of a room grouped by eye height: the room's explicit points, or a grid over the
    utilised area (the floor inset by ``settings.wall_margin_m``) at each eye height. Points on a
    glazing plane are moved :data:`GLAZING_OFFSET_M` into the room.

    Returns
    -------
    groups : list of (eye_height_m, (n, 3) float local [m])
    notes : list of str
    """
    notes = []
    if room.spec.view_points is not None:
        pts = scene.to_local(room.spec.view_points)
        heights = np.round(pts[:, 2] - room.floor_z, 3)
        groups = [(float(h), pts[heights == h]) for h in np.unique(heights)]
    else:
        utilised = room.floor.buffer(-settings.wall_margin_m, join_style="mitre")
        if utilised.is_empty:
            raise NotAssessable(f"the utilised area (floor inset by view.wall_margin_m = {settings.wall_margin_m} m) is empty; "
                                "reduce the margin or check the floor")
        xy = grid_points(utilised, settings.grid_spacing_m, settings.grid_offset)
        groups = [(float(h), np.column_stack([xy, np.full(len(xy), room.floor_z + h)])) for h in settings.eye_heights_m]
    out = []
    for h, p in groups:
        p = p.copy()
        moved = 0
        for w in room.windows:  # per window, vectorised over points
            c = w.centroid
            s = (p - c) @ w.normal
            close = np.abs(s) < GLAZING_OFFSET_M
            if np.any(close):
                p[close] -= (s[close] + GLAZING_OFFSET_M)[:, None] * w.normal
                moved += int(close.sum())
        if moved:
            notes.append(f"room '{room.name}': {moved} viewpoints at eye height {h} m lay on a glazing plane and were moved {GLAZING_OFFSET_M * 1000:.0f} mm into the room")
        out.append((h, p))
    return out, notes
