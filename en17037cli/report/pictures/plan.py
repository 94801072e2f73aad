"""Plan maps: a room's viewpoints as coloured cells on its floor plan, drawn in the room's own orientation."""
from __future__ import annotations

import functools
import math

import numpy as np

from en17037cli.report.pictures.canvas import Canvas, _scale_bar_m
from en17037cli.report.pictures.colours import (
    LAYER_COLOURS,
    LAYER_ORDER,
    LEVEL_COLOURS,
    LEVEL_NAMES,
    WINDOW_COLOUR,
    _continuous_norm,
    _layer_legend,
    _rgb,
    continuous_colours,
)
from en17037cli.report.pictures.parts import colour_bar, legend, north_arrow, scale_bar
from en17037cli.report.pictures.raster import render

#: Layout size [in / 100 px] (width, height); printed at PRINT_SCALE of it (3.5 x 2.8 in).
PLAN_SIZE_IN = (5.0, 3.6)
#: Plan maps: the box the plan is fitted into [px from the bottom-left] (left, bottom, width, height),
#: and the colour bar's (left, bottom, width, height) [px]. The picture has no title: the reports
#: caption it, so nothing long crosses the plan or the north arrow.
PLAN_BOX_PX = (10, 36, 212, 316)
COLOUR_BAR_PX = (236, 44, 14, 184)

_KINDS = ("sight_angle", "distance", "layers", "level", "daylight_factor", "share_of_hours")
_CONTINUOUS = ("sight_angle", "distance", "daylight_factor", "share_of_hours")


def _rot(angle_deg: float) -> np.ndarray:
    """2 x 2 matrix of the counter-clockwise rotation by ``angle_deg`` [deg]."""
    a = math.radians(angle_deg)
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


def _canonical_deg(a: float) -> float:
    """An angle [deg] in (-180, 180]."""
    a = math.fmod(a, 360.0)
    if a <= -180.0:
        a += 360.0
    elif a > 180.0:
        a -= 360.0
    return a


def plan_rotation(floor, windows=()) -> float:
    """Rotation of the plan [deg, counter-clockwise] that draws a room in its own orientation.

    The floor's minimum-area bounding rectangle (:func:`shapely.minimum_rotated_rectangle`) is
    made axis-parallel; of its four such rotations, the one that puts the windows' mean position
    (segment midpoints weighted by length) closest to the top edge is chosen, relative to the
    rectangle's half-height in that rotation. Without windows, or with windows balanced around
    the centre, the long side is horizontal.

    Parameters
    ----------
    floor : (k, 2) float [m], ring of the floor outline in the model frame
    windows : sequence of (2, 2) float [m], each window's plan trace

    Returns
    -------
    float [deg] in (-180, 180]
    """
    import shapely

    ring = np.asarray(floor, dtype=float)
    rect = np.asarray(shapely.minimum_rotated_rectangle(shapely.Polygon(ring)).exterior.coords)[:4]
    edges = np.diff(np.vstack([rect, rect[:1]]), axis=0)
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    long_edge = edges[int(np.argmax(lengths + 1e-9 * np.arange(4)[::-1]))]  # the first of equal sides
    base = -math.degrees(math.atan2(long_edge[1], long_edge[0]))  # long side horizontal
    centre = rect.mean(axis=0)
    segs = [np.asarray(w, dtype=float).reshape(2, 2) for w in windows]
    best, best_score = base, 0.0
    if segs:
        mids = np.array([s.mean(axis=0) for s in segs])
        wts = np.array([np.hypot(*(s[1] - s[0])) for s in segs]) + 1e-12
        mean = (mids * wts[:, None]).sum(axis=0) / wts.sum() - centre
        scale = max(float(lengths.max()), 1e-12)
        for k in range(4):
            a = base + 90.0 * k
            r = _rot(a)
            half_h = float(np.abs((rect - centre) @ r.T)[:, 1].max())
            score = float((r @ mean)[1]) / max(half_h, 1e-12)
            if score > best_score + 1e-6 and abs(float((r @ mean)[1])) > 1e-6 * scale:
                best, best_score = a, score
    return _canonical_deg(best)


