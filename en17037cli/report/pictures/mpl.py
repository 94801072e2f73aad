"""matplotlib's drawing for the pictures not drawn on a :class:`~.canvas.Canvas`: a figure rendered
to reproducible PNG bytes, and the parts several pictures draw (legends, north arrow, scale bar).

Every picture is reproducible as matplotlib's own test suite makes its images: a fixed figure
size and DPI, the Agg canvas (pyplot is never imported), matplotlib's default style with the
bundled DejaVu Sans font set locally through :func:`matplotlib.rc_context`, and no
``Software`` entry in the PNG metadata, so the same inputs give byte-identical files on one
installation (another FreeType or matplotlib version may move anti-aliased pixels).

Pictures are laid out in *layout pixels* from the bottom-left of the figure (:func:`layout_px`) and
drawn at the size they are printed at: a picture of ``size_px`` layout pixels is
``scale x size_px / 100`` inches, its PNG is written at ``100 / scale`` dots per inch (one PNG pixel
per layout pixel) and its SVG is vector. Text is set in points at that printed size, never below
:data:`MIN_FONT_PT` (8 pt on paper: EN ISO 216 A4 reports read at arm's length). matplotlib is
imported inside the functions that draw, so this module imports without it.
"""
from __future__ import annotations

import io
from collections.abc import Callable

import numpy as np

#: Layout pixels per inch at scale 1 (a picture's PNG has one pixel per layout pixel).
DPI = 100
#: The smallest text in any picture, at its printed size [pt].
MIN_FONT_PT = 8.0
#: The report's pictures are printed at this fraction of their layout size: a 500 px wide map is
#: 3.45 in on paper, two side by side on A4 (and its PNG, one pixel per layout pixel, is 145 dpi).
PRINT_SCALE = 0.69

_RC: dict = {
    # Text from a model (names, GlobalIds, whose alphabet includes "$") is data: never parsed as TeX
    # mathematics ("$...$"), which stopped AC11-Institute's run on "...IBf$$ZaZkjsa)" (issue 43).
    "text.parse_math": False,
    "font.family": "DejaVu Sans",
    "font.size": 8,
    "svg.hashsalt": "en17037cli",
    "svg.fonttype": "none",  # text stays text in the SVG: selectable, and measurable in a browser
    "lines.scale_dashes": False,
    "axes.titlesize": 9,
    "axes.labelsize": 8,
    "legend.fontsize": 8,
    "legend.frameon": False,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
}


def layout_px(fig):
    """The transform from layout pixels (bottom-left origin) to the figure, at any output resolution."""
    from matplotlib.transforms import Affine2D

    return Affine2D().scale(fig.en17037_scale / DPI) + fig.dpi_scale_trans


def pt_px(fig) -> float:
    """Layout pixels per printed point."""
    return DPI / 72.0 / fig.en17037_scale


def _render(draw: Callable, size_px: tuple[float, float], scale: float = PRINT_SCALE, fmt: str = "png"):
    """Draw on a fresh figure of ``size_px`` layout pixels printed ``scale`` x ``size_px / 100`` in.

    Returns the PNG bytes (one pixel per layout pixel), the SVG text as UTF-8 bytes, or for
    ``fmt="both"`` the pair (png, svg), drawn once.
    """
    import matplotlib
    import matplotlib.style
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    dpi = DPI / scale
    with matplotlib.style.context("default"), matplotlib.rc_context(_RC):  # the user's matplotlibrc does not leak in
        fig = Figure(figsize=(size_px[0] / dpi, size_px[1] / dpi), dpi=dpi)
        fig.en17037_scale = scale
        FigureCanvasAgg(fig)
        draw(fig)
        out = {}
        for kind in (("png", "svg") if fmt == "both" else (fmt,)):
            buf = io.BytesIO()
            meta = {"Software": None} if kind == "png" else {"Date": None, "Creator": None}
            fig.savefig(buf, format=kind, dpi=dpi, metadata=meta)
            out[kind] = buf.getvalue()
    return (out["png"], out["svg"]) if fmt == "both" else out[fmt]


def image_at(fig, rgb: np.ndarray, box_px: tuple[float, float, float, float]) -> None:
    """An RGB image (h, w, 3) uint8 shown pixel for pixel in ``box_px`` (left, bottom, width, height)
    layout pixels: an axes of its own, so it lands in place in the PNG and the SVG alike."""
    x0, y0, w, h = box_px
    W, H = fig.get_size_inches() * fig.dpi
    ax = fig.add_axes((x0 / W, y0 / H, w / W, h / H))
    ax.imshow(rgb, interpolation="nearest", aspect="auto", extent=(0, 1, 0, 1))
    ax.set_axis_off()


