"""The pictures of clause 5.4: the map of a room's critical positions, the DGP of every usage hour
(a carpet: days across, clock hours up), and a fisheye's luminance (point-in-time checks)."""
from __future__ import annotations

import math

import numpy as np

from en17037cli.report.pictures.colours import LEVEL_COLOURS, LEVEL_NAMES, WINDOW_COLOUR, _rgb
from en17037cli.report.pictures.mpl import (
    MIN_FONT_PT,
    _legend,
    _north_arrow,
    _render,
    _scale_bar,
    _scale_bar_m,
    image_at,
    layout_px,
)
from en17037cli.report.pictures.plan import PLAN_BOX_PX, PLAN_SIZE_IN, _rot, plan_rotation

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

    def draw(fig):
        from matplotlib.lines import Line2D
        from matplotlib.patches import FancyArrowPatch, Polygon
        from matplotlib.transforms import Affine2D

        T = Affine2D().translate(-mid[0], -mid[1]).scale(scale).translate(ox, oy) + layout_px(fig)
        fig.add_artist(Polygon(floor_t, closed=True, fill=False, edgecolor="black", linewidth=1.2, transform=T))
        for w in win_t:
            for colour, lw in (("black", 5.0), (WINDOW_COLOUR, 3.0)):
                fig.add_artist(Line2D(w[:, 0], w[:, 1], color=colour, linewidth=lw, solid_capstyle="butt", transform=T))
        for k, (e, d) in enumerate(zip(eyes_t, dirs_t)):  # a few views per room
            tip = e + arrow_m * d
            fig.add_artist(FancyArrowPatch(tuple(e), tuple(tip), arrowstyle="-|>", mutation_scale=9, linewidth=2.6,
                                           color="black", transform=T))
            fig.add_artist(FancyArrowPatch(tuple(e), tuple(tip), arrowstyle="-|>", mutation_scale=7, linewidth=1.4,
                                           color=LEVEL_COLOURS[int(np.clip(lv[k], 0, 3))], transform=T))
            lab = e + (arrow_m + 0.06 * size) * d
            fig.text(lab[0], lab[1], labels[k], ha="center", va="center", fontsize=MIN_FONT_PT, transform=T)
        if len(eyes_t):
            fig.add_artist(Line2D(eyes_t[:, 0], eyes_t[:, 1], linestyle="none", marker="o", markersize=4, color="black",
                                  transform=T))
        sb = _scale_bar_m(float(hi[0] - lo[0]))
        _scale_bar(fig, round(ox + (lo[0] - mid[0]) * scale), round(oy - 0.5 * (hi[1] - lo[1]) * scale - 22.0),
                   round(sb * scale), sb)
        _north_arrow(fig, (462.0, 320.0), north)
        _legend(fig, 232.0, 268.0, [("patch", LEVEL_COLOURS[i], LEVEL_NAMES[i]) for i in reversed(range(4))],
                title="level of the view")

    return _render(draw, (PLAN_SIZE_IN[0] * 100, PLAN_SIZE_IN[1] * 100), fmt=fmt)


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

    def draw(fig):
        from matplotlib.patches import Rectangle

        px = layout_px(fig)
        image_at(fig, rgb, box)
        fig.add_artist(Rectangle(box[:2], box[2], box[3], fill=False, edgecolor="black", linewidth=0.6, transform=px))
        step = max(1, (h1 - h0) // 5)
        for hh in range(h0, h1 + 1, step):
            y = box[1] + (hh - h0) / (h1 - h0) * box[3]
            fig.text(box[0] - 4, y, f"{hh:02d}:00", ha="right", va="center", fontsize=MIN_FONT_PT, transform=px)
        for k, i in enumerate(firsts):  # the month of each first usage day, every other month named
            x = box[0] + i / ndays * box[2]
            fig.add_artist(Rectangle((x, box[1] - 4), 0.01, 4, edgecolor="black", linewidth=0.6, transform=px))
            if k % 2 == 0:
                fig.text(x, box[1] - 6, _MONTHS[int(str(months[i])[5:7]) - 1], ha="left", va="top", fontsize=MIN_FONT_PT,
                         transform=px)
        fig.text(box[0], box[1] - 22, f"usage days of {str(days[0])[:4] if len(days) else ''} across, clock time up",
                 ha="left", va="top", fontsize=MIN_FONT_PT, transform=px)
        entries = [("patch", DGP_CLASS_COLOURS[i], f"DGP {lab[i]}: {counts[i]} h") for i in range(4)]
        _legend(fig, box[0], 46.0, entries[:2])
        _legend(fig, box[0] + 215.0, 46.0, entries[2:])

    return _render(draw, (CARPET_SIZE_IN[0] * 100, CARPET_SIZE_IN[1] * 100), fmt=fmt)


_MONTHS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")


def luminance_fisheye(luminance, *, title: str = "", fmt: str = "png"):
    """A 180 deg fisheye's luminance in false colour on a log scale (10 to 10⁶ cd/m², viridis), with
    its colour bar: what the occupant sees at a point-in-time check.

    Parameters
    ----------
    luminance : (rows, cols) [cd/m²], top row first (angular fisheye, -vta)
    """
    import matplotlib

    lum = np.asarray(luminance, dtype=float)
    t = (np.log10(np.clip(lum, 10.0, 1e6)) - 1.0) / 5.0
    rgb = np.round(np.asarray(matplotlib.colormaps["viridis"](t))[..., :3] * 255).astype(np.uint8)
    ny, nx = lum.shape
    yy, xx = np.mgrid[0:ny, 0:nx]
    outside = np.hypot((xx + 0.5) / nx * 2 - 1, (yy + 0.5) / ny * 2 - 1) > 1
    rgb[outside] = 255
    bar = np.round(np.asarray(matplotlib.colormaps["viridis"]((np.arange(200)[::-1] + 0.5) / 200))[:, :3] * 255).astype(np.uint8)

    def draw(fig):
        px = layout_px(fig)
        image_at(fig, rgb, (10.0, 20.0, 320.0, 320.0))
        image_at(fig, bar[:, None, :], (350.0, 60.0, 14.0, 240.0))
        for k in range(6):
            fig.text(370.0, 60.0 + k * 48.0, f"10{'⁰¹²³⁴⁵⁶'[k + 1]}", ha="left", va="center", fontsize=MIN_FONT_PT, transform=px)
        fig.text(350.0, 310.0, "cd/m²", ha="left", va="bottom", fontsize=MIN_FONT_PT, transform=px)

    return _render(draw, (LUMINANCE_SIZE_IN[0] * 100, LUMINANCE_SIZE_IN[1] * 100), fmt=fmt)
