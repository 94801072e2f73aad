"""Identity in the report: every room and window of report.json names the elements it was made from
(``source``), so scripts and BIM tools find them without parsing names (issue 43).

Expectations are the models' own ids, known by construction (an OBJ whose objects the test names,
the sample house whose GlobalIds ifcopenshell reads back), never the package's output: three panes
of one opening (two beside a 10 cm mullion, a third 2 cm behind them, hidden) are one window whose
source lists all three objects and the layer rule that made each glass.
"""
from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import jsonschema
import pytest
import yaml

from en17037cli import pipeline
from en17037cli.project import load_project
from en17037cli.report.document import build_report
from en17037cli.report.sources import format_of
from en17037cli.report.tables import rooms_csv, sunlight_days_csv
from en17037cli.samples.box import BoxRoom, box_room_polygons, write_obj
from en17037cli.schemas import load_schema

SUN = {"date": "03-21", "period": {"start": "03-21", "end": "03-21"}}


def three_pane_project(tmp: Path) -> Path:
    """A box room whose opening is drawn as three OBJ objects: 'pane west' and 'pane east' either side
    of a 0.1 m opaque strip, 'inner glass' 2 cm behind both (double glazing drawn as two layers)."""
    objects = box_room_polygons(BoxRoom(gap=0.1, second_pane=0.02))
    west, east, inner = objects.pop("glazing")
    model = {"room": objects["room"], "pane west": [west], "pane east": [east], "inner glass": [inner],
             "ground": objects["ground"], "building": objects["building"]}
    write_obj(tmp / "model.obj", model)
    doc = {"version": 1, "name": "three panes",
           "model": {"units": "m", "up_axis": "z", "files": [{"path": "model.obj", "layers": [
               {"match": "room", "layer": "interior"}, {"match": "pane*", "layer": "window"},
               {"match": "inner*", "layer": "window"}, {"match": "ground", "layer": "ground"},
               {"match": "building", "layer": "landscape"}]}]},
           "location": {"latitude": 52.0, "longitude": 4.36, "timezone": "Europe/Amsterdam"},
           "rooms": [{"name": "box room", "floor_z": 0.0}], "sunlight": SUN,
           "requirements": {"view": "none", "sunlight": "minimum"}}
    path = tmp / "project.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def three_panes(tmp_path_factory):
    path = three_pane_project(tmp_path_factory.mktemp("panes"))
    return build_report(pipeline.run(load_project(path, [])))


def test_joined_panes_keep_every_element_and_its_rule(three_panes):
    room = three_panes["rooms"][0]
    assert room["source"] == {"format": "project", "file": "project.yaml", "ids": [], "elements": [], "entry": "rooms[0]"}
    [window] = room["windows"]
    assert window["name"] == "pane west (+2 panes)"  # the name stays for people
    src = window["source"]
    assert (src["format"], src["file"]) == ("obj", "model.obj")
    assert src["ids"] == ["pane west", "pane east", "inner glass"]  # the hidden pane too
    by_id = {e["id"]: e for e in src["elements"]}
    assert by_id["pane east"]["object"] == "pane east"
    assert by_id["pane west"]["layer_rule"] == "model.files[0].layers[1] (match: 'pane*')"
    assert by_id["inner glass"]["layer_rule"] == "model.files[0].layers[2] (match: 'inner*')"
    jsonschema.validate(three_panes, load_schema("report"))


def test_csvs_carry_the_room_source(three_panes):
    rows = list(csv.DictReader(io.StringIO(rooms_csv(three_panes))))
    assert {(r["source_format"], r["source_file"], r["source_ids"]) for r in rows} == {("project", "project.yaml", "")}
    days = list(csv.DictReader(io.StringIO(sunlight_days_csv(three_panes))))
    assert days and all(r["room_source_ids"] == "" for r in days)


def test_file_layer_names_the_file_entry(tmp_path):
    """A whole file on the window layer (model.files[].layer): the rule is that entry."""
    objects = box_room_polygons(BoxRoom())
    write_obj(tmp_path / "glass.obj", {"glazing": objects.pop("glazing")})
    write_obj(tmp_path / "rest.obj", objects)
    doc = {"version": 1, "name": "two files",
           "model": {"units": "m", "up_axis": "z", "files": [
               {"path": "rest.obj", "layers": [{"match": "ground", "layer": "ground"}, {"match": "building", "layer": "landscape"},
                                               {"match": "*", "layer": "interior"}]},
               {"path": "glass.obj", "layer": "window"}]},
           "location": {"latitude": 52.0, "longitude": 4.36, "timezone": "Europe/Amsterdam"},
           "rooms": [{"name": "box room", "floor_z": 0.0}], "sunlight": SUN,
           "requirements": {"view": "none", "sunlight": "minimum"}}
    (tmp_path / "p.yaml").write_text(yaml.safe_dump(doc), encoding="utf-8")
    report = build_report(pipeline.run(load_project(tmp_path / "p.yaml", [])))
    [window] = report["rooms"][0]["windows"]
    assert window["source"] == {"format": "obj", "file": "glass.obj", "ids": ["glazing"],
                                "elements": [{"id": "glazing", "object": "glazing", "layer_rule": "model.files[1].layer"}]}


