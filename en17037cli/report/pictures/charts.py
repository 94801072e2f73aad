"""Charts: the hours of sunlight per day over the assessment period, and the tornado chart of a score's sensitivity."""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from en17037cli.report.numbers import fmt_duration, fmt_hm
from en17037cli.report.pictures.colours import ASSESSED_COLOUR, BAR_COLOUR
from en17037cli.report.pictures.mpl import _render

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
    d = len(hrs)
    k = int(assessed_index)

    def draw(fig):
        from matplotlib.collections import PolyCollection
        from matplotlib.patches import Rectangle
        from matplotlib.ticker import FixedLocator, FuncFormatter, MultipleLocator

        lines = per_window if per_window and len(per_window) <= MAX_WINDOW_LINES else None
        top_band = 0.065 * len(lines) if lines else 0.0  # the legend's rows, above the axes
        ax = fig.add_axes((0.17, 0.14, 0.57, 0.80 - top_band))
        x = np.arange(d)
        top = np.nan_to_num(hrs)
        others = np.flatnonzero(x != k)
        # one collection for the bars (one Rectangle each costs more than the drawing)
        ax.add_collection(PolyCollection([[(i - 0.4, 0), (i + 0.4, 0), (i + 0.4, top[i]), (i - 0.4, top[i])] for i in others],
                                         facecolors=BAR_COLOUR, edgecolors="none"))
        if 0 <= k < d:
            ax.add_patch(Rectangle((k - 0.4, 0), 0.8, top[k], facecolor=ASSESSED_COLOUR, edgecolor="white", linewidth=0, hatch="////"))
            # beside the bar's top, inside the axes (right of the assessed bar, left of it near the period's end):
            # never over the y tick labels
            right = k < 0.6 * d
            # two lines: one ran into the threshold labels right of the axes (FZK-Haus: assessed 16 Feb)
            ax.annotate(f"assessed {_date_label(dates[k])}:\n{fmt_duration(hrs[k])}", (k, float(np.nan_to_num(hrs[k]))),
                        xytext=(6 if right else -6, 3), textcoords="offset points", ha="left" if right else "right",
                        va="bottom", fontsize=8, bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none",
                                                       "alpha": 0.85})
        ymax = max([float(np.nanmax(hrs)) if np.isfinite(hrs).any() else 0.0] + [float(v) for v in thresholds.values()])
        if lines:
            for i, (name, v) in enumerate(lines.items()):
                w = np.asarray(v, dtype=float).reshape(-1)
                ax.plot(x, w, color="black", linewidth=0.8, linestyle=("-", (0, (3, 1.5)), (0, (1, 1.5)), (0, (5, 1.5, 1, 1.5)))[i % 4],
                        label=f"window {_short(name)}")
                if np.isfinite(w).any():
                    ymax = max(ymax, float(np.nanmax(w)))
        for name, ls in (("minimum", (0, (1, 1.5))), ("medium", (0, (4, 2))), ("high", "-")):
            v = float(thresholds[name])
            ax.axhline(v, color="black", linewidth=0.9, linestyle=ls)
            ax.text(1.01, v, f"{name} {fmt_hm(v)}", transform=ax.get_yaxis_transform(), ha="left", va="center", fontsize=8)
        ax.set_xlim(-0.7, max(d, 1) - 0.3)
        ax.set_ylim(0, 1.25 * ymax if ymax > 0 else 1.0)
        step = 0.5 if ymax <= 3 else (1.0 if ymax <= 8 else 2.0)
        ax.yaxis.set_major_locator(MultipleLocator(step))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: fmt_hm(v)))
        ax.set_ylabel("sunlight [h:mm]")
        ticks = [i for i in range(d) if i % (7 if d <= 28 else 14) == 0]  # labels 55 px wide at 8 pt
        ax.xaxis.set_major_locator(FixedLocator(ticks))
        ax.set_xticklabels([_date_label(dates[i]) for i in ticks])
        ax.spines[["top", "right"]].set_visible(False)
        if lines:
            fig.legend(loc="upper left", bbox_to_anchor=(0.13, 1.0), fontsize=8, ncols=1, frameon=False,
                       borderaxespad=0.2, handlelength=2.5)

    return _render(draw, (CHART_SIZE_IN[0] * 100, CHART_SIZE_IN[1] * 100), fmt=fmt)


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
