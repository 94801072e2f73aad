"""The canvas of the pictures: what a picture holds, written as SVG by :mod:`.svg` and drawn as PNG
by :mod:`.raster` (:func:`.raster.render`), without matplotlib.

A picture is laid out in *layout pixels* from its bottom-left corner, y up, and printed at
``scale`` of its size: a picture of ``size_px`` layout pixels is ``scale x size_px / 100`` inches,
its PNG has one pixel per layout pixel (``100 / scale`` dots per inch) and its SVG's ``viewBox`` is
in layout pixels. Text is set in points at that printed size, never below :data:`MIN_FONT_PT` (8 pt
on paper: EN ISO 216 A4 reports read at arm's length); line widths and dashes are in printed points.

A :class:`Canvas` records, in drawing order: pixel images and cells (filled without anti-aliasing,
so their pixels carry their exact colours), paths (polylines and polygons, stroked and filled),
markers (discs and rings) and text. Text is data, never markup: the SVG escapes it and keeps it as
text (selectable, measurable in a browser), with the characters XML cannot hold replaced by U+FFFD.
The same canvas gives byte-identical PNG and SVG on one installation (no dates, no version strings).
"""
from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from en17037cli.report.pictures.text import ASCENT, DESCENT, font

#: Layout pixels per inch at scale 1 (a picture's PNG has one pixel per layout pixel).
DPI = 100
#: The smallest text in any picture, at its printed size [pt].
MIN_FONT_PT = 8.0
#: The report's pictures are printed at this fraction of their layout size: a 500 px wide map is
#: 3.45 in on paper, two side by side on A4 (and its PNG, one pixel per layout pixel, is 145 dpi).
PRINT_SCALE = 0.69
#: Line spacing of text of several lines [font sizes] (as matplotlib set it).
LINE_SPACING = 1.2
_NAMED = {"black": "#000000", "white": "#ffffff"}
_XML_BAD = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def colour_hex(c) -> str:
    """``"#rrggbb"`` of a hex string, ``"black"``/``"white"`` or an RGB(A) row of floats in [0, 1]."""
    if isinstance(c, str):
        return _NAMED.get(c, c).lower()
    r, g, b = (int(round(float(v) * 255)) for v in list(c)[:3])
    return f"#{r:02x}{g:02x}{b:02x}"


def colour_rgb(c) -> tuple[int, int, int]:
    """(r, g, b) in 0..255 of a colour as :func:`colour_hex` takes it."""
    h = colour_hex(c)
    return int(h[1:3], 16), int(h[3:5], 16), int(h[5:7], 16)


def xml_text(s: str) -> str:
    """Text as XML character data: ``&``, ``<``, ``>`` escaped, characters XML 1.0 cannot hold as U+FFFD."""
    s = _XML_BAD.sub("\ufffd", str(s))
    return s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def split_nan(p: np.ndarray) -> list[np.ndarray]:
    """The runs of two or more finite points of a polyline (k, 2) with NaN breaks."""
    ok = np.all(np.isfinite(p), axis=1)
    if ok.all():
        return [p] if len(p) >= 2 else []
    edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.astype(np.int8), [0]])))
    return [p[a:b] for a, b in zip(edges[::2], edges[1::2]) if b - a >= 2]


def _thinned(p: np.ndarray, step_px: float = 6.0) -> np.ndarray:
    """A long polyline (k, 2) [layout px] with its points at least about ``step_px`` apart along it
    (the first point of each step, and the last point): a sun path sampled every 2 min has points
    half a pixel apart, and a chord of 6 px on a curve of radius 100 px is 0.05 px off it."""
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])
    _, first = np.unique(np.floor(s / step_px), return_index=True)
    if first[-1] != len(p) - 1:
        first = np.append(first, len(p) - 1)
    return p[first]


