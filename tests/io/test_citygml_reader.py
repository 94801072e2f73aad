"""CityGML reader: files written here with values worked out by hand, the same polygons as the
CityJSON sample, and the real Berlin tile of ../shared (skipped only when that folder is absent)."""
from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from citygml_files import NS3, box_polys, building, city_model, from_cityjson, multi_surface, polygon, write

from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals
from en17037cli.io import ReadOptions, is_context, read_model
from en17037cli.io.citygml import read_citygml
from en17037cli.io.citygml.crs import parse_srs_name

pytest.importorskip("lxml")
pytest.importorskip("pyproj")

ROOT = Path(__file__).resolve().parents[2]
ROTTERDAM = ROOT / "sample_projects" / "cityjson-rotterdam" / "rotterdam_subset.json"
BERLIN = ROOT.parent / "shared" / "data" / "real-models" / "berlin_3890_5819.gml"


def area(mesh, mask=None) -> float:
    tris = mesh.triangles if mask is None else mesh.triangles[mask]
    return float(triangle_normals(mesh.vertices[tris])[1].sum())


def part_area(mesh, **attrs) -> float:
    sel = [i for i, p in enumerate(mesh.parts) if all(p.attrs.get(k) == v for k, v in attrs.items())]
    return area(mesh, np.isin(mesh.part, sel))


def one_line(excinfo, path: Path) -> str:
    msg = str(excinfo.value)
    assert "\n" not in msg and str(path) in msg
    return msg


# --- srsName forms ------------------------------------------------------------------------------


@pytest.mark.parametrize("srs, expected", [
    ("EPSG:25833", "EPSG:25833"),
    ("urn:ogc:def:crs:EPSG::25833", "EPSG:25833"),
    ("urn:ogc:def:crs:EPSG:6.12:25832", "EPSG:25832"),
    ("urn:x-ogc:def:crs:EPSG:31467", "EPSG:31467"),
    ("urn:ogc:def:crs,crs:EPSG::25832,crs:EPSG::7837", "EPSG:25832"),
    ("http://www.opengis.net/def/crs/EPSG/0/6697", "EPSG:6697"),
    ("https://www.opengis.net/def/crs/EPSG/0/28992", "EPSG:28992"),
    ("http://www.opengis.net/gml/srs/epsg.xml#25833", "EPSG:25833"),
    ("urn:adv:crs:ETRS89_UTM32*DE_DHHN2016_NH", "EPSG:25832"),
    ("urn:adv:crs:ETRS89_UTM33*DE_DHHN92_NH", "EPSG:25833"),
    ("urn:adv:crs:DE_DHDN_3GK3*DE_DHHN92_NH", "EPSG:31467"),
    ("urn:ogc:def:crs:OGC:1.3:CRS84", "OGC:CRS84"),
    ("#local-CRS-1", None),
    ("urn:adv:crs:NOT_A_CRS", None),
])
def test_srs_name_forms(srs, expected):
    assert parse_srs_name(srs) == expected


# --- geometry ----------------------------------------------------------------------------------


def test_box_with_thematic_surfaces_exact_coordinates_and_areas(tmp_path):
    # 10 x 20 x 6 m box at (400000, 5800000): walls 2 (10 + 20) 6 = 360 m², roof and ground 200 m²
    b = building("b1", box_polys(400000.0, 400010.0, 5800000.0, 5800020.0, 30.0, 6.0), srs="EPSG:25832")
    p = write(tmp_path, city_model([b]))
    m = read_citygml(p)
    assert m.vertices.dtype == np.float64 and (m.units, m.up_axis) == ("m", "z")
    assert sorted(set(map(tuple, m.vertices.tolist()))) == sorted(
        {(x, y, z) for x in (400000.0, 400010.0) for y in (5800000.0, 5800020.0) for z in (30.0, 36.0)})
    assert abs(part_area(m, surface="WallSurface") - 360.0) < 1e-6
    assert abs(part_area(m, surface="RoofSurface") - 200.0) < 1e-6
    assert abs(part_area(m, surface="GroundSurface") - 200.0) < 1e-6
    assert len(m.triangles) == 12  # the repeated closing vertex of each GML ring is dropped: 6 quads
    assert [(dict(q.attrs), q.layer) for q in m.parts] == [
        ({"class": "Building", "id": "b1", "surface": "GroundSurface"}, "ignore"),
        ({"class": "Building", "id": "b1", "surface": "RoofSurface"}, "landscape"),
        ({"class": "Building", "id": "b1", "surface": "WallSurface"}, "landscape")]
    assert m.site.crs == "EPSG:25832" and m.site.reprojected_from is None
    assert "1 object" in m.summary and "Building LoD 2: 1" in m.summary
    assert is_context(p)


