"""DXF reader: drawings written here (with ezdxf, and by hand in EnergyPlus's own layout) whose
answers are known: the box room drawn as 3D faces gives the OBJ box room's report."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals
from en17037cli.io import ReadOptions, read_model
from en17037cli.io.dxf import read_dxf
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.samples.box import box_room_polygons

ezdxf = pytest.importorskip("ezdxf")

SUN = {"date": "02-01", "period": {"start": "02-01", "end": "02-01"}}
VIEW = {"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 2.0, "refine_levels": 2}


def area(mesh, mask=None) -> float:
    tris = mesh.triangles if mask is None else mesh.triangles[mask]
    return float(triangle_normals(mesh.vertices[tris])[1].sum())


def faces_dxf(path: Path, objects: dict, insunits: int | None = 6) -> Path:
    """Each polygon of {layer: [polygon...]} as a 3DFACE (triangles and quads; bigger ones fanned)."""
    doc = ezdxf.new("R2010")
    if insunits is not None:
        doc.header["$INSUNITS"] = insunits
    msp = doc.modelspace()
    for layer, polys in objects.items():
        for poly in polys:
            for k in range(1, len(poly) - 1, 2):  # quads (0, k, k+1, k+2), the last a triangle if odd
                pts = [poly[0], poly[k], poly[k + 1], poly[min(k + 2, len(poly) - 1)]]
                msp.add_3dface(pts, dxfattribs={"layer": layer})
    doc.saveas(path)
    return path


def run_project(tmp_path: Path, name: str, model: str, rules=None, b: BoxRoom | None = None) -> list:
    """The box room project (its street building and ground) with ``model`` as its one file; the report's rooms."""
    p = box_room_project(tmp_path / name, b or BoxRoom(), sunlight=SUN, view=VIEW)
    doc = yaml.safe_load(p.read_text())
    doc["model"]["files"][0]["path"] = model
    if rules is not None:
        doc["model"]["files"][0]["layers"] = rules
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / name / "r"), "--no-plots", "-q"],
                           catch_exceptions=False)
    assert r.exit_code in (0, 1), r.output
    return json.loads((tmp_path / name / "r" / "report.json").read_text())["rooms"]


def test_box_room_as_3dfaces_gives_the_obj_box_rooms_report(tmp_path):
    obj_rooms = run_project(tmp_path, "obj", "model.obj")
    d = tmp_path / "dxf"
    box_room_project(d, BoxRoom(), sunlight=SUN, view=VIEW)
    faces_dxf(d / "model.dxf", box_room_polygons(BoxRoom()))
    dxf_rooms = run_project(tmp_path, "dxf", "model.dxf")
    # the same figures; where they come from is each file's own (source: format, file, the layer or object name)
    assert [w["source"]["format"] for r in (*dxf_rooms, *obj_rooms) for w in r["windows"]] == ["dxf", "obj"]
    for r in (*dxf_rooms, *obj_rooms):
        for w in r["windows"]:
            w.pop("source")
    assert dxf_rooms == obj_rooms
    assert obj_rooms[0]["sunlight"]["hours_h"] > 0


def test_a_wall_drawn_whole_under_its_window_is_cut(tmp_path):
    # the facade wall as one 4 x 3 m face with the glazing on top of it (EnergyPlus's way): the same report
    obj_rooms = run_project(tmp_path, "obj", "model.obj")
    polys = box_room_polygons(BoxRoom())
    polys["room"] = [[(-2.0, 0.0, 0.0), (2.0, 0.0, 0.0), (2.0, 0.0, 3.0), (-2.0, 0.0, 3.0)]] + polys["room"][4:]
    d = tmp_path / "whole"
    box_room_project(d, BoxRoom(), sunlight=SUN, view=VIEW)
    faces_dxf(d / "model.dxf", polys)
    m = read_dxf(d / "model.dxf")
    assert m.openings_drawn and abs(area(m, np.isin(m.part, [i for i, q in enumerate(m.parts) if q.attrs["group"] == "room"]))
                                    - (12 + 2 * 24 + 2 * 18 + 12)) < 1e-9
    rooms = run_project(tmp_path, "whole", "model.dxf")
    assert rooms[0]["view"] == obj_rooms[0]["view"] and rooms[0]["sunlight"] == obj_rooms[0]["sunlight"]
    r = CliRunner().invoke(cli, ["validate", str(d / "project.yaml")], catch_exceptions=False)
    assert "1 window plane drawn on coplanar opaque faces" in r.output and "openings cut" in r.output


