"""The pictures of the client report: pure drawing functions that return PNG bytes.

Nothing here traces rays or reads files: the callers pass the values, this module draws them.
Every picture is reproducible as matplotlib's own test suite makes its images: a fixed figure
size and DPI, the Agg canvas (pyplot is never imported), matplotlib's default style with the
bundled DejaVu Sans font set locally through :func:`matplotlib.rc_context`, and no
``Software`` entry in the PNG metadata, so the same inputs give byte-identical files on one
installation (another FreeType or matplotlib version may move anti-aliased pixels).

Colours read in grey: continuous values use viridis or cividis (luminance rises monotonically),
levels and the eight layer combinations are samples of viridis ordered by luminance, and the
classes of the fisheye go from dark (blocked) to light (sky). :func:`relative_luminance` and
:func:`lightness` measure this (Rec. 709 primaries, sRGB transfer, CIE 1976 L*).

matplotlib is imported inside the functions that draw, so this module imports without it.
"""
from __future__ import annotations

import io
import math
from collections.abc import Callable, Sequence

import numpy as np

# ----------------------------------------------------------------------------------------------
# Layout and colours (hex strings, so the module needs no matplotlib to define them)
# ----------------------------------------------------------------------------------------------

#: Pixels per inch of every picture.
DPI = 100
#: Figure sizes [in] (width, height).
PLAN_SIZE_IN = (5.0, 4.0)
FISHEYE_SIZE_IN = (5.6, 4.0)
CHART_SIZE_IN = (5.0, 3.2)
#: Plan maps: the box the plan is fitted into [px from the bottom-left] (left, bottom, width, height),
#: and the colour bar's (left, bottom, width, height) [px].
PLAN_BOX_PX = (15, 50, 290, 300)
COLOUR_BAR_PX = (330, 70, 14, 200)
#: Fisheye: centre of the 180 deg circle [px] (column, row from the top of the PNG) and its radius [px].
FISHEYE_CENTRE_PX = (190, 205)
FISHEYE_RADIUS_PX = 160

#: Level colours, none .. high: viridis at 0, 1/3, 2/3, 1 (L* 15, 42, 67, 91).
LEVEL_COLOURS = ("#440154", "#31688e", "#35b779", "#fde725")
LEVEL_NAMES = ("none", "minimum", "medium", "high")

#: View-layer bitmask of clause 5.2 (sky = 1, landscape = 2, ground = 4).
SKY, LANDSCAPE, GROUND = 1, 2, 4
#: The eight layer combinations ordered darkest to lightest: first the four without landscape
#: (level none), then landscape alone (minimum), landscape with sky or ground (medium), all three
#: (high), so the order of luminance follows Table A.5.
LAYER_ORDER = (0, SKY, GROUND, SKY | GROUND, LANDSCAPE, SKY | LANDSCAPE, LANDSCAPE | GROUND, SKY | LANDSCAPE | GROUND)
#: Their colours: viridis at i / 7 (L* 15, 27, 38, 49, 60, 70, 81, 91).
LAYER_COLOURS = ("#440154", "#46327e", "#365c8d", "#277f8e", "#1fa187", "#4ac16d", "#a0da39", "#fde725")

#: Fisheye classes (the codes of the traced raster) and their colours, dark to light:
#: -1 outside the 180 deg circle, 0 blocked or interior, 1 sky, 2 landscape, 3 ground.
OUTSIDE, BLOCKED, CLASS_SKY, CLASS_LANDSCAPE, CLASS_GROUND = -1, 0, 1, 2, 3
CLASS_NAMES = {BLOCKED: "blocked, interior", CLASS_SKY: "sky", CLASS_LANDSCAPE: "landscape", CLASS_GROUND: "ground"}
CLASS_COLOURS = {OUTSIDE: "#ffffff", BLOCKED: "#333333", CLASS_GROUND: "#8a6a48", CLASS_LANDSCAPE: "#6aa84f", CLASS_SKY: "#bfe0f5"}
#: Windows on plans (light blue inside a black casing).
WINDOW_COLOUR = "#8fd3ff"
#: Sun paths (drawn over a black casing so they read on light and dark classes).
SUN_PATH_COLOUR = "#ff7f00"

#: Sun-hours chart: the days' bars and the assessed day's (dark and hatched) bar.
BAR_COLOUR, ASSESSED_COLOUR = "#b0b0b0", "#08306b"
#: Continuous colour maps (monotone luminance).
CMAP = {"sight_angle": "viridis", "distance": "cividis"}
#: Distances below this are drawn in the lowest colour [m].
DISTANCE_VMIN_M = 1.0

_KINDS = ("sight_angle", "distance", "layers", "level")
_MONTHS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")
_RC: dict = {
    "font.family": "DejaVu Sans",
    "font.size": 8,
    "svg.hashsalt": "en17037cli",
    "lines.scale_dashes": False,
    "axes.titlesize": 9,
    "legend.fontsize": 7,
    "legend.frameon": False,
    "xtick.labelsize": 7,
    "ytick.labelsize": 7,
}


# ----------------------------------------------------------------------------------------------
# Numbers and colours
# ----------------------------------------------------------------------------------------------

def fmt_duration(hours: float) -> str:
    """A duration as reports write it, rounded to the minute: ``"5 h 52 min"``, ``"18 min"``, ``"0 min"``, ``"4 h"``.

    Parameters
    ----------
    hours : float [h]
        NaN or infinite gives ``"n/a"``; a negative duration keeps its sign.

    Returns
    -------
    str
    """
    h = float(hours)
    if not math.isfinite(h):
        return "n/a"
    total = math.floor(abs(h) * 60.0 + 0.5)  # half a minute rounds up, whatever the parity
    sign = "-" if h < 0 and total else ""
    hh, mm = divmod(total, 60)
    if hh == 0:
        return f"{sign}{mm} min"
    return f"{sign}{hh} h" + (f" {mm} min" if mm else "")


