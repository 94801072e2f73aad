"""Charts: the hours of sunlight per day over the assessment period, and the tornado chart of a score's sensitivity."""
from __future__ import annotations

import io
from collections.abc import Callable, Sequence

import numpy as np

from en17037cli.report.numbers import fmt_duration, fmt_hm
from en17037cli.report.pictures.canvas import DPI, MIN_FONT_PT, PRINT_SCALE, Canvas
from en17037cli.report.pictures.colours import ASSESSED_COLOUR, BAR_COLOUR, _rgb
from en17037cli.report.pictures.raster import render

#: Layout size of the hours chart [in / 100 px] (width, height); printed at PRINT_SCALE (3.45 x 2.2 in).
CHART_SIZE_IN = (5.0, 3.2)

_MONTHS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")


def _date_label(d) -> str:
    """``"1 Feb"`` whatever the locale."""
    return f"{d.day} {_MONTHS[d.month - 1]}"


#: Each window's hours are drawn as a line for at most this many windows; with more, the chart
#: keeps the room's bars (each window's hours on the assessed day are in the report's table).
MAX_WINDOW_LINES = 3
#: Window names in the chart's legend are cut to this many characters, in the middle (exporters
#: put the type first and the element's id last: both ends tell windows apart).
MAX_NAME_CHARS = 26


def _short(name: str) -> str:
    if len(name) <= MAX_NAME_CHARS:
        return name
    half = (MAX_NAME_CHARS - 1) // 2
    return name[:half] + "…" + name[len(name) - (MAX_NAME_CHARS - 1 - half):]


def hours_chart(dates, hours, *, thresholds: dict, assessed_index: int, per_window: dict | None = None, title: str = "",
                fmt: str = "png"):
    """Sun hours per day over the assessment period, with the level thresholds and the assessed day.

    Parameters
    ----------
    dates : sequence of datetime.date, (d,)
    hours : (d,) float [h], the room's hours of sunlight each day
    thresholds : dict {"minimum", "medium", "high"} [h]
    assessed_index : int, position of the assessed day in ``dates`` (its bar is dark and hatched)
    per_window : dict name -> (d,) float [h], optional; each window's hours as thin lines (at most
        :data:`MAX_WINDOW_LINES` windows, named in a legend above the axes)
    title : str, not drawn: the reports caption the picture
    fmt : "png", "svg" or "both"

    Returns
    -------
    bytes, a PNG image of :data:`CHART_SIZE_IN` at :data:`DPI`
    """
    hrs = np.asarray(hours, dtype=float).reshape(-1)
    dates = list(dates)
    if len(dates) != len(hrs):
        raise ValueError(f"hours must have shape ({len(dates)},) like dates, not {hrs.shape}")
    d, k = len(hrs), int(assessed_index)
    c = Canvas(int(CHART_SIZE_IN[0] * 100), int(CHART_SIZE_IN[1] * 100))
    lines = per_window if per_window and len(per_window) <= MAX_WINDOW_LINES else None
    top_band = 0.065 * len(lines) if lines else 0.0  # the legend's rows, above the axes
    left, bottom, width, height = 0.17 * c.width, 0.14 * c.height, 0.57 * c.width, (0.80 - top_band) * c.height
    ymax = max([float(np.nanmax(hrs)) if np.isfinite(hrs).any() else 0.0] + [float(v) for v in thresholds.values()])
    if lines:
        ymax = max([ymax] + [float(np.nanmax(v)) for v in lines.values() if np.isfinite(np.asarray(v, dtype=float)).any()])
    xlim, ylim = (-0.7, max(d, 1) - 0.3), (0.0, 1.25 * ymax if ymax > 0 else 1.0)
    X = lambda x: left + (np.asarray(x, dtype=float) - xlim[0]) / (xlim[1] - xlim[0]) * width  # noqa: E731 - data -> layout px
    Y = lambda y: bottom + (np.asarray(y, dtype=float) - ylim[0]) / (ylim[1] - ylim[0]) * height  # noqa: E731
    x, top = np.arange(d), np.nan_to_num(hrs)
    bars = np.stack([np.column_stack([X(x + dx), Y(top * f)]) for dx, f in ((-0.4, 0), (0.4, 0), (0.4, 1), (-0.4, 1))], axis=1)
    rgb = np.tile(np.round(_rgb([BAR_COLOUR])[0] * 255).astype(np.uint8), (d, 1))
    if 0 <= k < d:
        rgb[k] = np.round(_rgb([ASSESSED_COLOUR])[0] * 255).astype(np.uint8)
    c.cells(bars, rgb)  # bars at their exact colours, the assessed day's dark
    if 0 <= k < d:
        c.path(_hatch(*bars[k, 0], *bars[k, 2], HATCH_PX), stroke="white", lw=1.0)  # and hatched
    if lines:
        for i, v in enumerate(lines.values()):  # at most MAX_WINDOW_LINES
            c.path(np.column_stack([X(x), Y(np.asarray(v, dtype=float).reshape(-1))]), stroke="black", lw=0.8,
                   dash=(None, (3, 1.5), (1, 1.5), (5, 1.5, 1, 1.5))[i % 4])
    for name, ls in (("minimum", (1, 1.5)), ("medium", (4, 2)), ("high", None)):
        v = float(thresholds[name])
        c.path(np.array([[left, Y(v)], [left + width, Y(v)]]), stroke="black", lw=0.9, dash=ls)
        c.text(left + 1.01 * width, float(Y(v)), f"{name} {fmt_hm(v)}", va="center")
    _axes(c, (left, bottom, width, height), X, Y, xlim, ylim, ymax, dates)
    if lines:
        _line_legend(c, 0.13 * c.width, c.height, [(f"window {_short(n)}", i) for i, n in enumerate(lines)])
    if 0 <= k < d:
        # beside the bar's top, inside the axes (right of the assessed bar, left of it near the period's end):
        # never over the y tick labels; two lines: one ran into the threshold labels right of the axes
        right = k < 0.6 * d
        c.text(float(X(k)) + (6 if right else -6) * c.pt, float(Y(float(np.nan_to_num(hrs[k])))) + 3 * c.pt,
               f"assessed {_date_label(dates[k])}:\n{fmt_duration(hrs[k])}", ha="left" if right else "right", va="bottom",
               box=("white", 0.85, 0.15))
    return render(c, fmt)