def warm_up() -> None:
    """Import matplotlib and load the font by drawing a tiny picture: the first picture's fixed
    cost (about 0.5 s), for a caller to pay in a background thread while it traces rays. The
    caller must wait for it (``Thread.join``) before drawing: matplotlib's settings are global."""
    _render(lambda fig: fig.text(0.5, 0.5, "0°"), (20, 20))


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
    px = layout_px(fig)
    fig.add_artist(Rectangle((x0, y0), length_px / 2, 5, facecolor="black", edgecolor="black", linewidth=0.6, transform=px))
    fig.add_artist(Rectangle((x0 + length_px / 2, y0), length_px / 2, 5, facecolor="white", edgecolor="black", linewidth=0.6,
                             transform=px))
    fig.text(x0 + length_px + 6, y0 + 2.5, f"{_fmt_num(length_m)} m", va="center", ha="left", fontsize=MIN_FONT_PT, transform=px)


def _legend(fig, x: float, y: float, entries: list, title: str | None = None, size: float = MIN_FONT_PT) -> float:
    """A legend drawn with plain artists from its top-left corner (x, y) [layout px]; returns the y below it.

    entries : list of (kind, style, label); kind "patch" (style: face colour), "line" (style: list
    of Line2D keyword dicts drawn on top of each other) or "marker" (style: Line2D keywords)
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Rectangle

    px = layout_px(fig)
    row = 1.4 * size * pt_px(fig)  # a line of text and a little air
    key = 1.1 * size * pt_px(fig)  # the swatch's width
    if title:
        fig.text(x, y, title, ha="left", va="top", fontsize=size, transform=px)
        y -= row + 2
    for kind, style, label in entries:
        cy = y - row / 2
        if kind == "patch":
            fig.add_artist(Rectangle((x, cy - 0.3 * key), key, 0.6 * key, facecolor=style, edgecolor="black", linewidth=0.4,
                                     transform=px))
        elif kind == "line":
            for kw in style:
                fig.add_artist(Line2D([x, x + key], [cy, cy], transform=px, **kw))
        else:
            fig.add_artist(Line2D([x + key / 2], [cy], linestyle="none", transform=px, **style))
        fig.text(x + key + 6, cy, label, ha="left", va="center", fontsize=size, transform=px)
        y -= row
    return y


def _colour_bar(fig, box_px: tuple[int, int, int, int], norm, cmap_name, extend, label, thresholds, kind):
    """A colour bar drawn as a pixel image in ``box_px`` (left, bottom, width, height) [px], the level thresholds across it."""
    import matplotlib
    from matplotlib.lines import Line2D
    from matplotlib.patches import Polygon, Rectangle
    px = layout_px(fig)
    cmap = matplotlib.colormaps[cmap_name]
    x0, y0, w, h = box_px
    t = (np.arange(h)[::-1] + 0.5) / h  # row 0 is the top
    column = np.round(np.asarray(cmap(t))[:, :3] * 255).astype(np.uint8)
    image_at(fig, column[:, None, :], (x0, y0, w, h))
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
            fig.text(x0 + w + 6, y, f"{name} {_fmt_num(v)}{unit}", ha="left", va="center", fontsize=MIN_FONT_PT, transform=px)
    lo_lab, hi_lab = (f"{_fmt_num(norm.vmin)}°", f"{_fmt_num(round(norm.vmax, 1))}°") if kind == "sight_angle" else \
        (f"≤ {_fmt_num(norm.vmin)} m", f"≥ {_fmt_num(round(norm.vmax))} m, unobstructed")
    if kind in ("daylight_factor", "share_of_hours"):
        lo_lab, hi_lab = f"{_fmt_num(norm.vmin)}{unit}", f"{_fmt_num(round(norm.vmax, 2))}{unit}"
    fig.text(x0 + w + 6, y0 - (tip if extend in ("min", "both") else 0), lo_lab, ha="left", va="center", fontsize=MIN_FONT_PT,
             color="#404040", transform=px)
    fig.text(x0 + w + 6, y0 + h + (tip if extend in ("max", "both") else 0), hi_lab, ha="left", va="center", fontsize=MIN_FONT_PT,
             color="#404040", transform=px)
    fig.text(x0, y0 + h + tip + 14, label, ha="left", va="bottom", fontsize=MIN_FONT_PT, transform=px)


def _north_arrow(fig, centre: tuple[float, float], north: np.ndarray, length: float = 44.0):
    """An arrow through ``centre`` [px] pointing along ``north`` (a vector of the picture), marked N."""
    from matplotlib.patches import FancyArrowPatch
    px = layout_px(fig)
    n = north / max(float(np.hypot(*north)), 1e-12)
    c = np.asarray(centre, dtype=float)
    fig.add_artist(FancyArrowPatch(tuple(c - 0.5 * length * n), tuple(c + 0.5 * length * n), arrowstyle="-|>", color="black",
                                   linewidth=1.2, mutation_scale=10, transform=px))
    tip = c + (0.5 * length + 9) * n
    fig.text(tip[0], tip[1], "N", ha="center", va="center", fontsize=MIN_FONT_PT + 1, fontweight="bold", transform=px)