@pytest.mark.parametrize("name, fmt", [("a/b.IFC", "ifc"), ("x.city.json", "cityjson"), ("t.xml", "gbxml"),
                                       ("m.glb", "gltf"), ("berlin.gml", "citygml"), ("d.dxf", "dxf"), ("noext", "")])
def test_format_of(name, fmt):
    assert format_of(name) == fmt


def test_ifc_rooms_and_windows_are_their_spaces_and_windows(tmp_path):
    """The sample house: each room's source is its IfcSpace (the GlobalId ifcopenshell reads back for
    the space of that Name), each window's ids are the IfcWindows of that room by the house's design."""
    ifcopenshell = pytest.importorskip("ifcopenshell")
    from en17037cli.samples.ifc import house

    ifc = house(tmp_path / "house.ifc")
    doc = {"version": 1, "name": "house", "model": {"files": [{"path": "house.ifc"}]},
           "location": {"timezone": "Europe/Amsterdam"}, "rooms": [{"ifc_spaces": "*"}], "sunlight": SUN,
           "requirements": {"view": "none", "sunlight": "minimum"}}
    (tmp_path / "p.yaml").write_text(yaml.safe_dump(doc), encoding="utf-8")
    report = build_report(pipeline.run(load_project(tmp_path / "p.yaml", [])))
    f = ifcopenshell.open(str(ifc))
    space = {s.Name: s.GlobalId for s in f.by_type("IfcSpace")}
    window = {w.Name: w.GlobalId for w in f.by_type("IfcWindow")}
    design = {"0.01": {"W living south", "W living west"}, "0.02": {"W kitchen north"}, "1.01": {"W bedroom south"},
              "1.02": {"W bedroom round"}}
    got = {}
    for room in report["rooms"]:
        src = room["source"]
        assert (src["format"], src["file"], src["entry"]) == ("ifc", "house.ifc", "rooms[0]")
        [el] = src["elements"]
        assert src["ids"] == [space[el["name"]]] and el["class"] == "IfcSpace"
        got[el["name"]] = {f.by_guid(i).Name for w in room["windows"] for i in w["source"]["ids"]}
        assert all(f.by_guid(i).is_a("IfcWindow") for w in room["windows"] for i in w["source"]["ids"])
    assert got == design
    assert {i for r in report["rooms"] for w in r["windows"] for i in w["source"]["ids"]} == set(window.values())
    assert json.loads(json.dumps(report)) == report  # plain JSON


MODELS = Path(__file__).resolve().parents[2] / "shared" / "data" / "real-models"


@pytest.mark.skipif(not (MODELS / "Urban_House_MEP.xml").is_file(), reason="the real models are absent")
def test_gbxml_rooms_and_windows_are_its_spaces_and_openings(tmp_path):
    """Revit MEP 2016's gbXML: each room's source is a Space id of the file, each window's ids are ids
    of Openings of the file (read here with ElementTree), the window layer from the format's table."""
    pytest.importorskip("lxml")
    import xml.etree.ElementTree as ET

    xml = MODELS / "Urban_House_MEP.xml"
    ids = {}
    for e in ET.parse(xml).iter():
        tag = e.tag.rsplit("}", 1)[-1]
        if tag in ("Space", "Opening") and e.get("id"):
            ids[e.get("id")] = tag
    doc = {"version": 1, "name": "gbxml", "model": {"files": [{"path": str(xml)}]},
           "location": {"timezone": "America/New_York"}, "rooms": [{"gbxml_spaces": "*"}], "sunlight": SUN,
           "requirements": {"view": "none", "sunlight": "minimum"}}
    (tmp_path / "p.yaml").write_text(yaml.safe_dump(doc), encoding="utf-8")
    report = build_report(pipeline.run(load_project(tmp_path / "p.yaml", [])))
    assert report["rooms"]
    for room in report["rooms"]:
        src = room["source"]
        assert src["format"] == "gbxml" and len(src["ids"]) == 1 and ids[src["ids"][0]] == "Space"
        for w in room["windows"]:
            assert w["source"]["format"] == "gbxml" and w["source"]["ids"]
            assert all(ids.get(i) == "Opening" for i in w["source"]["ids"]), w["source"]
            assert all(e["layer_rule"] == "the format's default" for e in w["source"]["elements"] if "layer_rule" in e)