#: Spacing of the assessed bar's hatching [layout px].
HATCH_PX = 13.0


def _hatch(x0: float, y0: float, x1: float, y1: float, step: float) -> list[np.ndarray]:
    """Lines at 45 deg ("/") across the rectangle (x0, y0)-(x1, y1) [px], ``step`` apart along x."""
    ks = np.arange(np.floor((x0 - y1) / step) * step, x1 - y0, step)  # the lines x - y = k
    ya, yb = np.maximum(y0, x0 - ks), np.minimum(y1, x1 - ks)
    keep = yb > ya
    return list(np.stack([np.column_stack([ks[keep] + ya[keep], ya[keep]]), np.column_stack([ks[keep] + yb[keep], yb[keep]])], axis=1))


def _axes(c: Canvas, box, X, Y, xlim, ylim, ymax: float, dates: list) -> None:
    """The left and bottom spines, their ticks (outwards, 3.5 pt) and labels, and the y axis's label."""
    left, bottom, width, height = box
    tick, pad = 3.5 * c.pt, 3.5 * c.pt
    c.path(np.array([[left, bottom + height], [left, bottom], [left + width, bottom]]), stroke="black", lw=0.8)
    step = 0.5 if ymax <= 3 else (1.0 if ymax <= 8 else 2.0)
    yt = np.arange(0.0, ylim[1] + 1e-9, step)
    d = len(dates)
    xt = [i for i in range(d) if i % (7 if d <= 28 else 14) == 0]  # labels 55 px wide at 8 pt
    c.path([np.array([[left - tick, Y(v)], [left, Y(v)]]) for v in yt] + [np.array([[X(i), bottom - tick], [X(i), bottom]]) for i in xt],
           stroke="black", lw=0.8)
    labels = [fmt_hm(v) for v in yt]
    for v, lab in zip(yt, labels):  # one per tick
        c.text(left - tick - pad, Y(v), lab, ha="right", va="center")
    for i in xt:
        c.text(X(i), bottom - tick - pad, _date_label(dates[i]), ha="center", va="top")
    widest = max((c.text_width(lab) for lab in labels), default=0.0)
    c.text(left - tick - pad - widest - 4 * c.pt, bottom + height / 2, "sunlight [h:mm]", ha="center", va="bottom", rotation=90)


def _line_legend(c: Canvas, x: float, y: float, entries: list) -> None:
    """The windows' lines named above the axes, from the top-left corner (x, y) [layout px]."""
    em = MIN_FONT_PT * c.pt
    x, y = x + 0.6 * em, y - 0.6 * em
    for label, i in entries:  # at most MAX_WINDOW_LINES
        cy = y - 0.65 * em
        c.path(np.array([[x, cy], [x + 2.5 * em, cy]]), stroke="black", lw=0.8, dash=(None, (3, 1.5), (1, 1.5), (5, 1.5, 1, 1.5))[i % 4])
        c.text(x + 3.3 * em, cy, label, va="center")
        y -= 1.3 * em


#: matplotlib's settings for the tornado chart (the one picture matplotlib still draws: a study's,
#: not a report's): its default style, DejaVu Sans, text never parsed as TeX, text kept as text in SVG.
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
                   loc="upper right", bbox_to_anchor=(0.99, 0.995), ncols=2, fontsize=8)
        if title:
            fig.text(0.02, 0.99, title, ha="left", va="top", fontsize=9)

    return _render(draw, (500, height * 100), scale=1.0)
