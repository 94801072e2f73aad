"""The canvas the pictures are drawn on (report/pictures/canvas.py, raster.py, svg.py, pngfile.py):
its PNG and SVG checked against values worked out by hand.

Cells are filled without anti-aliasing (each pixel whose centre lies in a cell, a pixel on a shared
edge in one cell only); paths are anti-aliased, so their ink is measured as coverage (the darkness
of a column summed over its pixels is the line's width in pixels); text and colour tables are
checked against DejaVu Sans's metrics and matplotlib's own colour maps.
"""
from __future__ import annotations

import io
import math
import struct
import xml.etree.ElementTree as ET
import zlib

import numpy as np
import pytest
from test_pictures import png_chunks  # the PNG chunk reader its tests use

from en17037cli.report.pictures import raster
from en17037cli.report.pictures.canvas import MIN_FONT_PT, Canvas, xml_text
from en17037cli.report.pictures.colourmaps import TABLES, lookup
from en17037cli.report.pictures.colours import Norm
from en17037cli.report.pictures.pngfile import encode_png
from en17037cli.report.pictures.raster import render

PIL = pytest.importorskip("PIL.Image")


def decode(png: bytes) -> np.ndarray:
    return np.asarray(PIL.open(io.BytesIO(png)).convert("RGB"))




def test_png_file_holds_the_pixels_and_nothing_else():
    rng = np.random.default_rng(7)
    rgb = rng.integers(0, 256, (37, 53, 3), dtype=np.uint8)
    png = encode_png(rgb, dpi=100 / 0.69)
    assert np.array_equal(decode(png), rgb)
    kinds = [k for k, _ in png_chunks(png)]
    assert kinds == [b"IHDR", b"pHYs", b"IDAT", b"IEND"]  # no date, no text, no version string
    ppm = struct.unpack(">IIB", dict(png_chunks(png))[b"pHYs"])
    assert ppm == (5706, 5706, 1)  # 144.93 dpi / 0.0254 m per inch = 5705.8 pixels per metre
    raw = zlib.decompress(dict(png_chunks(png))[b"IDAT"])
    assert len(raw) == 37 * (1 + 3 * 53) and all(raw[r * (1 + 3 * 53)] == 0 for r in range(37))  # every row unfiltered
    rgbx = np.concatenate([rgb, np.full((37, 53, 1), 9, np.uint8)], axis=2)
    assert encode_png(rgbx, dpi=100 / 0.69) == png  # RGBX: the fourth byte left out


def test_cells_on_pixel_edges_cover_each_pixel_once():
    """A 4 x 4 tiling of 10 px squares whose edges run through pixel centres (x.5): the half-open rule
    gives each cell exactly 10 x 10 pixels, none shared, none left out."""
    c = Canvas(60, 60)
    x0 = 10.5
    quads, rgb = [], []
    for i in range(4):
        for j in range(4):
            x, y = x0 + 10 * i, x0 + 10 * j
            quads.append([[x, y], [x + 10, y], [x + 10, y + 10], [x, y + 10]])
            rgb.append([20 * i + 1, 20 * j + 1, 200])
    c.cells(np.array(quads), np.array(rgb, dtype=np.uint8))
    img = decode(render(c))
    for colour in rgb:
        assert int(np.all(img == colour, axis=-1).sum()) == 100
    assert int(np.all(img == 255, axis=-1).sum()) == 60 * 60 - 1600


@pytest.mark.parametrize("angle_deg", [0.0, 17.0, 30.0, 45.0])
def test_a_rotated_tiling_leaves_no_seam(angle_deg):
    """Cells of a grid turned by any angle: every pixel centre inside the tiled square belongs to a
    cell (no white seam between cells), and the pixels per cell add up to the square's area within
    its rim."""
    side, n = 12.0, 8
    a = math.radians(angle_deg)
    u, v = np.array([math.cos(a), math.sin(a)]), np.array([-math.sin(a), math.cos(a)])
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    origin = np.array([100.0, 100.0]) - (n * side / 2) * (u + v)
    corners = origin + side * (i.ravel()[:, None] * u + j.ravel()[:, None] * v)
    quads = np.stack([corners, corners + side * u, corners + side * (u + v), corners + side * v], axis=1)
    c = Canvas(200, 200)
    c.cells(quads, np.tile(np.array([[10, 120, 30]], dtype=np.uint8), (n * n, 1)))
    img = decode(render(c))
    filled = np.all(img == [10, 120, 30], axis=-1)
    rows, cols = np.indices(filled.shape)
    p = np.stack([cols + 0.5, 200 - rows - 0.5], axis=-1) - origin  # pixel centres, y up
    s, t = p @ u / side, p @ v / side
    inner = (s > 0.05) & (s < n - 0.05) & (t > 0.05) & (t < n - 0.05)
    assert filled[inner].all()  # no seam
    assert abs(int(filled.sum()) - (n * side) ** 2) <= 4 * n * side  # the area, within one pixel of rim