def _hm(hours: float) -> str:
    """Axis tick in h:mm [h]."""
    total = math.floor(abs(hours) * 60.0 + 0.5)
    return f"{'-' if hours < 0 and total else ''}{total // 60}:{total % 60:02d}"


def _rgb(colours) -> np.ndarray:
    """(k, 3) float in [0, 1] from hex strings or RGB(A) rows."""
    rows = []
    for c in colours:
        if isinstance(c, str):
            s = c.lstrip("#")
            rows.append([int(s[i:i + 2], 16) / 255.0 for i in (0, 2, 4)])
        else:
            rows.append(list(c)[:3])
    return np.asarray(rows, dtype=float).reshape(-1, 3)


def relative_luminance(colours) -> np.ndarray:
    """Relative luminance Y of sRGB colours (Rec. 709 primaries and white, sRGB transfer curve).

    Parameters
    ----------
    colours : sequence of hex strings or (k, 3|4) float in [0, 1]

    Returns
    -------
    (k,) float in [0, 1]

    References
    ----------
    ITU-R BT.709-6 (2015), item 3.2 (luminance coefficients); IEC 61966-2-1:1999 (sRGB decoding).
    """
    c = _rgb(colours)
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return lin @ np.array([0.2126, 0.7152, 0.0722])


def lightness(colours) -> np.ndarray:
    """CIE 1976 lightness L* [0, 100] of sRGB colours, from :func:`relative_luminance`.

    Equal steps of L* look like equal steps of grey, which Y (linear in light) does not.

    Parameters
    ----------
    colours : sequence of hex strings or (k, 3|4) float in [0, 1]

    Returns
    -------
    (k,) float [0, 100]

    References
    ----------
    CIE 15:2004 Colorimetry, 8.2.1 (L* = 116 (Y/Yn)^(1/3) - 16, linear below (6/29)^3).
    """
    y = relative_luminance(colours)
    return np.where(y > 216 / 24389, 116 * np.cbrt(y) - 16, y * 24389 / 27)


# ----------------------------------------------------------------------------------------------
# Rendering
# ----------------------------------------------------------------------------------------------

def _render(draw: Callable, size_in: tuple[float, float]) -> bytes:
    """Draw on a fresh Agg figure of ``size_in`` [in] at :data:`DPI` and return the PNG bytes."""
    import matplotlib
    import matplotlib.style
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    with matplotlib.style.context("default"), matplotlib.rc_context(_RC):  # the user's matplotlibrc does not leak in
        fig = Figure(figsize=size_in, dpi=DPI)
        FigureCanvasAgg(fig)
        draw(fig)
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=DPI, metadata={"Software": None})
    return buf.getvalue()


# ----------------------------------------------------------------------------------------------
# Plan maps
# ----------------------------------------------------------------------------------------------

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


def _scale_bar_m(width_m: float) -> float:
    """The longest of 1, 2 or 5 m times a power of ten that fits in 30 % of ``width_m``."""
    target = max(0.3 * width_m, 1e-9)
    best = 0.1
    for e in range(-1, 4):
        for m in (1.0, 2.0, 5.0):
            v = m * 10.0**e
            if v <= target:
                best = v
    return best


def _fmt_num(v: float) -> str:
    """A threshold or bar length without trailing zeros."""
    return f"{v:.6g}"


