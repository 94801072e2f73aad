"""PLY reader: binary triangle meshes read here (one vectorised step), everything else through trimesh.

The fast path takes the common export: ``binary_little_endian`` or ``binary_big_endian``, an
element ``vertex`` of scalar properties including x, y and z, then an element ``face`` whose only
property is the list of vertex indices, every face a triangle with indices in range. Any other
file (ASCII, polygons, extra elements or face properties, anything out of the ordinary) goes to
:func:`~en17037cli.io.trimesh_formats.read_with_trimesh`, which gives the same mesh for the files
both read (one part named like trimesh's node, the file name).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from en17037cli.io.mesh import Mesh, Part
from en17037cli.io.registry import ReadOptions, register

#: PLY scalar types -> numpy type codes (without byte order).
PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2", "ushort": "u2",
             "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4", "float": "f4", "float32": "f4",
             "double": "f8", "float64": "f8"}


def _binary_triangles(data: bytes):
    """(vertices (n, 3) float64, triangles (m, 3) int64) of a binary PLY file of the fast path's
    form, or None for any other file."""
    end = data.find(b"end_header", 0, 1 << 16)
    if not data.startswith(b"ply") or end < 0:
        return None
    nl = data.find(b"\n", end)
    if nl < 0:
        return None
    try:
        lines = [ln.split() for ln in data[:end].decode("ascii").splitlines()[1:]]
    except UnicodeDecodeError:
        return None
    lines = [ln for ln in lines if ln and ln[0] not in ("comment", "obj_info")]
    if not lines or lines[0][:1] != ["format"] or len(lines[0]) != 3:
        return None
    order = {"binary_little_endian": "<", "binary_big_endian": ">"}.get(lines[0][1])
    if order is None:
        return None
    elements: list = []
    for ln in lines[1:]:
        if ln[0] == "element" and len(ln) == 3 and ln[2].isdigit():
            elements.append((ln[1], int(ln[2]), []))
        elif ln[0] == "property" and elements:
            elements[-1][2].append(ln[1:])
        else:
            return None
    if [e[0] for e in elements] != ["vertex", "face"]:
        return None
    (_, nv, vprops), (_, nf, fprops) = elements
    if any(len(p) != 2 or p[0] not in PLY_TYPES for p in vprops):
        return None
    names = [p[1] for p in vprops]
    if len(set(names)) != len(names) or not {"x", "y", "z"} <= set(names):
        return None
    if len(fprops) != 1 or len(fprops[0]) != 4 or fprops[0][0] != "list" or fprops[0][3] not in ("vertex_indices", "vertex_index"):
        return None
    ct, it = PLY_TYPES.get(fprops[0][1]), PLY_TYPES.get(fprops[0][2])
    if ct is None or it is None or it[0] == "f" or ct[0] == "f":
        return None
    vdt = np.dtype([(n, order + PLY_TYPES[t]) for t, n in vprops])
    fdt = np.dtype([("n", order + ct), ("i", order + it, (3,))])
    start = nl + 1
    if len(data) < start + nv * vdt.itemsize + nf * fdt.itemsize:
        return None
    vrec = np.frombuffer(data, vdt, count=nv, offset=start)
    frec = np.frombuffer(data, fdt, count=nf, offset=start + nv * vdt.itemsize)
    if nf == 0 or np.any(frec["n"] != 3):
        return None
    tri = frec["i"].astype(np.int64)
    if tri.min() < 0 or tri.max() >= nv:
        return None
    v = np.empty((nv, 3))
    for k, c in enumerate("xyz"):
        v[:, k] = vrec[c]
    return v, tri


@register(".ply")
def read_ply(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read a PLY file: binary triangle meshes here, any other PLY through trimesh (file units and
    axes; one part named after the file, as trimesh names its node)."""
    try:
        data = path.read_bytes()
    except OSError:
        data = b""
    got = _binary_triangles(data) if data else None
    if got is None:
        from en17037cli.io.trimesh_formats import read_with_trimesh

        return read_with_trimesh(path, options)
    v, tri = got
    v += 0.0  # -0.0 -> 0.0, as trimesh's identity node transform leaves them (it also spreads a NaN or infinite
    # coordinate over its vertex, whose faces the scene drops either way)
    return Mesh(v, tri, np.zeros(len(tri), np.int64), [Part({"object": path.name, "group": path.name, "material": ""})], [])
