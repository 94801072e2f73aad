"""City context from CityJSON in a project: layers without rules, placement, CRS, radius, the
checked building left out, and the same answers as the same scene written as OBJ.

Box room (en17037cli.samples.BoxRoom): window x in [-1, 1], z in [0.8, 2.2] in the plane y = 0,
facing south; here without the generated street building, which comes from a CityJSON file.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.samples import BoxRoom, box_room_project

ROOT = Path(__file__).resolve().parents[1]
SUN = {"date": "02-01", "period": {"start": "02-01", "end": "02-01"}}
VIEW = {"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 2.0, "refine_levels": 2}


def box_solid(x0, x1, y0, y1, h, scale=0.001):
    """Vertices (integers, for ``transform.scale``) and a Solid's boundaries of an axis-aligned box."""
    q = lambda v: [round(c / scale) for c in v]  # noqa: E731
    v = [q(p) for p in ((x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0), (x0, y0, h), (x1, y0, h), (x1, y1, h), (x0, y1, h))]
    faces = [[[0, 3, 2, 1]], [[4, 5, 6, 7]], [[0, 1, 5, 4]], [[1, 2, 6, 5]], [[2, 3, 7, 6]], [[3, 0, 4, 7]]]
    semantics = {"surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"}, {"type": "WallSurface"}],
                 "values": [[0, 1, 2, 2, 2, 2]]}
    return v, faces, semantics


def city(path: Path, buildings: dict, translate=(0.0, 0.0, 0.0), crs="https://www.opengis.net/def/crs/EPSG/0/7415"):
    """Write a CityJSON 2.0 file of box buildings {id: (x0, x1, y0, y1, height)} [m]."""
    vertices, objects = [], {}
    for oid, (x0, x1, y0, y1, h) in buildings.items():
        v, faces, sem = box_solid(x0 - translate[0], x1 - translate[0], y0 - translate[1], y1 - translate[1], h)
        off = len(vertices)
        vertices += v
        faces = [[[i + off for i in ring] for ring in f] for f in faces]
        objects[oid] = {"type": "Building", "geometry": [{"type": "Solid", "lod": "2.2", "boundaries": [faces],
                                                          "semantics": sem}]}
    doc = {"type": "CityJSON", "version": "2.0", "transform": {"scale": [0.001, 0.001, 0.001], "translate": list(translate)},
           "metadata": {"referenceSystem": crs}, "CityObjects": objects, "vertices": vertices}
    path.write_text(json.dumps(doc))
    return path


def project_with_city(tmp_path: Path, buildings: dict, place=(0.0, 0.0, 0.0), **file_keys) -> Path:
    """The box room without its street building, placed at ``place``, with a CityJSON context."""
    path = box_room_project(tmp_path / "p", BoxRoom(building_height=0), sunlight=SUN, view=VIEW)
    city(path.parent / "context.city.json", buildings, translate=(85000.0, 446000.0, 0.0))
    doc = yaml.safe_load(path.read_text())
    doc["model"]["files"][0]["transform"] = {"translate_m": list(place)}
    doc["model"]["files"].append({"path": "context.city.json", **file_keys})
    doc["rooms"][0]["floor_z"] = place[2]
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def run(path: Path, out: Path, *extra):
    r = CliRunner().invoke(cli, ["check", str(path), "--out", str(out), "-q", *extra], catch_exceptions=False)
    assert r.exit_code in (0, 1), r.output  # each test asserts the levels it cares about
    return json.loads((out / "report.json").read_text())


#: The street building of BoxRoom as a CityJSON building: x +-200 m, y -35..-25 m, 10 m high,
#: around the room placed at (85000, 446000) in EPSG:7415.
PLACE = (85000.0, 446000.0, 0.0)
STREET = {"NL.street": (85000 - 200.0, 85000 + 200.0, 446000 - 35.0, 446000 - 25.0, 10.0)}


