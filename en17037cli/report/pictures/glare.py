"""The pictures of clause 5.4: the map of a room's critical positions, the DGP of every usage hour
(a carpet: days across, clock hours up), and a fisheye's luminance (point-in-time checks)."""
from __future__ import annotations

import math

import numpy as np

from en17037cli.report.pictures.canvas import MIN_FONT_PT, Canvas, _scale_bar_m
from en17037cli.report.pictures.colourmaps import lookup
from en17037cli.report.pictures.colours import LEVEL_COLOURS, LEVEL_NAMES, WINDOW_COLOUR, _rgb
from en17037cli.report.pictures.parts import arrow, legend, north_arrow, scale_bar
from en17037cli.report.pictures.plan import PLAN_BOX_PX, PLAN_SIZE_IN, _rot, plan_rotation
from en17037cli.report.pictures.raster import render

#: The DGP classes of the carpet, low to high: below high's limit, then each limit to the next (the
#: level a view keeps if the hour were its 5 % hour), above minimum's; light to dark.
DGP_CLASS_COLOURS = ("#fde725", "#35b779", "#31688e", "#440154")
#: Layout size of the carpet [in / 100 px].
CARPET_SIZE_IN = (5.0, 3.2)
#: Layout size of a fisheye [in / 100 px].
LUMINANCE_SIZE_IN = (4.2, 3.6)


def positions_map(floor, windows, eyes_xy, directions_xy, levels, labels, *, true_north_deg: float, title: str = "",
                  fmt: str = "png"):
    """A room's plan with its critical positions: each eye a dot, each view direction an arrow
    coloured by the level the view reaches, numbered as the report's table lists them.

    Parameters
    ----------
    floor : (k, 2) [m], ring of the floor outline; windows : sequence of (2, 2) [m] plan traces
    eyes_xy : (n, 2) [m] the eye of each view (model frame); directions_xy : (n, 2) unit vectors
    levels : (n,) int 0..3 per view; labels : (n,) str drawn at the arrows' tips
    true_north_deg : azimuth of true north clockwise from model +Y [deg]
    """
    floor_r = np.asarray(floor, dtype=float).reshape(-1, 2)
    win = [np.asarray(w, dtype=float).reshape(2, 2) for w in (windows or ())]
    r = _rot(plan_rotation(floor_r, win))
    centre = floor_r.mean(axis=0)
    tf = lambda p: np.round((np.asarray(p, dtype=float).reshape(-1, 2) - centre) @ r.T, 9)  # noqa: E731
    floor_t, win_t = tf(floor_r), [tf(w) for w in win]
    eyes_t = tf(eyes_xy)
    dirs_t = np.asarray(directions_xy, dtype=float).reshape(-1, 2) @ r.T
    north = r @ np.array([math.sin(math.radians(true_north_deg)), math.cos(math.radians(true_north_deg))])
    lo, hi = floor_t.min(axis=0), floor_t.max(axis=0)
    size = max(float((hi - lo).max()), 1e-6)
    arrow_m = 0.18 * size
    (bx0, by0), (bw, bh) = PLAN_BOX_PX[:2], PLAN_BOX_PX[2:]
    scale = min(bw / max(float(hi[0] - lo[0]), 1e-9), (bh - 30.0) / max(float(hi[1] - lo[1]), 1e-9))
    mid = 0.5 * (lo + hi)
    ox, oy = bx0 + bw / 2, by0 + bh / 2 + 15.0
    lv = np.asarray(levels, dtype=int)

    c = Canvas(int(PLAN_SIZE_IN[0] * 100), int(PLAN_SIZE_IN[1] * 100))
    to_px = lambda p: (np.asarray(p, dtype=float).reshape(-1, 2) - mid) * scale + (ox, oy)  # noqa: E731 - metres -> layout px
    c.path(to_px(floor_t), stroke="black", lw=1.2, closed=True)
    for w in win_t:  # one per window
        for colour, lw in (("black", 5.0), (WINDOW_COLOUR, 3.0)):
            c.path(to_px(w), stroke=colour, lw=lw)
    for k, (e, d) in enumerate(zip(eyes_t, dirs_t)):  # a few views per room
        tail, tip = to_px(e)[0], to_px(e + arrow_m * d)[0]
        arrow(c, tail, tip, lw=2.6, head=9)
        arrow(c, tail, tip, colour=LEVEL_COLOURS[int(np.clip(lv[k], 0, 3))], lw=1.4, head=7)
        lab = to_px(e + (arrow_m + 0.06 * size) * d)[0]
        c.text(lab[0], lab[1], labels[k], ha="center", va="center")
    sb = _scale_bar_m(float(hi[0] - lo[0]))
    scale_bar(c, round(ox + (lo[0] - mid[0]) * scale), round(oy - 0.5 * (hi[1] - lo[1]) * scale - 22.0), round(sb * scale), sb)
    north_arrow(c, (462.0, 320.0), north)
    legend(c, 232.0, 268.0, [("patch", LEVEL_COLOURS[i], LEVEL_NAMES[i]) for i in reversed(range(4))], title="level of the view")
    if len(eyes_t):
        c.markers(to_px(eyes_t), 4, fill="black", stroke="black", lw=1.0)
    return render(c, fmt)


