"""A :class:`~.canvas.Canvas` written as an SVG document: its size in printed points, its ``viewBox``
in layout pixels (y down); paths as paths, cells without anti-aliasing (``crispEdges``: no seams
between cells in a browser), images as inline PNG scaled without smoothing, text as text (``svg.fonttype
none`` of matplotlib: selectable and measurable in a browser), escaped as XML."""
from __future__ import annotations

import base64
import math

import numpy as np

from en17037cli.report.pictures.canvas import Canvas, colour_hex, xml_text
from en17037cli.report.pictures.pngfile import encode_png
from en17037cli.report.pictures.text import text_box


def _n(v: float) -> str:
    """A coordinate for the SVG: two decimals, never an exponent."""
    s = f"{v:.2f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def svg(c: Canvas) -> bytes:
    """The canvas as an SVG document: vector paths, cells without anti-aliasing, images as inline
    PNG, text as text; its size in printed points, its ``viewBox`` in layout pixels (y down). The
    layers of the PNG (:mod:`.raster`): images and cells, then paths and markers, then text."""
    W, H = c.width, c.height
    out = ['<?xml version="1.0" encoding="utf-8" standalone="no"?>\n'
           f'<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="{_n(W * c.scale * 0.72)}pt" '
           f'height="{_n(H * c.scale * 0.72)}pt" viewBox="0 0 {W} {H}" version="1.1">\n'
           f'<rect width="{W}" height="{H}" style="fill: #ffffff"/>\n']
    layer = {"image": 0, "cells": 0, "path": 1, "markers": 1, "text": 2}  # as the PNG draws them: text on top
    for item in sorted(c.items, key=lambda it: layer[it[0]]):  # a stable sort: in order within a layer
        kind = item[0]
        if kind == "image":
            _, pixels, (x0, y0, w, h), palette = item
            data = base64.b64encode(encode_png(pixels, palette=palette)).decode("ascii")
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


def _svg_path(c: Canvas, pieces, stroke, lw, fill, closed, dash, alpha, box, H) -> str:
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
        x0, y0, x1, y1 = text_box(lines, em, ha, bold, box[2])
        out.append(f'<rect x="{_n(x0)}" y="{_n(H - y1)}" width="{_n(x1 - x0)}" height="{_n(y1 - y0)}" rx="{_n(0.3 * em)}" '
                   f'style="fill: {colour_hex(box[0])}; opacity: {box[1]:g}"/>\n')
    for line, lx, ly in lines:
        rot = f' transform="rotate(-90 {_n(lx)} {_n(H - ly)})"' if rotation == 90 else ""
        out.append(f'<text style="{style}" x="{_n(lx)}" y="{_n(H - ly)}"{rot}>{xml_text(line)}</text>\n')
    return "".join(out)
