"""en17037 compare and check --baseline: what changed between two reports, and the exit codes on
constructed before/after pairs."""
from __future__ import annotations

import copy
import json

import pytest
from click.testing import CliRunner

import en17037cli
from en17037cli.cli import cli
from en17037cli.compare import compare_reports, comparison_markdown, load_report
from en17037cli.errors import InputError
from en17037cli.samples import BoxRoom, box_room_project

VIEW = {"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 3, "refine_levels": 1}
SUN = {"period": {"start": "02-01", "end": "02-03"}, "date": "worst"}


def invoke(*args, **kw):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False, **kw)


@pytest.fixture(scope="module")
def box(tmp_path_factory):
    return box_room_project(tmp_path_factory.mktemp("cmp") / "box", BoxRoom(), view=VIEW, sunlight=SUN)


@pytest.fixture(scope="module")
def report(box, tmp_path_factory):
    """The box room's report: view medium (required medium, 75 % of the points), sunlight medium
    (3.3366 h on 1 February, required minimum), one dwelling (the whole project): PASS."""
    doc = en17037cli.write_reports(en17037cli.run(en17037cli.load_project(box)), tmp_path_factory.mktemp("r"))
    room = doc["rooms"][0]
    assert (room["view"]["level"], room["view"]["status"], room["sunlight"]["level"], room["sunlight"]["hours_h"]) == \
        ("medium", "pass", "medium", 3.3366)
    return json.loads(json.dumps(doc))


def edited(doc, criterion=None, room=0, **fields):
    out = copy.deepcopy(doc)
    if criterion is not None:
        out["rooms"][room][criterion].update(fields)
    return out


def changes(before, after):
    c = compare_reports(before, after)
    return c, {(ch.name, ch.criterion): ch for ch in c.changes}


def test_the_same_report_has_no_change(report):
    c, by = changes(report, report)
    assert c.exit_code == 0 and {ch.change for ch in c.changes} == {"same"}
    # the room's two criteria and the project's sunlight rule
    assert set(by) == {("box room", "view"), ("box room", "sunlight"), ("(whole project)", "dwelling")}


def test_a_level_that_drops_is_a_regression(report):
    after = edited(report, "view", level="minimum", status="fail")
    c, by = changes(report, after)
    ch = by[("box room", "view")]
    assert (ch.change, ch.regression, c.exit_code) == ("worse", True, 1)
    assert ch.what == ["level medium → minimum", "status PASS → FAIL"]
    # still passing, one level down (sunlight medium -> minimum against minimum required): worse too
    c, by = changes(report, edited(report, "sunlight", level="minimum", hours_h=2.0))
    assert by[("box room", "sunlight")].change == "worse" and c.exit_code == 1
    assert by[("box room", "sunlight")].what == ["level medium → minimum", "hours 3 h 20 min → 2 h (-1 h 20 min)"]  # 3.3366 h, 2.0 h


def test_a_level_that_rises_is_better_and_passes(report):
    before = edited(report, "view", level="minimum", status="fail")
    c, by = changes(before, report)
    assert (by[("box room", "view")].change, c.exit_code) == ("better", 0)


def test_only_figures_changed_is_not_a_regression(report):
    c, by = changes(report, edited(report, "sunlight", hours_h=3.0))
    ch = by[("box room", "sunlight")]
    assert (ch.change, ch.regression, c.exit_code) == ("changed", False, 0)
    assert ch.what == ["hours 3 h 20 min → 3 h (-20 min)"]  # 3.3366 h → 3.0 h


def test_a_status_that_drops_at_the_same_level_is_a_regression(report):
    # the requirement raised to high: same level, PASS -> FAIL
    c, by = changes(report, edited(report, "view", required="high", status="fail"))
    assert by[("box room", "view")].change == "worse" and c.exit_code == 1
    # a room that can no longer be assessed
    gone = edited(report, "view", level=None, status="not_assessable", reason="no window bounds the room")
    c, by = changes(report, gone)
    assert by[("box room", "view")].what == ["level medium → -", "status PASS → NOT ASSESSABLE", "share 0.75 → -"]
    assert c.exit_code == 1


def test_rooms_added_and_removed(report):
    after = copy.deepcopy(report)
    new = copy.deepcopy(after["rooms"][0])
    new["name"] = "annex"
    new["view"].update(level="minimum", status="fail")
    after["rooms"].append(new)
    after["dwellings"][0]["rooms"].append("annex")
    c, by = changes(report, after)
    assert by[("annex", "view")].change == "added" and by[("annex", "view")].regression  # a new failure
    assert by[("annex", "sunlight")].change == "added" and not by[("annex", "sunlight")].regression
    assert c.exit_code == 1
    c, by = changes(after, report)  # the annex removed: listed, not a regression
    assert by[("annex", "view")].change == "removed" and c.exit_code == 0
    new["view"].update(level="medium", status="pass")
    c, _ = changes(report, after)
    assert c.exit_code == 0  # a new room that passes


