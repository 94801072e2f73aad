"""STL reader: binary STL read here (one vectorised step), ASCII STL through trimesh.

A binary STL's header states its triangle count; exports that get it wrong are common. Where the
file's size fits a whole number of 50-byte records, that number is read, with a warning; where it
does not, the file is refused with one line.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.mesh import Mesh, Part
from en17037cli.io.registry import ReadOptions, register

#: A binary STL record: normal, three vertices (float32), attribute byte count (uint16).
RECORD = np.dtype([("normal", "<f4", (3,)), ("v", "<f4", (3, 3)), ("attr", "<u2")])


def is_ascii_stl(head: bytes) -> bool:
    """ASCII STL starts with ``solid`` and has ``facet`` soon after (binary headers may start with 'solid' too)."""
    return head.lstrip().lower().startswith(b"solid") and b"facet" in head.lower()


@register(".stl")
def read_stl(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read an STL file, binary or ASCII (file units and axes; one part named after the file)."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read model file: {exc.strerror}") from None
    if is_ascii_stl(data[:1024]):
        from en17037cli.io.trimesh_formats import read_with_trimesh

        return read_with_trimesh(path, options)
    if len(data) < 84:
        raise InputError(f"{path}: not an STL file ({len(data)} bytes, shorter than a binary STL header); re-export it")
    stated = int(np.frombuffer(data[80:84], "<u4")[0])
    body = len(data) - 84
    warnings = []
    if body != stated * RECORD.itemsize:
        if body % RECORD.itemsize:
            raise InputError(f"{path}: binary STL header says {stated:,} triangles but the file holds {body:,} bytes of "
                             f"triangle records, not a multiple of {RECORD.itemsize}; the file is cut short or corrupt, re-export it")
        warnings.append(f"{path.name}: binary STL header says {stated:,} triangles, the file holds {body // RECORD.itemsize:,}; "
                        "all of them were read")
    rec = np.frombuffer(data, RECORD, count=body // RECORD.itemsize, offset=84)
    if len(rec) == 0:
        raise InputError(f"{path}: no triangles found in the model file")
    vertices = rec["v"].reshape(-1, 3).astype(np.float64)
    triangles = np.arange(len(vertices), dtype=np.int64).reshape(-1, 3)
    return Mesh(vertices, triangles, np.zeros(len(triangles), np.int64), [Part({"object": path.stem})], warnings)