def test_city_context_needs_no_rule_and_gives_the_obj_answers(tmp_path):
    """The same street as the box room's own (OBJ) and as a CityJSON building: same view and sun."""
    report = run(project_with_city(tmp_path, STREET, place=PLACE), tmp_path / "o")
    obj = box_room_project(tmp_path / "obj", BoxRoom(), sunlight=SUN, view=VIEW)  # street as OBJ, at the origin
    ref = run(obj, tmp_path / "r")
    a, b = report["rooms"][0], ref["rooms"][0]
    assert a["sunlight"]["hours_h"] == b["sunlight"]["hours_h"]
    pa, pb = a["view"]["eye_heights"][0]["points"], b["view"]["eye_heights"][0]["points"]
    assert len(pa) == len(pb)
    for p, q in zip(pa, pb):
        assert abs(p["horizontal_sight_angle_deg"] - q["horizontal_sight_angle_deg"]) <= 1e-4  # the bisection tolerance
        assert abs(p["outside_distance_m"] - q["outside_distance_m"]) <= 1e-3  # float32 rays at 25-60 m
        for k in ("sky", "landscape", "ground"):
            # the same geometry in another frame: only float32 round-off at a cell's corner can differ
            assert abs(p["solid_angle_sr"][k] - q["solid_angle_sr"][k]) <= p["solid_angle_error_sr"][k] + q["solid_angle_error_sr"][k] + 1e-9
    assert a["view"]["level"] == b["view"]["level"] == "medium"  # 25 m street: distance 'medium'
    assert report["inputs"]["local_origin_m"][:2] == [85000.0, 446000.0]


def test_the_checked_building_in_the_city_model_is_left_out(tmp_path):
    """A 3D BAG tile holds the checked building too: its plan overlaps the model's, so it goes."""
    buildings = {**STREET, "NL.self": (85000 - 2.0, 85000 + 2.0, 446000 + 0.0, 446000 + 6.0, 3.0)}
    report = run(project_with_city(tmp_path, buildings, place=PLACE), tmp_path / "o")
    assert any("1 building(s) overlapping the model's own plan left out (exclude_overlapping): NL.self" in n
               for n in report["notes"])
    # the room is not inside a solid copy of itself: the street's answer, as without the copy
    assert report["rooms"][0]["sunlight"]["hours_h"] == run(project_with_city(tmp_path / "s", STREET, place=PLACE),
                                                          tmp_path / "o3")["rooms"][0]["sunlight"]["hours_h"]
    # with exclude_overlapping off, the city model's copy of the building covers the glazing: the
    # uncut-wall check stops the run and names both
    path = project_with_city(tmp_path / "b", buildings, place=PLACE, exclude_overlapping=False)
    r = CliRunner().invoke(cli, ["check", str(path), "-q", "--out", str(tmp_path / "o2")])
    assert r.exit_code == 2 and "window 'glazing' (model: glazing) lies on 'context.city: NL.self'" in r.output


def test_exclude_by_id_and_the_context_radius(tmp_path):
    far = {"NL.far": (85000 + 1500.0, 85000 + 1510.0, 446000 - 10.0, 446000 + 10.0, 200.0)}
    report = run(project_with_city(tmp_path, {**STREET, **far}, place=PLACE), tmp_path / "o")
    # the 200 m tower 1.5 km east lies beyond the 1000 m radius around the window (85000, 446000)
    assert "context.city.json: 1 object lying entirely farther than 1000 m from (85000, 446000) left out" in report["notes"]
    report = run(project_with_city(tmp_path / "x", STREET, place=PLACE, exclude=["NL.street"]), tmp_path / "o2")
    # without the street building the model has no landscape left: the layers cannot be judged
    # (and are not traced); with it, every point sees some landscape
    view = report["rooms"][0]["view"]
    assert view["status"] == "not_assessable" and "the model has no landscape" in view["reason"]
    assert all(p["solid_angle_sr"]["landscape"] is None for p in view["eye_heights"][0]["points"])
    report = run(project_with_city(tmp_path / "y", STREET, place=PLACE), tmp_path / "o3")
    assert all(p["solid_angle_sr"]["landscape"] > 0 for p in report["rooms"][0]["view"]["eye_heights"][0]["points"])


