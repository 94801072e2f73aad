"""Which triangles touch: welded vertices, shared edges and connected pieces (numpy, no loop over faces)."""
from __future__ import annotations

import numpy as np


def weld(vertices: np.ndarray, triangles: np.ndarray, tol_m: float) -> np.ndarray:
    """(m, 3) int: ``triangles`` re-indexed so that vertices closer than ``tol_m`` [m] (on a grid
    of that size) share one index; only the vertices the triangles use are welded."""
    used, inverse = np.unique(triangles, return_inverse=True)
    keys = np.round(vertices[used] / tol_m).astype(np.int64)
    _, welded = np.unique(keys, axis=0, return_inverse=True)
    return welded.reshape(-1)[inverse.reshape(triangles.shape)]


def shared_edges(tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pairs (a, b) of faces (rows of ``tri``, welded vertex ids) that share an edge."""
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(tri)), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    e, o = edges[order], owner[order]
    same = np.all(e[1:] == e[:-1], axis=1)
    return o[:-1][same], o[1:][same]


def connected_components(n: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Component label (the smallest member index) of each of ``n`` nodes joined by edges (a, b).

    Vectorised min-label propagation with pointer jumping; converges in at most the
    component diameter.
    """
    label = np.arange(n)
    while True:
        new = label.copy()
        np.minimum.at(new, a, label[b])
        np.minimum.at(new, b, label[a])
        new = new[new]
        if np.array_equal(new, label):
            return label
        label = new


def pieces(vertices: np.ndarray, triangles: np.ndarray, tol_m: float = 1e-5) -> np.ndarray:
    """(m,) int: the edge-connected piece of each triangle (label = its smallest member's index),
    vertices welded within ``tol_m`` [m]."""
    if len(triangles) == 0:
        return np.zeros(0, np.int64)
    t = weld(vertices, triangles, tol_m)
    a, b = shared_edges(t)
    return connected_components(len(t), a, b)
