"""Wavefront OBJ reader: n-gons, concave ones included, ear-clipped in their best-fit plane.

trimesh's OBJ reader fans n-gons, which adds area outside a concave polygon (the seed scene's
buildings would load 19 % too large), so OBJ is read here.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangulate_polygons
from en17037cli.io import ReadOptions, register
from en17037cli.io.mesh import Mesh, Part


@register(".obj")
def read_obj(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read a Wavefront OBJ file: ``v``, ``f`` (any ``v/vt/vn`` form, negative indices),
    ``o``, ``g`` and ``usemtl`` for names. Other statements are ignored."""
    vertices: list = []
    faces: list = []
    face_names: list = []
    names: dict = {}
    obj, group, mtl = "", "", ""
    current = None
    warnings: list = []
    bad_faces = 0
    try:
        fh = path.open("r", encoding="utf-8-sig", errors="replace")  # -sig: a byte-order mark is not part of line 1
    except OSError as exc:
        raise InputError(f"{path}: cannot read model file: {exc.strerror}") from None
    with fh:
        for lineno, line in enumerate(fh, 1):
            if not line or line[0] == "#":
                continue
            parts = line.split()
            if not parts:
                continue
            tag = parts[0]
            if tag == "v":
                try:
                    vertices.append((float(parts[1]), float(parts[2]), float(parts[3])))
                except (ValueError, IndexError):
                    raise InputError(f"{path}:{lineno}: corrupt OBJ vertex line {line.strip()[:60]!r}; re-export the model") from None
            elif tag == "f":
                nv = len(vertices)
                try:
                    idx = [int(p.split("/", 1)[0]) for p in parts[1:]]
                except ValueError:
                    raise InputError(f"{path}:{lineno}: corrupt OBJ face line {line.strip()[:60]!r}; re-export the model") from None
                idx = [i - 1 if i > 0 else nv + i for i in idx]
                if len(idx) < 3 or min(idx) < 0 or max(idx) >= nv:
                    if len(idx) >= 3:
                        raise InputError(f"{path}:{lineno}: face refers to a vertex that does not exist; re-export the model")
                    bad_faces += 1
                    continue
                if current is None:
                    key = (obj, group, mtl)
                    current = names.setdefault(key, len(names))
                faces.append(idx)
                face_names.append(current)
            elif tag == "o":
                obj = " ".join(parts[1:])
                current = None
            elif tag == "g":
                group = " ".join(parts[1:])
                current = None
            elif tag == "usemtl":
                mtl = " ".join(parts[1:])
                current = None
    if bad_faces:
        warnings.append(f"{path.name}: {bad_faces} faces with fewer than 3 vertices dropped")
    if not faces:
        raise InputError(f"{path}: no faces found; is this an OBJ model file?")
    verts = np.array(vertices, dtype=np.float64).reshape(-1, 3)
    tris, tri_names, n_failed = _triangulate_faces(verts, faces, face_names)
    if n_failed:
        warnings.append(f"{path.name}: {n_failed} polygons could not be fully triangulated (self-intersecting or degenerate); their remaining area was dropped")
    parts = [Part({"object": o, "group": g, "material": m}) for (o, g, m) in names]  # dicts keep insertion order
    return Mesh(verts, tris, tri_names, parts, warnings)


def _triangulate_faces(verts: np.ndarray, faces: list, face_names: list):
    """Triangles of all faces: triangles as they are, quads and n-gons ear-clipped."""
    sizes = np.fromiter((len(f) for f in faces), dtype=int, count=len(faces))
    names = np.asarray(face_names, dtype=int)
    out_tris = []
    out_names = []
    tri_mask = sizes == 3
    if tri_mask.any():
        out_tris.append(np.array([f for f, s in zip(faces, tri_mask) if s], dtype=int).reshape(-1, 3))
        out_names.append(names[tri_mask])
    n_failed = 0
    for k in np.unique(sizes[~tri_mask]):  # polygons grouped by vertex count
        rows = np.flatnonzero(sizes == k)
        idx = np.array([faces[i] for i in rows], dtype=int)
        for r, ix, local in zip(rows, idx, triangulate_polygons(verts[idx])):
            if len(local) < k - 2:
                n_failed += 1
            if len(local):
                out_tris.append(ix[local])
                out_names.append(np.full(len(local), names[r]))
    if not out_tris:
        return np.zeros((0, 3), dtype=int), np.zeros(0, dtype=int), n_failed
    return np.concatenate(out_tris), np.concatenate(out_names), n_failed
