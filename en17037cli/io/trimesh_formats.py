"""glTF/GLB and OFF through trimesh (and the PLY and STL files their own readers pass on); node and geometry names become part attributes."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.mesh import Mesh, Part
from en17037cli.io.registry import ReadOptions, register


@register(".glb", ".gltf", ".off")
def read_with_trimesh(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read glTF/GLB, PLY, STL or OFF through trimesh; node and geometry names become face names."""
    import trimesh

    try:
        loaded = trimesh.load(str(path), force="scene", process=False)
    except Exception as exc:  # trimesh raises many types for corrupt files
        raise InputError(f"{path}: cannot read model file ({type(exc).__name__}: {exc}); re-export it") from None
    verts, tris, ids, names = [], [], [], []
    offset = 0
    for node in sorted(loaded.graph.nodes_geometry):
        transform, geom_name = loaded.graph[node]
        geom = loaded.geometry[geom_name]
        if not hasattr(geom, "faces") or len(geom.faces) == 0:
            continue
        v = np.asarray(geom.vertices, dtype=np.float64)
        v = v @ transform[:3, :3].T + transform[:3, 3]
        material = getattr(getattr(geom.visual, "material", None), "name", None) or ""
        names.append(Part({"object": str(node), "group": str(geom_name), "material": str(material)}))
        verts.append(v)
        tris.append(np.asarray(geom.faces, dtype=int) + offset)
        ids.append(np.full(len(geom.faces), len(names) - 1))
        offset += len(v)
    if not tris:
        raise InputError(f"{path}: no triangles found in the model file")
    gltf = path.suffix.lower() in (".glb", ".gltf")  # glTF 2.0 fixes metres and +Y up
    return Mesh(np.concatenate(verts), np.concatenate(tris), np.concatenate(ids), names, [],
                units="m" if gltf else None, up_axis="y" if gltf else None)