@functools.lru_cache(maxsize=16)
def _rotation_of(floor: bytes, windows: bytes) -> float:
    """:func:`plan_rotation` of a floor and windows given as the bytes of their float arrays, kept:
    a room's maps (four per eye height, its daylight map) share them."""
    return plan_rotation(np.frombuffer(floor).reshape(-1, 2), list(np.frombuffer(windows).reshape(-1, 2, 2)))


@functools.lru_cache(maxsize=16)
def _squares_of(points: bytes, spacing_m: float | None) -> np.ndarray:
    """:func:`_cell_squares` of points given as the bytes of their (n, 2) float array, kept (read only):
    the maps of one eye height share them."""
    out = _cell_squares(np.frombuffer(points).reshape(-1, 2), spacing_m)
    out.flags.writeable = False
    return out


def _nearest_neighbour(points: np.ndarray, sample: int = 256) -> tuple[np.ndarray, np.ndarray]:
    """Distance [m] and offset (k, 2) [m] from up to ``sample`` evenly spread points to their nearest other point.

    A sample is enough to read a grid's spacing and direction, and keeps the cost at
    ``sample`` x n distances for rooms of thousands of viewpoints.
    """
    n = len(points)
    idx = np.unique(np.linspace(0, n - 1, min(n, sample)).round().astype(int))
    d = points[None, :, :] - points[idx, None, :]
    d2 = np.einsum("ijk,ijk->ij", d, d)
    d2[np.arange(len(idx)), idx] = np.inf
    j = np.argmin(d2, axis=1)
    rows = np.arange(len(idx))
    return np.sqrt(d2[rows, j]), d[rows, j]


def _cell_squares(xy: np.ndarray, spacing_m: float | None) -> np.ndarray:
    """(n, 4, 2) corners of a square cell around each point, oriented like the points' grid."""
    n = len(xy)
    angle = 0.0
    if n > 1:
        dist, off = _nearest_neighbour(xy)
        if spacing_m is None:
            spacing_m = float(np.median(dist))
        # the grid's direction modulo 90 deg: mean of 4 theta on the unit circle
        t = 4.0 * np.arctan2(off[:, 1], off[:, 0])
        angle = 0.25 * math.atan2(float(np.sin(t).sum()), float(np.cos(t).sum()))
    if not spacing_m or not math.isfinite(spacing_m):
        spacing_m = 1.0
    h = 0.5 * spacing_m
    corners = np.array([[-h, -h], [h, -h], [h, h], [-h, h]]) @ _rot(math.degrees(angle)).T
    return xy[:, None, :] + corners[None, :, :]


