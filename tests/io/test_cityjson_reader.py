"""CityJSON reader: small files written here with values worked out by hand, and the Rotterdam sample."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import shapely

from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals
from en17037cli.io import ReadOptions, read_model
from en17037cli.io.cityjson import footprint_overlap, normalise_crs, read_cityjson, without_objects

ROOT = Path(__file__).resolve().parents[2]
ROTTERDAM = ROOT / "sample_projects" / "cityjson-rotterdam" / "rotterdam_subset.json"

SCALE = [0.001, 0.001, 0.001]
TRANSLATE = [85000.0, 446000.0, 0.0]
CRS_20 = "https://www.opengis.net/def/crs/EPSG/0/7415"

# unit cube in mm: corners 0-3 at z = 0, 4-7 at z = 1000
CUBE_V = [[0, 0, 0], [1000, 0, 0], [1000, 1000, 0], [0, 1000, 0],
          [0, 0, 1000], [1000, 0, 1000], [1000, 1000, 1000], [0, 1000, 1000]]
# outward faces: ground, roof, 4 walls
CUBE_SHELL = [[[0, 3, 2, 1]], [[4, 5, 6, 7]], [[0, 1, 5, 4]], [[1, 2, 6, 5]], [[2, 3, 7, 6]], [[3, 0, 4, 7]]]
CUBE_SEM = {"surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"}, {"type": "WallSurface"}],
            "values": [[0, 1, 2, 2, 2, 2]]}


def geom(gtype: str, boundaries, lod="2", semantics=None) -> dict:
    g = {"type": gtype, "lod": lod, "boundaries": boundaries}
    if semantics:
        g["semantics"] = semantics
    return g


def obj(cls: str, *geoms, **members) -> dict:
    return {"type": cls, **members, "geometry": list(geoms)}


def instance(template: int, ref: int, matrix) -> dict:
    return {"type": "GeometryInstance", "template": template, "boundaries": [ref], "transformationMatrix": matrix}


def cityjson(objects: dict, vertices: list, version: str = "2.0", crs: str | None = CRS_20, **extra) -> dict:
    doc = {"type": "CityJSON", "version": version, "CityObjects": objects, "vertices": vertices}
    if "transform" not in extra:
        doc["transform"] = {"scale": SCALE, "translate": TRANSLATE}
    if crs:
        doc["metadata"] = {"referenceSystem": crs}
    doc.update({k: v for k, v in extra.items() if v is not None})
    return doc


def write(tmp_path: Path, doc, name: str = "model.city.json") -> Path:
    p = tmp_path / name
    p.write_text(doc if isinstance(doc, str) else json.dumps(doc))
    return p


def shifted(vertices, dx=0, dy=0, dz=0) -> list:
    return [[x + dx, y + dy, z + dz] for x, y, z in vertices]


def offset(boundaries, k: int):
    """Boundaries (any depth) with every vertex index moved by k."""
    return [offset(b, k) for b in boundaries] if isinstance(boundaries, list) else boundaries + k


def area(mesh, tri_mask=None) -> float:
    tris = mesh.triangles if tri_mask is None else mesh.triangles[tri_mask]
    return float(triangle_normals(mesh.vertices[tris])[1].sum())


def part_area(mesh, **attrs) -> float:
    sel = [i for i, p in enumerate(mesh.parts) if all(p.attrs.get(k) == v for k, v in attrs.items())]
    return area(mesh, np.isin(mesh.part, sel))


def m_vertices_of(mesh, oid: str) -> np.ndarray:
    """The vertices the triangles of object ``oid`` use, in vertex order."""
    sel = [i for i, p in enumerate(mesh.parts) if p.attrs["id"] == oid]
    return mesh.vertices[np.unique(mesh.triangles[np.isin(mesh.part, sel)])]


def square(x0, y0, side, z=0):
    """Four vertices (mm) of a horizontal square, counterclockwise seen from above."""
    return [[x0, y0, z], [x0 + side, y0, z], [x0 + side, y0 + side, z], [x0, y0 + side, z]]


def one_line_error(excinfo, path: Path) -> str:
    msg = str(excinfo.value)
    assert "\n" not in msg
    assert str(path) in msg
    return msg


# --- coordinates and geometry types ---------------------------------------------------------


def test_unit_cube_solid_transform_area_and_exact_coordinates(tmp_path):
    p = write(tmp_path, cityjson({"c": obj("Building", geom("Solid", [CUBE_SHELL]))}, CUBE_V))
    m = read_cityjson(p, ReadOptions())
    expected = np.array(CUBE_V, dtype=np.int64) * np.array(SCALE) + np.array(TRANSLATE)
    assert m.vertices.dtype == np.float64
    assert np.array_equal(m.vertices, expected)  # float64 exact, all 8 used, in file order
    assert m.vertices[6].tolist() == [85001.0, 446001.0, 1.0]
    assert abs(area(m) - 6.0) < 1e-9
    assert m.triangles.shape == (12, 3) and m.triangles.dtype == np.int64
    assert (m.units, m.up_axis) == ("m", "z")
    assert m.site.crs == "EPSG:7415" and m.site.source == "model.city.json: metadata.referenceSystem"
    assert [dict(p.attrs) for p in m.parts] == [{"class": "Building", "id": "c"}]
    assert m.warnings == [] and m.notes == []
    normals, _ = triangle_normals(m.vertices[m.triangles])
    centre = m.vertices.mean(axis=0)
    outward = np.einsum("ij,ij->i", normals, m.vertices[m.triangles].mean(axis=1) - centre)
    assert (outward > 0).all()  # ring orientation kept through ear clipping


def test_square_with_square_hole_has_outer_minus_inner_area(tmp_path):
    # 10 m square with a 4 m square hole, horizontal, and the same as a vertical wall with a window opening
    flat = square(0, 0, 10000) + square(3000, 3000, 4000)
    wall = [[x, 20000, y] for x, y, _ in flat]  # in the plane y = 20 m
    hole_ring = [7, 6, 5, 4]  # clockwise: holes turn the other way
    geom = {"type": "MultiSurface", "lod": "2", "boundaries": [[[0, 1, 2, 3], hole_ring], [[8, 9, 10, 11], [15, 14, 13, 12]]]}
    p = write(tmp_path, cityjson({"h": {"type": "GenericCityObject", "geometry": [geom]}}, flat + wall))
    m = read_cityjson(p)
    assert abs(area(m) - 2 * (100.0 - 16.0)) < 1e-9
    c = m.vertices[m.triangles].mean(axis=1) - [85000, 446000, 0]
    horizontal = np.abs(c[:, 2]) < 1e-9
    in_hole = (c[:, 0] > 3) & (c[:, 0] < 7) & np.where(horizontal, (c[:, 1] > 3) & (c[:, 1] < 7), (c[:, 2] > 3) & (c[:, 2] < 7))
    assert not in_hole.any()
    assert horizontal.sum() == 8 and (~horizontal).sum() == 8  # earcut: 4 + 4 - 2 + 2 * 1 holes
    normals, _ = triangle_normals(m.vertices[m.triangles])  # the outer ring's turn is kept: up, and -y for the wall
    assert np.allclose(normals[horizontal], [0, 0, 1]) and np.allclose(normals[~horizontal], [0, -1, 0])
    assert m.warnings == []


def test_concave_l_shaped_sloping_roof_area(tmp_path):
    # L: (0,0) (2,0) (2,1) (1,1) (1,2) (0,2), plan area 3 m^2, on the slope z = 3 + y / 2
    ring = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    v = [[x * 1000, y * 1000, 3000 + y * 500] for x, y in ring]
    geom = {"type": "MultiSurface", "lod": "2.2", "boundaries": [[[0, 1, 2, 3, 4, 5]]],
            "semantics": {"surfaces": [{"type": "RoofSurface"}], "values": [0]}}
    m = read_cityjson(write(tmp_path, cityjson({"r": {"type": "Building", "geometry": [geom]}}, v)))
    assert abs(area(m) - 3.0 * np.sqrt(1.25)) < 1e-9
    c = m.vertices[m.triangles].mean(axis=1) - [85000, 446000, 0]
    assert ((c[:, 0] < 1) | (c[:, 1] < 1)).all()  # no triangle over the missing corner
    assert len(m.triangles) == 4


def test_multisolid_compositesolid_compositesurface_multisurface(tmp_path):
    two = CUBE_V + shifted(CUBE_V, dx=2000)
    solids = [[CUBE_SHELL], [offset(CUBE_SHELL, 8)]]
    sem = {"surfaces": [{"type": "RoofSurface"}, {"type": "WallSurface"}],
           "values": [[[None, 0, 1, 1, 1, 1]], [[None, 0, 1, 1, 1, 1]]]}
    objects = {
        "ms": {"type": "Building", "geometry": [{"type": "MultiSolid", "lod": "2", "boundaries": solids, "semantics": sem}]},
        "cs": {"type": "Building", "geometry": [{"type": "CompositeSolid", "lod": "2", "boundaries": solids}]},
        "csf": {"type": "Building", "geometry": [{"type": "CompositeSurface", "lod": "2", "boundaries": CUBE_SHELL[:3]}]},
        "msf": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2", "boundaries": [CUBE_SHELL[1]]}]},
    }
    m = read_cityjson(write(tmp_path, cityjson(objects, two)))
    assert abs(part_area(m, id="ms") - 12.0) < 1e-9
    assert abs(part_area(m, id="ms", surface="RoofSurface") - 2.0) < 1e-9
    assert abs(part_area(m, id="ms", surface="WallSurface") - 8.0) < 1e-9
    ms_parts = [dict(p.attrs) for p in m.parts if p.attrs["id"] == "ms"]
    assert ms_parts == [{"class": "Building", "id": "ms", "surface": "RoofSurface"},
                        {"class": "Building", "id": "ms", "surface": "WallSurface"},
                        {"class": "Building", "id": "ms"}]  # the null semantic value: no surface
    assert abs(part_area(m, id="cs") - 12.0) < 1e-9
    assert abs(part_area(m, id="csf") - 3.0) < 1e-9
    assert abs(part_area(m, id="msf") - 1.0) < 1e-9
    assert len(m.triangles) == 24 + 24 + 6 + 2


def test_geometry_template_instanced_twice_lands_at_hand_computed_places(tmp_path):
    templates = {
        "templates": [
            {"type": "MultiSurface", "lod": "2", "boundaries": [[[0, 1, 2, 3]]]},  # unit square
            {"type": "MultiSurface", "lod": "2", "boundaries": [[[4, 5, 6]]]},  # uses template vertices 4-6 only
        ],
        "vertices-templates": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 0], [2, 0, 0], [0, 0, 3]],
    }
    translate = [1, 0, 0, 2, 0, 1, 0, 3, 0, 0, 1, 0, 0, 0, 0, 1]  # row-major: x + 2, y + 3
    turn_and_scale = [0, -2, 0, 0, 2, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1]  # 90 degrees about z, then x2
    ref = [[10000, 20000, 1000], [50000, 60000, 0]]  # (85010, 446020, 1) and (85050, 446060, 0)
    objects = {
        "t1": obj("SolitaryVegetationObject", instance(0, 0, translate)),
        "t2": obj("SolitaryVegetationObject", instance(0, 1, translate)),
        "t3": obj("CityFurniture", instance(1, 1, turn_and_scale)),
    }
    m = read_cityjson(write(tmp_path, cityjson(objects, ref, **{"geometry-templates": templates})))

    def verts_of(oid):
        return m_vertices_of(m, oid)

    t1 = [[85012, 446023, 1], [85013, 446023, 1], [85013, 446024, 1], [85012, 446024, 1]]
    t2 = [[85052, 446063, 0], [85053, 446063, 0], [85053, 446064, 0], [85052, 446064, 0]]
    np.testing.assert_allclose(verts_of("t1"), t1, rtol=0, atol=1e-9)
    np.testing.assert_allclose(verts_of("t2"), t2, rtol=0, atol=1e-9)
    # template vertices (0,0,0) (2,0,0) (0,0,3) -> turned: (0,0,0) (0,4,0) (0,0,6) -> + reference point
    np.testing.assert_allclose(verts_of("t3"), [[85050, 446060, 0], [85050, 446064, 0], [85050, 446060, 6]], rtol=0, atol=1e-9)
    assert abs(part_area(m, id="t1") - 1.0) < 1e-9 and abs(part_area(m, id="t3") - 12.0) < 1e-9
    assert all(p.layer == "landscape" and p.obstructs_sun for p in m.parts)


# --- LoD --------------------------------------------------------------------------------------


def lod_file(tmp_path, version="2.0"):
    """a: LoD 1.2 (1 m^2) and 2.2 (4 m^2); b: LoD 1.2 only (1 m^2); c: LoD 3 only (9 m^2)."""
    v = square(0, 0, 1000) + square(0, 0, 2000) + square(0, 0, 3000)
    sq = [[[0, 1, 2, 3]]], [[[4, 5, 6, 7]]], [[[8, 9, 10, 11]]]
    objects = {
        "a": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "1.2", "boundaries": sq[0]},
                                               {"type": "MultiSurface", "lod": "2.2", "boundaries": sq[1]}]},
        "b": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "1.2", "boundaries": sq[0]}]},
        "c": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "3", "boundaries": sq[2]}]},
    }
    return write(tmp_path, cityjson(objects, v, version=version))


@pytest.mark.parametrize("lod, areas, notes", [
    ("highest", {"a": 4.0, "b": 1.0, "c": 9.0}, []),
    ("2.2", {"a": 4.0, "b": 1.0}, ["model.city.json: LoD 2.2 requested; 1 object fell back to a lower LoD (LoD 1.2: 1)",
                                   "model.city.json: 1 object without surface geometry at or below LoD 2.2 left out"]),
    ("2", {"a": 4.0, "b": 1.0}, ["model.city.json: LoD 2 requested; 1 object fell back to a lower LoD (LoD 1.2: 1)",
                                 "model.city.json: 1 object without surface geometry at or below LoD 2 left out"]),
    ("1.2", {"a": 1.0, "b": 1.0}, ["model.city.json: 1 object without surface geometry at or below LoD 1.2 left out"]),
    ("3", {"a": 4.0, "b": 1.0, "c": 9.0},
     ["model.city.json: LoD 3 requested; 2 objects fell back to a lower LoD (LoD 2.2: 1, LoD 1.2: 1)"]),
])
def test_lod_choice_and_fallback_notes(tmp_path, lod, areas, notes):
    m = read_cityjson(lod_file(tmp_path), ReadOptions(lod=lod))
    got = {p.attrs["id"]: round(part_area(m, id=p.attrs["id"]), 9) for p in m.parts}
    assert got == areas
    assert m.notes == notes


def test_bad_lod_option(tmp_path):
    p = lod_file(tmp_path)
    with pytest.raises(InputError) as e:
        read_cityjson(p, ReadOptions(lod="LoD2"))
    assert "'LoD2'" in one_line_error(e, p)


# --- parts and default layers ---------------------------------------------------------------


def test_part_attributes_parent_and_scalar_attributes_only(tmp_path):
    ms = {"type": "Solid", "lod": "2", "boundaries": [CUBE_SHELL], "semantics": CUBE_SEM}
    objects = {
        "b1": obj("Building", ms, children=["b1-p"],
                  attributes={"roofType": "gable", "height": 12.5, "storeys": 3, "listed": True,
                              "address": {"street": "Oude Delft"}, "uses": ["office"], "note": None, "empty": ""}),
        "b1-p": {"type": "BuildingPart", "parents": ["b1"], "attributes": {"part": "east"}, "geometry": [ms]},
    }
    m = read_cityjson(write(tmp_path, cityjson(objects, CUBE_V)))
    free = {"attr.roofType": "gable", "attr.height": "12.5", "attr.storeys": "3", "attr.listed": "True"}
    assert [dict(p.attrs) for p in m.parts] == [
        {"class": "Building", "id": "b1", "surface": "GroundSurface", **free},
        {"class": "Building", "id": "b1", "surface": "RoofSurface", **free},
        {"class": "Building", "id": "b1", "surface": "WallSurface", **free},
        {"class": "BuildingPart", "id": "b1-p", "parent": "Building", "surface": "GroundSurface", "attr.part": "east"},
        {"class": "BuildingPart", "id": "b1-p", "parent": "Building", "surface": "RoofSurface", "attr.part": "east"},
        {"class": "BuildingPart", "id": "b1-p", "parent": "Building", "surface": "WallSurface", "attr.part": "east"},
    ]
    assert [p.layer for p in m.parts] == ["ignore", "landscape", "landscape"] * 2
    assert abs(part_area(m, id="b1", surface="WallSurface") - 4.0) < 1e-9


LAYER_ROWS = [  # (CityObject type, geometry type, semantic surface or None, expected layer)
    ("Building", "Solid", "GroundSurface", "ignore"),
    ("Building", "Solid", "RoofSurface", "landscape"),
    ("Building", "Solid", "WallSurface", "landscape"),
    ("Building", "Solid", "Window", "landscape"),
    ("Building", "Solid", "ClosureSurface", "ignore"),
    ("BuildingPart", "Solid", "GroundSurface", "ignore"),
    ("BuildingPart", "Solid", "WallSurface", "landscape"),
    ("BuildingInstallation", "MultiSurface", None, "landscape"),
    ("BuildingInstallation", "MultiSurface", "GroundSurface", "landscape"),
    ("BuildingConstructiveElement", "MultiSurface", None, "landscape"),
    ("BuildingRoom", "Solid", "FloorSurface", "ignore"),
    ("BuildingRoom", "Solid", None, "ignore"),
    ("BuildingStorey", "MultiSurface", None, "ignore"),
    ("BuildingUnit", "Solid", None, "ignore"),
    ("BuildingFurniture", "MultiSurface", None, "ignore"),
    ("Bridge", "Solid", None, "landscape"),
    ("BridgePart", "Solid", None, "landscape"),
    ("BridgeInstallation", "MultiSurface", None, "landscape"),
    ("BridgeConstructiveElement", "Solid", None, "landscape"),
    ("BridgeConstructionElement", "Solid", None, "landscape"),
    ("BridgeRoom", "Solid", None, "ignore"),
    ("BridgeFurniture", "MultiSurface", None, "ignore"),
    ("Tunnel", "Solid", None, "landscape"),
    ("TunnelPart", "Solid", None, "landscape"),
    ("TunnelInstallation", "MultiSurface", None, "landscape"),
    ("TunnelConstructiveElement", "Solid", None, "landscape"),
    ("TunnelHollowSpace", "Solid", None, "ignore"),
    ("TunnelFurniture", "MultiSurface", None, "ignore"),
    ("CityFurniture", "MultiSurface", None, "landscape"),
    ("GenericCityObject", "Solid", None, "landscape"),
    ("OtherConstruction", "Solid", None, "landscape"),
    ("SolitaryVegetationObject", "Solid", None, "landscape"),
    ("PlantCover", "MultiSolid", None, "landscape"),
    ("PlantCover", "Solid", None, "landscape"),
    ("PlantCover", "CompositeSolid", None, "landscape"),
    ("PlantCover", "MultiSurface", None, "ground"),
    ("PlantCover", "CompositeSurface", None, "ground"),
    ("TINRelief", "CompositeSurface", None, "ground"),
    ("LandUse", "MultiSurface", None, "ground"),
    ("Road", "MultiSurface", "TrafficArea", "ground"),
    ("Railway", "MultiSurface", None, "ground"),
    ("TransportSquare", "MultiSurface", None, "ground"),
    ("Waterway", "MultiSurface", None, "ground"),
    ("WaterBody", "Solid", "WaterSurface", "ground"),
    ("WaterBody", "Solid", "WaterClosureSurface", "ignore"),
    ("CityObjectGroup", "MultiSurface", None, "ignore"),
    ("+NoiseBarrier", "MultiSurface", None, "landscape"),
]


def test_default_layer_table(tmp_path):
    objects = {}
    for i, (cls, gtype, surface, _) in enumerate(LAYER_ROWS):
        b = {"MultiSurface": CUBE_SHELL, "CompositeSurface": CUBE_SHELL, "Solid": [CUBE_SHELL],
             "MultiSolid": [[CUBE_SHELL]], "CompositeSolid": [[CUBE_SHELL]]}[gtype]
        values = {"MultiSurface": [0] * 6, "CompositeSurface": [0] * 6, "Solid": [[0] * 6]}.get(gtype, [[[0] * 6]])
        sem = {"surfaces": [{"type": surface}], "values": values} if surface else None
        objects[f"o{i}"] = obj(cls, geom(gtype, b, semantics=sem))
    # cubes 0.4 m tall: the steep sides of ground-type objects rising more than 0.5 m are landscape
    # (tests/io/test_city_relief.py); here the table alone
    low = [[x, y, z * 2 // 5] for x, y, z in CUBE_V]
    m = read_cityjson(write(tmp_path, cityjson(objects, low)))
    assert len(m.parts) == len(LAYER_ROWS)
    got = [(p.attrs["class"], p.attrs.get("surface"), p.layer) for p in m.parts]
    assert got == [(cls, surface, layer) for cls, _, surface, layer in LAYER_ROWS]
    assert all(p.obstructs_sun for p in m.parts)  # vegetation included: the project decides
    unknown = "1 object of types that are not CityJSON core types given layer landscape (+NoiseBarrier: 1)"
    assert m.notes == [f"model.city.json: {unknown}"]


# --- exclude and near -----------------------------------------------------------------------


def test_exclude_by_id_takes_children_and_grandchildren(tmp_path):
    two = CUBE_V + shifted(CUBE_V, dx=5000)
    cube = {"type": "Solid", "lod": "2", "boundaries": [CUBE_SHELL]}
    cube2 = {"type": "Solid", "lod": "2", "boundaries": [offset(CUBE_SHELL, 8)]}
    objects = {
        "b1": {"type": "Building", "children": ["b1-p"], "geometry": [cube]},
        "b1-p": {"type": "BuildingPart", "parents": ["b1"], "geometry": [cube]},
        "b1-p-i": {"type": "BuildingInstallation", "parents": ["b1-p"], "geometry": [cube]},  # linked by "parents" only
        "b2": {"type": "Building", "geometry": [cube2]},
    }
    p = write(tmp_path, cityjson(objects, two))
    assert len(read_cityjson(p).parts) == 4
    m = read_cityjson(p, ReadOptions(exclude=("b1", "nope")))
    assert [p.attrs["id"] for p in m.parts] == ["b2"]
    assert len(m.triangles) == 12 and len(m.vertices) == 8
    assert m.notes == ["model.city.json: 3 objects left out by exclude (1 listed, 2 of their descendants)",
                       "model.city.json: 1 excluded id not in the file: nope"]
    m = read_cityjson(p, ReadOptions(exclude=("b1-p",)))
    assert [p.attrs["id"] for p in m.parts] == ["b1", "b2"]


def test_near_culls_by_vertex_bounding_box(tmp_path):
    v = CUBE_V + shifted(CUBE_V, dx=100000) + square(-50000, -50000, 100000)
    objects = {
        "near": {"type": "Building", "geometry": [{"type": "Solid", "lod": "2", "boundaries": [CUBE_SHELL]}]},
        "far": {"type": "Building", "geometry": [{"type": "Solid", "lod": "2", "boundaries": [offset(CUBE_SHELL, 8)]}]},
        # 100 m square around the point: every vertex is 70.7 m away, but its bounding box holds the point
        "big": {"type": "TINRelief", "geometry": [{"type": "CompositeSurface", "lod": "1", "boundaries": [[[16, 17, 18, 19]]]}]},
    }
    p = write(tmp_path, cityjson(objects, v))
    m = read_cityjson(p, ReadOptions(near=((85000.0, 446000.0), 10.0)))
    assert [p.attrs["id"] for p in m.parts] == ["near", "big"]
    assert m.notes == ["model.city.json: 1 object lying entirely farther than 10 m from (85000, 446000) left out"]
    # the far cube's nearest corner is (85100, 446000), 100 m away
    for radius, ids in ((100.5, ["near", "far", "big"]), (99.5, ["near", "big"])):
        assert [p.attrs["id"] for p in read_cityjson(p, ReadOptions(near=((85000.0, 446000.0), radius))).parts] == ids


# --- CityJSONSeq and versions ---------------------------------------------------------------


def test_cityjsonseq_gives_the_same_mesh_as_the_equivalent_file(tmp_path):
    templates = {"templates": [geom("MultiSurface", [[[0, 1, 2]]])], "vertices-templates": [[0, 0, 0], [2, 0, 0], [0, 0, 2]]}
    b1 = {"b1": obj("Building", geom("Solid", [CUBE_SHELL], semantics=CUBE_SEM), attributes={"h": 1}, children=["b1-p"]),
          "b1-p": obj("BuildingPart", geom("MultiSurface", [[[4, 5, 6, 7]]]), parents=["b1"])}
    # the second feature's vertices are indexed locally from 0, the tree's reference point too
    half_x = [1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]  # x + 0.5
    b2 = {"b2": obj("Building", geom("Solid", [CUBE_SHELL])), "tree": obj("SolitaryVegetationObject", instance(0, 6, half_x))}
    f1 = {"type": "CityJSONFeature", "id": "b1", "CityObjects": b1, "vertices": CUBE_V}
    f2 = {"type": "CityJSONFeature", "id": "b2", "CityObjects": b2, "vertices": shifted(CUBE_V, dx=3000)}
    header = cityjson({}, [], **{"geometry-templates": templates})
    seq = write(tmp_path, "\n".join(json.dumps(d) for d in (header, f1, f2)) + "\n", "tile.city.jsonl")
    objects = {**b1, "b2": obj("Building", geom("Solid", [offset(CUBE_SHELL, 8)])),
               "tree": obj("SolitaryVegetationObject", instance(0, 14, half_x))}
    whole = write(tmp_path, cityjson(objects, CUBE_V + shifted(CUBE_V, dx=3000), **{"geometry-templates": templates}))
    a, b = read_cityjson(seq), read_model(whole)
    assert np.array_equal(a.vertices, b.vertices)
    assert np.array_equal(a.triangles, b.triangles) and np.array_equal(a.part, b.part)
    assert [dict(p.attrs) for p in a.parts] == [dict(p.attrs) for p in b.parts]
    assert [p.layer for p in a.parts] == [p.layer for p in b.parts]
    assert a.site.crs == "EPSG:7415" and a.site.source == "tile.city.jsonl: metadata.referenceSystem"
    assert abs(area(a) - 15.0) < 1e-9  # 6 + 1 (roof of the part) + 6 + 2 (the tree's triangle)
    # reference point: the feature's local vertex 6, (4000, 1000, 1000) mm -> (85004, 446001, 1)
    tree = [[85004.5, 446001, 1], [85006.5, 446001, 1], [85004.5, 446001, 3]]
    np.testing.assert_allclose(m_vertices_of(a, "tree"), tree, rtol=0, atol=1e-9)
    # a sequence saved with a .json name is read as one too
    assert np.array_equal(read_model(write(tmp_path, seq.read_text(), "tile.json")).triangles, a.triangles)


@pytest.mark.parametrize("version, crs, lod", [
    ("1.0", "urn:ogc:def:crs:EPSG::7415", 2),
    ("1.0", "urn:ogc:def:crs:EPSG:6.3:7415", 2.0),
    ("1.1", "https://www.opengis.net/def/crs/EPSG/0/7415", "2"),
    ("2.0", "https://www.opengis.net/def/crs/EPSG/0/7415", "2"),
])
def test_versions_read_alike(tmp_path, version, crs, lod):
    cube = obj("Building", geom("Solid", [CUBE_SHELL], lod=lod, semantics=CUBE_SEM))
    doc = cityjson({"c": cube}, CUBE_V, version=version, crs=crs)
    m = read_cityjson(write(tmp_path, doc))
    assert m.site.crs == "EPSG:7415"
    assert abs(area(m) - 6.0) < 1e-9 and len(m.triangles) == 12
    assert [p.attrs["surface"] for p in m.parts] == ["GroundSurface", "RoofSurface", "WallSurface"]


def test_version_1_0_without_transform_reads_real_coordinates(tmp_path):
    v = [[85000.5 + x / 1000, 446000.25 + y / 1000, z / 1000] for x, y, z in CUBE_V]
    doc = cityjson({"c": obj("Building", geom("Solid", [CUBE_SHELL], lod=1))}, v, version="1.0", transform=None)
    assert "transform" not in doc
    m = read_cityjson(write(tmp_path, doc))
    assert np.array_equal(m.vertices, np.array(v))
    assert abs(area(m) - 6.0) < 1e-9


@pytest.mark.parametrize("given, expected", [
    ("urn:ogc:def:crs:EPSG::7415", "EPSG:7415"),
    ("https://www.opengis.net/def/crs/EPSG/0/28992", "EPSG:28992"),
    ("http://www.opengis.net/def/crs/EPSG/0/7415", "EPSG:7415"),
    ("EPSG:25832", "EPSG:25832"),
    ("urn:ogc:def:crs:EPSG:6.3:7415", "EPSG:7415"),
    ("my local grid", "my local grid"),
    ("", None),
    (None, None),
])
def test_normalise_crs(given, expected):
    assert normalise_crs(given) == expected


def test_no_metadata_no_site_and_points_lines_noted(tmp_path):
    geoms = [geom("MultiPoint", [0, 1], "1"), geom("MultiLineString", [[0, 1]], "1"), geom("MultiSurface", [[[0, 1, 2]]], "1")]
    m = read_cityjson(write(tmp_path, cityjson({"x": obj("CityFurniture", *geoms)}, CUBE_V, crs=None)))
    assert m.site is None
    assert m.notes == ["model.city.json: 2 point/line geometries (MultiPoint, MultiLineString) left out: no surfaces"]
    assert abs(area(m) - 0.5) < 1e-9


def test_same_file_same_mesh(tmp_path):
    p = lod_file(tmp_path)
    a, b = read_cityjson(p), read_cityjson(p)
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.triangles, b.triangles) and np.array_equal(a.part, b.part)
    assert a.parts == b.parts and a.notes == b.notes


def test_degenerate_surfaces_are_counted(tmp_path):
    geom = {"type": "MultiSurface", "lod": "2", "boundaries": [[[0, 1]], [[0, 1, 2, 3]], []]}
    m = read_cityjson(write(tmp_path, cityjson({"x": {"type": "Building", "geometry": [geom]}}, CUBE_V)))
    assert m.warnings == ["model.city.json: 2 surfaces with fewer than 3 vertices dropped"]
    assert abs(area(m) - 1.0) < 1e-9


def test_semantics_that_do_not_fit_are_ignored_with_a_warning(tmp_path):
    bad_index = geom("Solid", [CUBE_SHELL], semantics={"surfaces": [{"type": "RoofSurface"}], "values": [[0, 0, 0, 0, 0, 7]]})
    too_short = geom("MultiSurface", CUBE_SHELL[:2], semantics={"surfaces": [{"type": "RoofSurface"}], "values": [0]})
    m = read_cityjson(write(tmp_path, cityjson({"a": obj("Building", bad_index), "b": obj("Building", too_short)}, CUBE_V)))
    warning = "model.city.json: 2 geometries with semantics.values that do not match their surfaces: their semantics ignored"
    assert m.warnings == [warning]
    assert [dict(p.attrs) for p in m.parts] == [{"class": "Building", "id": "a"}, {"class": "Building", "id": "b"}]
    assert abs(area(m) - 8.0) < 1e-9


# --- bad input ------------------------------------------------------------------------------


def cube_obj(gtype="Solid", boundaries=None):
    return obj("Building", geom(gtype, [CUBE_SHELL] if boundaries is None else boundaries))


@pytest.mark.parametrize("content, name, expect", [
    ('{"type": "CityJSON",\n"version" "2.0"}', "model.city.json", ":2:11: not valid JSON"),
    ('{"type": "FeatureCollection", "features": []}', "model.json", "not CityJSON"),
    ("[1, 2, 3]", "model.json", "not CityJSON"),
    (cityjson({"c": cube_obj()}, CUBE_V, version="0.9"), "model.city.json", "version '0.9' is not supported"),
    (cityjson({"c": cube_obj()}, CUBE_V, version="3.0"), "model.city.json", "upgrade it with 'cjio model.city.json upgrade"),
    ({"type": "CityJSON", "version": "2.0", "CityObjects": {}}, "model.city.json", "no 'vertices' list"),
    (cityjson({}, []), "model.city.json", "no vertices"),
    (cityjson({"b7": cube_obj("MultiSurface", [[[0, 1, 99]]])}, CUBE_V),
     "model.city.json", "object 'b7' geometry[0] (MultiSurface) refers to vertex 99 but there are 8 vertices"),
    (cityjson({"x1": cube_obj("Polyhedron", [])}, CUBE_V),
     "model.city.json", "object 'x1' geometry[0] has unknown type 'Polyhedron'"),
    (cityjson({"s": cube_obj("Solid", CUBE_SHELL)}, CUBE_V), "model.city.json",
     "object 's' geometry[0] (Solid): 'boundaries' are not nested as a Solid"),
    (cityjson({"s": cube_obj("MultiSurface", [CUBE_SHELL])}, CUBE_V), "model.city.json", "object 's' geometry[0] (MultiSurface)"),
    (cityjson({"c": cube_obj()}, [[0, 0], [1, 1]]), "model.city.json", "'vertices' must be a list of [x, y, z] numbers"),
    (cityjson({"c": cube_obj()}, CUBE_V, crs="urn:ogc:def:crs:EPSG::4326"), "model.city.json", "EPSG:4326, in degrees"),
    (cityjson({"t": obj("SolitaryVegetationObject", instance(2, 0, [1, 0, 0, 0] * 4))}, CUBE_V),
     "model.city.json", "object 't' geometry[0] (GeometryInstance) refers to template 2"),
    ('{"type": "CityJSON", "version": "2.0", "CityObjects": {}, "vertices": []}\n{"type": "CityJSON"}\n', "t.city.jsonl",
     ":2: expected a CityJSONFeature line"),
    ('{"type": "CityJSON", "version": "2.0", "CityObjects": {}, "vertices": []}\n{"type": \n', "t.city.jsonl",
     ":2:10: not valid JSON"),
    ('{"type": "CityJSONFeature"}\n', "t.city.jsonl", ":1: JSON but not CityJSON"),
])
def test_bad_input_is_one_line_naming_the_file(tmp_path, content, name, expect):
    p = write(tmp_path, content, name)
    with pytest.raises(InputError) as e:
        read_model(p)
    assert expect in one_line_error(e, p)


def test_vertex_out_of_range_in_a_sequence_names_line_and_object(tmp_path):
    header = cityjson({}, [])
    f1 = {"type": "CityJSONFeature", "id": "a", "CityObjects": {"a": cube_obj()}, "vertices": CUBE_V}
    f2 = {"type": "CityJSONFeature", "id": "b", "CityObjects": {"b": cube_obj()}, "vertices": CUBE_V[:7]}  # 8 referenced, 7 local
    p = write(tmp_path, "\n".join(json.dumps(d) for d in (header, f1, f2)), "t.city.jsonl")
    with pytest.raises(InputError) as e:
        read_cityjson(p)
    assert f"{p}:3: object 'b' geometry[0] (Solid) refers to vertex 7 but there are 7 vertices" in one_line_error(e, p)


# --- scene helpers --------------------------------------------------------------------------


def test_footprint_overlap_and_without_objects(tmp_path):
    # A: 10 x 10 m box at x 0..10 with a part; B: 10 x 10 m box at x 12..22; ground over everything
    box = [[x, y, z] for z in (0, 6000) for x, y in ((0, 0), (10000, 0), (10000, 10000), (0, 10000))]
    v = box + shifted(box, dx=12000) + square(-20000, -20000, 60000)
    shell_b = offset(CUBE_SHELL, 8)
    objects = {
        "A": obj("Building", geom("Solid", [CUBE_SHELL], semantics=CUBE_SEM), children=["A-1"]),
        "A-1": obj("BuildingPart", geom("MultiSurface", [CUBE_SHELL[1]]), parents=["A"]),
        "B": {"type": "Building", "geometry": [{"type": "Solid", "lod": "2", "boundaries": [shell_b]}]},
        "G": {"type": "TINRelief", "geometry": [{"type": "CompositeSurface", "lod": "1", "boundaries": [[[16, 17, 18, 19]]]}]},
    }
    m = read_cityjson(write(tmp_path, cityjson(objects, v)))
    fp = shapely.box(85000.5, 446000.5, 85010.5, 446010.5)  # the checked building's footprint, 0.5 m off
    assert footprint_overlap(m, fp) == ["A", "A-1"]  # 90.25 % of A; B and the ground (not a building) untouched
    wide = shapely.box(85000.0, 446000.0, 85016.0, 446010.0)  # 40 % of B
    assert footprint_overlap(m, wide) == ["A", "A-1"]
    assert footprint_overlap(m, wide, min_share=0.3) == ["A", "A-1", "B"]
    assert footprint_overlap(m, shapely.box(0, 0, 1, 1)) == []
    rest = without_objects(m, footprint_overlap(m, fp))
    assert [p.attrs["id"] for p in rest.parts] == ["B", "G"]
    assert len(rest.triangles) == 12 + 2 and np.array_equal(rest.vertices, m.vertices)
    assert abs(area(rest) - (2 * 100 + 4 * 60 + 3600)) < 1e-6
    assert [rest.parts[i].attrs["id"] for i in np.unique(rest.part)] == ["B", "G"]


def test_footprint_overlap_of_a_building_with_no_plan_area_is_none(tmp_path):
    # a building drawn as one vertical wall (every triangle flat in plan) inside the footprint: it
    # covers no plan area, so it overlaps nothing (an internal IndexError before)
    v = [[0, 0, 0], [10000, 0, 0], [10000, 0, 6000], [0, 0, 6000]]
    objects = {"W": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2", "boundaries": [[[0, 1, 2, 3]]]}]}}
    m = read_cityjson(write(tmp_path, cityjson(objects, v)))
    assert len(m.triangles) == 2
    assert footprint_overlap(m, shapely.box(84990.0, 445990.0, 85020.0, 446010.0)) == []


# --- real data ------------------------------------------------------------------------------


def test_rotterdam_subset_loads():
    m = read_model(ROTTERDAM)
    doc = json.loads(ROTTERDAM.read_text())
    ids = list(doc["CityObjects"])
    assert len(ids) == 16
    assert list(dict.fromkeys(p.attrs["id"] for p in m.parts)) == ids  # file order
    assert {p.attrs["class"] for p in m.parts} == {doc["CityObjects"][i]["type"] for i in ids} == {"Building"}
    assert len(m.parts) == 48 and {p.attrs["surface"] for p in m.parts} == {"RoofSurface", "WallSurface", "GroundSurface"}
    assert m.parts[0].attrs["attr.bron_geo"] == "Lidar 15-30 punten - nov. 2008"
    assert m.site is None  # the file has no metadata.referenceSystem (Dutch grid coordinates, see SOURCE.md)
    assert m.warnings == [] and m.notes == []
    assert len(m.triangles) == 622
    # independent check: the surfaces' Newell areas (no holes in this file); triangles of a slightly non-planar
    # polygon cover a hair more than its projection
    t = doc["transform"]
    v = np.array(doc["vertices"]) * t["scale"] + t["translate"]
    newell = 0.0
    for o in doc["CityObjects"].values():
        for g in o["geometry"]:
            for s in g["boundaries"]:
                c = v[s[0]] - v[s[0]].mean(axis=0)
                newell += 0.5 * np.linalg.norm(np.cross(c, np.roll(c, -1, axis=0)).sum(axis=0))
    assert 10_000 < area(m) and abs(area(m) - newell) < 1e-5 * newell
    assert m.vertices[:, 0].min() > 90_000 and m.vertices[:, 1].min() > 435_000
