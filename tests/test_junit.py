"""JUnit XML (check --junit, batch --junit) against the JUnit schema CI systems read, and GitHub
Actions annotations."""
from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import xmlschema
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.report.junit import annotation, junit_xml
from en17037cli.report.summary import RunRecord
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.samples.block import Block, block_project

#: The Apache Ant JUnit schema (windyroad/JUnit-Schema, Apache-2.0; see the file's header).
XSD = Path(__file__).parent / "data" / "JUnit.xsd"
#: surroundings_min_share 0: the block's only context lies across the street to the south; its north rooms'
#: layers are judged on it (by default they are not assessable: no surroundings in front of them)
VIEW = {"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 3, "refine_levels": 1,
        "surroundings_min_share": 0}
SUN = {"period": {"start": "02-01", "end": "02-03"}, "date": "worst"}


@pytest.fixture(scope="module")
def schema():
    return xmlschema.XMLSchema(XSD)


def invoke(*args, env=None):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False, env=env)


@pytest.fixture
def box(tmp_path):
    return box_room_project(tmp_path / "box", BoxRoom(), view=VIEW, sunlight=SUN)


def cases(path: Path) -> dict[str, ET.Element]:
    return {c.get("name"): c for c in ET.parse(path).getroot().iter("testcase")}


def test_check_junit_is_valid_one_case_per_room_and_criterion(box, tmp_path, schema):
    junit = tmp_path / "junit.xml"
    r = invoke("check", box, "--out", tmp_path / "out", "-q", "--junit", junit, "--set", "requirements.view=high")
    assert r.exit_code == 1
    schema.validate(junit)
    suite = ET.parse(junit).getroot().find("testsuite")
    assert (suite.get("tests"), suite.get("failures"), suite.get("errors"), suite.get("skipped")) == ("2", "1", "0", "0")
    c = cases(junit)
    assert set(c) == {"box room: view out (5.2)", "box room: exposure to sunlight (5.3)"}
    f = c["box room: view out (5.2)"].find("failure")
    assert f.get("type") == "FAIL" and f.get("message") == "view out (5.2): level medium reached, high required"
    assert list(c["box room: exposure to sunlight (5.3)"]) == []  # passes: no child
    assert float(c["box room: view out (5.2)"].get("time")) > 0


def test_not_assessed_is_an_error(box, tmp_path, schema):
    junit = tmp_path / "junit.xml"
    r = invoke("check", box, "--out", tmp_path / "out", "-q", "--only", "view", "--junit", junit)
    assert r.exit_code == 1  # sunlight is required and did not run
    schema.validate(junit)
    e = cases(junit)["box room: exposure to sunlight (5.3)"].find("error")
    assert e.get("type") == "NOT ASSESSED" and e.get("message") == "exposure to sunlight (5.3): NOT ASSESSED: --only view left it out"


def test_a_dwelling_that_meets_the_sunlight_rule_passes_its_rooms(tmp_path, schema):
    """Three south rooms and three north rooms, one dwelling, sunlight asked of any room: the north
    rooms' sunlight FAIL does not fail the check, so their test cases pass; their view fails."""
    p = block_project(tmp_path / "block", Block(storeys=1, rooms_per_side=3), view=VIEW, sunlight=SUN,
                      requirements={"view": "none", "sunlight": "minimum", "sunlight_rooms": "any"})
    junit = tmp_path / "junit.xml"
    r = invoke("check", p, "--out", tmp_path / "out", "-q", "--junit", junit)
    assert r.exit_code == 0
    schema.validate(junit)
    suite = ET.parse(junit).getroot().find("testsuite")
    assert (suite.get("tests"), suite.get("failures"), suite.get("errors")) == ("12", "0", "0")


def test_batch_junit_with_a_failed_run_and_annotations(box, tmp_path, schema):
    missing = tmp_path / "missing.yaml"
    junit = tmp_path / "junit.xml"
    r = invoke("batch", box, missing, "--out", tmp_path / "out", "--jobs", 1, "-q", "--junit", junit,
               "--set", "requirements.view=high", env={"GITHUB_ACTIONS": "true"})
    assert r.exit_code == 2
    schema.validate(junit)
    suites = ET.parse(junit).getroot().findall("testsuite")
    assert [s.get("name") for s in suites] == [f"en17037 {box}", f"en17037 {missing}"]
    assert [(s.get("id"), s.get("tests"), s.get("failures"), s.get("errors")) for s in suites] == \
        [("0", "2", "1", "0"), ("1", "1", "0", "1")]
    err = suites[1].find("testcase/error")
    assert err.get("type") == "bad input" and err.get("message") == f"{missing}: project file not found"
    lines = [x for x in r.output.splitlines() if x.startswith("::")]
    assert lines == [
        f"::error file={box},title=EN 17037 FAIL%3A box room%2C view out (5.2)::view out (5.2): level medium reached, "
        f"high required ({box})",
        f"::error file={missing},title=EN 17037 bad input%3A {missing}::{missing}: project file not found"]
    r = invoke("batch", box, "--out", tmp_path / "out2", "--jobs", 1, "-q", env={"GITHUB_ACTIONS": "false"})
    assert "::" not in r.output


def test_the_same_inputs_give_the_same_junit_apart_from_times(box, tmp_path, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1767225600")  # 2026-01-01T00:00:00 UTC
    texts = []
    for i in range(2):
        invoke("check", box, "--out", tmp_path / f"out{i}", "-q", "--junit", tmp_path / f"j{i}.xml")
        texts.append(re.sub(r'time="[0-9.]+"', 'time=""', (tmp_path / f"j{i}.xml").read_text()))
    assert 'timestamp="2026-01-01T00:00:00"' in texts[0]
    assert texts[0].replace(str(tmp_path / "out0"), "") == texts[1].replace(str(tmp_path / "out1"), "")  # the report property


def test_names_with_control_characters_still_make_valid_xml(schema, tmp_path):
    row = {"room": "flat\x01 1 <&>", "criterion": "view", "level": "none", "required": "minimum", "status": "fail",
           "verdict": "fail", "dwelling": "", "hours_h": None, "assessed_date": None, "time_s": 0.1, "message": ""}
    (tmp_path / "j.xml").write_text(junit_xml([RunRecord(project="p.yaml", exit_code=1, rows=[row])], now=0.0))
    schema.validate(tmp_path / "j.xml")
    assert next(iter(cases(tmp_path / "j.xml"))) == "flat 1 <&>: view out (5.2)"
    assert ET.parse(tmp_path / "j.xml").getroot().find("testsuite/testcase").get("classname") == "en17037.p"


def test_annotation_escapes_workflow_command_syntax():
    assert annotation("error", "50% of\nthe points", "t: a, b", "dir/p.yaml") == \
        "::error file=dir/p.yaml,title=t%3A a%2C b::50%25 of%0Athe points"
