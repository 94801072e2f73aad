"""The fisheye from point P: what a person sees through the window, with the sun's paths.

An equidistant projection looking horizontally out of the window: :func:`fisheye_xy` maps
directions to the picture, :func:`fisheye_directions` maps the picture's pixels back to the
directions the caller traces, and :func:`fisheye` draws the traced classes with the sun paths.
"""
from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np

from en17037cli.geometry.fisheye import fisheye_directions, fisheye_pixel_xy, fisheye_xy
from en17037cli.report.pictures import colours
from en17037cli.report.pictures.canvas import DPI, Canvas, _fmt_num
from en17037cli.report.pictures.parts import legend
from en17037cli.report.pictures.raster import render

__all__ = ["fisheye", "fisheye_directions", "fisheye_pixel", "fisheye_pixel_xy", "fisheye_xy"]

#: Figure size [in] (width, height).
FISHEYE_SIZE_IN = (5.0, 3.6)
#: Fisheye: centre of the 180 deg circle [px] (column, row from the top of the PNG) and its radius [px].
FISHEYE_CENTRE_PX = (160, 185)
FISHEYE_RADIUS_PX = 140
#: A sun path whose top lies farther than this from the vertical through the centre (in units of
#: the radius) is labelled inwards from its top [-] ...
LABEL_INWARD = 0.3
#: ... and a path label closer than this to one already drawn, across, goes under it [px].
LABEL_CLEAR_PX = 110
#: Hour labels closer than this to one already drawn are left out [px] (at 8 pt printed at PRINT_SCALE,
#: "07:00" is 51 px wide).
HOUR_LABEL_GAP_PX = 56


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


@functools.lru_cache(maxsize=8)
def _resampling(n: int, m: int) -> tuple[np.ndarray, np.ndarray]:
    """The source row (and column) of each of ``m`` picture pixels from an (n, n) raster, and the
    (m, m) pixels outside the circle."""
    src = np.minimum(((np.arange(m) + 0.5) * n / m).astype(int), n - 1)
    x, y = fisheye_pixel_xy(m)
    return src, np.hypot(x, y) > 1.0


def _fisheye_raster(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The class raster as (2R, 2R) indices of the PNG's pixels (the class + 1, nearest source
    pixel, 0 outside the circle) and their palette (5, 3) uint8, :data:`~.colours.CLASS_COLOURS`."""
    src, outside = _resampling(image.shape[0], 2 * FISHEYE_RADIUS_PX)
    index = (np.clip(image.astype(np.int8)[src][:, src], colours.OUTSIDE, colours.CLASS_GROUND) + 1).astype(np.uint8)
    index[outside] = colours.OUTSIDE + 1
    palette = np.zeros((5, 3), dtype=np.uint8)
    for k, colour in colours.CLASS_COLOURS.items():
        palette[k + 1] = np.round(colours._rgb([colour])[0] * 255).astype(np.uint8)
    return index, palette


_COMPASS = (("N", 0), ("NE", 45), ("E", 90), ("SE", 135), ("S", 180), ("SW", 225), ("W", 270), ("NW", 315))


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Half-open index ranges [a, b) of the runs of True in ``mask``."""
    m = np.concatenate([[False], mask, [False]]).astype(np.int8)
    d = np.diff(m)
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1)))


def _nan_joined(xs: np.ndarray, ys: np.ndarray, runs: list[tuple[int, int]]) -> tuple[np.ndarray, np.ndarray]:
    """One polyline per run, joined with NaN breaks (one path of many pieces)."""
    px: list[np.ndarray] = []
    py: list[np.ndarray] = []
    for a, b in runs:
        px += [xs[a:b], np.array([np.nan])]
        py += [ys[a:b], np.array([np.nan])]
    return (np.concatenate(px), np.concatenate(py)) if px else (np.zeros(0), np.zeros(0))