def test_wall_with_window_hole_and_citygml3_names(tmp_path):
    # 10 x 5 m wall in the plane y = 0 with a 2 x 1 m hole: 48 m²; CityGML 3.0 namespaces (core:boundary, con:)
    wall = [(0.0, 0.0, 0.0), (10.0, 0.0, 0.0), (10.0, 0.0, 5.0), (0.0, 0.0, 5.0)]
    hole = [(4.0, 0.0, 2.0), (4.0, 0.0, 3.0), (6.0, 0.0, 3.0), (6.0, 0.0, 2.0)]
    ms = f"<gml:MultiSurface><gml:surfaceMember>{polygon([wall, hole])}</gml:surfaceMember></gml:MultiSurface>"
    b = (f'<bldg:Building gml:id="w"><core:boundary><con:WallSurface gml:id="ws"><core:lod2MultiSurface>{ms}'
         "</core:lod2MultiSurface></con:WallSurface></core:boundary></bldg:Building>")
    m = read_citygml(write(tmp_path, city_model([b], ns=NS3)))
    assert abs(area(m) - 48.0) < 1e-9
    c = m.vertices[m.triangles].mean(axis=1)
    assert not (((c[:, 0] > 4) & (c[:, 0] < 6)) & ((c[:, 2] > 2) & (c[:, 2] < 3))).any()
    assert [dict(q.attrs) for q in m.parts] == [{"class": "Building", "id": "w", "surface": "WallSurface"}]
    assert m.site is None  # no srsName anywhere: coordinates as they are


def test_solid_by_reference_counts_polygons_once_and_lod_choice(tmp_path):
    # LoD1 block (solid written out) and LoD2 thematic surfaces whose polygons the lod2Solid lists by xlink
    lod1 = box_polys(0.0, 10.0, 0.0, 10.0, 0.0, 3.0)
    solid1 = "".join(f"<gml:surfaceMember>{polygon(r)}</gml:surfaceMember>" for polys in lod1.values() for r in polys)
    lod2 = box_polys(0.0, 10.0, 0.0, 10.0, 0.0, 4.0)
    ids = [f"p{k}" for k in range(6)]
    them, k = "", 0
    for stype, polys in lod2.items():
        them += (f"<bldg:boundedBy><bldg:{stype}><bldg:lod2MultiSurface>{multi_surface(polys, ids=ids[k:k + len(polys)])}"
                 f"</bldg:lod2MultiSurface></bldg:{stype}></bldg:boundedBy>")
        k += len(polys)
    refs = "".join(f'<gml:surfaceMember xlink:href="#{i}"/>' for i in ids)
    b = (f'<bldg:Building gml:id="b"><bldg:lod1Solid><gml:Solid><gml:exterior><gml:CompositeSurface>{solid1}'
         f"</gml:CompositeSurface></gml:exterior></gml:Solid></bldg:lod1Solid>"
         f"<bldg:lod2Solid><gml:Solid><gml:exterior><gml:CompositeSurface>{refs}</gml:CompositeSurface></gml:exterior>"
         f"</gml:Solid></bldg:lod2Solid>{them}</bldg:Building>")
    p = write(tmp_path, city_model([b]))
    m = read_citygml(p)  # highest: LoD2, each polygon once (the solid's references add nothing)
    assert abs(area(m) - (2 * 100 + 4 * 40)) < 1e-9 and len(m.triangles) == 12
    m1 = read_citygml(p, ReadOptions(lod="1"))
    assert abs(area(m1) - (2 * 100 + 4 * 30)) < 1e-9 and len(m1.parts) == 1 and "surface" not in m1.parts[0].attrs
    m0 = read_citygml(p, ReadOptions(lod="0"))
    assert len(m0.triangles) == 0 and any("without surface geometry at or below LoD 0" in n for n in m0.notes)