def dgp_classes(dgp, limits: dict) -> np.ndarray:
    """Class of each DGP for the carpet: 0 at or below high's limit, 1 medium's, 2 minimum's, 3 above."""
    v = np.asarray(dgp, dtype=float)
    return (v > limits["high"]).astype(int) + (v > limits["medium"]) + (v > limits["minimum"])


def dgp_carpet(local_times, dgp, *, limits: dict, title: str = "", fmt: str = "png"):
    """The DGP of every usage hour of a view: one column per usage day (days without usage hours
    left out), one row per clock hour (up), each cell coloured by the level limit its DGP stays
    under (see :data:`DGP_CLASS_COLOURS`), with the hours of each class counted in the legend.

    Parameters
    ----------
    local_times : (h,) datetime64[m], each usage hour's start on the local clock
    dgp : (h,) DGP of each hour
    limits : {"minimum", "medium", "high"} the DGP limits
    """
    t = np.asarray(local_times, dtype="datetime64[m]")
    day = t.astype("datetime64[D]")
    days, col = np.unique(day, return_inverse=True)
    hour = ((t - day).astype(int) // 60).astype(int)
    h0, h1 = (int(hour.min()), int(hour.max()) + 1) if len(hour) else (8, 18)
    ndays = max(len(days), 1)
    cls = dgp_classes(dgp, limits)
    rgb = np.full((h1 - h0, ndays, 3), 255, dtype=np.uint8)
    table = np.round(_rgb(DGP_CLASS_COLOURS) * 255).astype(np.uint8)
    rgb[h1 - 1 - hour, col] = table[cls]  # row 0 is the latest hour (the top)
    counts = np.bincount(cls, minlength=4)
    lab = [f"≤ {limits['high']:g}", f"{limits['high']:g} to {limits['medium']:g}", f"{limits['medium']:g} to {limits['minimum']:g}",
           f"> {limits['minimum']:g}"]
    months = days.astype("datetime64[M]")
    firsts = np.flatnonzero(np.concatenate([[True], months[1:] != months[:-1]])) if len(days) else np.zeros(0, int)
    box = (52.0, 96.0, 430.0, 200.0)

    c = Canvas(int(CARPET_SIZE_IN[0] * 100), int(CARPET_SIZE_IN[1] * 100))
    c.image(rgb, (int(box[0]), int(box[1]), int(box[2]), int(box[3])))
    c.rect(*box, stroke="black", lw=0.6)
    step = max(1, (h1 - h0) // 5)
    for hh in range(h0, h1 + 1, step):  # a few clock hours
        c.text(box[0] - 4, box[1] + (hh - h0) / (h1 - h0) * box[3], f"{hh:02d}:00", ha="right", va="center")
    for k, i in enumerate(firsts):  # the month of each first usage day, every other month named
        x = box[0] + i / ndays * box[2]
        c.path(np.array([[x, box[1] - 4], [x, box[1]]]), stroke="black", lw=0.6)
        if k % 2 == 0:
            c.text(x, box[1] - 6, _MONTHS[int(str(months[i])[5:7]) - 1], ha="left", va="top")
    c.text(box[0], box[1] - 22, f"usage days of {str(days[0])[:4] if len(days) else ''} across, clock time up", ha="left", va="top")
    entries = [("patch", DGP_CLASS_COLOURS[i], f"DGP {lab[i]}: {counts[i]} h") for i in range(4)]
    legend(c, box[0], 46.0, entries[:2])
    legend(c, box[0] + 215.0, 46.0, entries[2:])
    return render(c, fmt)


_MONTHS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")


def luminance_fisheye(luminance, *, title: str = "", fmt: str = "png"):
    """A 180 deg fisheye's luminance in false colour on a log scale (10 to 10⁶ cd/m², viridis), with
    its colour bar: what the occupant sees at a point-in-time check.

    Parameters
    ----------
    luminance : (rows, cols) [cd/m²], top row first (angular fisheye, -vta)
    """
    lum = np.asarray(luminance, dtype=float)
    t = (np.log10(np.clip(lum, 10.0, 1e6)) - 1.0) / 5.0
    rgb = lookup("viridis", t)
    ny, nx = lum.shape
    yy, xx = np.mgrid[0:ny, 0:nx]
    outside = np.hypot((xx + 0.5) / nx * 2 - 1, (yy + 0.5) / ny * 2 - 1) > 1
    rgb[outside] = 255
    bar = lookup("viridis", (np.arange(200)[::-1] + 0.5) / 200)
    c = Canvas(int(LUMINANCE_SIZE_IN[0] * 100), int(LUMINANCE_SIZE_IN[1] * 100))
    c.image(rgb, (10, 20, 320, 320))
    c.image(bar[:, None, :], (350, 60, 14, 240))
    for k in range(6):
        c.text(370.0, 60.0 + k * 48.0, f"10{'⁰¹²³⁴⁵⁶'[k + 1]}", ha="left", va="center", size=MIN_FONT_PT)
    c.text(350.0, 310.0, "cd/m²", ha="left", va="bottom")
    return render(c, fmt)