def plan_map(points_xy, values, *, kind: str, thresholds: dict | None, floor, utilised, windows, true_north_deg: float,
             near=None, spacing_m: float | None = None, title: str = "") -> bytes:
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
    title : str

    Returns
    -------
    bytes, a PNG image of :data:`PLAN_SIZE_IN` at :data:`DPI`
    """
    if kind not in _KINDS:
        raise ValueError(f"kind must be one of {', '.join(_KINDS)}, not {kind!r}")
    pts = np.asarray(points_xy, dtype=float).reshape(-1, 2)
    vals = np.asarray(values, dtype=float).reshape(-1)
    if len(vals) != len(pts):
        raise ValueError(f"values must have shape ({len(pts)},) like points_xy, not {vals.shape}")
    if kind in ("sight_angle", "distance") and not thresholds:
        raise ValueError(f"kind={kind!r} needs thresholds {{'minimum', 'medium', 'high'}}")
    near_m = None if near is None else np.asarray(near, dtype=bool).reshape(-1)
    floor_r = np.asarray(floor, dtype=float).reshape(-1, 2)
    win = [np.asarray(w, dtype=float).reshape(2, 2) for w in (windows or ())]
    angle = plan_rotation(floor_r, win)
    r = _rot(angle)
    centre = floor_r.mean(axis=0)  # a point of the room, whatever the model's axes
    # rounded to a nanometre: the same room in another model frame then gives the same coordinates,
    # so Agg snaps the same edges to pixels (an edge 1e-15 off the horizontal is not snapped)
    tf = lambda p: np.round((np.asarray(p, dtype=float).reshape(-1, 2) - centre) @ r.T, 9)
    floor_t = tf(floor_r)
    util_t = None if utilised is None else tf(utilised)
    win_t = [tf(w) for w in win]
    pts_t = tf(pts)
    squares = _cell_squares(pts_t, spacing_m)
    north = r @ np.array([math.sin(math.radians(true_north_deg)), math.cos(math.radians(true_north_deg))])

    faces, legend, bar = _plan_colours(kind, vals, thresholds)
    ok = np.all(np.isfinite(faces), axis=1)
    allxy = np.vstack([floor_t, squares.reshape(-1, 2)] + ([util_t] if util_t is not None else []))
    lo, hi = allxy.min(axis=0), allxy.max(axis=0)
    (bx0, by0), (bw, bh) = PLAN_BOX_PX[:2], PLAN_BOX_PX[2:]
    bar_px = 30.0  # room for the scale bar under the plan
    scale = min(bw / max(float(hi[0] - lo[0]), 1e-9), (bh - bar_px) / max(float(hi[1] - lo[1]), 1e-9))  # [px/m]
    mid = 0.5 * (lo + hi)
    # the plan and its scale bar centred in the box
    ox, oy = bx0 + bw / 2, by0 + bh / 2 + 0.5 * bar_px
    has_near = near_m is not None and bool(near_m.any())

    def draw(fig):
        from matplotlib.collections import PolyCollection
        from matplotlib.lines import Line2D
        from matplotlib.patches import Polygon, Rectangle
        from matplotlib.transforms import Affine2D, IdentityTransform

        px = IdentityTransform()
        T = Affine2D().translate(-mid[0], -mid[1]).scale(scale).translate(ox, oy)
        if ok.any():
            # not anti-aliased: neighbouring cells share their edges without a light seam
            fig.add_artist(PolyCollection(squares[ok], facecolors=faces[ok], edgecolors="none", antialiased=False, transform=T))
        if (~ok).any():
            fig.add_artist(PolyCollection(squares[~ok], facecolors="none", edgecolors="#999999", linewidths=0.5, transform=T))
        fig.add_artist(Polygon(floor_t, closed=True, fill=False, edgecolor="black", linewidth=1.2, transform=T))
        if util_t is not None:
            fig.add_artist(Polygon(util_t, closed=True, fill=False, edgecolor="black", linewidth=0.8, linestyle=(0, (4, 3)), transform=T))
        for w in win_t:
            for colour, lw in (("black", 5.0), (WINDOW_COLOUR, 3.0)):
                fig.add_artist(Line2D(w[:, 0], w[:, 1], color=colour, linewidth=lw, solid_capstyle="butt", transform=T))
        if has_near:
            for colour, mew in (("white", 2.0), ("black", 0.9)):
                fig.add_artist(Line2D(pts_t[near_m, 0], pts_t[near_m, 1], linestyle="none", marker="o", markersize=5,
                                      markerfacecolor="none", markeredgecolor=colour, markeredgewidth=mew, transform=T))
        # scale bar under the plan: two halves, black and white
        sb = _scale_bar_m(float(hi[0] - lo[0]))
        # on whole pixels, so that rounding in the plan's extent does not shade it differently
        x0, y0, L = round(ox + (lo[0] - mid[0]) * scale), round(oy - 0.5 * (hi[1] - lo[1]) * scale - 22.0), round(sb * scale)
        fig.add_artist(Rectangle((x0, y0), L / 2, 5, facecolor="black", edgecolor="black", linewidth=0.6, transform=px))
        fig.add_artist(Rectangle((x0 + L / 2, y0), L / 2, 5, facecolor="white", edgecolor="black", linewidth=0.6, transform=px))
        fig.text(x0 + L + 6, y0 + 2.5, f"{_fmt_num(sb)} m", va="center", ha="left", fontsize=7, transform=px)
        if title:
            fig.text(12, PLAN_SIZE_IN[1] * DPI - 8, title, ha="left", va="top", fontsize=9, transform=px)
        _north_arrow(fig, (420.0, 350.0), north)
        near_entry = [("marker", {"marker": "o", "markersize": 5, "markerfacecolor": "none", "markeredgecolor": "black"},
                       "within error of a threshold")] if has_near else []
        if bar is not None:
            _colour_bar(fig, *bar)
            if near_entry:
                _legend(fig, 318.0, 30.0, near_entry)
        else:
            _legend(fig, 318.0, 300.0, [("patch", c, lab) for c, lab in legend] + near_entry,
                    title="level" if kind == "level" else "layers seen")

    return _render(draw, PLAN_SIZE_IN)


def _legend(fig, x: float, y: float, entries: list, title: str | None = None, row: float = 15.0, size: float = 6.5) -> float:
    """A legend drawn with plain artists from its top-left corner (x, y) [px]; returns the y below it.

    entries : list of (kind, style, label); kind "patch" (style: face colour), "line" (style: list
    of Line2D keyword dicts drawn on top of each other) or "marker" (style: Line2D keywords)
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Rectangle
    from matplotlib.transforms import IdentityTransform

    px = IdentityTransform()
    if title:
        fig.text(x, y, title, ha="left", va="top", fontsize=size + 0.5, transform=px)
        y -= row + 2
    for kind, style, label in entries:
        cy = y - row / 2
        if kind == "patch":
            fig.add_artist(Rectangle((x, cy - 5), 16, 10, facecolor=style, edgecolor="black", linewidth=0.4, transform=px))
        elif kind == "line":
            for kw in style:
                fig.add_artist(Line2D([x, x + 16], [cy, cy], transform=px, **kw))
        else:
            fig.add_artist(Line2D([x + 8], [cy], linestyle="none", transform=px, **style))
        fig.text(x + 22, cy, label, ha="left", va="center", fontsize=size, transform=px)
        y -= row
    return y


def _continuous_norm(kind: str, vals: np.ndarray, thresholds: dict):
    """(norm, colour map name, extend, label) of a continuous plan map."""
    from matplotlib.colors import LogNorm, Normalize

    finite = vals[np.isfinite(vals)]
    high = float(thresholds["high"])
    if kind == "sight_angle":
        vmax = max(1.25 * high, float(finite.max()) if finite.size else 0.0)
        return Normalize(0.0, vmax), CMAP[kind], "neither", "horizontal sight angle [°]"
    vmax = max(2.0 * high, float(finite.max()) if finite.size else 0.0, 2.0 * DISTANCE_VMIN_M)
    return LogNorm(DISTANCE_VMIN_M, vmax), CMAP[kind], "both", "outside distance [m]\n(top: unobstructed)"