def test_rules_on_semantic_surfaces(tmp_path):
    """Roofs to 'ignore' by a rule on the surface type: the building's roof no longer blocks the
    sun; its walls still do."""
    path = project_with_city(tmp_path, STREET, place=PLACE,
                             layers=[{"class": "Building", "surface": "RoofSurface", "layer": "ignore"}])
    report = run(path, tmp_path / "o")
    r = CliRunner().invoke(cli, ["validate", str(path), "--objects"])
    assert "object context.city: class=Building, id=NL.street, surface=WallSurface: layer landscape, 8 faces" in r.output
    assert "surface=RoofSurface" not in r.output  # ignored faces are not loaded
    assert report["rooms"][0]["view"]["level"] == "medium"


def test_a_crs_different_from_the_models_is_an_input_error(tmp_path):
    path = project_with_city(tmp_path, STREET, place=PLACE)
    doc = yaml.safe_load(path.read_text())
    doc["model"]["files"][0]["crs"] = "EPSG:25831"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    r = CliRunner().invoke(cli, ["check", str(path), "-q"])
    assert r.exit_code == 2 and len(r.output.strip().splitlines()) == 1
    assert "model.obj is in EPSG:25831 but context.city.json is in EPSG:7415" in r.output
    # RD New and RD New + NAP line up in plan
    doc["model"]["files"][0]["crs"] = "EPSG:28992"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    assert CliRunner().invoke(cli, ["validate", str(path)]).exit_code == 0


@pytest.mark.parametrize("deg", [90.0, -30.0])
def test_transform_rotates_then_translates(tmp_path, deg):
    """rotate_deg turns the model counterclockwise seen from above, then translate_m moves it."""
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight=None, view=VIEW)
    doc = yaml.safe_load(path.read_text())
    doc["model"]["files"][0]["transform"] = {"rotate_deg": deg, "translate_m": [10.0, 20.0, 3.0]}
    doc["model"]["true_north_deg"] = -deg  # north turned alike: the same answers
    doc["rooms"][0]["floor_z"] = 3.0
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    report = run(path, tmp_path / "o", "--set", "requirements.sunlight=none")
    w = report["rooms"][0]["windows"][0]
    a = np.radians(deg)
    expected = [round(float(np.sin(a)) + 0.0, 6), round(float(-np.cos(a)) + 0.0, 6), 0.0]  # (0, -1, 0) turned
    assert np.allclose(w["outward_normal"], expected, atol=1e-6)
    assert w["sill_z_m"] == 3.8 and w["head_z_m"] == 5.2
    # the window's centre (0, 0) lands on the translation
    assert np.allclose(report["inputs"]["local_origin_m"], [10.0, 20.0, 4.5], atol=1e-6)


def test_the_rotterdam_sample_project(tmp_path):
    """sample_projects/cityjson-rotterdam: the box room 20 m north of 15 LoD2 buildings of Rotterdam,
    no layer rule for the city model."""
    path = ROOT / "sample_projects" / "cityjson-rotterdam" / "project.yaml"
    report = run(path, tmp_path / "o")
    assert report["inputs"]["model_files"]["rotterdam_subset.json"].startswith("sha256:")
    r = CliRunner().invoke(cli, ["validate", str(path)])
    assert "faces per layer: window 2, interior 18, ground 2, landscape 534" in r.output
    s = report["rooms"][0]["sunlight"]
    assert s["assessed_date"] == "2026-02-01" and 2.5 < s["hours_h"] < 3.5  # the block's 15 m roofs, 20 m south