def plan_map(points_xy, values, *, kind: str, thresholds: dict | None, floor, utilised, windows, true_north_deg: float,
             near=None, spacing_m: float | None = None, title: str = "", fmt: str = "png"):
    """A room's plan with one coloured cell per viewpoint, drawn in the room's own orientation.

    The plan is rotated by :func:`plan_rotation` (the floor's bounding rectangle axis-parallel,
    the windows at the top if possible). Each viewpoint is a filled square of side ``spacing_m``
    oriented like the viewpoint grid; the floor outline is solid, the utilised area dashed, the
    windows thick; a north arrow points to true north in the rotated picture, a scale bar and a
    colour bar (continuous values, thresholds marked) or legend (levels, layers) explain it.

    Parameters
    ----------
    points_xy : (n, 2) float [m], viewpoints in the model frame
    values : (n,) float
        ``kind="sight_angle"``: horizontal sight angle [deg]; ``"distance"``: outside distance [m],
        ``+inf`` where unobstructed; ``"level"``: level index 0..3 (none .. high); ``"layers"``:
        bitmask of the layers seen (:data:`SKY` | :data:`LANDSCAPE` | :data:`GROUND`). NaN: not
        drawn (an empty cell).
    kind : {"sight_angle", "distance", "layers", "level"}
    thresholds : dict {"minimum", "medium", "high"} in the value's unit, or None (layers, level)
    floor : (k, 2) float [m], ring of the floor outline
    utilised : (k, 2) float [m], ring of the utilised area, or None
    windows : sequence of (2, 2) float [m], each window's plan trace (outer edge)
    true_north_deg : float [deg], azimuth of true north clockwise from model +Y
    near : (n,) bool, optional; points within their error estimate of a threshold (ringed)
    spacing_m : float [m], optional; cell side, default the median nearest-neighbour distance
    title : str, not drawn: the reports caption the picture (kept for callers)
    fmt : "png", "svg" or "both" (see :meth:`~en17037cli.report.pictures.canvas.Canvas.render`)

    Returns
    -------
    bytes, a PNG image of :data:`PLAN_SIZE_IN` at :data:`DPI` (or the SVG, or both)
    """
    if kind not in _KINDS:
        raise ValueError(f"kind must be one of {', '.join(_KINDS)}, not {kind!r}")
    pts = np.asarray(points_xy, dtype=float).reshape(-1, 2)
    vals = np.asarray(values, dtype=float).reshape(-1)
    if len(vals) != len(pts):
        raise ValueError(f"values must have shape ({len(pts)},) like points_xy, not {vals.shape}")
    if kind in _CONTINUOUS and not thresholds:
        raise ValueError(f"kind={kind!r} needs thresholds {{'minimum', 'medium', 'high'}}")
    near_m = None if near is None else np.asarray(near, dtype=bool).reshape(-1)
    floor_r = np.asarray(floor, dtype=float).reshape(-1, 2)
    win = [np.asarray(w, dtype=float).reshape(2, 2) for w in (windows or ())]
    angle = _rotation_of(floor_r.tobytes(), b"".join(w.tobytes() for w in win))
    r = _rot(angle)
    centre = floor_r.mean(axis=0)  # a point of the room, whatever the model's axes
    # rounded to a nanometre: the same room in another model frame then gives the same coordinates,
    # so the same pixels are filled (a cell edge through pixel centres is not moved by 1e-15)
    tf = lambda p: np.round((np.asarray(p, dtype=float).reshape(-1, 2) - centre) @ r.T, 9)
    floor_t = tf(floor_r)
    util_t = None if utilised is None else tf(utilised)
    win_t = [tf(w) for w in win]
    pts_t = tf(pts)
    squares = _squares_of(pts_t.tobytes(), spacing_m)
    north = r @ np.array([math.sin(math.radians(true_north_deg)), math.cos(math.radians(true_north_deg))])

    faces, legend_entries, bar = _plan_colours(kind, vals, thresholds)
    ok = np.all(np.isfinite(faces), axis=1)
    allxy = np.vstack([floor_t, squares.reshape(-1, 2)] + ([util_t] if util_t is not None else []) + win_t)
    lo, hi = allxy.min(axis=0), allxy.max(axis=0)
    (bx0, by0), (bw, bh) = PLAN_BOX_PX[:2], PLAN_BOX_PX[2:]
    bar_px = 30.0  # room for the scale bar under the plan
    scale = min(bw / max(float(hi[0] - lo[0]), 1e-9), (bh - bar_px) / max(float(hi[1] - lo[1]), 1e-9))  # [px/m]
    mid = 0.5 * (lo + hi)
    # the plan and its scale bar centred in the box
    ox, oy = bx0 + bw / 2, by0 + bh / 2 + 0.5 * bar_px
    has_near = near_m is not None and bool(near_m.any())

    c = Canvas(int(PLAN_SIZE_IN[0] * 100), int(PLAN_SIZE_IN[1] * 100))
    to_px = lambda p: (np.asarray(p, dtype=float) - mid) * scale + (ox, oy)  # noqa: E731 - metres of the plan -> layout px
    if ok.any():
        # not anti-aliased: neighbouring cells share their edges without a light seam
        c.cells(to_px(squares[ok]), np.round(faces[ok, :3] * 255).astype(np.uint8))
    if (~ok).any():  # an empty cell: a grey square with a white one 1 px inside it
        empty = to_px(squares[~ok])
        c.cells(empty, np.full((len(empty), 3), 0x99, dtype=np.uint8))
        side = float(np.hypot(*(empty[0, 1] - empty[0, 0])))
        if side > 3.0:
            mean = empty.mean(axis=1, keepdims=True)
            c.cells(mean + (empty - mean) * (1.0 - 2.0 / side), np.full((len(empty), 3), 0xFF, dtype=np.uint8))
    c.path(to_px(floor_t), stroke="black", lw=1.2, closed=True)
    if util_t is not None:
        c.path(to_px(util_t), stroke="black", lw=0.8, closed=True, dash=(4, 3))
    for w in win_t:  # one per window
        for colour, lw in (("black", 5.0), (WINDOW_COLOUR, 3.0)):
            c.path(to_px(w), stroke=colour, lw=lw)
    # scale bar under the plan: two halves, black and white
    sb = _scale_bar_m(float(hi[0] - lo[0]))
    # on whole pixels, so that rounding in the plan's extent does not shade it differently
    x0, y0, L = round(ox + (lo[0] - mid[0]) * scale), round(oy - 0.5 * (hi[1] - lo[1]) * scale - 22.0), round(sb * scale)
    scale_bar(c, x0, y0, L, sb)
    north_arrow(c, (462.0, 320.0), north)
    near_entry = [("marker", {"size": 5, "stroke": "black", "lw": 1.0}, "within error of a threshold")] if has_near else []
    if bar is not None:
        colour_bar(c, COLOUR_BAR_PX, *bar)
        if near_entry:
            legend(c, 232.0, 30.0, near_entry)
    else:
        legend(c, 232.0, 268.0, [("patch", col, lab) for col, lab in legend_entries] + near_entry,
               title="level" if kind == "level" else "layers seen")
    if has_near:  # rings last: one pass of markers over the paths
        for colour, mew in (("white", 2.0), ("black", 0.9)):
            c.markers(to_px(pts_t[near_m]), 5, stroke=colour, lw=mew)
    return render(c, fmt)