def continuous_colours(kind: str, values, thresholds: dict, all_values=None) -> np.ndarray:
    """RGBA of ``values`` as :func:`plan_map` colours them for a continuous ``kind``.

    Parameters
    ----------
    kind : {"sight_angle", "distance"}
    values : (m,) float in the thresholds' unit
    thresholds : dict {"minimum", "medium", "high"}
    all_values : (n,) float, optional; the map's values that set the scale (default ``values``)

    Returns
    -------
    (m, 4) float in [0, 1]; NaN rows where the value is NaN
    """
    import matplotlib

    v = np.asarray(values, dtype=float).reshape(-1)
    scale = v if all_values is None else np.asarray(all_values, dtype=float).reshape(-1)
    norm, cmap_name, _, _ = _continuous_norm(kind, scale, thresholds)
    cmap = matplotlib.colormaps[cmap_name]
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.ma.filled(norm(np.where(np.isnan(v), 1.0, np.where(np.isinf(v), norm.vmax, v))), 0.0)  # <= 0 on a log scale: lowest
    t = np.clip(np.nan_to_num(t, nan=0.0), 0.0, 1.0)
    rgba = np.asarray(cmap(t), dtype=float)
    rgba[np.isnan(v)] = np.nan
    return rgba


def _plan_colours(kind: str, vals: np.ndarray, thresholds: dict | None):
    """Face colours (n, 4) with NaN rows for missing values, legend entries, colour-bar spec."""
    n = len(vals)
    faces = np.full((n, 4), np.nan)
    if kind in ("sight_angle", "distance"):
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
        legend = [(LAYER_COLOURS[i], _layer_legend(LAYER_ORDER[i])) for i in reversed(range(8))]
    faces[ok, :3] = table[np.clip(idx[ok], 0, len(table) - 1)]
    faces[ok, 3] = 1.0
    return faces, legend, None


def layer_label(code: int) -> str:
    """Names of the layers in a bitmask, ``"sky + landscape"``; ``"none"`` for 0.

    Parameters
    ----------
    code : int, bitmask of :data:`SKY`, :data:`LANDSCAPE`, :data:`GROUND`
    """
    names = [n for bit, n in ((SKY, "sky"), (LANDSCAPE, "landscape"), (GROUND, "ground")) if int(code) & bit]
    return " + ".join(names) if names else "none"


def _layer_legend(code: int) -> str:
    """Legend entry of a layer combination: its layers and the level they reach."""
    return f"{'all three layers' if code == SKY | LANDSCAPE | GROUND else layer_label(code)} ({_layer_level(code)})"


def _layer_level(code: int) -> str:
    """Level a layer combination reaches by Table A.5 (landscape; and sky or ground; all three)."""
    if not code & LANDSCAPE:
        return "none"
    if code & SKY and code & GROUND:
        return "high"
    return "medium" if code & (SKY | GROUND) else "minimum"


def _colour_bar(fig, norm, cmap_name, extend, label, thresholds, kind):
    """A colour bar drawn as a pixel image at :data:`COLOUR_BAR_PX`, the level thresholds across it."""
    import matplotlib
    from matplotlib.lines import Line2D
    from matplotlib.patches import Polygon, Rectangle
    from matplotlib.transforms import IdentityTransform

    px = IdentityTransform()
    cmap = matplotlib.colormaps[cmap_name]
    x0, y0, w, h = COLOUR_BAR_PX
    t = (np.arange(h)[::-1] + 0.5) / h  # row 0 is the top
    column = np.round(np.asarray(cmap(t))[:, :3] * 255).astype(np.uint8)
    fig.figimage(np.repeat(column[:, None, :], w, axis=1), xo=x0, yo=y0, origin="upper")
    tip = 0.6 * w
    if extend in ("min", "both"):
        fig.add_artist(Polygon([(x0, y0), (x0 + w, y0), (x0 + w / 2, y0 - tip)], facecolor=cmap(0.0), edgecolor="black",
                               linewidth=0.5, transform=px))
    if extend in ("max", "both"):
        fig.add_artist(Polygon([(x0, y0 + h), (x0 + w, y0 + h), (x0 + w / 2, y0 + h + tip)], facecolor=cmap(1.0),
                               edgecolor="black", linewidth=0.5, transform=px))
    fig.add_artist(Rectangle((x0, y0), w, h, fill=False, edgecolor="black", linewidth=0.5, transform=px))
    unit = "°" if kind == "sight_angle" else " m"
    for name in ("minimum", "medium", "high"):
        v = float(thresholds[name])
        if norm.vmin <= v <= norm.vmax:
            y = y0 + float(norm(v)) * h
            fig.add_artist(Line2D([x0, x0 + w + 3], [y, y], color="white", linewidth=2.4, transform=px))
            fig.add_artist(Line2D([x0, x0 + w + 3], [y, y], color="black", linewidth=1.0, transform=px))
            fig.text(x0 + w + 6, y, f"{name} {_fmt_num(v)}{unit}", ha="left", va="center", fontsize=6.5, transform=px)
    lo_lab, hi_lab = (f"{_fmt_num(norm.vmin)}°", f"{_fmt_num(round(norm.vmax, 1))}°") if kind == "sight_angle" else \
        (f"≤ {_fmt_num(norm.vmin)} m", f"≥ {_fmt_num(round(norm.vmax))} m, unobstructed")
    fig.text(x0 + w + 6, y0 - (tip if extend in ("min", "both") else 0), lo_lab, ha="left", va="center", fontsize=6,
             color="#404040", transform=px)
    fig.text(x0 + w + 6, y0 + h + (tip if extend in ("max", "both") else 0), hi_lab, ha="left", va="center", fontsize=6,
             color="#404040", transform=px)
    fig.text(x0, y0 + h + tip + 14, label, ha="left", va="bottom", fontsize=6.5, transform=px)