def fisheye(image, *, sun_paths: Sequence[dict], min_altitude_deg: float, view_azimuth_deg: float, title: str = "",
            fmt: str = "png"):
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
    title : str, not drawn: the reports caption the picture
    fmt : "png", "svg" or "both"

    Returns
    -------
    bytes, a PNG image of :data:`FISHEYE_SIZE_IN` at :data:`DPI`
    """
    img = np.asarray(image)
    if img.ndim != 2 or img.shape[0] != img.shape[1]:
        raise ValueError(f"image must have shape (N, N), not {img.shape}")
    raster, palette = _fisheye_raster(img)
    R = float(FISHEYE_RADIUS_PX)
    height_px = FISHEYE_SIZE_IN[1] * DPI
    cx, cy = float(FISHEYE_CENTRE_PX[0]), height_px - FISHEYE_CENTRE_PX[1]  # layout px, y up
    pt = DPI / 72.0  # the offsets' unit [px]
    c = Canvas(int(FISHEYE_SIZE_IN[0] * 100), int(height_px))
    to_px = lambda x, y: np.column_stack([cx + R * np.asarray(x, dtype=float), cy + R * np.asarray(y, dtype=float)])  # noqa: E731
    line = lambda x, y, **kw: c.path(to_px(x, y), **kw)  # noqa: E731

    def text(x, y, s, dy=0.0, box=None, **kw):
        c.text(cx + R * x, cy + R * y + dy * pt, s, box=None if box is None else ("white", 0.7, box), **kw)

    c.image(raster, (int(cx - R), int(cy - R), raster.shape[1], raster.shape[0]), palette=palette)
    ring = np.linspace(0.0, 2.0 * math.pi, 121)  # 7 px chords: 0.05 px off the circle
    line(np.cos(ring), np.sin(ring), stroke="black", lw=1.0, closed=True)
    line([-1, 1], [0, 0], stroke="black", lw=0.5, alpha=0.6)  # horizon
    # minimum sun altitude: the curve altitude = const within the field
    az = view_azimuth_deg + np.linspace(-90.0, 90.0, 181)
    mx, my = fisheye_xy(az, np.full_like(az, min_altitude_deg), view_azimuth_deg)
    line(mx, my, stroke="black", lw=1.8)
    line(mx, my, stroke="white", lw=0.9, dash=(3, 2))
    marks: dict[str, list] = {}
    hour_marks: list = []
    placed: list[tuple[float, float]] = []  # the path labels drawn: (x [-1, 1], y [px] above the centre)
    for p in sun_paths:  # one per day drawn
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
        for seen, lw, casing, ls in ((False, 0.9, 1.8, (3, 2)), (True, 2.2, 3.6, None)):
            runs = [(s0, e + 1) for s0, e in _runs(seg_vis if seen else seg_ok & ~seg_vis)]
            if runs:
                jx, jy = _nan_joined(x, y, runs)
                line(jx, jy, stroke="black", lw=casing, dash=ls)
                line(jx, jy, stroke=colours.SUN_PATH_COLOUR, lw=lw, dash=ls)
        top = int(np.argmax(np.where(ok, y, -np.inf)))
        if p.get("label"):
            # a path whose top is at the rim (a window facing east or west) is labelled inwards, not
            # over the picture's edge; a label on one already drawn goes under it
            ha = "left" if x[top] < -LABEL_INWARD else "right" if x[top] > LABEL_INWARD else "center"
            dy = 4.0
            while any(abs(x[top] - ox) * R < LABEL_CLEAR_PX and abs(y[top] * R + dy * pt - oy) < 11 * pt for ox, oy in placed):
                dy -= 11.0
            placed.append((float(x[top]), float(y[top] * R + dy * pt)))
            text(x[top], y[top], str(p["label"]), dy=dy, ha=ha, va="bottom", box=0.15)
        hour_marks += list(p.get("hour_marks", ()))
    if hour_marks:  # each hour's dots by its label, those above the horizon and in the field
        ma, mh = np.array([[float(m[0]), float(m[1])] for m in hour_marks]).T
        hx, hy = fisheye_xy(ma, mh, view_azimuth_deg)
        for (_, _, lab), x_, y_, ok_ in zip(hour_marks, hx.tolist(), hy.tolist(), ((mh >= 0) & (np.hypot(hx, hy) <= 1.0)).tolist()):
            if ok_:
                marks.setdefault(str(lab), []).append((x_, y_))
    # hour marks: a dot on each path, the same hour joined across the dates, labelled once below; a
    # label that would touch the previous one kept is left out (at 8 pt an hour's label is wider
    # than the hour's step near the horizon)
    kept: list = []
    dots = []
    for lab, xy in marks.items():  # one per hour
        xy_a = np.array(xy)
        if len(xy_a) > 1:
            line(xy_a[:, 0], xy_a[:, 1], stroke="black", lw=0.5)
        dots.append(xy_a)
        low = xy_a[int(np.argmin(xy_a[:, 1]))]
        if all(abs(R * (low[0] - k[0])) > HOUR_LABEL_GAP_PX or abs(R * (low[1] - k[1])) > 14 for k in kept):
            text(low[0], low[1], lab, dy=-4, ha="center", va="top", box=0.1)
            kept.append(low)
    # compass points on the horizon (at the rim where they fall on it)
    for name, cmp in _COMPASS:
        d = (cmp - view_azimuth_deg + 180.0) % 360.0 - 180.0
        if abs(d) <= 90.0:
            x = d / 90.0
            line([x, x], [-0.03, 0.03], stroke="black", lw=0.8)
            if abs(d) >= 85.0:
                text(math.copysign(1.07, d), 0.0, name, ha="center", va="center", bold=True)
            else:
                text(x, -0.05, name, ha="center", va="top", bold=True, box=0.1)
    text(0.0, 1.0, "zenith", dy=3, ha="center", va="bottom")
    legend_order = (colours.CLASS_SKY, colours.CLASS_LANDSCAPE, colours.CLASS_GROUND, colours.BLOCKED)
    entries = [("patch", colours.CLASS_COLOURS[k], colours.CLASS_NAMES[k]) for k in legend_order]
    entries += [
        ("line", [{"stroke": "black", "lw": 3.6}, {"stroke": colours.SUN_PATH_COLOUR, "lw": 2.2}], "sun path, seen"),
        ("line", [{"stroke": "black", "lw": 1.8, "dash": (3, 2)}, {"stroke": colours.SUN_PATH_COLOUR, "lw": 0.9, "dash": (3, 2)}],
         "sun path, hidden"),
        ("line", [{"stroke": "black", "lw": 1.8}, {"stroke": "white", "lw": 0.9, "dash": (3, 2)}],
         f"sun altitude {_fmt_num(min_altitude_deg)}°"),
    ]
    legend(c, cx + R + 22, cy + R, entries, title=f"facing {_compass_name(view_azimuth_deg)} {_fmt_num(round(view_azimuth_deg % 360.0))}°")
    if dots:  # the hour marks' dots over every line
        dot = np.vstack(dots)
        c.markers(to_px(dot[:, 0], dot[:, 1]), 2.8, fill="black", stroke="white", lw=0.5)
    return render(c, fmt)


def _compass_name(azimuth_deg: float) -> str:
    """The nearest of the 8 compass points."""
    return _COMPASS[int(math.floor((azimuth_deg % 360.0) / 45.0 + 0.5)) % 8][0]
