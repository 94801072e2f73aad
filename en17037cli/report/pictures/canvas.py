"""The canvas of the pictures: what a picture holds, written as SVG text here and drawn as PNG by
:mod:`.raster`, without matplotlib.

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

import base64
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

#: Layout pixels per inch at scale 1 (a picture's PNG has one pixel per layout pixel).
DPI = 100
#: The smallest text in any picture, at its printed size [pt].
MIN_FONT_PT = 8.0
#: The report's pictures are printed at this fraction of their layout size: a 500 px wide map is
#: 3.45 in on paper, two side by side on A4 (and its PNG, one pixel per layout pixel, is 145 dpi).
PRINT_SCALE = 0.69
#: Line spacing of text of several lines [font sizes] (as matplotlib set it).
LINE_SPACING = 1.2
#: The height of a line of text above and below its baseline [em]: the top of DejaVu Sans's "l" and
#: the bottom of its "p" (1556 and 426 of 2048 units), the box matplotlib aligns a line of text by.
ASCENT, DESCENT = 1556 / 2048, 426 / 2048

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


def _n(v: float) -> str:
    """A coordinate for the SVG: two decimals, never an exponent."""
    s = f"{v:.2f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def split_nan(p: np.ndarray) -> list[np.ndarray]:
    """The runs of two or more finite points of a polyline (k, 2) with NaN breaks."""
    ok = np.all(np.isfinite(p), axis=1)
    if ok.all():
        return [p] if len(p) >= 2 else []
    edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.astype(np.int8), [0]])))
    return [p[a:b] for a, b in zip(edges[::2], edges[1::2]) if b - a >= 2]


def _thinned(p: np.ndarray, step_px: float = 2.0) -> np.ndarray:
    """A long polyline (k, 2) [layout px] with its points at least about ``step_px`` apart along it
    (the first point of each step, and the last point): a sun path sampled every 2 min has points
    half a pixel apart, and a chord of 2 px on a curve of radius 100 px is 0.005 px off it."""
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

    def image(self, rgb: np.ndarray, box: tuple[int, int, int, int]) -> None:
        """An RGB image (h, w, 3) uint8 pixel for pixel in ``box`` (left, bottom, w, h) [whole layout px]."""
        self.items.append(("image", np.ascontiguousarray(rgb, dtype=np.uint8), tuple(int(v) for v in box)))

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
        pieces = [_thinned(p) if len(p) > 64 else p for p in pieces]  # a long curve's points 2 px apart
        if pieces and (stroke is not None or fill is not None):
            self.items.append(("path", pieces, None if stroke is None else colour_hex(stroke), float(lw),
                               None if fill is None else colour_hex(fill), bool(closed), tuple(dash) if dash else None, alpha))

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
        from en17037cli.report.pictures.raster import font

        f = font(size * self.pt, bold)
        return max(f.getlength(line) for line in str(s).split("\n"))

    def render(self, fmt: str = "png"):
        """The PNG bytes, the SVG as UTF-8 bytes, or for ``fmt="both"`` the pair (png, svg)."""
        if fmt not in ("png", "svg", "both"):
            raise ValueError(f"fmt must be 'png', 'svg' or 'both', not {fmt!r}")
        from en17037cli.report.pictures.raster import png

        if fmt == "png":
            return png(self)
        return (png(self), svg(self)) if fmt == "both" else svg(self)


def svg(c: Canvas) -> bytes:
    """The canvas as an SVG document: vector paths, cells without anti-aliasing, images as inline
    PNG, text as text; its size in printed points, its ``viewBox`` in layout pixels (y down)."""
    from en17037cli.report.pictures.raster import encode_png

    W, H = c.width, c.height
    out = ['<?xml version="1.0" encoding="utf-8" standalone="no"?>\n'
           f'<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="{_n(W * c.scale * 0.72)}pt" '
           f'height="{_n(H * c.scale * 0.72)}pt" viewBox="0 0 {W} {H}" version="1.1">\n'
           f'<rect width="{W}" height="{H}" style="fill: #ffffff"/>\n']
    for item in c.items:
        kind = item[0]
        if kind == "image":
            _, rgb, (x0, y0, w, h) = item
            data = base64.b64encode(encode_png(rgb)).decode("ascii")
            out.append(f'<image x="{x0}" y="{H - y0 - h}" width="{w}" height="{h}" preserveAspectRatio="none" '
                       f'style="image-rendering: pixelated" xlink:href="data:image/png;base64,{data}"/>\n')
        elif kind == "cells":
            out.append(_svg_cells(item[1], item[2], H))
        elif kind == "path":
            out.append(_svg_path(c, *item[1:], H))
        elif kind == "markers":
            _, p, size, fill, stroke, lw = item
            r = 0.5 * size * c.pt
            style = f"fill: {fill or 'none'}" + (f"; stroke: {stroke}; stroke-width: {_n(lw * c.pt)}" if stroke else "")
            arc = f"a{_n(r)} {_n(r)} 0 1 0 {_n(2 * r)} 0a{_n(r)} {_n(r)} 0 1 0 {_n(-2 * r)} 0z"
            d = ("M%.2f %.2f" + arc.replace("%", "%%")) * len(p) % tuple(np.column_stack([p[:, 0] - r, H - p[:, 1]]).ravel().tolist())
            out.append(f'<path d="{d}" style="{style}"/>\n')
        else:
            out.append(_svg_text(c, *item[1:], H))
    out.append("</svg>\n")
    return "".join(out).encode("utf-8")


def _svg_cells(quads: np.ndarray, rgb: np.ndarray, H: int) -> str:
    """One path per colour (cells grouped by colour), not anti-aliased: no seams between cells."""
    q = quads.copy()
    q[..., 1] = H - q[..., 1]
    key = (rgb[:, 0].astype(np.int64) << 16) | (rgb[:, 1].astype(np.int64) << 8) | rgb[:, 2]
    order = np.argsort(key, kind="stable")
    keys, starts = np.unique(key[order], return_index=True)
    ends = np.append(starts[1:], len(order))
    out = ['<g style="shape-rendering: crispEdges">\n']
    for k, a, b in zip(keys, starts, ends):  # one per colour
        flat = tuple(q[order[a:b]].reshape(-1).tolist())
        d = ("M%.2f %.2fL%.2f %.2fL%.2f %.2fL%.2f %.2fZ" * (b - a)) % flat
        out.append(f'<path d="{d}" style="fill: #{int(k):06x}"/>\n')
    out.append("</g>\n")
    return "".join(out)


def _svg_d(p: np.ndarray, H: float, closed: bool) -> str:
    """The ``d`` of a polyline (k, 2) [layout px, y up]: two decimals (one format of all its points)."""
    q = p.copy()
    q[:, 1] = H - q[:, 1]
    return "M" + ("%.2f %.2fL" * len(q) % tuple(q.ravel().tolist()))[:-1] + ("Z" if closed else "")


def _svg_path(c: Canvas, pieces, stroke, lw, fill, closed, dash, alpha, H) -> str:
    d = "".join(_svg_d(p, H, closed) for p in pieces)
    style = [f"fill: {fill}" if fill else "fill: none"]
    if stroke:
        style.append(f"stroke: {stroke}; stroke-width: {_n(lw * c.pt)}; stroke-linecap: butt; stroke-linejoin: round")
        if dash:
            style.append("stroke-dasharray: " + ",".join(_n(v * c.pt) for v in dash))
    if alpha < 1:
        style.append(f"opacity: {alpha:g}")
    return f'<path d="{d}" style="{"; ".join(style)}"/>\n'


def _svg_text(c: Canvas, x, y, s, size, ha, va, colour, bold, rotation, box, H) -> str:
    em = size * c.pt
    anchor = {"left": "start", "center": "middle", "right": "end"}[ha]
    style = (("font-weight: 700; " if bold else "") + f"font-size: {math.ceil(em * 1000) / 1000:g}px; "
             f"font-family: 'DejaVu Sans', sans-serif; text-anchor: {anchor}" + ("" if colour == "#000000" else f"; fill: {colour}"))
    out = []
    lines = c.lines_of(x, y, s, size, ha, va, rotation)
    if box is not None:
        from en17037cli.report.pictures.raster import text_box

        x0, y0, x1, y1 = text_box(c, lines, size, ha, bold, box[2])
        out.append(f'<rect x="{_n(x0)}" y="{_n(H - y1)}" width="{_n(x1 - x0)}" height="{_n(y1 - y0)}" rx="{_n(0.3 * em)}" '
                   f'style="fill: {colour_hex(box[0])}; opacity: {box[1]:g}"/>\n')
    for line, lx, ly in lines:
        rot = f' transform="rotate(-90 {_n(lx)} {_n(H - ly)})"' if rotation == 90 else ""
        out.append(f'<text style="{style}" x="{_n(lx)}" y="{_n(H - ly)}"{rot}>{xml_text(line)}</text>\n')
    return "".join(out)


def warm_up() -> None:
    """Load the drawing code and the fonts by drawing a tiny picture: the first picture's fixed cost,
    for a caller to pay in a background process while it traces rays."""
    c = Canvas(20, 20)
    c.text(2, 10, "0°")
    c.path(np.array([[0, 0], [10, 10]]))
    c.render("both")


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