def _north_arrow(fig, centre: tuple[float, float], north: np.ndarray, length: float = 44.0):
    """An arrow through ``centre`` [px] pointing along ``north`` (a vector of the picture), marked N."""
    from matplotlib.patches import FancyArrowPatch
    from matplotlib.transforms import IdentityTransform

    px = IdentityTransform()
    n = north / max(float(np.hypot(*north)), 1e-12)
    c = np.asarray(centre, dtype=float)
    fig.add_artist(FancyArrowPatch(tuple(c - 0.5 * length * n), tuple(c + 0.5 * length * n), arrowstyle="-|>", color="black",
                                   linewidth=1.2, mutation_scale=10, transform=px))
    tip = c + (0.5 * length + 9) * n
    fig.text(tip[0], tip[1], "N", ha="center", va="center", fontsize=8, fontweight="bold", transform=px)


# ----------------------------------------------------------------------------------------------
# Fisheye
# ----------------------------------------------------------------------------------------------

def fisheye_xy(azimuth_deg, altitude_deg, view_azimuth_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Equidistant fisheye coordinates of directions, looking horizontally at ``view_azimuth_deg``.

    The radius is proportional to the angle from the optical axis (1 at 90 deg, the rim of the
    180 deg field); x is to the right when looking out, y up (the zenith is at (0, 1)).
    Directions behind the viewer get radii above 1.

    Parameters
    ----------
    azimuth_deg : array_like [deg], clockwise from true north
    altitude_deg : array_like [deg], above the horizon
    view_azimuth_deg : float [deg], azimuth of the optical axis (the window's outward normal)

    Returns
    -------
    x, y : arrays of the broadcast shape, in [-1, 1] within the field
    """
    a = np.radians(np.asarray(azimuth_deg, dtype=float) - view_azimuth_deg)
    h = np.radians(np.asarray(altitude_deg, dtype=float))
    fwd = np.cos(h) * np.cos(a)
    right = np.cos(h) * np.sin(a)
    up = np.sin(h)
    side = np.hypot(right, up)
    rho = np.arctan2(side, fwd) / (0.5 * np.pi)  # angle off axis / 90 deg
    with np.errstate(invalid="ignore", divide="ignore"):
        x = np.where(side > 0, rho * right / side, np.where(fwd >= 0, 0.0, rho))  # straight behind: off the field
        y = np.where(side > 0, rho * up / side, 0.0)
    return x, y


def fisheye_pixel_xy(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Fisheye coordinates (x, y) of the pixel centres of an (n, n) raster, row 0 at the top.

    Returns
    -------
    x, y : (n, n) float, x[i, j] = (2 j + 1) / n - 1 and y[i, j] = 1 - (2 i + 1) / n
    """
    c = (2.0 * np.arange(n) + 1.0) / n - 1.0
    return np.broadcast_to(c[None, :], (n, n)), np.broadcast_to(-c[:, None], (n, n))


def fisheye_directions(n: int, view_azimuth_deg: float, true_north_deg: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors in the model frame through the pixel centres of an (n, n) equidistant fisheye.

    The inverse of :func:`fisheye_xy` on the raster of :func:`fisheye_pixel_xy`. A direction of
    azimuth A (clockwise from true north) and altitude h is the model-frame vector
    (sin(A + tn) cos h, cos(A + tn) cos h, sin h), tn = ``true_north_deg``, as
    :func:`en17037cli.criteria.sunlight.solar_position.direction_vectors` has it.

    Parameters
    ----------
    n : int, pixels per side
    view_azimuth_deg : float [deg], azimuth of the optical axis clockwise from true north
    true_north_deg : float [deg], azimuth of true north clockwise from model +Y

    Returns
    -------
    dirs : (n, n, 3) float, unit vectors; pixels outside the circle get the continuation of the
        projection (directions behind the viewer), to be ignored
    inside : (n, n) bool, pixel centre within the 180 deg circle (radius <= 1)
    """
    x, y = fisheye_pixel_xy(n)
    rho = np.hypot(x, y)
    theta = 0.5 * np.pi * rho
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(rho > 0, np.sin(theta) / rho, 0.5 * np.pi)
    fwd, right, up = np.cos(theta), s * x, s * y
    v = math.radians(view_azimuth_deg + true_north_deg)
    f = np.array([math.sin(v), math.cos(v), 0.0])
    r = np.array([math.cos(v), -math.sin(v), 0.0])
    # unit by construction: cos^2 + sin^2 (x^2 + y^2) / rho^2 = 1
    dirs = np.stack([fwd * f[0] + right * r[0], fwd * f[1] + right * r[1], up], axis=-1)
    return dirs, rho <= 1.0


def fisheye_pixel(x, y) -> tuple[np.ndarray, np.ndarray]:
    """Row and column of the PNG pixel of :func:`fisheye` that holds fisheye point (x, y).

    For tests and image maps: the circle is centred on :data:`FISHEYE_CENTRE_PX` with radius
    :data:`FISHEYE_RADIUS_PX`, and the class raster is placed on the PNG's pixel grid without
    resampling filters (nearest pixel).

    Returns
    -------
    row, col : int arrays, row 0 at the top of the image
    """
    c0, r0 = FISHEYE_CENTRE_PX
    col = c0 + np.asarray(x, dtype=float) * FISHEYE_RADIUS_PX
    row = r0 - np.asarray(y, dtype=float) * FISHEYE_RADIUS_PX
    return np.floor(row).astype(int), np.floor(col).astype(int)


def _fisheye_raster(image: np.ndarray) -> np.ndarray:
    """The class raster as (2R, 2R, 3) uint8 pixels of the PNG, nearest source pixel, white outside the circle."""
    n, m = image.shape[0], 2 * FISHEYE_RADIUS_PX
    src = np.minimum(((np.arange(m) + 0.5) * n / m).astype(int), n - 1)
    classes = np.clip(image[np.ix_(src, src)].astype(int), OUTSIDE, CLASS_GROUND)
    x, y = fisheye_pixel_xy(m)
    classes[np.hypot(x, y) > 1.0] = OUTSIDE
    lut = np.zeros((5, 3), dtype=np.uint8)
    for k, colour in CLASS_COLOURS.items():
        lut[k + 1] = np.round(_rgb([colour])[0] * 255).astype(np.uint8)
    return lut[classes + 1]


_COMPASS = (("N", 0), ("NE", 45), ("E", 90), ("SE", 135), ("S", 180), ("SW", 225), ("W", 270), ("NW", 315))


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Half-open index ranges [a, b) of the runs of True in ``mask``."""
    m = np.concatenate([[False], mask, [False]]).astype(np.int8)
    d = np.diff(m)
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1)))