def test_polyface_polymesh_mesh_and_inserted_blocks_with_transforms(tmp_path):
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4  # millimetres
    msp = doc.modelspace()
    cube_v = [(0, 0, 0), (1000, 0, 0), (1000, 1000, 0), (0, 1000, 0), (0, 0, 1000), (1000, 0, 1000), (1000, 1000, 1000), (0, 1000, 1000)]
    cube_f = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    pf = msp.add_polyface(dxfattribs={"layer": "pf"})
    pf.append_faces([[cube_v[i] for i in f] for f in cube_f])
    pm = msp.add_polymesh((3, 2), dxfattribs={"layer": "pm"})  # 3 x 2 vertices: a 2000 x 1000 mm strip, 2 quads
    for m_ in range(3):
        for n_ in range(2):
            pm.set_mesh_vertex((m_, n_), (m_ * 1000.0, n_ * 1000.0, 5000.0))
    mesh = msp.add_mesh(dxfattribs={"layer": "mesh"})
    with mesh.edit_data() as data:
        data.vertices = [(0, 0, 9000), (3000, 0, 9000), (3000, 4000, 9000)]
        data.faces = [(0, 1, 2)]
    blk = doc.blocks.new("TREE")
    blk.add_3dface([(0, 0, 0), (1000, 0, 0), (1000, 1000, 0), (0, 1000, 0)], dxfattribs={"layer": "0"})
    outer = doc.blocks.new("PAIR")
    outer.add_blockref("TREE", (0, 0, 0), dxfattribs={"layer": "0"})
    outer.add_blockref("TREE", (10000, 0, 0), dxfattribs={"layer": "0"})
    msp.add_blockref("PAIR", (100000, 0, 0), dxfattribs={"layer": "trees", "xscale": 2, "yscale": 2, "zscale": 2, "rotation": 90})
    msp.add_line((0, 0, 0), (1, 1, 1))
    msp.add_text("hello")
    p = tmp_path / "parts.dxf"
    doc.saveas(p)
    m = read_model(p)
    assert m.units == "mm" and m.up_axis == "z" and m.openings_drawn
    m.vertices = m.vertices / 1000.0  # the scene scales by the units; here by hand

    def of(layer):
        return np.isin(m.part, [i for i, q in enumerate(m.parts) if q.attrs["group"] == layer])
    assert abs(area(m, of("pf")) - 6.0) < 1e-9 and of("pf").sum() == 12
    assert abs(area(m, of("pm")) - 2.0) < 1e-9 and np.allclose(m.vertices[m.triangles[of("pm")]][..., 2], 5.0)
    assert abs(area(m, of("mesh")) - 6.0) < 1e-9
    # PAIR at (100, 0, 0) m, scaled 2, turned 90 deg: TREE squares become 2 x 2 m at x 98..100, y 0..2 and y 20..22
    trees = m.vertices[m.triangles[of("trees")]].reshape(-1, 3)
    assert abs(area(m, of("trees")) - 8.0) < 1e-9
    assert np.allclose(sorted(set(np.round(trees[:, 0], 9))), [98.0, 100.0])
    assert np.allclose(sorted(set(np.round(trees[:, 1], 9))), [0.0, 2.0, 20.0, 22.0])
    tree_parts = [dict(q.attrs) for q in m.parts if q.attrs["group"] == "trees"]
    assert tree_parts == [{"group": "trees", "class": "3DFACE", "colour": "7", "type": "TREE"}]  # the block they are drawn in
    assert {q.attrs["class"] for q in m.parts} == {"POLYFACE", "POLYMESH", "MESH", "3DFACE"}
    assert any("LINE: 1" in n and "TEXT: 1" in n for n in m.notes)
    assert any("$INSUNITS 4 (Millimeters): drawing units mm" in n for n in m.notes)
    assert "on 4 layers" in m.summary and "left out: LINE: 1, TEXT: 1" in m.summary


