"""The public Python API gives what the CLI gives."""
from __future__ import annotations

import json

from click.testing import CliRunner

import en17037cli
from en17037cli.cli import cli


def test_api_report_equals_the_cli_report(box_project, tmp_path):
    project = en17037cli.load_project(box_project)
    result = en17037cli.run(project)
    doc = en17037cli.write_reports(result, tmp_path / "api")
    r = CliRunner().invoke(cli, ["check", str(box_project), "--out", str(tmp_path / "cli"), "-q"], catch_exceptions=False)
    assert r.exit_code == (0 if result.status == "pass" else 1)
    cli_doc = json.loads((tmp_path / "cli" / "report.json").read_text())
    for d in (doc, cli_doc):
        d.pop("timings_s")
    assert doc == json.loads(json.dumps(cli_doc))
    # typed results: the box room's 2 x 1.4 m south window, 25 m street (see en17037cli.samples)
    room = result.rooms[0]
    assert room.room.name == "box room" and set(room.results) == {"view", "sunlight", "daylight", "glare"}
    assert room.level("view") == doc["rooms"][0]["view"]["level"]
    assert [e.eye_height_m for e in room.results["view"].eye_heights] == [1.2, 1.7]