def _nan_joined(xs: np.ndarray, ys: np.ndarray, runs: list[tuple[int, int]]) -> tuple[np.ndarray, np.ndarray]:
    """One polyline per run, joined with NaN breaks (one Line2D for many pieces)."""
    px: list[np.ndarray] = []
    py: list[np.ndarray] = []
    for a, b in runs:
        px += [xs[a:b], np.array([np.nan])]
        py += [ys[a:b], np.array([np.nan])]
    return (np.concatenate(px), np.concatenate(py)) if px else (np.zeros(0), np.zeros(0))


def fisheye(image, *, sun_paths: Sequence[dict], min_altitude_deg: float, view_azimuth_deg: float, title: str = "") -> bytes:
    """What a person at point P sees through the window: an equidistant fisheye with the sun's paths.

    The optical axis is horizontal at ``view_azimuth_deg`` (the window's outward normal), the field
    180 deg, the zenith up. The class raster is drawn with :data:`CLASS_COLOURS`; each sun path is
    projected the same way where the sun is above the horizon and in the field, solid and thick
    where it is seen from P, thin and dashed where it is hidden, with its hour marks; the curve of
    the minimum sun altitude is dashed; the compass points are marked on the horizon.

    Parameters
    ----------
    image : (N, N) int8, classes traced by the caller on :func:`fisheye_directions` (N,
        view_azimuth_deg): -1 outside the circle, 0 blocked or interior, 1 sky, 2 landscape,
        3 ground; row 0 at the top
    sun_paths : sequence of dict
        ``{"label": str, "azimuth_deg": (t,) float [deg], "altitude_deg": (t,) float [deg],
        "visible": (t,) bool, "hour_marks": [(azimuth_deg, altitude_deg, "10:00"), ...]}``
    min_altitude_deg : float [deg], the lowest sun altitude that counts (clause 5.3)
    view_azimuth_deg : float [deg], clockwise from true north
    title : str

    Returns
    -------
    bytes, a PNG image of :data:`FISHEYE_SIZE_IN` at :data:`DPI`
    """
    img = np.asarray(image)
    if img.ndim != 2 or img.shape[0] != img.shape[1]:
        raise ValueError(f"image must have shape (N, N), not {img.shape}")
    raster = _fisheye_raster(img)
    R = float(FISHEYE_RADIUS_PX)
    height_px = FISHEYE_SIZE_IN[1] * DPI
    cx, cy = float(FISHEYE_CENTRE_PX[0]), height_px - FISHEYE_CENTRE_PX[1]  # display coordinates, y up
    pt = DPI / 72.0  # [px/pt]
    boxed = {"boxstyle": "round,pad=0.1", "facecolor": "white", "edgecolor": "none", "alpha": 0.7}

    def draw(fig):
        from matplotlib.lines import Line2D
        from matplotlib.patches import Circle
        from matplotlib.transforms import Affine2D, IdentityTransform

        px = IdentityTransform()
        T = Affine2D().scale(R).translate(cx, cy)
        line = lambda x, y, **kw: fig.add_artist(Line2D(x, y, transform=T, **kw))
        text = lambda x, y, s, dy=0.0, **kw: fig.text(cx + R * x, cy + R * y + dy * pt, s, transform=px, **kw)
        fig.figimage(raster, xo=int(cx - R), yo=int(cy - R), origin="upper")
        fig.add_artist(Circle((0, 0), 1.0, fill=False, edgecolor="black", linewidth=1.0, transform=T))
        line([-1, 1], [0, 0], color="black", linewidth=0.5, alpha=0.6)  # horizon
        # minimum sun altitude: the curve altitude = const within the field
        az = view_azimuth_deg + np.linspace(-90.0, 90.0, 181)
        mx, my = fisheye_xy(az, np.full_like(az, min_altitude_deg), view_azimuth_deg)
        line(mx, my, color="black", linewidth=1.8)
        line(mx, my, color="white", linewidth=0.9, linestyle=(0, (3, 2)))
        marks: dict[str, list] = {}
        for p in sun_paths:
            a = np.asarray(p["azimuth_deg"], dtype=float).reshape(-1)
            h = np.asarray(p["altitude_deg"], dtype=float).reshape(-1)
            vis = np.asarray(p["visible"], dtype=bool).reshape(-1)
            x, y = fisheye_xy(a, h, view_azimuth_deg)
            ok = (h >= 0) & (np.hypot(x, y) <= 1.0)
            if not ok.any():
                continue
            # a segment i..i+1 is drawn when both ends are in the field; seen where both are seen
            seg_ok = ok[:-1] & ok[1:]
            seg_vis = seg_ok & vis[:-1] & vis[1:]
            for seen, lw, casing, ls in ((False, 0.9, 1.8, (0, (3, 2))), (True, 2.2, 3.6, "-")):
                runs = [(s0, e + 1) for s0, e in _runs(seg_vis if seen else seg_ok & ~seg_vis)]
                if runs:
                    jx, jy = _nan_joined(x, y, runs)
                    line(jx, jy, color="black", linewidth=casing, linestyle=ls, solid_capstyle="butt")
                    line(jx, jy, color=SUN_PATH_COLOUR, linewidth=lw, linestyle=ls, solid_capstyle="butt")
            top = int(np.argmax(np.where(ok, y, -np.inf)))
            if p.get("label"):
                    text(x[top], y[top], str(p["label"]), dy=4, ha="center", va="bottom", fontsize=6.5,
                     bbox=boxed | {"boxstyle": "round,pad=0.15"})
            for ma, mh, lab in p.get("hour_marks", ()):
                hx, hy = fisheye_xy(ma, mh, view_azimuth_deg)
                if mh >= 0 and float(np.hypot(hx, hy)) <= 1.0:
                    marks.setdefault(str(lab), []).append((float(hx), float(hy)))
        # hour marks: a dot on each path, the same hour joined across the dates, labelled once below
        for lab, xy in marks.items():
            xy_a = np.array(xy)
            if len(xy_a) > 1:
                line(xy_a[:, 0], xy_a[:, 1], color="black", linewidth=0.5)
            line(xy_a[:, 0], xy_a[:, 1], linestyle="none", marker="o", markersize=2.8, color="black", markeredgecolor="white",
                 markeredgewidth=0.5)
            low = xy_a[int(np.argmin(xy_a[:, 1]))]
            text(low[0], low[1], lab, dy=-4, ha="center", va="top", fontsize=5.5, bbox=boxed)
        # compass points on the horizon (at the rim where they fall on it)
        for name, c in _COMPASS:
            d = (c - view_azimuth_deg + 180.0) % 360.0 - 180.0
            if abs(d) <= 90.0:
                x = d / 90.0
                line([x, x], [-0.03, 0.03], color="black", linewidth=0.8)
                if abs(d) >= 85.0:
                    text(math.copysign(1.06, d), 0.0, name, ha="center", va="center", fontsize=7, fontweight="bold")
                else:
                    text(x, -0.05, name, ha="center", va="top", fontsize=7, fontweight="bold", bbox=boxed)
        text(0.0, 1.0, "zenith", dy=3, ha="center", va="bottom", fontsize=6.5)
        if title:
            fig.text(12, height_px - 6, title, ha="left", va="top", fontsize=9, transform=px)
        entries = [("patch", CLASS_COLOURS[k], CLASS_NAMES[k]) for k in (CLASS_SKY, CLASS_LANDSCAPE, CLASS_GROUND, BLOCKED)]
        entries += [
            ("line", [{"color": "black", "linewidth": 3.6}, {"color": SUN_PATH_COLOUR, "linewidth": 2.2}], "sun path, seen"),
            ("line", [{"color": "black", "linewidth": 1.8, "linestyle": (0, (3, 2))},
                      {"color": SUN_PATH_COLOUR, "linewidth": 0.9, "linestyle": (0, (3, 2))}], "sun path, hidden"),
            ("line", [{"color": "black", "linewidth": 1.8}, {"color": "white", "linewidth": 0.9, "linestyle": (0, (3, 2))}],
             f"sun altitude {_fmt_num(min_altitude_deg)}°"),
        ]
        _legend(fig, cx + R + 30, cy + R, entries,
                title=f"looking {_compass_name(view_azimuth_deg)} ({_fmt_num(round(view_azimuth_deg % 360.0, 1))}°)")

    return _render(draw, FISHEYE_SIZE_IN)