def _plan_colours(kind: str, vals: np.ndarray, thresholds: dict | None):
    """Face colours (n, 4) with NaN rows for missing values, legend entries, colour-bar spec."""
    n = len(vals)
    faces = np.full((n, 4), np.nan)
    if kind in _CONTINUOUS:
        assert thresholds is not None
        norm, cmap_name, extend, label = _continuous_norm(kind, vals, thresholds)
        faces = continuous_colours(kind, vals, thresholds, all_values=vals)
        return faces, None, (norm, cmap_name, extend, label, thresholds, kind)
    ok = np.isfinite(vals)
    code = np.where(ok, vals, -1).astype(int)
    if kind == "level":
        table = _rgb(LEVEL_COLOURS)
        ok &= (code >= 0) & (code <= 3)
        idx = code
        legend = [(LEVEL_COLOURS[i], LEVEL_NAMES[i]) for i in reversed(range(4))]
    else:
        table = _rgb(LAYER_COLOURS)
        position = np.empty(8, dtype=int)
        position[list(LAYER_ORDER)] = np.arange(8)  # bitmask -> place in the luminance order
        ok &= (code >= 0) & (code <= 7)
        idx = position[np.clip(code, 0, 7)]
        present = set(np.clip(idx[ok], 0, 7).tolist())  # only the combinations the map shows
        legend = [(LAYER_COLOURS[i], _layer_legend(LAYER_ORDER[i])) for i in reversed(range(8)) if i in present]
    faces[ok, :3] = table[np.clip(idx[ok], 0, len(table) - 1)]
    faces[ok, 3] = 1.0
    return faces, legend, None
