"""A :class:`~.canvas.Canvas` drawn as PNG with Pillow and numpy (Pillow comes with matplotlib, the
``plot`` extra; it is imported inside the functions that draw, so the package imports without it).

One PNG pixel per layout pixel, drawn in four layers whatever the order of the canvas's items
within a layer: (1) images and cells at their exact colours, without anti-aliasing (a pixel whose
centre lies in a cell takes its colour, each pixel in at most one cell of a tiling); (2) paths,
anti-aliased by drawing them at :data:`SUPERSAMPLE` x the resolution as an index image (Pillow's
polygons and lines, one index per colour) and averaging each pixel's samples, so that a pixel no
path touches keeps its exact colour; markers, anti-aliased by their coverage (numpy, in their
place among the paths); (3) text by FreeType (Pillow), with the DejaVu Sans matplotlib bundles.

Reproducible: the same canvas gives the same bytes on one installation (Pillow writes no date and
no version string; the zlib level is fixed).
"""
from __future__ import annotations

import functools
import math
import os
import struct
import threading
import zlib

import numpy as np

from en17037cli.report.pictures.canvas import ASCENT, DESCENT, DPI, Canvas, colour_rgb

#: Samples per pixel side of the anti-aliased paths (4: a pixel's row of samples is a 32-bit word).
SUPERSAMPLE = 4
#: zlib level of the PNG files (1: about 1 ms for a 500 x 360 picture, 20 % larger than at 6).
PNG_LEVEL = 1
#: Most cell-pixel candidates tested at once (memory bound of :func:`_fill_cells`).
_CHUNK = 1 << 21


@functools.cache
def _font_dir() -> str | None:
    """matplotlib's bundled fonts (found without importing matplotlib), or None."""
    import importlib.util

    spec = importlib.util.find_spec("matplotlib")
    if spec is None or not spec.submodule_search_locations:
        return None
    path = os.path.join(list(spec.submodule_search_locations)[0], "mpl-data", "fonts", "ttf")
    return path if os.path.isdir(path) else None


@functools.lru_cache(maxsize=64)
def font(size_px: float, bold: bool = False):
    """DejaVu Sans (bold) at ``size_px`` pixels, laid out by Raqm where Pillow has it (right-to-left
    scripts in their order, as matplotlib draws them), else character by character."""
    from PIL import ImageFont, features

    d = _font_dir()
    name = "DejaVuSans-Bold.ttf" if bold else "DejaVuSans.ttf"
    if d is None:
        return ImageFont.load_default(size_px)
    layout = ImageFont.Layout.RAQM if features.check("raqm") else ImageFont.Layout.BASIC
    return ImageFont.truetype(os.path.join(d, name), size_px, layout_engine=layout)


def encode_png(rgb: np.ndarray, dpi: float | None = None) -> bytes:
    """PNG bytes of an RGB image (h, w, 3) or RGBX image (h, w, 4) uint8: 8 bits a channel, rows
    unfiltered (the pictures' flat colours compress well without), zlib at :data:`PNG_LEVEL`; its
    resolution (``pHYs``) if ``dpi`` is given, no date and no version string.

    References
    ----------
    W3C, Portable Network Graphics (PNG) Specification, 3rd ed. (2025), 5 (chunks), 11.2.1 (IHDR),
    11.3.5.3 (pHYs), 7.3 and 9 (filter type 0).
    """
    h, w = rgb.shape[:2]
    raw = _scratch("raw", (h, 1 + 3 * w))  # each row: its filter type (0, none), then its pixels
    raw[:, 0] = 0
    pixels = raw[:, 1:].reshape(h, w, 3)
    for k in range(3):  # a channel at a time: numpy copies every fourth byte slowly
        pixels[..., k] = rgb[..., k]

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    out = [b"\x89PNG\r\n\x1a\n", chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))]
    if dpi:
        ppm = int(round(dpi / 0.0254))
        out.append(chunk(b"pHYs", struct.pack(">IIB", ppm, ppm, 1)))
    out += [chunk(b"IDAT", zlib.compress(memoryview(raw).cast("B"), PNG_LEVEL)), chunk(b"IEND", b"")]
    return b"".join(out)