def _compass_name(azimuth_deg: float) -> str:
    """The nearest of the 8 compass points."""
    return _COMPASS[int(math.floor((azimuth_deg % 360.0) / 45.0 + 0.5)) % 8][0]


# ----------------------------------------------------------------------------------------------
# Charts
# ----------------------------------------------------------------------------------------------

def _date_label(d) -> str:
    """``"1 Feb"`` whatever the locale."""
    return f"{d.day} {_MONTHS[d.month - 1]}"


def hours_chart(dates, hours, *, thresholds: dict, assessed_index: int, per_window: dict | None = None, title: str = "") -> bytes:
    """Sun hours per day over the assessment period, with the level thresholds and the assessed day.

    Parameters
    ----------
    dates : sequence of datetime.date, (d,)
    hours : (d,) float [h], the room's hours of sunlight each day
    thresholds : dict {"minimum", "medium", "high"} [h]
    assessed_index : int, position of the assessed day in ``dates`` (its bar is dark and hatched)
    per_window : dict name -> (d,) float [h], optional; each window's hours as thin lines
    title : str

    Returns
    -------
    bytes, a PNG image of :data:`CHART_SIZE_IN` at :data:`DPI`
    """
    hrs = np.asarray(hours, dtype=float).reshape(-1)
    dates = list(dates)
    if len(dates) != len(hrs):
        raise ValueError(f"hours must have shape ({len(dates)},) like dates, not {hrs.shape}")
    d = len(hrs)
    k = int(assessed_index)

    def draw(fig):
        from matplotlib.collections import PolyCollection
        from matplotlib.patches import Rectangle
        from matplotlib.ticker import FixedLocator, FuncFormatter, MultipleLocator

        ax = fig.add_axes((0.1, 0.12, 0.72, 0.72))
        x = np.arange(d)
        top = np.nan_to_num(hrs)
        others = np.flatnonzero(x != k)
        # one collection for the bars (one Rectangle each costs more than the drawing)
        ax.add_collection(PolyCollection([[(i - 0.4, 0), (i + 0.4, 0), (i + 0.4, top[i]), (i - 0.4, top[i])] for i in others],
                                         facecolors=BAR_COLOUR, edgecolors="none"))
        if 0 <= k < d:
            ax.add_patch(Rectangle((k - 0.4, 0), 0.8, top[k], facecolor=ASSESSED_COLOUR, edgecolor="white", linewidth=0, hatch="////"))
            ax.annotate(f"assessed {_date_label(dates[k])}\n{fmt_duration(hrs[k])}", (k, float(np.nan_to_num(hrs[k]))),
                        xytext=(0, 4), textcoords="offset points", ha="center", va="bottom", fontsize=6.5,
                        bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none", "alpha": 0.8})
        ymax = max([float(np.nanmax(hrs)) if np.isfinite(hrs).any() else 0.0] + [float(v) for v in thresholds.values()])
        if per_window:
            for i, (name, v) in enumerate(per_window.items()):
                w = np.asarray(v, dtype=float).reshape(-1)
                ax.plot(x, w, color="black", linewidth=0.8, linestyle=("-", (0, (3, 1.5)), (0, (1, 1.5)), (0, (5, 1.5, 1, 1.5)))[i % 4],
                        label=f"window {name}")
                if np.isfinite(w).any():
                    ymax = max(ymax, float(np.nanmax(w)))
        for name, ls in (("minimum", (0, (1, 1.5))), ("medium", (0, (4, 2))), ("high", "-")):
            v = float(thresholds[name])
            ax.axhline(v, color="black", linewidth=0.9, linestyle=ls)
            ax.text(1.01, v, f"{name}\n{fmt_duration(v)}", transform=ax.get_yaxis_transform(), ha="left", va="center", fontsize=6.5)
        ax.set_xlim(-0.7, max(d, 1) - 0.3)
        ax.set_ylim(0, 1.18 * ymax if ymax > 0 else 1.0)
        step = 0.5 if ymax <= 3 else (1.0 if ymax <= 8 else 2.0)
        ax.yaxis.set_major_locator(MultipleLocator(step))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: _hm(v)))
        ax.set_ylabel("sunlight [h:mm]")
        ticks = [i for i in range(d) if i % 7 == 0]
        ax.xaxis.set_major_locator(FixedLocator(ticks))
        ax.set_xticklabels([_date_label(dates[i]) for i in ticks])
        ax.spines[["top", "right"]].set_visible(False)
        if per_window:
            fig.legend(loc="upper right", bbox_to_anchor=(0.82, 0.93), fontsize=6.5, ncols=min(len(per_window), 4))
        if title:
            fig.text(0.02, 0.985, title, ha="left", va="top", fontsize=9)

    return _render(draw, CHART_SIZE_IN)


