"""A :class:`~.canvas.Canvas` drawn as PNG with Pillow and numpy (Pillow comes with matplotlib, the
``plot`` extra; it is imported inside the functions that draw, so the package imports without it).

One PNG pixel per layout pixel, drawn in three layers, in order within each: (1) images and cells at
their exact colours, without anti-aliasing (a pixel whose centre lies in a cell takes its colour,
each pixel in one cell of a tiling); (2) paths, anti-aliased by drawing them at :data:`SUPERSAMPLE` x
the resolution as an index image (Pillow's polygons and lines in C, one index per colour) and
averaging each pixel's samples, so that a pixel no path touches keeps its exact colour; markers
among them, anti-aliased by their coverage (numpy); (3) text by FreeType (:mod:`.text`). The
picture is held as 32-bit words, one a pixel, which Pillow draws into directly (its RGBX layout).

Reproducible: the same canvas gives the same bytes on one installation (:mod:`.pngfile` writes no
date and no version string, its zlib level is fixed).
"""
from __future__ import annotations

import functools
import math
import threading

import numpy as np

from en17037cli.report.pictures.canvas import DPI, Canvas, colour_rgb
from en17037cli.report.pictures.pngfile import encode_png
from en17037cli.report.pictures.text import glyphs, text_box

#: Samples per pixel side of the anti-aliased paths (4: a pixel's row of samples is a 32-bit word).
SUPERSAMPLE = 4
#: A cell's coordinates (u, v) of a pixel centre in [-EPS, 1 - EPS) put it in the cell [-].
_EPS = 1e-9
#: Most cell-pixel candidates tested at once (memory bound of :func:`_fill_cells`).
_CHUNK = 1 << 21


def _drawable(name: str, shape: tuple[int, ...], mode: str):
    """A scratch array of ``shape`` (uint8; (h, w) for mode ``"L"``, (h, w, 4) for ``"RGBX"``) and a
    Pillow image that draws into it: Pillow maps the buffer (``frombuffer``) and is told it may write
    to it, so no pixel is copied either way; both kept for the next picture of this thread. Where a
    Pillow would copy instead (checked once, :func:`_maps_buffers`): None and an image of its own."""
    from PIL import Image

    images = _IMAGES.__dict__.setdefault("images", {})
    mapped = _maps_buffers()
    key = (name, shape, mode, mapped)
    if key not in images:
        if mapped:
            a = np.empty(shape, dtype=np.uint8)  # its own buffer, kept with its image
            im = Image.frombuffer(mode, (shape[1], shape[0]), a, "raw", mode, 0, 1)
            im.readonly = 0
            images[key] = (a, im)
        else:
            images[key] = (None, Image.new("RGB" if mode == "RGBX" else mode, (shape[1], shape[0])))
    return images[key]


_IMAGES = threading.local()


@functools.lru_cache(maxsize=1)
def _maps_buffers() -> bool:
    """Whether this Pillow draws into a buffer given to ``frombuffer`` once told it may."""
    from PIL import Image, ImageDraw

    a = np.zeros((2, 2), dtype=np.uint8)
    im = Image.frombuffer("L", (2, 2), a, "raw", "L", 0, 1)
    im.readonly = 0
    ImageDraw.Draw(im).point((1, 1), fill=7)
    return int(a[1, 1]) == 7


def render(c: Canvas, fmt: str = "png"):
    """The canvas as PNG bytes, as the SVG document's UTF-8 bytes (:func:`~.svg.svg`), or for
    ``fmt="both"`` the pair (png, svg)."""
    from en17037cli.report.pictures.svg import svg

    if fmt not in ("png", "svg", "both"):
        raise ValueError(f"fmt must be 'png', 'svg' or 'both', not {fmt!r}")
    if fmt == "png":
        return png(c)
    return (png(c), svg(c)) if fmt == "both" else svg(c)