def test_building_parts_exclude_and_attributes(tmp_path):
    part = building("bp", box_polys(20.0, 25.0, 0.0, 5.0, 0.0, 3.0), cls="bldg:BuildingPart")
    attrs = ('<bldg:function>1000</bldg:function><gen:stringAttribute name="Gemeinde"><gen:value>Berlin</gen:value>'
             "</gen:stringAttribute>")
    main = building("b", box_polys(0.0, 10.0, 0.0, 10.0, 0.0, 3.0), extra=attrs)
    main = main.replace("</bldg:Building>", f"<bldg:consistsOfBuildingPart>{part}</bldg:consistsOfBuildingPart></bldg:Building>")
    other = building("o", box_polys(100.0, 110.0, 0.0, 10.0, 0.0, 3.0))
    p = write(tmp_path, city_model([main, other]))
    m = read_citygml(p)
    bp = [dict(q.attrs) for q in m.parts if q.attrs["id"] == "bp"]
    assert bp[0] == {"class": "BuildingPart", "id": "bp", "parent": "Building", "surface": "GroundSurface"}
    b = next(dict(q.attrs) for q in m.parts if q.attrs["id"] == "b")
    assert b["attr.function"] == "1000" and b["attr.Gemeinde"] == "Berlin"
    ex = read_citygml(p, ReadOptions(exclude=("b", "nope")))
    assert {q.attrs["id"] for q in ex.parts} == {"o"}
    assert any("2 objects left out by exclude (1 listed, 1 inside them)" in n for n in ex.notes)
    assert any("1 excluded id not in the file: nope" in n for n in ex.notes)


def test_near_radius_leaves_out_far_objects_while_streaming(tmp_path):
    members = [building(f"b{k}", box_polys(100.0 * k, 100.0 * k + 10, 0.0, 10.0, 0.0, 3.0)) for k in range(10)]
    p = write(tmp_path, city_model(members))
    m = read_citygml(p, ReadOptions(near=((0.0, 5.0), 250.0)))  # b0, b1, b2 come within 250 m; b3 starts at x 300
    assert sorted({q.attrs["id"] for q in m.parts}) == ["b0", "b1", "b2"]
    assert any("7 objects lying entirely farther than 250 m from (0, 5) left out" in n for n in m.notes)


def test_implicit_geometry_template_placed_and_reused_by_reference(tmp_path):
    tpl = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)]
    ms = multi_surface([[tpl]]).replace("<gml:MultiSurface>", '<gml:MultiSurface gml:id="tree">')
    turn = "0 -2 0 0 2 0 0 0 0 0 2 0 0 0 0 1"  # 90 degrees about z, then x2 (row major)

    def tree(gid, rel, ref):
        return (f'<veg:SolitaryVegetationObject gml:id="{gid}"><veg:lod2ImplicitRepresentation><ImplicitGeometry>'
                f"<transformationMatrix>{turn}</transformationMatrix><relativeGMLGeometry{rel}</relativeGMLGeometry>"
                f"<referencePoint><gml:Point><gml:pos>{ref}</gml:pos></gml:Point></referencePoint></ImplicitGeometry>"
                "</veg:lod2ImplicitRepresentation></veg:SolitaryVegetationObject>")
    t1 = tree("t1", f">{ms}", "10 20 1")
    t2 = tree("t2", ' xlink:href="#tree">', "50 60 0")
    m = read_citygml(write(tmp_path, city_model([t1, t2])))
    v1 = m.vertices[np.unique(m.triangles[m.part == 0])]
    v2 = m.vertices[np.unique(m.triangles[m.part == 1])]
    # (x, y) -> (-2y, 2x) + ref: the unit square becomes [8, 10] x [20, 22] at z 1
    assert sorted(map(tuple, v1.tolist())) == sorted([(10.0, 20.0, 1.0), (10.0, 22.0, 1.0), (8.0, 22.0, 1.0), (8.0, 20.0, 1.0)])
    assert sorted(map(tuple, v2.tolist())) == sorted([(50.0, 60.0, 0.0), (50.0, 62.0, 0.0), (48.0, 62.0, 0.0), (48.0, 60.0, 0.0)])
    assert [q.layer for q in m.parts] == ["landscape", "landscape"]


