"""A generated city of box buildings, for benchmarks of large contexts."""
from __future__ import annotations

from pathlib import Path

import numpy as np


def city_context(n_triangles: int, seed: int = 0, keep_clear=(-40.0, 40.0, -60.0, 30.0), extent_m: float = 1000.0):
    """A generated city of box buildings with finely meshed faces, about ``n_triangles`` triangles.

    Buildings stand on a grid over a square of side ``extent_m`` centred on the origin, outside the
    rectangle ``keep_clear`` (x0, x1, y0, y1) [m] around the box room and its street; each has four
    walls and a roof split into k x k quads (two triangles each), like detailed facade models.
    Deterministic for a given ``seed``.

    Returns
    -------
    vertices : (n, 3) float [m]; faces : (m, 3) int
    """
    rng = np.random.default_rng(seed)
    k = 7  # quads per face side: 5 faces x 2 k^2 = 490 triangles per building
    per_building = 5 * 2 * k * k
    want = max(1, int(round(n_triangles / per_building)))
    side = int(np.ceil(np.sqrt(want * 1.3))) + 1
    cells = (np.arange(side) + 0.5) / side * extent_m - extent_m / 2
    cx, cy = [a.ravel() for a in np.meshgrid(cells, cells, indexing="ij")]
    x0, x1, y0, y1 = keep_clear
    pad = extent_m / side
    free = ~((cx > x0 - pad) & (cx < x1 + pad) & (cy > y0 - pad) & (cy < y1 + pad))
    pick = np.sort(rng.choice(int(free.sum()), size=min(want, int(free.sum())), replace=False))
    cx, cy = cx[free][pick], cy[free][pick]
    b = len(cx)
    w = rng.uniform(0.3, 0.8, b) * pad
    length = rng.uniform(0.3, 0.8, b) * pad
    h = rng.uniform(6.0, 40.0, b)
    o = np.stack([cx - w / 2, cy - length / 2, np.zeros(b)], axis=1)
    ex = np.stack([w, np.zeros(b), np.zeros(b)], axis=1)
    ey = np.stack([np.zeros(b), length, np.zeros(b)], axis=1)
    ez = np.stack([np.zeros(b), np.zeros(b), h], axis=1)
    # five faces per building: origin and two edge vectors
    origins = np.stack([o, o + ey, o, o + ex, o + ez], axis=1)
    e1 = np.stack([ex, ex, ey, ey, ex], axis=1)
    e2 = np.stack([ez, ez, ez, ez, ey], axis=1)
    s = np.linspace(0.0, 1.0, k + 1)
    a, c = [g.ravel() for g in np.meshgrid(s, s, indexing="ij")]
    verts = origins[:, :, None, :] + a[None, None, :, None] * e1[:, :, None, :] + c[None, None, :, None] * e2[:, :, None, :]
    i, j = [g.ravel() for g in np.meshgrid(np.arange(k), np.arange(k), indexing="ij")]
    v00 = i * (k + 1) + j
    quad = np.stack([v00, v00 + k + 1, v00 + k + 2, v00 + 1], axis=1)
    tmpl = np.concatenate([quad[:, [0, 1, 2]], quad[:, [0, 2, 3]]])  # (2 k^2, 3) per face
    nv = (k + 1) ** 2
    offsets = (np.arange(b * 5) * nv)[:, None, None]
    faces = (tmpl[None, :, :] + offsets).reshape(-1, 3)
    return verts.reshape(-1, 3), faces


def write_ply(path: Path, vertices: np.ndarray, faces: np.ndarray) -> None:
    """Write a binary little-endian PLY file (float32 vertices, int32 triangle indices)."""
    v = np.ascontiguousarray(vertices, dtype="<f4")
    f = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    f["n"] = 3
    f["i"] = faces
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(v)}\nproperty float x\nproperty float y\n"
              f"property float z\nelement face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n")
    with open(path, "wb") as fh:
        fh.write(header.encode("ascii"))
        fh.write(v.tobytes())
        fh.write(f.tobytes())