def test_unitless_drawing_takes_the_projects_units(tmp_path):
    p = faces_dxf(tmp_path / "u.dxf", {"a": [[(0, 0, 0), (100, 0, 0), (100, 100, 0), (0, 100, 0)]]}, insunits=0)
    m = read_dxf(p)
    assert m.units is None and abs(area(m) - 1e4) < 1e-6


def test_no_3d_faces_and_not_a_dxf_are_one_line_errors(tmp_path):
    doc = ezdxf.new("R2010")
    doc.modelspace().add_line((0, 0, 0), (1, 0, 0))
    doc.modelspace().add_lwpolyline([(0, 0), (1, 0), (1, 1)])
    p = tmp_path / "lines.dxf"
    doc.saveas(p)
    with pytest.raises(InputError) as e:
        read_dxf(p)
    msg = str(e.value)
    assert "\n" not in msg and str(p) in msg and "no 3D face" in msg and "LINE: 1" in msg and "LWPOLYLINE: 1" in msg
    q = tmp_path / "x.dxf"
    q.write_text("hello\n")
    with pytest.raises(InputError) as e:
        read_dxf(q)
    assert "not a DXF file" in str(e.value)
    proj = box_room_project(tmp_path / "c", BoxRoom(), sunlight=SUN, view=VIEW)
    doc = yaml.safe_load(proj.read_text())
    (tmp_path / "c" / "lines.dxf").write_bytes(p.read_bytes())
    doc["model"]["files"][0]["path"] = "lines.dxf"
    proj.write_text(yaml.safe_dump(doc))
    r = CliRunner().invoke(cli, ["check", str(proj), "--out", str(tmp_path / "c" / "r"), "-q"])
    lines = [x for x in r.output.splitlines() if x.strip()]
    assert r.exit_code == 2 and len(lines) == 1 and "no 3D face" in lines[0]


# --- EnergyPlus's DXF output: written here in its own layout (an ENTITIES section only, 999 comments) ------


def _eplus_face(layer: str, colour: int, pts) -> str:
    pts = list(pts) + [pts[-1]] * (4 - len(pts))
    out = f"  0\n3DFACE\n  8\n{layer}\n 62\n{colour:3d}\n"
    for k, (x, y, z) in enumerate(pts):
        out += f" 1{k}\n{x:15.5f}\n 2{k}\n{y:15.5f}\n 3{k}\n{z:15.5f}\n"
    return out