def test_tin_relief_and_an_ade_class(tmp_path):
    tri = [(0.0, 0.0, 1.0), (10.0, 0.0, 1.0), (0.0, 10.0, 1.0)]
    tin = ('<dem:ReliefFeature gml:id="rf"><dem:lod>2</dem:lod><dem:reliefComponent><dem:TINRelief gml:id="tin">'
           "<dem:lod>2</dem:lod><dem:tin><gml:TriangulatedSurface><gml:trianglePatches><gml:Triangle><gml:exterior>"
           f"<gml:LinearRing><gml:posList>{' '.join(f'{c!r}' for p in tri + tri[:1] for c in p)}</gml:posList></gml:LinearRing>"
           "</gml:exterior></gml:Triangle></gml:trianglePatches></gml:TriangulatedSurface></dem:tin></dem:TINRelief>"
           "</dem:reliefComponent></dem:ReliefFeature>")
    ade = f'<x:Silo xmlns:x="urn:example" gml:id="s"><x:lod1Geometry>{multi_surface([[tri]])}</x:lod1Geometry></x:Silo>'
    m = read_citygml(write(tmp_path, city_model([tin, ade])))
    assert [(q.attrs["class"], q.layer) for q in m.parts] == [("TINRelief", "ground"), ("Silo", "landscape")]
    assert abs(part_area(m, id="tin") - 50.0) < 1e-9
    assert any("1 object of types that are not in the class table given layer landscape (Silo: 1)" in n for n in m.notes)


# --- CRSs --------------------------------------------------------------------------------------


def _square_deg(lat0, lon0, d, lat_first: bool):
    pts = [(lat0, lon0), (lat0, lon0 + d), (lat0 + d, lon0 + d), (lat0 + d, lon0)]
    return [((a, b, 5.0) if lat_first else (b, a, 5.0)) for a, b in pts]


@pytest.mark.parametrize("srs, lat_first", [
    ("urn:ogc:def:crs:EPSG::4326", True), ("http://www.opengis.net/def/crs/EPSG/0/4326", True),
    ("EPSG:4326", False), ("urn:ogc:def:crs:OGC:1.3:CRS84", False)])
def test_degrees_projected_to_the_projects_crs(tmp_path, srs, lat_first):
    # on UTM zone 32's central meridian (9 deg E) at the equator: E = 500000 m, N = 0 m exactly (k0 = 0.9996 there)
    ring = _square_deg(0.0, 9.0, 0.001, lat_first)
    p = write(tmp_path, city_model([building("g", {"RoofSurface": [[ring]]}, srs=srs)]))
    m = read_citygml(p, ReadOptions(target_crs="EPSG:32632"))
    v = m.vertices
    assert np.allclose(v[np.isclose(v[:, 0], v[:, 0].min()), 0], 500000.0, atol=1e-6)
    assert np.allclose(v[:, 1].min(), 0.0, atol=1e-6)
    # 0.001 deg of longitude at the equator on the central meridian: a (1 - e^2 sin^2)^-1/2 cos(0) dλ k0 ~ 111.28 m x 0.9996
    assert 111.1 < v[:, 0].max() - 500000.0 < 111.3 and 110.5 < v[:, 1].max() < 110.7
    assert np.allclose(v[:, 2], 5.0)  # heights kept
    assert m.site.crs == "EPSG:32632" and m.site.reprojected_from == "EPSG:4326" or m.site.reprojected_from == "OGC:CRS84"
    assert any("projected to EPSG:32632" in n for n in m.notes)


