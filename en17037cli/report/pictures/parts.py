"""The parts several pictures draw on a :class:`~.canvas.Canvas`: legends, colour bars, a north
arrow, a scale bar, an arrow. Positions are layout pixels from the bottom-left, sizes in points."""
from __future__ import annotations

import numpy as np

from en17037cli.report.pictures.canvas import MIN_FONT_PT, Canvas, _fmt_num
from en17037cli.report.pictures.colourmaps import lookup


def scale_bar(c: Canvas, x0: float, y0: float, length_px: float, length_m: float) -> None:
    """A scale bar from (x0, y0) [px], two halves black and white, ``length_px`` long for ``length_m`` [m]."""
    c.rect(x0, y0, length_px / 2, 5, fill="black", stroke="black", lw=0.6)
    c.rect(x0 + length_px / 2, y0, length_px / 2, 5, fill="white", stroke="black", lw=0.6)
    c.text(x0 + length_px + 6, y0 + 2.5, f"{_fmt_num(length_m)} m", va="center")


def legend(c: Canvas, x: float, y: float, entries: list, title: str | None = None, size: float = MIN_FONT_PT) -> float:
    """A legend from its top-left corner (x, y) [layout px]; returns the y below it.

    entries : list of (kind, style, label); kind "patch" (style: face colour), "line" (style: list
    of :meth:`Canvas.path` keyword dicts drawn on top of each other) or "marker" (style:
    :meth:`Canvas.markers` keywords with ``size``)
    """
    row = 1.4 * size * c.pt  # a line of text and a little air
    key = 1.1 * size * c.pt  # the swatch's width
    if title:
        c.text(x, y, title, ha="left", va="top", size=size)
        y -= row + 2
    for kind, style, label in entries:  # one per entry
        cy = y - row / 2
        if kind == "patch":
            c.rect(x, cy - 0.3 * key, key, 0.6 * key, fill=style, stroke="black", lw=0.4)
        elif kind == "line":
            for kw in style:
                c.path(np.array([[x, cy], [x + key, cy]]), **kw)
        else:
            c.markers([[x + key / 2, cy]], **style)
        c.text(x + key + 6, cy, label, ha="left", va="center", size=size)
        y -= row
    return y


def arrow(c: Canvas, tail, tip, *, colour="black", lw: float = 1.2, head: float = 10.0, shrink_pt: float = 2.0) -> None:
    """An arrow from ``tail`` to ``tip`` [layout px] with a filled triangular head (matplotlib's "-|>"
    at ``mutation_scale`` = ``head``: 0.4 x head long, 0.2 x head wide each side [pt]), both ends
    drawn ``shrink_pt`` short."""
    t0, t1 = np.asarray(tail, dtype=float), np.asarray(tip, dtype=float)
    length = float(np.hypot(*(t1 - t0)))
    if length <= 2 * shrink_pt * c.pt:
        return
    u = (t1 - t0) / length
    t0, t1 = t0 + shrink_pt * c.pt * u, t1 - shrink_pt * c.pt * u
    hl, hw = 0.4 * head * c.pt, 0.2 * head * c.pt
    base = t1 - hl * u
    n = np.array([-u[1], u[0]])
    c.path(np.array([t0, base + 0.5 * hl * u]), stroke=colour, lw=lw)
    c.path(np.array([t1, base + hw * n, base - hw * n]), stroke=colour, lw=lw, fill=colour, closed=True)


def north_arrow(c: Canvas, centre: tuple[float, float], north: np.ndarray, length: float = 44.0) -> None:
    """An arrow through ``centre`` [px] pointing along ``north`` (a vector of the picture), marked N."""
    n = north / max(float(np.hypot(*north)), 1e-12)
    ctr = np.asarray(centre, dtype=float)
    arrow(c, ctr - 0.5 * length * n, ctr + 0.5 * length * n)
    tip = ctr + (0.5 * length + 9) * n
    c.text(tip[0], tip[1], "N", ha="center", va="center", size=MIN_FONT_PT + 1, bold=True)


def colour_bar(c: Canvas, box_px: tuple[int, int, int, int], norm, cmap_name: str, extend: str, label: str, thresholds: dict,
               kind: str) -> None:
    """A colour bar drawn as a pixel image in ``box_px`` (left, bottom, width, height) [px], the level
    thresholds across it; ``norm`` maps a value to [0, 1] (:class:`~.colours.Norm`)."""
    x0, y0, w, h = box_px
    t = (np.arange(h)[::-1] + 0.5) / h  # row 0 is the top
    c.image(np.repeat(lookup(cmap_name, t)[:, None, :], w, axis=1), (x0, y0, w, h))
    tip = 0.6 * w
    lo_rgb, hi_rgb = lookup(cmap_name, np.array([0.0, 1.0])) / 255.0
    if extend in ("min", "both"):
        c.path(np.array([(x0, y0), (x0 + w, y0), (x0 + w / 2, y0 - tip)]), fill=lo_rgb, stroke="black", lw=0.5, closed=True)
    if extend in ("max", "both"):
        c.path(np.array([(x0, y0 + h), (x0 + w, y0 + h), (x0 + w / 2, y0 + h + tip)]), fill=hi_rgb, stroke="black", lw=0.5,
               closed=True)
    c.rect(x0, y0, w, h, stroke="black", lw=0.5)
    unit = {"sight_angle": "°", "daylight_factor": " %", "share_of_hours": ""}.get(kind, " m")
    for name in ("minimum", "medium", "high"):
        v = float(thresholds[name])
        if norm.vmin <= v <= norm.vmax:
            y = y0 + float(norm(v)) * h
            for colour, lw in (("white", 2.4), ("black", 1.0)):
                c.path(np.array([[x0, y], [x0 + w + 3, y]]), stroke=colour, lw=lw)
            c.text(x0 + w + 6, y, f"{name} {_fmt_num(v)}{unit}", va="center")
    lo_lab, hi_lab = (f"{_fmt_num(norm.vmin)}°", f"{_fmt_num(round(norm.vmax, 1))}°") if kind == "sight_angle" else \
        (f"≤ {_fmt_num(norm.vmin)} m", f"≥ {_fmt_num(round(norm.vmax))} m, unobstructed")
    if kind in ("daylight_factor", "share_of_hours"):
        lo_lab, hi_lab = f"{_fmt_num(norm.vmin)}{unit}", f"{_fmt_num(round(norm.vmax, 2))}{unit}"
    c.text(x0 + w + 6, y0 - (tip if extend in ("min", "both") else 0), lo_lab, va="center", colour="#404040")
    c.text(x0 + w + 6, y0 + h + (tip if extend in ("max", "both") else 0), hi_lab, va="center", colour="#404040")
    c.text(x0, y0 + h + tip + 14, label, va="bottom")