def tornado(rows: Sequence[tuple[str, float, float, float]], *, title: str = "") -> bytes:
    """Sensitivity of a score to each modelling choice: bars from the low to the high result.

    Parameters
    ----------
    rows : sequence of (label, low, high, default), scores in [0, 3] (a continuous level:
        0 none, 1 minimum, 2 medium, 3 high)
    title : str

    Returns
    -------
    bytes, a PNG image at :data:`DPI`, 5 in wide, 4 in high up to 10 rows and 0.3 in more per row
    """
    items = [(str(lab), float(lo), float(hi), float(de)) for lab, lo, hi, de in rows]
    items.sort(key=lambda r: (abs(r[2] - r[1]), r[0]))  # largest span at the top
    n = len(items)
    height = 4.0 if n <= 10 else 4.0 + 0.3 * (n - 10)

    def draw(fig):
        ax = fig.add_axes((0.36, 0.12 * 4.0 / height, 0.58, 1.0 - 0.22 * 4.0 / height))
        y = np.arange(n)
        for i, (_, lo, hi, de) in enumerate(items):
            ax.barh(i, lo - de, left=de, height=0.6, color="#31688e", edgecolor="black", linewidth=0.4)
            ax.barh(i, hi - de, left=de, height=0.6, color="#fde725", edgecolor="black", linewidth=0.4)
            ax.plot([de, de], [i - 0.4, i + 0.4], color="black", linewidth=1.2)
        vals = [v for r in items for v in r[1:]]
        lo_x = min([0.0] + vals)
        hi_x = max([3.0] + vals)
        ax.set_xlim(lo_x - 0.05, hi_x + 0.05)
        ax.set_ylim(-0.7, max(n, 1) - 0.3)
        ax.set_yticks(y, labels=[r[0] for r in items])
        ax.set_xticks([0, 1, 2, 3], labels=["none", "minimum", "medium", "high"])
        for v in (1, 2, 3):
            ax.axvline(v, color="#808080", linewidth=0.6, linestyle=(0, (2, 2)), zorder=0)
        ax.set_xlabel("score (level, continuous)")
        ax.spines[["top", "right"]].set_visible(False)
        from matplotlib.patches import Patch

        fig.legend(handles=[Patch(facecolor="#31688e", edgecolor="black", linewidth=0.4, label="low choice"),
                            Patch(facecolor="#fde725", edgecolor="black", linewidth=0.4, label="high choice")],
                   loc="upper right", bbox_to_anchor=(0.99, 0.995), ncols=2, fontsize=6.5)
        if title:
            fig.text(0.02, 0.99, title, ha="left", va="top", fontsize=9)

    return _render(draw, (5.0, height))
