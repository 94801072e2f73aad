"""docs/bim.md's round trip, run as written: its commands in a shell, in order, on the sample house
saved as ``building.ifc`` with the README's "From an IFC" project as ``building.yaml`` (its view
made coarse to keep the test short; the commands are the document's). A page that drifts from the
tool fails here.

What each command prints is checked against the files themselves: the window ids the script
prints are the IfcWindows of the file (read with ifcopenshell), the rooms the selector lists are
the IfcSpaces whose room fails sunlight in report.json.
"""
from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

pytest.importorskip("ifcopenshell")
import ifcopenshell  # noqa: E402

from en17037cli.samples.ifc import house  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
COARSE_VIEW = {"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 3.0, "refine_levels": 0}


def section(path: Path, marker: str) -> str:
    m = re.search(rf"<!-- {marker}.*?-->(.*?)<!-- /{marker} -->", path.read_text(encoding="utf-8"), re.S)
    assert m, f"{path.name}: the {marker} markers are gone"
    return m.group(1)


def readme_ifc_project() -> dict:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    part = text[text.index("## From an IFC"):]
    return yaml.safe_load(re.search(r"```yaml\n(.*?)```", part, re.S).group(1))


def run(line: str, cwd: Path) -> subprocess.CompletedProcess:
    """A command of the page: ``en17037`` as ``python -m en17037cli``, ``python`` as this interpreter."""
    exe = f'"{sys.executable}"'
    line = re.sub(r"^en17037 ", f"{exe} -m en17037cli ", line)
    line = re.sub(r"^python ", f"{exe} ", line)
    return subprocess.run(line, shell=True, cwd=cwd, capture_output=True, text=True, timeout=600)


def test_round_trip_as_written(tmp_path):
    ifc = house(tmp_path / "building.ifc")
    doc = readme_ifc_project()
    assert doc["model"]["files"][0]["path"] == "building.ifc"
    doc["view"] = COARSE_VIEW
    (tmp_path / "building.yaml").write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    [body] = re.findall(r"```sh\n(.*?)```", section(ROOT / "docs" / "bim.md", "round trip"), re.S)
    lines = [x for x in body.splitlines() if x.strip()]
    assert len(lines) == 3
    checked = run(lines[0], tmp_path)
    assert checked.returncode in (0, 1), checked.stderr
    assert re.search(r"^bcf: \d+ topic\(s\) in issues.bcf$", checked.stderr, re.M)
    assert "ifc: results of building.ifc in results.ifc" in checked.stderr
    report = json.loads((tmp_path / "en17037-report" / "building" / "report.json").read_text("utf-8"))
    f = ifcopenshell.open(str(ifc))
    windows = {w.GlobalId for w in f.by_type("IfcWindow")}

    listed = run(lines[1], tmp_path)
    assert listed.returncode == 0, listed.stderr
    rows = [r.split("\t") for r in listed.stdout.splitlines()]
    assert {(room["name"], w["name"]) for room in report["rooms"] for w in room["windows"]} == {(r[0], r[1]) for r in rows}
    assert {i for r in rows for i in r[2:]} == windows

    failing = run(lines[2], tmp_path)
    assert failing.returncode == 0, failing.stderr
    want = sorted(f.by_guid(room["source"]["ids"][0]).Name for room in report["rooms"] if room["sunlight"]["status"] == "fail")
    assert failing.stdout.split() == want and want  # the sample house's north kitchen has no sun on its worst day