_SCRATCH = threading.local()


def _scratch(name: str, shape: tuple[int, ...]) -> np.ndarray:
    """A uint8 array of ``shape`` on a buffer kept for the next picture of this thread (its content
    is what the last user left): a fresh array of a few megabytes each picture costs more in page
    faults than the drawing."""
    n = int(np.prod(shape))
    b = getattr(_SCRATCH, name, None)
    if b is None or b.size < n:
        b = np.empty(n, dtype=np.uint8)
        setattr(_SCRATCH, name, b)
    return b[:n].reshape(shape)


def _drawable(a: np.ndarray, mode: str):
    """A Pillow image of mode ``"L"`` or ``"RGBX"`` that draws into the array ``a`` itself ((h, w) or
    (h, w, 4) uint8, C-contiguous): Pillow maps the buffer (``frombuffer``) and is told it may write
    to it, so no copy of the pixels is made either way. Where a Pillow would copy instead (checked once,
    :func:`_maps_buffers`), None."""
    from PIL import Image

    if not _maps_buffers():
        return None
    im = Image.frombuffer(mode, (a.shape[1], a.shape[0]), a, "raw", mode, 0, 1)
    im.readonly = 0
    return im


@functools.lru_cache(maxsize=1)
def _maps_buffers() -> bool:
    """Whether this Pillow draws into a buffer given to ``frombuffer`` once told it may."""
    from PIL import Image, ImageDraw

    a = np.zeros((2, 2), dtype=np.uint8)
    im = Image.frombuffer("L", (2, 2), a, "raw", "L", 0, 1)
    im.readonly = 0
    ImageDraw.Draw(im).point((1, 1), fill=7)
    return int(a[1, 1]) == 7


def png(c: Canvas) -> bytes:
    """The canvas drawn as PNG (see the module)."""
    from PIL import Image

    W, H = int(c.width), int(c.height)
    buf = _scratch("picture", (H, W, 4))  # RGBX, as Pillow holds RGB
    buf.fill(255)
    img = buf[..., :3]
    for item in c.items:
        if item[0] == "image":
            _, rgb, (x0, y0, w, h) = item
            r0, c0 = H - y0 - h, x0
            r1, c1 = min(r0 + h, H), min(c0 + w, W)
            if r1 > max(r0, 0) and c1 > max(c0, 0):
                img[max(r0, 0):r1, max(c0, 0):c1] = rgb[max(-r0, 0):r1 - r0, max(-c0, 0):c1 - c0]
        elif item[0] == "cells":
            q = item[1].copy()
            q[..., 1] = H - q[..., 1]
            _fill_cells(img, q, item[2])
    batch: list = []
    for item in c.items:
        if item[0] == "path":
            batch.append(item)
        elif item[0] == "markers":
            _paths(img, c, batch)
            batch = []
            _markers(img, c, item)
    _paths(img, c, batch)
    im = _drawable(buf, "RGBX")
    im = Image.fromarray(np.ascontiguousarray(img), "RGB") if im is None else im
    for item in c.items:
        if item[0] == "text":
            _text(im, c, *item[1:])
    return encode_png(buf if im.mode == "RGBX" else np.asarray(im), DPI / c.scale)


