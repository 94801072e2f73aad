"""The shared drawing of the pictures: a figure rendered to reproducible PNG bytes, and the parts
several pictures draw (legends, colour bars, north arrow, scale bar).

Every picture is reproducible as matplotlib's own test suite makes its images: a fixed figure
size and DPI, the Agg canvas (pyplot is never imported), matplotlib's default style with the
bundled DejaVu Sans font set locally through :func:`matplotlib.rc_context`, and no
``Software`` entry in the PNG metadata, so the same inputs give byte-identical files on one
installation (another FreeType or matplotlib version may move anti-aliased pixels).

Parts are drawn with plain artists in pixels from the bottom-left of the figure; matplotlib is
imported inside the functions that draw, so this module imports without it.
"""
from __future__ import annotations

import io
from collections.abc import Callable

import numpy as np

#: Pixels per inch of every picture.
DPI = 100

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


def warm_up() -> None:
    """Import matplotlib and load the font by drawing a tiny picture: the first picture's fixed
    cost (about 0.5 s), for a caller to pay in a background thread while it traces rays. The
    caller must wait for it (``Thread.join``) before drawing: matplotlib's settings are global."""
    _render(lambda fig: fig.text(0.5, 0.5, "0°"), (0.2, 0.2))


def _fmt_num(v: float) -> str:
    """A threshold or bar length without trailing zeros."""
    return f"{v:.6g}"


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


def _scale_bar(fig, x0: float, y0: float, length_px: float, length_m: float) -> None:
    """A scale bar from (x0, y0) [px], two halves black and white, ``length_px`` long for ``length_m`` [m]."""
    from matplotlib.patches import Rectangle
    from matplotlib.transforms import IdentityTransform

    px = IdentityTransform()
    fig.add_artist(Rectangle((x0, y0), length_px / 2, 5, facecolor="black", edgecolor="black", linewidth=0.6, transform=px))
    fig.add_artist(Rectangle((x0 + length_px / 2, y0), length_px / 2, 5, facecolor="white", edgecolor="black", linewidth=0.6,
                             transform=px))
    fig.text(x0 + length_px + 6, y0 + 2.5, f"{_fmt_num(length_m)} m", va="center", ha="left", fontsize=7, transform=px)


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


def _colour_bar(fig, box_px: tuple[int, int, int, int], norm, cmap_name, extend, label, thresholds, kind):
    """A colour bar drawn as a pixel image in ``box_px`` (left, bottom, width, height) [px], the level thresholds across it."""
    import matplotlib
    from matplotlib.lines import Line2D
    from matplotlib.patches import Polygon, Rectangle
    from matplotlib.transforms import IdentityTransform

    px = IdentityTransform()
    cmap = matplotlib.colormaps[cmap_name]
    x0, y0, w, h = box_px
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
    unit = {"sight_angle": "°", "daylight_factor": " %", "share_of_hours": ""}.get(kind, " m")
    for name in ("minimum", "medium", "high"):
        v = float(thresholds[name])
        if norm.vmin <= v <= norm.vmax:
            y = y0 + float(norm(v)) * h
            fig.add_artist(Line2D([x0, x0 + w + 3], [y, y], color="white", linewidth=2.4, transform=px))
            fig.add_artist(Line2D([x0, x0 + w + 3], [y, y], color="black", linewidth=1.0, transform=px))
            fig.text(x0 + w + 6, y, f"{name} {_fmt_num(v)}{unit}", ha="left", va="center", fontsize=6.5, transform=px)
    lo_lab, hi_lab = (f"{_fmt_num(norm.vmin)}°", f"{_fmt_num(round(norm.vmax, 1))}°") if kind == "sight_angle" else \
        (f"≤ {_fmt_num(norm.vmin)} m", f"≥ {_fmt_num(round(norm.vmax))} m, unobstructed")
    if kind in ("daylight_factor", "share_of_hours"):
        lo_lab, hi_lab = f"{_fmt_num(norm.vmin)}{unit}", f"{_fmt_num(round(norm.vmax, 2))}{unit}"
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
