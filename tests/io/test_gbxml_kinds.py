"""A gbXML Space's kind: its spaceType attribute (a load category: read last, after its Name) and its Name."""
from __future__ import annotations

import json

import pytest
import yaml
from click.testing import CliRunner
from gbxml_files import box_room_gbxml, write

from en17037cli.cli import cli
from en17037cli.io.gbxml import read_gbxml
from en17037cli.samples import BoxRoom, box_room_project

pytest.importorskip("lxml")


def kind_of(tmp_path, name: str, space_type: str) -> dict:
    """``validate --json``'s kind of the box room written as one gbXML Space ``name`` of ``space_type``."""
    p = box_room_project(tmp_path, BoxRoom(), sunlight=None, view={})
    write(tmp_path, box_room_gbxml(space_name=name, space_type=space_type))
    doc = yaml.safe_load(p.read_text())
    doc["model"]["files"] = [{"path": "model.xml", "layers": [{"match": "ground", "layer": "ground"}]}]
    doc["rooms"] = [{"gbxml_spaces": "*"}]
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    r = CliRunner().invoke(cli, ["validate", str(p), "--json"], catch_exceptions=False)
    assert r.exit_code == 0, r.output
    (room,) = json.loads(r.output)["rooms"]
    return room["kind"]


def test_the_reader_keeps_the_space_type(tmp_path):
    write(tmp_path, box_room_gbxml(space_name="Bed 2", space_type="DormitoryBedroom"))
    (space,) = read_gbxml(tmp_path / "model.xml").spaces
    assert space.usage == (("Name", "Bed 2"), ("gbXML spaceType", "DormitoryBedroom"))
    write(tmp_path, box_room_gbxml())
    assert read_gbxml(tmp_path / "model.xml").spaces[0].usage == (("Name", "box room"),)


@pytest.mark.parametrize("name, space_type, uses, source", [
    ("box room", "DormitoryBedroom", ["bedroom"], "gbXML spaceType 'DormitoryBedroom'"),
    ("box room", "FoodPreparation", ["kitchen"], "gbXML spaceType 'FoodPreparation'"),
    ("box room", "OfficeOpenPlan", ["office"], "gbXML spaceType 'OfficeOpenPlan'"),
    # Revit writes LivingQuartersHotel on every habitable room of a house: the Name decides, else nothing
    ("Kitchen", "LivingQuartersHotel", ["kitchen"], "Name 'Kitchen': name table 'kitchen'"),
    ("box room", "LivingQuartersHotel", ["other"], None),
    # the Name before the load category: a dining room typed FoodPreparation is a living room
    ("Dining Room", "FoodPreparation", ["living_room"], "Name 'Dining Room': name table 'dining'")])
def test_a_gbxml_spaces_kind(tmp_path, name, space_type, uses, source):
    kind = kind_of(tmp_path, name, space_type)
    assert kind["uses"] == uses
    if source is not None:
        assert kind["source"] == source