def _fill_cells(img: np.ndarray, quads: np.ndarray, rgb: np.ndarray) -> None:
    """Parallelograms (n, 4, 2) [px, x right, y down] filled where the pixel centres lie, half-open
    (a point of a shared edge belongs to one cell), later cells over earlier ones."""
    H, W = img.shape[:2]
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
        inside = (u >= 0) & (u < 1) & (v >= 0) & (v < 1) & ok[sl, None, None]
        inside &= (rows >= 0) & (rows < H) & (cols >= 0) & (cols < W)
        cell = np.broadcast_to(np.arange(s0, s0 + len(det[sl]))[:, None, None], inside.shape)
        img[np.broadcast_to(rows, inside.shape)[inside], np.broadcast_to(cols, inside.shape)[inside]] = rgb[cell[inside]]


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
        p = np.vstack(it[1])
        p = p[np.all(np.isfinite(p), axis=1)]
        if len(p):
            m = 2 + it[3] * c.pt
            groups.append([max(int(math.floor(p[:, 0].min() - m)), 0), max(int(math.floor(H - p[:, 1].max() - m)), 0),
                           min(int(math.ceil(p[:, 0].max() + m)), W), min(int(math.ceil(H - p[:, 1].min() + m)), H), [it]])
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


def _paths(img: np.ndarray, c: Canvas, items: list) -> None:
    """Paths drawn anti-aliased over ``img``, group by group (:func:`_boxes`)."""
    for box, group in _boxes(c, items, img.shape[0], img.shape[1]):
        _path_group(img, c, box, group)


def _path_group(img: np.ndarray, c: Canvas, box: tuple[int, int, int, int], items: list) -> None:
    """Paths drawn anti-aliased over ``img`` in ``box``: an index image at SUPERSAMPLE x, each pixel
    the mean of its samples (0: the pixel below). Indices start at 8, so that Pillow's mean of a
    pixel's samples (rounded) is 0 only where no path touches it."""
    from PIL import Image, ImageDraw

    S, H = SUPERSAMPLE, img.shape[0]
    x0, y0, x1, y1 = box
    samples = _scratch("samples", ((y1 - y0) * S, (x1 - x0) * S))
    samples.fill(0)
    ix = _drawable(samples, "L")
    mapped = ix is not None
    ix = ix if mapped else Image.new("L", samples.shape[::-1], 0)
    draw = ImageDraw.Draw(ix).draw  # Pillow's drawing core: polygons and lines in C
    palette: list = []
    shift = np.array([x0 * S + 0.5, 0.5 - (H - y0) * S])
    flip = np.array([S, -S], dtype=float)
    for _, pieces, stroke, lw, fill, closed, dash, alpha in items:  # one per path
        for colour in (fill, stroke):
            if colour is not None and (colour, alpha) not in palette:
                palette.append((colour, alpha))
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
    ty, tx = np.nonzero(np.asarray(ix.reduce(S)))
    if not len(ty):
        return
    # each pixel's S x S samples: its S rows of S bytes, read as S 32-bit words (S = 4)
    words = (samples if mapped else np.ascontiguousarray(np.asarray(ix))).view(np.uint32).ravel()
    at = (ty[:, None] * S + np.arange(S)[None, :]) * (x1 - x0) + tx[:, None]
    sub = words[at].view(np.uint8).reshape(len(ty), S * S)
    region = img[y0:y1, x0:x1]
    pal = np.array([colour_rgb(col) for col, _ in palette], dtype=float)
    alpha = np.array([al for _, al in palette])
    # a pixel all of whose samples have one index (inside a thick line) takes its colour at once
    first = sub[:, 0]
    same = first.astype(np.uint64) * np.uint64(0x0101010101010101)
    pure = np.all(sub.view(np.uint64) == same[:, None], axis=1)
    k = first[pure].astype(np.intp) - 8
    py, px = ty[pure], tx[pure]
    region[py, px] = np.round(region[py, px] * (1.0 - alpha[k])[:, None] + pal[k] * alpha[k][:, None]).astype(np.uint8)
    # the others: the mean of their samples, each the pixel below or a colour over it
    ty, tx, sub = ty[~pure], tx[~pure], sub[~pure]
    n = len(palette) + 8
    counts = np.bincount((np.arange(len(ty))[:, None] * n + sub).ravel(), minlength=len(ty) * n).reshape(len(ty), n)[:, 8:]
    w = counts * (alpha / (S * S))[None, :]
    out = region[ty, tx] * (1.0 - w.sum(axis=1))[:, None]
    for j in range(len(palette)):  # a few colours (no BLAS for a 3-column product)
        out += w[:, j, None] * pal[j]
    region[ty, tx] = np.clip(np.round(out), 0, 255).astype(np.uint8)


