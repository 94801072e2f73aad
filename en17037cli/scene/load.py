"""Reading the model files of a project into one set of world-frame float64 triangles with layers."""
from __future__ import annotations

import hashlib
from dataclasses import replace
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals
from en17037cli.io import read_model
from en17037cli.project.settings import ModelSettings
from en17037cli.scene.layers import assign_layers
from en17037cli.scene.model import WINDOW, Geometry

#: Length of one model unit [m].
UNIT_SCALE_M = {"m": 1.0, "cm": 0.01, "mm": 0.001, "ft": 0.3048, "in": 0.0254}

#: Faces smaller than this are degenerate and dropped [m^2].
MIN_FACE_AREA_M2 = 1e-10


def file_hash(path: Path) -> str:
    """``sha256:<hex>`` of a file's bytes."""
    h = hashlib.sha256()
    with path.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return "sha256:" + h.hexdigest()


def to_metres_z_up(vertices: np.ndarray, units: str, up_axis: str) -> np.ndarray:
    """Scale to metres and rotate y-up to z-up: (x, y, z) -> (x, -z, y)."""
    v = vertices * UNIT_SCALE_M[units]
    if up_axis == "y":
        v = np.column_stack([v[:, 0], -v[:, 2], v[:, 1]])
    return v


def load_geometry(model: ModelSettings, where: str) -> Geometry:
    """Read every model file into world-frame float64 triangles with layers (:class:`Geometry`).

    ``where`` names the project file in messages. Degenerate, NaN and infinite faces are dropped
    with one counted warning.
    """
    all_v, all_t, all_l, all_s, all_p, parts, notes, warnings, hashes = [], [], [], [], [], [], [], [], {}
    offset = 0
    dropped = glazing_parts = 0
    for i, spec in enumerate(model.files):  # one pass per model file
        if spec.all_ignored:
            notes.append(f"{spec.display}: every face goes to 'ignore'; file not loaded")
            continue
        hashes[spec.display] = file_hash(spec.path)
        mesh = read_model(spec.path)
        warnings.extend(mesh.warnings)
        units = spec.units or mesh.units or model.units
        up = spec.up_axis or mesh.up_axis or model.up_axis
        verts = to_metres_z_up(mesh.vertices, units, up)
        part_layer, part_sun, unmatched = assign_layers(spec, mesh, f"{where}: model.files[{i}]", spec.path.stem)
        warnings.extend(unmatched)
        glazing_parts += int(np.count_nonzero(part_layer == WINDOW))
        layer, sun = part_layer[mesh.part], part_sun[mesh.part]
        tris = mesh.triangles
        keep = layer >= 0
        tri_v = verts[tris]
        finite = np.all(np.isfinite(tri_v), axis=(1, 2))
        _, areas = triangle_normals(np.where(finite[:, None, None], tri_v, 0.0))
        good = finite & (areas > MIN_FACE_AREA_M2)
        dropped += int(np.count_nonzero(keep & ~good))
        keep &= good
        all_v.append(np.where(np.isfinite(verts), verts, 0.0))
        all_t.append(tris[keep] + offset)
        all_l.append(layer[keep])
        all_s.append(sun[keep])
        all_p.append(mesh.part[keep] + len(parts))
        parts.extend(replace(p, attrs={**p.attrs, "file": spec.path.stem}) for p in mesh.parts)
        offset += len(verts)
    if dropped:
        warnings.append(f"{dropped} degenerate, NaN or infinite faces dropped")
    if not all_v:
        raise InputError(f"{where}: model.files: no geometry loaded (every file is 'ignore')")
    g = Geometry(np.concatenate(all_v), np.concatenate(all_t).astype(np.int64), np.concatenate(all_l).astype(np.int8),
                 np.concatenate(all_s), parts, np.concatenate(all_p), notes, warnings, hashes)
    if glazing_parts and not np.any(g.layer == WINDOW):
        raise InputError(f"{where}: model.files: every face of the {glazing_parts} object(s) on the 'window' layer is "
                         "degenerate, NaN or infinite (zero area); re-export the glazing")
    return g