def energyplus_dxf(path: Path, b: BoxRoom) -> Path:
    """The box room as EnergyPlus draws it: zone layer BOX_ROOM, walls 43 (the facade whole), window 143,
    floor 8, roof 15; the street building as Building Shading (195); ground on its own layer; the north arrow."""
    polys = box_room_polygons(b)
    hw = b.width / 2
    text = "  0\nSECTION\n  2\nENTITIES\n999\nDXF created from EnergyPlus\n999\nProgram Version,EnergyPlus, Version 9.6.0\n"
    text += "999\nPolygon Action,ThickPolyline\n999\nColor Scheme,Default\n"
    text += _eplus_face("1", 3, [(-10.0, 3.0, 0.1), (-10.0, 3.0, 0.0), (-10.0, 0.0, 0.0), (-10.0, 0.0, 0.1)])  # arrow stem
    walls = [[(-hw, 0.0, 0.0), (hw, 0.0, 0.0), (hw, 0.0, b.height), (-hw, 0.0, b.height)]] + polys["room"][6:]
    for k, w in enumerate(walls):
        text += f"999\nBOX ROOM:WALL {k + 1}\n{_eplus_face('BOX_ROOM', 43, w)}"
    text += "999\nBOX ROOM:FLOOR\n" + _eplus_face("BOX_ROOM", 8, polys["room"][4])
    text += "999\nBOX ROOM:ROOF\n" + _eplus_face("BOX_ROOM", 15, polys["room"][5])
    for g in polys["glazing"]:
        text += "999\nBOX ROOM:WINDOW 1\n" + _eplus_face("BOX_ROOM", 143, g)
    for k, s in enumerate(polys["building"]):
        text += f"999\nBuilding Shading:STREET {k + 1}\n" + _eplus_face("Building Shading", 195, s)
    text += "999\nFixed Shading:GROUND\n" + _eplus_face("Ground", 9, polys["ground"][0])
    path.write_text(text + "  0\nENDSEC\n  0\nEOF\n")
    return path


def test_energyplus_dxf_needs_no_rule_but_the_ground_and_gives_the_obj_report(tmp_path):
    b = BoxRoom()
    obj_rooms = run_project(tmp_path, "obj", "model.obj", b=b)
    d = tmp_path / "eplus"
    box_room_project(d, b, sunlight=SUN, view=VIEW)
    energyplus_dxf(d / "eplusout.dxf", b)
    m = read_dxf(d / "eplusout.dxf")
    assert m.units is None  # EnergyPlus writes no header: the project's units (metres)
    layers = {(q.attrs["group"], q.attrs["colour"]): q.layer for q in m.parts}
    assert layers == {("1", "3"): "ignore", ("BOX_ROOM", "43"): "interior", ("BOX_ROOM", "8"): "interior",
                      ("BOX_ROOM", "15"): "interior", ("BOX_ROOM", "143"): "window",
                      ("Building Shading", "195"): "landscape", ("Ground", "9"): "landscape"}
    assert [q.attrs["name"] for q in m.parts if q.layer == "window"] == ["BOX ROOM:WINDOW 1"]
    assert any("EnergyPlus DXF output" in n for n in m.notes)
    rooms = run_project(tmp_path, "eplus", "eplusout.dxf", rules=[{"match": "Ground", "layer": "ground"}], b=b)
    assert rooms[0]["sunlight"]["windows"][0]["name"] == "BOX ROOM:WINDOW 1"  # EnergyPlus's own surface name
    for r in (rooms, obj_rooms):  # the same figures, the window named as each file names it
        r[0]["sunlight"]["windows"][0]["name"] = r[0]["windows"][0]["name"] = "w"
    assert rooms[0]["view"] == obj_rooms[0]["view"] and rooms[0]["sunlight"] == obj_rooms[0]["sunlight"]


def test_rotated_insert_keeps_float64_far_from_the_origin(tmp_path):
    doc = ezdxf.new("R2010")
    blk = doc.blocks.new("Q")
    blk.add_3dface([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)])
    doc.modelspace().add_blockref("Q", (389500.125, 5819600.25, 34.0), dxfattribs={"rotation": 30, "layer": "far"})
    p = tmp_path / "far.dxf"
    doc.saveas(p)
    m = read_dxf(p, ReadOptions())
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    expect = {(389500.125 + x * c - y * s, 5819600.25 + x * s + y * c, 34.0) for x, y in ((0, 0), (1, 0), (1, 1), (0, 1))}
    got = {tuple(v) for v in m.vertices.tolist()}
    assert len(got) == 4 and all(min(np.hypot(g[0] - e[0], g[1] - e[1]) for g in got) < 1e-9 for e in expect)


REAL = Path(__file__).resolve().parents[3] / "shared" / "data" / "real-models"