def png(c: Canvas) -> bytes:
    """The canvas drawn as PNG (see the module)."""
    from PIL import Image

    W, H = int(c.width), int(c.height)
    buf, im = _drawable("picture", (H, W, 4), "RGBX")  # RGBX, as Pillow holds RGB
    buf = np.empty((H, W, 4), dtype=np.uint8) if buf is None else buf
    buf.fill(255)
    img = buf[..., :3]
    px = buf.view("<u4").reshape(H, W)  # a pixel a word: R | G << 8 | B << 16 | X << 24
    for item in c.items:
        if item[0] == "image":
            _, pixels, (x0, y0, w, h), palette = item
            if pixels.shape[:2] != (h, w):  # nearest pixel
                rows = np.minimum(((np.arange(h) + 0.5) * pixels.shape[0] / h).astype(int), pixels.shape[0] - 1)
                cols = np.minimum(((np.arange(w) + 0.5) * pixels.shape[1] / w).astype(int), pixels.shape[1] - 1)
                pixels = pixels[rows][:, cols]
            words = _pack(palette)[pixels] if palette is not None else _pack(pixels.reshape(-1, 3)).reshape(h, w)
            r0, c0 = H - y0 - h, x0
            r1, c1 = min(r0 + h, H), min(c0 + w, W)
            if r1 > max(r0, 0) and c1 > max(c0, 0):
                px[max(r0, 0):r1, max(c0, 0):c1] = words[max(-r0, 0):r1 - r0, max(-c0, 0):c1 - c0]
        elif item[0] == "cells":
            q = item[1].copy()
            q[..., 1] = H - q[..., 1]
            _fill_cells(px, q, item[2])
    batch: list = []
    for item in c.items:
        if item[0] == "path":
            batch.append(item)
        elif item[0] == "markers":
            _paths(px, c, batch)
            batch = []
            _markers(px, c, item)
    _paths(px, c, batch)
    if im.mode != "RGBX":  # a Pillow that copies: the pixels into its image and back
        im.paste(Image.fromarray(np.ascontiguousarray(img), "RGB"))
    for item in c.items:
        if item[0] == "text":
            _text(im, c, *item[1:])
    return encode_png(buf if im.mode == "RGBX" else np.asarray(im), DPI / c.scale)


def _pack(rgb: np.ndarray) -> np.ndarray:
    """(n, 3) colours 0..255 as (n,) pixel words (R | G << 8 | B << 16 | 255 << 24)."""
    c = np.asarray(rgb).astype(np.uint32)
    return c[:, 0] | (c[:, 1] << 8) | (c[:, 2] << 16) | np.uint32(0xFF000000)


def _unpack(words: np.ndarray) -> np.ndarray:
    """(n,) pixel words as (n, 3) float colours 0..255."""
    return ((words[:, None] >> np.array([0, 8, 16], dtype=np.uint32)) & 0xFF).astype(float)


