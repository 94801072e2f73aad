"""The colours of the pictures: their tables, how light they read, and the labels of the view layers.

Colours read in grey: continuous values use viridis or cividis (luminance rises monotonically),
levels and the eight layer combinations are samples of viridis ordered by luminance, and the
classes of the fisheye go from dark (blocked) to light (sky). :func:`relative_luminance` and
:func:`lightness` measure this (Rec. 709 primaries, sRGB transfer, CIE 1976 L*).

The tables are hex strings and the continuous colour maps 8-bit tables (:mod:`.colourmaps`), so
nothing here needs matplotlib.
"""
from __future__ import annotations

import numpy as np

from en17037cli.report.pictures.colourmaps import lookup

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
CMAP = {"sight_angle": "viridis", "distance": "cividis", "daylight_factor": "viridis", "share_of_hours": "cividis"}
#: Distances below this are drawn in the lowest colour [m].
DISTANCE_VMIN_M = 1.0


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


class Norm:
    """A value's place on a colour bar, in [0, 1] between ``vmin`` and ``vmax`` (linear, or on a log
    scale; values at or below 0 on a log scale: NaN). matplotlib's ``Normalize`` and ``LogNorm``
    without clipping."""

    def __init__(self, vmin: float, vmax: float, log: bool = False):
        self.vmin, self.vmax, self.log = float(vmin), float(vmax), log

    def __call__(self, v):
        v = np.asarray(v, dtype=float)
        if self.log:
            with np.errstate(invalid="ignore", divide="ignore"):
                lv = np.where(v > 0, np.log10(np.where(v > 0, v, 1.0)), np.nan)
            lo, hi = np.log10(self.vmin), np.log10(self.vmax)
            return (lv - lo) / (hi - lo) if hi > lo else np.zeros_like(v)
        return (v - self.vmin) / (self.vmax - self.vmin) if self.vmax > self.vmin else np.zeros_like(v)


def _continuous_norm(kind: str, vals: np.ndarray, thresholds: dict):
    """(norm, colour map name, extend, label) of a continuous plan map."""
    finite = vals[np.isfinite(vals)]
    high = float(thresholds["high"])
    if kind == "sight_angle":
        vmax = max(1.25 * high, float(finite.max()) if finite.size else 0.0)
        return Norm(0.0, vmax), CMAP[kind], "neither", "horizontal sight angle [°]"
    if kind == "daylight_factor":
        vmax = max(1.25 * high, float(finite.max()) if finite.size else 0.0)
        return Norm(0.0, vmax), CMAP[kind], "neither", "daylight factor [%]\n(marks: D_T of each level)"
    if kind == "share_of_hours":
        return Norm(0.0, 1.0), CMAP[kind], "neither", "share of daylight hours\nreaching the target"
    vmax = max(2.0 * high, float(finite.max()) if finite.size else 0.0, 2.0 * DISTANCE_VMIN_M)
    return Norm(DISTANCE_VMIN_M, vmax, log=True), CMAP[kind], "both", "outside distance [m]\n(top: unobstructed)"


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
    v = np.asarray(values, dtype=float).reshape(-1)
    scale = v if all_values is None else np.asarray(all_values, dtype=float).reshape(-1)
    norm, cmap_name, _, _ = _continuous_norm(kind, scale, thresholds)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = norm(np.where(np.isnan(v), 1.0, np.where(np.isinf(v), norm.vmax, v)))
    t = np.clip(np.nan_to_num(t, nan=0.0), 0.0, 1.0)  # <= 0 on a log scale: the lowest colour
    rgba = np.ones((len(v), 4))
    rgba[:, :3] = lookup(cmap_name, t) / 255.0
    rgba[np.isnan(v)] = np.nan
    return rgba


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
