"""An IfcSpace's kind from what the file says of it: LongName, ObjectType, its IfcSpaceType's name and
classification references (IfcRelAssociatesClassification), read from a house built in code (three
spaces side by side, a south window each) and shown by ``validate``."""
from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from tests.ifc_box import box_shell

pytest.importorskip("ifcopenshell")

#: The three spaces: (x0, x1) [m] inside the walls, Name, LongName, ObjectType, classification refs (system, code, name).
SPACES = [((0.3, 2.3), "1.01", "Room A", "Bedroom", [("DIN 277", "2 HNF", "Büroarbeit")]),
          ((2.3, 4.3), "1.02", "Wohnküche", None, []),
          ((4.3, 6.3), "1.03", "Raum", "Office", [("Uniclass 2015", "SL_45_10_23", "Domestic kitchens")])]


def house(path: Path) -> Path:
    b, st, walls = box_shell()
    systems = {}
    for (x0, x1), name, long_name, object_type, refs in SPACES:
        s = b.space(name, long_name, st, [(x0, 0.3), (x1, 0.3), (x1, 5.3), (x0, 5.3)], 0.0, 2.4)
        s.ObjectType = object_type
        for system, code, ref_name in refs:
            if system not in systems:
                systems[system] = b.api.run("classification.add_classification", b.f, classification=system)
            b.api.run("classification.add_reference", b.f, products=[s], identification=code, name=ref_name,
                      classification=systems[system])
        b.window(f"W {name}", st, walls[0], ((x0 + x1) / 2, 0.0, 1.5), (0, -1, 0), (1, 0, 0), 1.2, 1.2, spaces=[s])
    return b.write(path)


@pytest.fixture(scope="module")
def validated(tmp_path_factory):
    d = tmp_path_factory.mktemp("kinds-ifc")
    ifc = house(d / "house.ifc")
    doc = {"version": 1, "name": "kinds", "model": {"files": [{"path": ifc.name}]}, "location": {"timezone": "Europe/London"},
           "rooms": [{"ifc_spaces": "*"}], "view": {}, "practice": "gb-br209-2022",
           "daylight": {"median_diffuse_lx": 14000}, "requirements": {"view": "none", "sunlight": "none"}}
    (d / "project.yaml").write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True), encoding="utf-8")
    out = {}
    for args in ([], ["--json"]):
        r = CliRunner().invoke(cli, ["validate", str(d / "project.yaml"), *args], catch_exceptions=False)
        assert r.exit_code == 0, r.output
        out[bool(args)] = r.output
    return out[False], json.loads(out[True])


def test_the_reader_gives_every_text_the_file_has(tmp_path):
    from en17037cli.io import read_model

    mesh = read_model(house(tmp_path / "house.ifc"))
    usage = {s.name: s.usage for s in mesh.spaces}
    assert usage["1.01"] == (("LongName", "Room A"), ("Name", "1.01"), ("ObjectType", "Bedroom"),
                             ("classification 'DIN 277'", "2 HNF Büroarbeit"))
    assert usage["1.02"] == (("LongName", "Wohnküche"), ("Name", "1.02"))
    assert usage["1.03"][-1] == ("classification 'Uniclass 2015'", "SL_45_10_23 Domestic kitchens")


def test_each_spaces_kind_and_where_it_came_from(validated):
    text, doc = validated
    kinds = {r["name"]: r["kind"] for r in doc["rooms"]}
    assert set(kinds) == {"Room A (1.01)", "Wohnküche (1.02)", "Raum (1.03)"}
    # ObjectType (the DIN 277 usage group classes buildings, not rooms: left out)
    assert kinds["Room A (1.01)"]["uses"] == ["bedroom"]
    assert kinds["Room A (1.01)"]["source"] == "ObjectType 'Bedroom': name table 'bedroom'"
    # the German LongName by the default table: a room of two uses, the kitchen's 200 lx
    assert kinds["Wohnküche (1.02)"]["uses"] == ["living_room", "kitchen"]
    assert kinds["Wohnküche (1.02)"]["set"]["thresholds.daylight_target_lx.minimum"] == \
        {"value": 200.0, "from": "practice gb-br209-2022, kitchen"}
    # the Uniclass code before the ObjectType 'Office'
    assert kinds["Raum (1.03)"]["uses"] == ["kitchen"]
    assert kinds["Raum (1.03)"]["source"] == \
        "classification 'Uniclass 2015' 'SL_45_10_23 Domestic kitchens': Uniclass SL_45_10_23"
    assert kinds["Room A (1.01)"]["set"]["thresholds.daylight_target_lx.minimum"]["value"] == 100.0
    assert "  kind: bedroom (ObjectType 'Bedroom': name table 'bedroom'); daylight target 100 lx at minimum, no daylight " \
           "minimum target at minimum (practice gb-br209-2022, bedroom)" in text.splitlines()