def _fill_cells(px: np.ndarray, quads: np.ndarray, rgb: np.ndarray) -> None:
    """Parallelograms (n, 4, 2) [px, x right, y down] filled where the pixel centres lie, half-open
    (a point of a shared edge belongs to one cell), later cells over earlier ones; ``px`` the
    picture's pixel words (H, W)."""
    H, W = px.shape
    words = _pack(rgb)
    c0 = quads[:, 0]
    a, b = quads[:, 1] - c0, quads[:, 3] - c0
    det = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    ok = np.abs(det) > 1e-12
    lo = np.floor(quads.min(axis=1)).astype(int)
    kx, ky = (np.ceil((quads.max(axis=1) - quads.min(axis=1)).max(axis=0)).astype(int) + 1).tolist()  # the largest cell's box
    step = max(1, _CHUNK // (kx * ky))
    for s0 in range(0, len(quads), step):  # chunks of cells, a bounded memory
        sl = slice(s0, s0 + step)
        cols = lo[sl, 0, None, None] + np.arange(kx)[None, None, :]
        rows = lo[sl, 1, None, None] + np.arange(ky)[None, :, None]
        dx, dy = cols + 0.5 - c0[sl, 0, None, None], rows + 0.5 - c0[sl, 1, None, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            d = det[sl, None, None]
            u = (dx * b[sl, 1, None, None] - dy * b[sl, 0, None, None]) / d
            v = (a[sl, 0, None, None] * dy - a[sl, 1, None, None] * dx) / d
        # half-open, shifted by the rounding of u and v: a centre on a shared edge falls in one cell
        inside = (u >= -_EPS) & (u < 1 - _EPS) & (v >= -_EPS) & (v < 1 - _EPS) & ok[sl, None, None]
        inside &= (rows >= 0) & (rows < H) & (cols >= 0) & (cols < W)
        cell = np.broadcast_to(np.arange(s0, s0 + len(det[sl]))[:, None, None], inside.shape)
        flat = (rows * W + cols)  # the pixels' places in the picture
        px.reshape(-1)[np.broadcast_to(flat, inside.shape)[inside]] = words[cell[inside]]


def _dashes(p: np.ndarray, pattern: tuple, closed: bool) -> list[list[float]]:
    """The drawn pieces of a polyline (k, 2) dashed by ``pattern`` (on, off, ... lengths, same unit),
    each a flat list of coordinates."""
    if closed:
        p = np.vstack([p, p[:1]])
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])
    total, period = s[-1], float(sum(pattern))
    if total <= 0 or period <= 0:
        return []
    bounds = np.concatenate([[0.0], np.cumsum(np.tile(pattern, int(total // period) + 1))])
    a, b = bounds[0:-1:2], np.minimum(bounds[1::2], total)
    a, b = a[b > a], b[b > a]
    ends = np.column_stack([np.interp(a, s, p[:, 0]), np.interp(a, s, p[:, 1]), np.interp(b, s, p[:, 0]), np.interp(b, s, p[:, 1])])
    ia, ib = np.searchsorted(s, a, side="right"), np.searchsorted(s, b, side="left")  # the vertices inside each dash
    out = ends.tolist()
    for k in np.flatnonzero(ib > ia):  # the dashes round a corner
        out[k] = [*out[k][:2], *p[ia[k]:ib[k]].ravel().tolist(), *out[k][2:]]
    return out


#: Paths of at most this many points are drawn with round joins (a disc at each point).
_JOINED = 64


#: Groups of paths closer than this are drawn as one (a legend's entries) [px].
_NEAR = 16


def _boxes(c: Canvas, items: list, H: int, W: int) -> list[tuple[tuple[int, int, int, int], list]]:
    """The paths grouped by where they are drawn: (x0, y0, x1, y1) [PNG px, y down] of each group
    and its paths in drawing order; groups whose boxes meet are merged, so the groups' boxes are
    disjoint and each is drawn on its own (a picture's plan, colour bar, north arrow apart); groups nearer than
    :data:`_NEAR` are merged too."""
    groups = []
    for it in items:
        (xa, ya, xb, yb), m = it[8], 2 + it[3] * c.pt  # the path's box, its line's half width and a pixel more
        groups.append([max(int(math.floor(xa - m)), 0), max(int(math.floor(H - yb - m)), 0), min(int(math.ceil(xb + m)), W),
                       min(int(math.ceil(H - ya + m)), H), [it]])
    merged = True
    while merged:  # a handful of groups
        merged = False
        for i in range(len(groups)):
            for j in range(i + 1, len(groups)):
                a, b = groups[i], groups[j]
                if a[0] < b[2] + _NEAR and b[0] < a[2] + _NEAR and a[1] < b[3] + _NEAR and b[1] < a[3] + _NEAR:
                    groups[i] = [min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]), a[4] + b[4]]
                    del groups[j]
                    merged = True
                    break
            if merged:
                break
    order = {id(it): k for k, it in enumerate(items)}
    return [((g[0], g[1], g[2], g[3]), sorted(g[4], key=lambda it: order[id(it)])) for g in groups if g[2] > g[0] and g[3] > g[1]]


def _paths(px: np.ndarray, c: Canvas, items: list) -> None:
    """Paths drawn anti-aliased over the picture's pixel words ``px``, group by group (:func:`_boxes`)."""
    for box, group in _boxes(c, items, px.shape[0], px.shape[1]):
        _path_group(px, c, box, group)


def _path_group(px: np.ndarray, c: Canvas, box: tuple[int, int, int, int], items: list) -> None:
    """Paths drawn anti-aliased over the pixel words ``px`` in ``box``: an index image at SUPERSAMPLE x, each pixel
    the mean of its samples (0: the pixel below). Indices start at 8, so that Pillow's mean of a
    pixel's samples (rounded) is 0 only where no path touches it."""
    from PIL import ImageDraw

    S, H, W = SUPERSAMPLE, px.shape[0], px.shape[1]
    x0, y0, x1, y1 = box
    samples, ix = _drawable("samples", (H * S, W * S), "L")  # the whole picture's samples, this box cleared
    draw = ImageDraw.Draw(ix).draw  # Pillow's drawing core: polygons and lines in C
    if samples is None:
        draw.draw_rectangle((x0 * S, y0 * S, x1 * S - 1, y1 * S - 1), 0, 1, 0)
    else:
        samples[y0 * S:y1 * S, x0 * S:x1 * S] = 0
    palette: list = []
    shift = np.array([0.5, 0.5 - H * S])  # layout px -> the samples' pixels, y down
    flip = np.array([S, -S], dtype=float)
    for _, pieces, stroke, lw, fill, closed, dash, alpha, _ in items:  # one per path
        for colour in (fill, stroke):
            if colour is not None and (colour, alpha) not in palette:
                palette.append((colour, alpha))
        if len(palette) > 255 - 8:
            raise ValueError("the paths of one part of a picture take at most 247 colours")
        width = max(1, int(round(lw * c.pt * S)))
        for p in pieces:
            q = p * flip - shift  # the index image's pixels
            if fill is not None and len(q) >= 3:
                draw.draw_polygon(q.ravel().tolist(), palette.index((fill, alpha)) + 8, 1)
            if stroke is None:
                continue
            ink = palette.index((stroke, alpha)) + 8
            if dash:
                for r in _dashes(q, tuple(v * c.pt * S for v in dash), closed):  # one per dash
                    draw.draw_lines(r, ink, width)
                continue
            draw.draw_lines((np.vstack([q, q[:1]]) if closed else q).ravel().tolist(), ink, width)
            if width > 2 and 2 < len(q) <= _JOINED:  # round joins
                for x, y in (q if closed else q[1:-1]).tolist():
                    draw.draw_ellipse((x - width / 2, y - width / 2, x + width / 2, y + width / 2), ink, 1, 0)
    ty, tx = np.nonzero(np.asarray(ix.reduce(S, box=(x0 * S, y0 * S, x1 * S, y1 * S))))
    if not len(ty):
        return
    ty, tx = ty + y0, tx + x0
    # each pixel's S x S samples: its S rows of S bytes, read as S 32-bit words (S = 4)
    words = (samples if samples is not None else np.asarray(ix)).view(np.uint32).ravel()
    rows = (ty * (S * W) + tx)[:, None] + np.arange(0, S * W, W)[None, :]
    sub = words[rows].view(np.uint8).reshape(len(ty), S * S)
    pal = np.array([colour_rgb(col) for col, _ in palette], dtype=float)
    alpha = np.array([al for _, al in palette])
    flat = px.reshape(-1)
    at = ty * W + tx  # the pixels' places in the picture
    # a pixel all of whose samples have one index (inside a thick line) takes its colour at once
    first = sub[:, 0]
    same = first.astype(np.uint64) * np.uint64(0x0101010101010101)
    pure = np.all(sub.view(np.uint64) == same[:, None], axis=1)
    k = first[pure].astype(np.intp) - 8
    if (alpha == 1.0).all():
        flat[at[pure]] = _pack(pal.astype(np.uint8))[k]
    else:
        below = _unpack(flat[at[pure]])
        flat[at[pure]] = _pack(np.round(below * (1.0 - alpha[k])[:, None] + pal[k] * alpha[k][:, None]))
    # the others: the mean of their samples, each the pixel below or a colour over it
    at, sub = at[~pure], sub[~pure]
    n = len(palette) + 8
    counts = np.bincount((np.arange(len(at))[:, None] * n + sub).ravel(), minlength=len(at) * n).reshape(len(at), n)[:, 8:]
    w = counts * (alpha / (S * S))[None, :]
    out = _unpack(flat[at]) * (1.0 - w.sum(axis=1))[:, None]
    for j in range(len(palette)):  # a few colours (no BLAS for a 3-column product)
        out += w[:, j, None] * pal[j]
    flat[at] = _pack(np.clip(np.round(out), 0, 255))


def _markers(px: np.ndarray, c: Canvas, item) -> None:
    """Discs and rings anti-aliased by their coverage of each pixel (a box filter of the distance to
    the centre); all the discs first, then all the rings."""
    _, p, size, fill, stroke, lw = item
    H, W = px.shape
    r, w = 0.5 * size * c.pt, lw * c.pt if stroke else 0.0
    k = int(math.ceil(2 * r + w)) + 3
    cx, cy = p[:, 0], H - p[:, 1]
    off = np.arange(k)
    cols = np.floor(cx - k / 2).astype(int)[:, None, None] + off[None, None, :]
    rows = np.floor(cy - k / 2).astype(int)[:, None, None] + off[None, :, None]
    rows, cols = np.broadcast_arrays(rows, cols)
    d = np.hypot(cols + 0.5 - cx[:, None, None], rows + 0.5 - cy[:, None, None])
    inside = (rows >= 0) & (rows < H) & (cols >= 0) & (cols < W)
    layers = []
    if fill:
        layers.append((fill, np.clip(r + 0.5 - d, 0.0, 1.0)))
    if stroke:
        layers.append((stroke, np.clip(0.5 + 0.5 * w - np.abs(d - r), 0.0, 1.0) * min(1.0, w)))
    flat = px.reshape(-1)
    for colour, cov in layers:  # where two markers cover a pixel, the later one's coverage
        sel = inside & (cov > 0)
        at, a = rows[sel] * W + cols[sel], cov[sel][:, None]
        flat[at] = _pack(np.round(_unpack(flat[at]) * (1 - a) + np.array(colour_rgb(colour), dtype=float) * a))


def _text(im, c: Canvas, x, y, s, size, ha, va, colour, bold, rotation, box) -> None:
    """A text item drawn onto the Pillow image ``im``: each line's FreeType coverage (:func:`_glyphs`)
    at a whole pixel, in its colour; its box first."""
    from PIL import Image

    H = im.height
    lines = c.lines_of(x, y, s, size, ha, va, rotation)
    if box is not None:
        bx0, by0, bx1, by1 = text_box(lines, size * c.pt, ha, bold, box[2])
        w, h = int(round(bx1 - bx0)), int(round(by1 - by0))
        if w > 0 and h > 0:
            im.paste(colour_rgb(box[0]), (int(round(bx0)), int(round(H - by1))), Image.new("L", (w, h), int(round(255 * box[1]))))
    rgb = colour_rgb(colour)
    for line, lx, ly in lines:
        mask, (ox, oy) = glyphs(line, size * c.pt, bold, ha, rotation)
        if mask is not None:
            im.paste(rgb, (int(round(lx)) + ox, int(round(H - ly)) + oy), mask)


def warm_up() -> None:
    """Load the drawing code and the fonts by drawing a tiny picture: the first picture's fixed cost,
    for a caller to pay in a background process while it traces rays."""
    c = Canvas(20, 20)
    c.text(2, 10, "0°")
    c.text(2, 10, "N", bold=True)
    c.path(np.array([[0, 0], [10, 10]]))
    render(c, "both")