@pytest.mark.skipif(not any(REAL.glob("*.dxf")), reason="no real DXF in ../shared/data/real-models yet")
@pytest.mark.parametrize("path", sorted(REAL.glob("*.dxf")), ids=lambda p: p.name)
def test_every_real_dxf_of_the_corpus_reads(path):
    """Any real DXF put in ../shared/data/real-models is read as a user would: faces, a summary
    line, and either glazing on the window layer or a note saying why none is."""
    m = read_model(path, ReadOptions())
    assert len(m.triangles) > 0 and m.summary
    assert any(q.layer == "window" for q in m.parts) or m.notes or m.warnings


def stacked_zones_dxf(path: Path) -> Path:
    """Two 4 x 5 m zones, one over the other with a 0.6 m plenum between (z 0-3, 3-3.6, 3.6-6.6), as
    EnergyPlus draws them: each zone's own faces, floors facing down and ceilings up (out of their
    zone), coincident where zones meet; a 2 x 1.4 m window drawn on each south wall."""
    text = "  0\nSECTION\n  2\nENTITIES\n999\nDXF created from EnergyPlus\n999\nProgram Version,EnergyPlus, Version 23.2.0\n"
    text += "999\nPolygon Action,ThickPolyline\n999\nColor Scheme,Default\n"
    x0, x1, y0, y1 = -2.0, 2.0, 0.0, 5.0
    for zone, (z0, z1, win) in {"ZONE_A": (0.0, 3.0, True), "PLENUM": (3.0, 3.6, False), "ZONE_B": (3.6, 6.6, True)}.items():
        text += f"999\n{zone}:FLOOR\n" + _eplus_face(zone, 8, [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)])  # floor, facing down
        text += _eplus_face(zone, 15, [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)])  # ceiling, facing up
        for a, b in (((x0, y0), (x1, y0)), ((x1, y0), (x1, y1)), ((x1, y1), (x0, y1)), ((x0, y1), (x0, y0))):
            text += _eplus_face(zone, 43, [(*a, z0), (*b, z0), (*b, z1), (*a, z1)])
        if win:
            text += f"999\n{zone}:WINDOW\n" + _eplus_face(zone, 143, [(-1.0, 0.0, z0 + 0.8), (1.0, 0.0, z0 + 0.8), (1.0, 0.0, z0 + 2.2), (-1.0, 0.0, z0 + 2.2)])
    path.write_text(text + "  0\nENDSEC\n  0\nEOF\n")
    return path


def test_auto_rooms_in_an_energyplus_drawing_of_stacked_zones(tmp_path):
    """rooms: auto on EnergyPlus's zones: a level is a floor where a room's height lies clear above
    it, whichever way its faces turn: the two zones at z 0 and 3.6 m, each 20 m² with its window,
    not the plenum's floor at 3.0 m (0.6 m clear). Before: floors were upward-facing faces only, so
    the ceilings were taken for floors: one room, at z 3.0 (the plenum's floor)."""
    d = tmp_path / "p"
    p = box_room_project(d, BoxRoom(), sunlight=SUN, view=None)
    stacked_zones_dxf(d / "eplusout.dxf")
    doc = yaml.safe_load(p.read_text())
    doc["model"]["files"] = [{"path": "eplusout.dxf"}]
    doc["rooms"] = [{"auto": True}]
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(d / "r"), "--no-plots", "-q"], catch_exceptions=False)
    assert r.exit_code in (0, 1), r.output
    rooms = json.loads((d / "r" / "report.json").read_text())["rooms"]
    assert [x["name"] for x in rooms] == ["z 0.00 room at (0.0, 2.5)", "z 3.60 room at (0.0, 2.5)"]
    assert [x["floor_area_m2"] for x in rooms] == pytest.approx([20.0, 20.0], abs=1e-6)
    assert [[w["name"] for w in x["windows"]] for x in rooms] == [["ZONE_A:WINDOW"], ["ZONE_B:WINDOW"]]