def test_degrees_without_a_target_and_unknown_crs_are_one_line_errors(tmp_path):
    ring = _square_deg(52.5, 13.4, 0.001, True)
    p = write(tmp_path, city_model([building("g", {"RoofSurface": [[ring]]}, srs="urn:ogc:def:crs:EPSG::4326")]))
    with pytest.raises(InputError) as e:
        read_citygml(p)
    msg = one_line(e, p)
    assert "in degrees" in msg and "'crs' key" in msg and "EPSG:32633" in msg  # the UTM zone of Berlin, as a hint
    q = write(tmp_path, city_model([building("g", box_polys(0, 1, 0, 1, 0, 1), srs="urn:adv:crs:NOT_A_CRS")]), "u.gml")
    with pytest.raises(InputError) as e:
        read_citygml(q)
    assert "unknown CRS srsName 'urn:adv:crs:NOT_A_CRS'" in one_line(e, q)
    r = write(tmp_path, city_model([building("g", box_polys(0, 1, 0, 1, 0, 1), srs="EPSG:999999")]), "r.gml")
    with pytest.raises(InputError) as e:
        read_citygml(r)
    assert "PROJ does not know" in one_line(e, r)
    ok = read_citygml(r, ReadOptions(crs="EPSG:25832"))  # the project's crs key wins over the file's srsName
    assert ok.site.crs == "EPSG:25832"


def test_axis_order_of_a_projected_crs_is_decided_by_the_data(tmp_path):
    # EPSG:31468 (Gauss-Krüger zone 4) is northing-first by definition; files write easting first
    ring = [(4490655.0, 5322005.0, 548.0), (4490665.0, 5322005.0, 548.0), (4490665.0, 5322015.0, 548.0)]
    p = write(tmp_path, city_model([building("g", {"RoofSurface": [[ring]]}, srs="EPSG:31468")]))
    m = read_citygml(p)
    assert m.vertices[:, 0].min() == 4490655.0 and any("(east, north)" in n for n in m.notes)
    flipped = [(y, x, z) for x, y, z in ring]
    q = write(tmp_path, city_model([building("g", {"RoofSurface": [[flipped]]}, srs="EPSG:31468")]), "f.gml")
    assert np.array_equal(read_citygml(q).vertices, m.vertices)


def test_adv_urn_and_envelope_default_srs(tmp_path):
    b = building("b", box_polys(390000.0, 390010.0, 5820000.0, 5820010.0, 30.0, 6.0))  # no srsName on the geometry
    doc = city_model([b], srs="urn:adv:crs:ETRS89_UTM33*DE_DHHN2016_NH",
                     envelope=("390000 5820000 30", "390010 5820010 36"))
    m = read_citygml(write(tmp_path, doc))
    assert m.site.crs == "EPSG:25833"
    m2 = read_citygml(write(tmp_path, doc, "b.gml"), ReadOptions(target_crs="EPSG:25833"))
    assert np.array_equal(m2.vertices, m.vertices) and m2.site.reprojected_from is None


# --- bad files ---------------------------------------------------------------------------------