def test_a_dwelling_that_fails_its_sunlight_rule_is_a_regression(report):
    after = copy.deepcopy(report)
    after["dwellings"][0]["sunlight"].update(status="fail", shortfall_h=0.5)
    c, by = changes(report, after)
    assert by[("(whole project)", "dwelling")].change == "worse" and c.exit_code == 1


def test_markdown_table_for_a_pull_request(report):
    c = compare_reports(report, edited(report, "view", level="minimum", status="fail"), "main/report.json", "pr/report.json")
    md = comparison_markdown(c)
    assert md.splitlines() == [
        "### EN 17037: `main/report.json` → `pr/report.json`", "",
        "status PASS → PASS; 1 regression, 0 better, 0 changed, 2 unchanged, 0 added, 0 removed.", "",
        "| change | room | criterion | level | status | figures |", "|---|---|---|---|---|---|",
        "| **worse** | box room | view out (5.2) | medium → minimum | PASS → FAIL |  |"]
    assert comparison_markdown(compare_reports(report, report)).endswith("No room's level, status, hours or share changed.\n")


def test_compare_command_exit_codes_and_formats(report, tmp_path):
    before, after = tmp_path / "before", tmp_path / "after.json"
    before.mkdir()
    (before / "report.json").write_text(json.dumps(report))
    after.write_text(json.dumps(edited(report, "view", level="minimum", status="fail")))
    r = invoke("compare", before, after, "--format", "md")
    assert r.exit_code == 1 and "| **worse** | box room | view out (5.2) | medium → minimum | PASS → FAIL |  |" in r.output
    r = invoke("compare", after, before, "--format", "json")
    doc = json.loads(r.output)
    assert r.exit_code == 0 and doc["regressions"] == 0 and doc["counts"]["better"] == 1
    r = invoke("compare", before, before / "report.json")
    assert r.exit_code == 0 and "0 regressions" in r.output
    r = invoke("compare", before, tmp_path / "nothing")
    assert r.exit_code == 2 and r.output.count("\n") == 1
    assert f"error: AFTER {tmp_path / 'nothing'}: {tmp_path / 'nothing'} not found; give a report.json or a report folder" in r.output
    (tmp_path / "other.json").write_text('{"rooms": []}')
    r = invoke("compare", before, tmp_path / "other.json")
    assert r.exit_code == 2 and "not an en17037 report" in r.output


def test_load_report_names_the_argument(tmp_path):
    with pytest.raises(InputError, match="^--baseline .*holds no report.json"):
        load_report(tmp_path, "--baseline")


def test_check_with_a_baseline_fails_only_on_regressions(box, tmp_path):
    # a project that knowingly starts below the standard: view high required, medium reached
    high = ["--set", "requirements.view=high"]
    assert invoke("check", box, "--out", tmp_path / "old", "-q", *high).exit_code == 1
    r = invoke("check", box, "--out", tmp_path / "same", "-q", *high, "--baseline", tmp_path / "old")
    assert r.exit_code == 0  # still FAIL, but nothing got worse
    assert json.loads((tmp_path / "same" / "report.json").read_text())["status"] == "fail"
    # turning the window to face east loses sun on the worst day: sunlight medium -> minimum
    r = invoke("check", box, "--out", tmp_path / "east", *high, "--set", "model.true_north_deg=90",
               "--baseline", tmp_path / "old" / "report.json", "--junit", tmp_path / "junit.xml")
    assert r.exit_code == 1
    assert "status FAIL → FAIL; 1 regression, 0 better, 1 changed, 1 unchanged, 0 added, 0 removed" in r.output
    junit = (tmp_path / "junit.xml").read_text()
    assert junit.count('<failure type="REGRESSION"') == 1 and junit.count("<skipped ") == 1  # the view, known
    assert 'message="worse than the baseline (level medium → minimum; hours 3 h 20 min → ' in junit
    r = invoke("check", box, "--out", tmp_path / "x", "--baseline", tmp_path / "none.json")
    assert r.exit_code == 2 and r.output.startswith(f"error: --baseline {tmp_path / 'none.json'}: ")
    assert not (tmp_path / "x").exists()  # stopped before any work
