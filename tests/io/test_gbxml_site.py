"""The null site from a gbXML file: the rule is the scene's (scene/site.py), for any reader that
gives a location; tests/test_site_checks.py has the IFC cases."""
from __future__ import annotations

import yaml
from click.testing import CliRunner
from gbxml_files import box_room_gbxml

from en17037cli.cli import cli


def test_a_gbxml_null_site_is_not_a_location(tmp_path):
    """A gbXML Campus/Location at latitude 0, longitude 0 and a project that leaves the location out."""
    path = tmp_path / "model.xml"
    path.write_text(box_room_gbxml().replace("<Latitude>52.0</Latitude><Longitude>4.36</Longitude>",
                                             "<Latitude>0</Latitude><Longitude>0</Longitude>"))
    doc = {"version": 1, "name": "g", "model": {"files": [{"path": "model.xml", "layers": [{"match": "ground", "layer": "ground"}]}]},
           "location": {"timezone": "UTC"}, "rooms": [{"gbxml_spaces": "*"}], "sunlight": {}}
    (tmp_path / "p.yaml").write_text(yaml.safe_dump(doc))
    r = CliRunner().invoke(cli, ["validate", str(tmp_path / "p.yaml")])
    assert r.exit_code == 2 and len(r.output.strip().splitlines()) == 1
    assert "model.xml gives latitude 0 and longitude 0, the null site" in r.output