def test_a_line_is_as_dark_as_it_is_wide():
    """A horizontal black line of 1.2 pt (2.415 layout px at the print scale): each column across it
    is darkened by its width in pixels (the anti-aliased coverage adds up), to a sample (1/4 px)."""
    c = Canvas(100, 40)
    c.path(np.array([[10.0, 20.3], [90.0, 20.3]]), stroke="black", lw=1.2)
    img = decode(render(c)).astype(float)
    darkness = (255.0 - img[:, 20:80, 0]) / 255.0
    width_px = 1.2 * c.pt
    assert width_px == pytest.approx(2.415, abs=1e-3)
    assert np.allclose(darkness.sum(axis=0), width_px, atol=0.25)
    assert (img[:, :5] == 255).all()  # nothing beyond its butt ends


def test_a_ring_is_as_dark_as_its_length_times_its_width():
    """A ring of 5 pt diameter and 1 pt line (r = 5.03 px, w = 2.01 px): its ink is 2 pi r w."""
    c = Canvas(60, 60)
    c.markers([[30.2, 29.6]], 5, stroke="black", lw=1.0)
    img = decode(render(c)).astype(float)
    ink = ((255.0 - img[..., 0]) / 255.0).sum()
    r, w = 2.5 * c.pt, 1.0 * c.pt
    assert ink == pytest.approx(2 * math.pi * r * w, rel=0.03)


def test_paths_leave_untouched_pixels_exact_and_keep_their_order():
    c = Canvas(80, 80)
    c.cells(np.array([[[0, 0], [80, 0], [80, 80], [0, 80]]], dtype=float), np.array([[53, 183, 121]], dtype=np.uint8))
    c.path(np.array([[10.0, 40.0], [70.0, 40.0]]), stroke="black", lw=5.0)
    c.path(np.array([[10.0, 40.0], [70.0, 40.0]]), stroke="#8fd3ff", lw=3.0)  # a window: light inside a black casing
    img = decode(render(c))
    assert np.array_equal(img[5, 5], [53, 183, 121]) and np.array_equal(img[75, 75], [53, 183, 121])
    assert np.array_equal(img[39, 40], [0x8F, 0xD3, 0xFF])  # the later path on top
    column = img[:, 40]
    casing = np.flatnonzero(np.all(column == 0, axis=-1))
    assert len(casing) >= 2 and casing.min() < 37 and casing.max() > 41  # the casing shows on both sides


def test_text_lands_where_it_is_anchored():
    """'N' (DejaVu Sans, 9 pt) centred on (50, 30): its ink's box is centred there within a pixel
    (the box of 'l' and 'p' centres a line: the cap height of N sits 0.02 em above that centre)."""
    c = Canvas(100, 60)
    c.text(50.0, 30.0, "N", size=MIN_FONT_PT + 1, ha="center", va="center", bold=True)
    img = decode(render(c))
    rows, cols = np.nonzero(img[..., 0] < 128)
    cx, cy = 0.5 * (cols.min() + cols.max() + 1), 60 - 0.5 * (rows.min() + rows.max() + 1)
    assert abs(cx - 50.0) <= 1.0
    em = 9 * c.pt
    expected = 30.0 - (1556 / 2048 - 426 / 2048) / 2 * em + 0.5 * (1493 / 2048) * em  # baseline + half the cap height
    assert abs(cy - expected) <= 1.0