def test_malformed_and_foreign_xml_are_one_line_errors(tmp_path):
    good = city_model([building("b", box_polys(0.0, 1.0, 0.0, 1.0, 0.0, 1.0))])
    cut = write(tmp_path, good[: len(good) // 2])
    with pytest.raises(InputError) as e:
        read_citygml(cut)
    assert re.search(r"city\.gml:\d+: not well-formed XML", one_line(e, cut))
    other = write(tmp_path, '<?xml version="1.0"?><gbXML xmlns="http://www.gbxml.org/schema"><Campus/></gbXML>', "o.gml")
    with pytest.raises(InputError) as e:
        read_citygml(other)
    assert "not CityGML (root element 'gbXML'" in one_line(e, other)
    nums = write(tmp_path, good.replace("0.0 0.0 0.0", "0.0 zero 0.0", 1), "n.gml")
    with pytest.raises(InputError) as e:
        read_citygml(nums)
    assert "posList holds something else than numbers" in one_line(e, nums)


# --- by construction: the CityJSON sample written as CityGML -------------------------------------


def test_the_cityjson_sample_as_citygml_gives_the_same_faces_per_layer():
    doc = json.loads(ROTTERDAM.read_text())
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        p = write(Path(d), from_cityjson(doc, "urn:ogc:def:crs,crs:EPSG::28992,crs:EPSG::5709"))
        g = read_model(p, ReadOptions(crs="EPSG:7415"))
    j = read_model(ROTTERDAM)
    assert len(g.triangles) == len(j.triangles) == 622
    layers = lambda m: [(dict(q.attrs)["id"], q.attrs.get("surface"), q.layer) for q in m.parts]  # noqa: E731
    assert layers(g) == layers(j)
    for k in range(len(j.parts)):  # per part, the same triangles (same coordinates, same order)
        assert np.array_equal(g.vertices[g.triangles[g.part == k]], j.vertices[j.triangles[j.part == k]])
    assert g.site.crs == "EPSG:7415"


# --- the real Berlin tile ---------------------------------------------------------------------


def _newell_areas(path: Path) -> dict:
    """Independent of the reader: area of every gml:Polygon (exterior minus interiors, Newell's formula on
    the posList as written) summed by the thematic surface it lies in, and the polygon counts."""
    from lxml import etree

    gml = "{http://www.opengis.net/gml}"
    out: dict = {}
    for surf in etree.parse(str(path)).iter("{*}WallSurface", "{*}RoofSurface", "{*}GroundSurface"):
        kind = etree.QName(surf).localname
        for poly in surf.iter(f"{gml}Polygon"):
            a = 0.0
            for k, ring in enumerate(poly.iter(f"{gml}posList")):
                v = np.array(ring.text.split(), dtype=float).reshape(-1, 3)
                c = v - v.mean(axis=0)
                a += (1 if k == 0 else -1) * 0.5 * np.linalg.norm(np.cross(c[:-1], c[1:]).sum(axis=0))
            n, s = out.get(kind, (0, 0.0))
            out[kind] = (n + 1, s + a)
    return out


@pytest.mark.skipif(not BERLIN.is_file(), reason="../shared/data/real-models absent")
def test_real_berlin_tile():
    m = read_model(BERLIN)
    assert m.site.crs == "EPSG:25833" and not m.warnings
    assert "40 objects" in m.summary and "Building LoD 2: 40" in m.summary
    assert {q.attrs["class"] for q in m.parts} == {"Building"} and len(m.parts) == 120
    expected = _newell_areas(BERLIN)
    for kind, (_n, a) in expected.items():
        # triangles cover each polygon's area: ear clipping loses none (1e-6 relative: float64 sums of ~1e3 m² terms)
        assert abs(part_area(m, surface=kind) - a) < 1e-6 * a, kind
    assert expected["WallSurface"][0] >= 1102 and expected["RoofSurface"][0] >= 652  # the README's counts
    z = m.vertices[:, 2]
    assert 30.5 < z.min() < 30.6 and 86.0 < z.max() < 86.1
    near = read_model(BERLIN, ReadOptions(near=((389500.0, 5819600.0), 150.0), exclude=("BLDG_0003000e00284e98",)))
    kept = {q.attrs["id"] for q in near.parts}
    assert 0 < len(kept) < 40 and "BLDG_0003000e00284e98" not in kept