@dataclass
class Canvas:
    """A picture of ``width`` x ``height`` layout pixels printed at ``scale`` (see the module)."""

    width: int
    height: int
    scale: float = PRINT_SCALE
    items: list = field(default_factory=list)

    @property
    def pt(self) -> float:
        """Layout pixels per printed point."""
        return DPI / 72.0 / self.scale

    def image(self, pixels: np.ndarray, box: tuple[int, int, int, int], palette: np.ndarray | None = None) -> None:
        """An image in ``box`` (left, bottom, w, h) [whole layout px], row 0 at the top: RGB (r, c, 3)
        uint8, or indices (r, c) uint8 into ``palette`` (k, 3) uint8 (a class raster); pixel for pixel
        where (r, c) = (h, w), else each pixel the nearest of the image's (the SVG holds the image as
        it is, scaled without smoothing)."""
        pal = None if palette is None else np.ascontiguousarray(palette, dtype=np.uint8).reshape(-1, 3)
        self.items.append(("image", np.ascontiguousarray(pixels, dtype=np.uint8), tuple(int(v) for v in box), pal))

    def cells(self, quads: np.ndarray, rgb: np.ndarray) -> None:
        """Parallelograms (n, 4, 2) [layout px, corners in turn] filled with (n, 3) uint8 colours, not
        anti-aliased: a pixel whose centre lies in a cell takes the cell's exact colour."""
        q = np.asarray(quads, dtype=float).reshape(-1, 4, 2)
        if len(q):
            self.items.append(("cells", q, np.asarray(rgb, dtype=np.uint8).reshape(-1, 3)))

    def path(self, xy, *, stroke="black", lw: float = 1.0, fill=None, closed: bool = False, dash: Sequence[float] | None = None,
             alpha: float = 1.0) -> None:
        """A polyline or polygon (k, 2) [layout px], or several of the same style (a list of them).

        stroke, fill : colour or None; lw : line width [pt]; dash : on, off, ... lengths [pt]; the
        line's ends are butt, its joins round; alpha : opacity of the stroke and fill.
        """
        pieces = [q for p in (xy if isinstance(xy, list) else [xy]) for q in split_nan(np.asarray(p, dtype=float).reshape(-1, 2))]
        pieces = [_thinned(p) if len(p) > 64 else p for p in pieces]  # a long curve's points 6 px apart
        if pieces and (stroke is not None or fill is not None):
            allp = np.vstack(pieces)
            box = (float(allp[:, 0].min()), float(allp[:, 1].min()), float(allp[:, 0].max()), float(allp[:, 1].max()))
            self.items.append(("path", pieces, None if stroke is None else colour_hex(stroke), float(lw),
                               None if fill is None else colour_hex(fill), bool(closed), tuple(dash) if dash else None, alpha, box))

    def rect(self, x: float, y: float, w: float, h: float, **kw) -> None:
        """A rectangle from its bottom-left corner (x, y) [layout px]; keywords of :meth:`path`."""
        self.path(np.array([[x, y], [x + w, y], [x + w, y + h], [x, y + h]]), closed=True, **kw)

    def markers(self, xy, size: float, *, fill=None, stroke=None, lw: float = 1.0) -> None:
        """A disc or ring of diameter ``size`` [pt] (matplotlib's marker size) at each point (m, 2) [layout px]."""
        p = np.asarray(xy, dtype=float).reshape(-1, 2)
        p = p[np.all(np.isfinite(p), axis=1)]
        if len(p):
            self.items.append(("markers", p, float(size), None if fill is None else colour_hex(fill),
                               None if stroke is None else colour_hex(stroke), float(lw)))

    def text(self, x: float, y: float, s: str, *, size: float = MIN_FONT_PT, ha: str = "left", va: str = "baseline",
             colour="black", bold: bool = False, rotation: int = 0, box: tuple | None = None) -> None:
        """Text at (x, y) [layout px]: ``size`` [pt], ``ha`` left/center/right, ``va`` top/center/
        baseline/bottom (of its block of lines), ``rotation`` 0 or 90 [deg], ``box`` (colour,
        opacity, pad [em]) behind it. Lines break at ``\\n``; the text is drawn as written."""
        s = str(s)
        if s:
            self.items.append(("text", float(x), float(y), s, float(size), ha, va, colour_hex(colour), bool(bold), int(rotation),
                               box))

    def lines_of(self, x: float, y: float, s: str, size: float, ha: str, va: str, rotation: int = 0):
        """Each line of a text item with its anchor [layout px]: (line, x, baseline y) with the block
        aligned by ``va``; rotated by 90 deg the lines stack to the right."""
        lines = s.split("\n")
        em = size * self.pt
        step = LINE_SPACING * em
        block = (len(lines) - 1) * step + (ASCENT + DESCENT) * em
        top = {"top": 0.0, "center": block / 2, "bottom": block}.get(va, ASCENT * em)  # from y up to the block's top
        first = top - ASCENT * em
        out = []
        for k, line in enumerate(lines):
            off = first - k * step  # the line's baseline relative to y, along the text's "up"
            out.append((line, x - off, y) if rotation == 90 else (line, x, y + off))
        return out

    def text_width(self, s: str, size: float = MIN_FONT_PT, bold: bool = False) -> float:
        """Width [layout px] of the widest line of ``s`` in DejaVu Sans at ``size`` [pt]."""
        f = font(size * self.pt, bold)
        return max(f.getlength(line) for line in str(s).split("\n"))


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