def test_a_pillow_that_copies_buffers_gives_the_same_picture(monkeypatch):
    """Pillow is told it may draw into numpy's buffers (no copies); where it would not, the drawing
    falls back to copies and must give the same bytes."""
    c = Canvas(120, 80)
    c.cells(np.array([[[10, 10], [50, 10], [50, 50], [10, 50]]], dtype=float), np.array([[68, 1, 84]], dtype=np.uint8))
    c.path(np.array([[5.0, 5.0], [110.0, 70.0]]), stroke="black", lw=1.5, dash=(4, 3))
    c.markers([[60.0, 40.0]], 5, stroke="white", lw=2.0)
    c.text(60.0, 20.0, "medium 28°", va="center", box=("white", 0.7, 0.1))
    fast = render(c, "both")
    monkeypatch.setattr(raster, "_maps_buffers", lambda: False)
    assert render(c, "both") == fast


def test_svg_is_xml_with_the_text_as_written():
    name = "Bürø \u0007 $\\alpha$ <b>&amp; \"q\" مرحبا 😀 \ud800x"
    c = Canvas(200, 100)
    c.cells(np.array([[[0, 0], [10, 0], [10, 10], [0, 10]], [[10, 0], [20, 0], [20, 10], [10, 10]]], dtype=float),
            np.array([[1, 2, 3], [1, 2, 3]], dtype=np.uint8))
    c.text(5.0, 50.0, name + "\nsecond line", va="center")
    svg = render(c, "svg")
    root = ET.fromstring(svg)
    ns = "{http://www.w3.org/2000/svg}"
    texts = [t.text for t in root.iter(ns + "text")]
    assert texts == [name.replace("\u0007", "\ufffd").replace("\ud800", "\ufffd"), "second line"]
    assert xml_text("<&>") == "&lt;&amp;&gt;"
    cells = [p for p in root.iter(ns + "path") if "#010203" in p.get("style", "")]
    assert len(cells) == 1 and cells[0].get("d").count("M") == 2  # one path for the cells of one colour
    assert root.get("viewBox") == "0 0 200 100" and root.get("width") == "99.36pt"  # 200 px x 0.69 x 0.72 pt/px


def test_colour_tables_are_matplotlibs():
    matplotlib = pytest.importorskip("matplotlib")
    for name, table in TABLES.items():
        cmap = matplotlib.colormaps[name]
        assert np.array_equal(table, np.round(np.asarray(cmap.colors) * 255).astype(np.uint8))
        t = np.concatenate([np.linspace(0.0, 1.0, 1001), [-0.2, 1.3]])
        assert np.array_equal(lookup(name, t), np.round(cmap(t)[:, :3] * 255).astype(np.uint8))  # the same entry


def test_norms_are_matplotlibs():
    colors = pytest.importorskip("matplotlib.colors")
    v = np.array([0.5, 1.0, 3.0, 20.0, 155.0, 400.0])
    assert np.allclose(Norm(1.0, 155.0, log=True)(v), colors.LogNorm(1.0, 155.0)(v), atol=1e-12)
    assert np.allclose(Norm(0.0, 67.5)(v), colors.Normalize(0.0, 67.5)(v), atol=1e-12)
    assert np.isnan(Norm(1.0, 10.0, log=True)(np.array([0.0, -1.0]))).all()  # no logarithm: the lowest colour's caller fills it


def test_a_long_curve_is_thinned_to_chords_close_to_it():
    """A sun path is sampled every 2 min, half a pixel apart: it is drawn by chords of about 6 px,
    which stay within s^2 / (8 r) = 0.045 px of a curve of radius r = 100 px (0.1 allowed)."""
    t = np.linspace(0.0, math.pi, 629)  # 0.5 px steps on a half circle of radius 100 px
    curve = np.column_stack([250 + 100 * np.cos(t), 100 + 100 * np.sin(t)])
    c = Canvas(500, 360)
    c.path(curve, stroke="black", lw=1.0)
    (chords,) = c.items[0][1]
    assert 40 <= len(chords) <= 60 and np.array_equal(chords[0], curve[0]) and np.array_equal(chords[-1], curve[-1])
    a, b = chords[:-1], chords[1:]  # each point of the curve against its nearest chord
    d = b - a
    u = np.clip(np.einsum("pij,ij->pi", curve[:, None, :] - a[None], d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
    dist = np.linalg.norm(curve[:, None, :] - (a[None] + u[..., None] * d[None]), axis=-1).min(axis=1)
    assert dist.max() < 0.1
