"""The text of the pictures: DejaVu Sans (the font matplotlib bundles, found without importing it),
the box a line of text is aligned by, and lines of text drawn once as coverage masks (Pillow and
FreeType; Raqm lays out right-to-left scripts where Pillow has it)."""
from __future__ import annotations

import functools
import os

#: The height of a line of text above and below its baseline [em]: the top of DejaVu Sans's "l" and
#: the bottom of its "p" (1556 and 426 of 2048 units), the box matplotlib aligns a line of text by.
ASCENT, DESCENT = 1556 / 2048, 426 / 2048


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


def text_box(lines: list, em: float, ha: str, bold: bool, pad: float) -> tuple[float, float, float, float]:
    """(x0, y0, x1, y1) [layout px, y up] around lines of text (each (line, x, baseline y), as
    :meth:`~.canvas.Canvas.lines_of` gives them) at ``em`` [px], ``pad`` [em] of air on each side."""
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
def glyphs(line: str, size_px: float, bold: bool, ha: str, rotation: int):
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
