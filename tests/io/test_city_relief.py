"""Ground-type city objects drawn as blocks: their steep sides stand above the ground (landscape),
their tops, kerbs and gentle banks stay ground; CityJSON and CityGML alike.

The cases, by hand (metres, z up): a park as a LoD1 PlantCover block given as surfaces (10 x 10 m,
3 m tall: a top of 100 m² and four sides of 30 m² each); a LandUse lot with a 0.3 m kerb along
one side (a vertical face 10 x 0.3 m); a LandUse bank rising 2 m over 4 m (26.6 deg, 10 m wide:
10 x sqrt(20) m²) up to a flat 10 x 4 m top; a WaterBody's flat surface.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from citygml_files import NS2, city_model, multi_surface

from en17037cli.geometry import triangle_normals
from en17037cli.io.cityjson import read_cityjson
from en17037cli.io.cityjson.relief import RISE_M

pytest.importorskip("lxml")


def block(x0, y0, w, d, h):
    """Rings of a LoD1 block given as surfaces: its top and four sides (no bottom), outward."""
    c = [(x0, y0, 0.0), (x0 + w, y0, 0.0), (x0 + w, y0 + d, 0.0), (x0, y0 + d, 0.0)]
    t = [(x, y, h) for x, y, _ in c]
    return [t] + [[c[i], c[(i + 1) % 4], t[(i + 1) % 4], t[i]] for i in range(4)]


#: object id -> (type, surfaces (rings of (x, y, z)))
CASES = {
    "park": ("PlantCover", block(0.0, 0.0, 10.0, 10.0, 3.0)),
    "lot": ("LandUse", [[(20.0, 0.0, 0.3), (30.0, 0.0, 0.3), (30.0, 10.0, 0.3), (20.0, 10.0, 0.3)],  # the raised lot
                        [(20.0, 0.0, 0.0), (30.0, 0.0, 0.0), (30.0, 0.0, 0.3), (20.0, 0.0, 0.3)]]),  # its kerb, 0.3 m
    "bank": ("LandUse", [[(40.0, 0.0, 0.0), (50.0, 0.0, 0.0), (50.0, 4.0, 2.0), (40.0, 4.0, 2.0)],  # 26.6 deg
                         [(40.0, 4.0, 2.0), (50.0, 4.0, 2.0), (50.0, 8.0, 2.0), (40.0, 8.0, 2.0)]]),
    "canal": ("WaterBody", [[(60.0, 0.0, -0.4), (70.0, 0.0, -0.4), (70.0, 10.0, -0.4), (60.0, 10.0, -0.4)]]),
}


def write_cityjson(path: Path) -> Path:
    vertices, objects = [], {}
    for oid, (cls, rings) in CASES.items():
        surfaces = []
        for ring in rings:
            surfaces.append([[len(vertices) + k for k in range(len(ring))]])
            vertices += [[round(c * 1000) for c in p] for p in ring]
        objects[oid] = {"type": cls, "geometry": [{"type": "MultiSurface", "lod": "1", "boundaries": surfaces}]}
    doc = {"type": "CityJSON", "version": "2.0", "transform": {"scale": [0.001] * 3, "translate": [0.0, 0.0, 0.0]},
           "CityObjects": objects, "vertices": vertices}
    path.write_text(json.dumps(doc))
    return path


def write_citygml(path: Path) -> Path:
    ns = {"veg": "http://www.opengis.net/citygml/vegetation/2.0", "luse": "http://www.opengis.net/citygml/landuse/2.0",
          "wtr": "http://www.opengis.net/citygml/waterbody/2.0"}
    members = []
    for oid, (cls, rings) in CASES.items():
        p = {"PlantCover": "veg", "LandUse": "luse", "WaterBody": "wtr"}[cls]
        members.append(f'<{p}:{cls} gml:id="{oid}"><{p}:lod1MultiSurface>{multi_surface([[r] for r in rings])}'
                       f'</{p}:lod1MultiSurface></{p}:{cls}>')
    path.write_text(city_model(members, {**NS2, **ns}), encoding="utf-8")
    return path


def areas_by(mesh) -> dict:
    """(object id, layer, slope) -> area [m²]."""
    _, a = triangle_normals(mesh.vertices[mesh.triangles])
    out: dict = {}
    for i, p in enumerate(mesh.parts):
        key = (p.attrs["id"], p.layer, p.attrs.get("slope"))
        out[key] = out.get(key, 0.0) + float(a[mesh.part == i].sum())
    return {k: round(v, 9) for k, v in out.items()}


@pytest.mark.parametrize("fmt", ["cityjson", "citygml"])
def test_steep_sides_of_ground_objects_are_landscape(tmp_path, fmt):
    if fmt == "cityjson":
        mesh = read_cityjson(write_cityjson(tmp_path / "c.city.json"))
    else:
        from en17037cli.io.citygml import read_citygml

        mesh = read_citygml(write_citygml(tmp_path / "c.gml"))
    assert areas_by(mesh) == {
        ("park", "ground", None): 100.0,  # the block's top stays ground
        ("park", "landscape", "steep"): 120.0,  # four sides of 10 x 3 m
        ("lot", "ground", None): 100.0 + 3.0,  # the 0.3 m kerb is below RISE_M: ground
        ("bank", "ground", None): round(10 * np.sqrt(20.0) + 40.0, 9),  # 26.6 deg is not steep
        ("canal", "ground", None): 100.0,
    }
    note = next(n for n in mesh.notes if "steep face" in n)
    assert "8 steep faces of 1 ground-type object (PlantCover 1)" in note and f"more than {RISE_M:g} m" in note