def _markers(img: np.ndarray, c: Canvas, item) -> None:
    """Discs and rings anti-aliased by their coverage of each pixel (a box filter of the distance to
    the centre); all the discs first, then all the rings."""
    _, p, size, fill, stroke, lw = item
    H, W = img.shape[:2]
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
    for colour, cov in layers:  # where two markers cover a pixel, the later one's coverage
        sel = inside & (cov > 0)
        rr, cc, a = rows[sel], cols[sel], cov[sel][:, None]
        img[rr, cc] = np.round(img[rr, cc] * (1 - a) + np.array(colour_rgb(colour)) * a).astype(np.uint8)


def text_box(c: Canvas, lines: list, size: float, ha: str, bold: bool, pad: float) -> tuple[float, float, float, float]:
    """(x0, y0, x1, y1) [layout px] around the lines of a text (as :meth:`Canvas.lines_of` gives
    them), ``pad`` [em] of air on each side."""
    em = size * c.pt
    f = font(em, bold)
    xs, ys = [], []
    for line, lx, ly in lines:
        w = f.getlength(line)
        left = lx - {"left": 0.0, "center": 0.5 * w, "right": w}[ha]
        xs += [left, left + w]
        ys += [ly - DESCENT * em, ly + ASCENT * em]
    p = pad * em
    return min(xs) - p, min(ys) - p, max(xs) + p, max(ys) + p


@functools.lru_cache(maxsize=4096)
def _glyphs(line: str, size_px: float, bold: bool, ha: str, rotation: int):
    """A line of text as a coverage mask (an ``"L"`` image) and the offset [px] from its anchor (the
    baseline at its left, centre or right) to the mask's top-left corner, rotated by 0 or 90 deg
    counter-clockwise. Kept for the next picture: a process draws the same labels again and again."""
    from PIL import Image, ImageDraw

    f = font(size_px, bold)
    anchor = {"left": "l", "center": "m", "right": "r"}[ha] + "s"
    left, top, right, bottom = f.getbbox(line, anchor=anchor)
    if right <= left or bottom <= top:
        return None, (0, 0)
    mask = Image.new("L", (right - left, bottom - top), 0)
    ImageDraw.Draw(mask).text((-left, -top), line, fill=255, font=f, anchor=anchor)
    if rotation == 90:  # (u, v) of the text -> (v, -u) of the picture
        return mask.transpose(Image.Transpose.ROTATE_90), (top, -right)
    return mask, (left, top)


def _text(im, c: Canvas, x, y, s, size, ha, va, colour, bold, rotation, box) -> None:
    """A text item drawn onto the Pillow image ``im``: each line's FreeType coverage (:func:`_glyphs`)
    at a whole pixel, in its colour; its box first."""
    from PIL import Image

    H = im.height
    lines = c.lines_of(x, y, s, size, ha, va, rotation)
    if box is not None:
        bx0, by0, bx1, by1 = text_box(c, lines, size, ha, bold, box[2])
        w, h = int(round(bx1 - bx0)), int(round(by1 - by0))
        if w > 0 and h > 0:
            im.paste(colour_rgb(box[0]), (int(round(bx0)), int(round(H - by1))), Image.new("L", (w, h), int(round(255 * box[1]))))
    rgb = colour_rgb(colour)
    for line, lx, ly in lines:
        mask, (ox, oy) = _glyphs(line, size * c.pt, bold, ha, rotation)
        if mask is not None:
            im.paste(rgb, (int(round(lx)) + ox, int(round(H - ly)) + oy), mask)
