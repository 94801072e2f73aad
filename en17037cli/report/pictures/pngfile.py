"""PNG files written with zlib and numpy: RGB, 8 bits a channel, unfiltered rows, no date and no
version string (the same pixels give the same bytes on one installation); and the scratch buffers
the drawing reuses from one picture to the next."""
from __future__ import annotations

import struct
import threading
import zlib

import numpy as np

#: zlib level of the PNG files (1: about 1 ms for a 500 x 360 picture, 20 % larger than at 6).
PNG_LEVEL = 1


def encode_png(rgb: np.ndarray, dpi: float | None = None, palette: np.ndarray | None = None) -> bytes:
    """PNG bytes of an RGB image (h, w, 3) or RGBX image (h, w, 4) uint8, 8 bits a channel, or of
    indices (h, w) uint8 into ``palette`` (k, 3) uint8, k <= 256: rows unfiltered (the pictures'
    flat colours compress well without), zlib at :data:`PNG_LEVEL`; its resolution (``pHYs``) if
    ``dpi`` is given, no date and no version string.

    References
    ----------
    W3C, Portable Network Graphics (PNG) Specification, 3rd ed. (2025), 5 (chunks), 11.2.1 (IHDR),
    11.2.2 (PLTE), 11.3.5.3 (pHYs), 7.3 and 9 (filter type 0).
    """
    h, w = rgb.shape[:2]
    depth = 1 if palette is not None else 3
    raw = scratch("raw", (h, 1 + depth * w))  # each row: its filter type (0, none), then its pixels
    raw[:, 0] = 0
    if palette is not None:
        raw[:, 1:] = rgb
    else:
        pixels = raw[:, 1:].reshape(h, w, 3)
        for k in range(3):  # a channel at a time: numpy copies every fourth byte slowly
            pixels[..., k] = rgb[..., k]

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    out = [b"\x89PNG\r\n\x1a\n", chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 3 if palette is not None else 2, 0, 0, 0))]
    if palette is not None:
        out.append(chunk(b"PLTE", np.ascontiguousarray(palette, dtype=np.uint8).tobytes()))
    if dpi:
        ppm = int(round(dpi / 0.0254))
        out.append(chunk(b"pHYs", struct.pack(">IIB", ppm, ppm, 1)))
    out += [chunk(b"IDAT", zlib.compress(memoryview(raw).cast("B"), PNG_LEVEL)), chunk(b"IEND", b"")]
    return b"".join(out)


_SCRATCH = threading.local()


def scratch(name: str, shape: tuple[int, ...]) -> np.ndarray:
    """A uint8 array of ``shape`` on a buffer kept for the next picture of this thread (its content
    is what the last user left): a fresh array of a few megabytes each picture costs more in page
    faults than the drawing."""
    n = int(np.prod(shape))
    b = getattr(_SCRATCH, name, None)
    if b is None or b.size < n:
        b = np.empty(n, dtype=np.uint8)
        setattr(_SCRATCH, name, b)
    return b[:n].reshape(shape)
