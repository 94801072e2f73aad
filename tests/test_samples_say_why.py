"""Every sample project passes its own check or says in its description that it fails by design,
and why; the pinned reports of the samples (tests/golden) hold the verdict the description claims."""
from __future__ import annotations

import gzip
import json
from pathlib import Path

import pytest

from en17037cli.project import load_project
from tests.golden.scenes import SAMPLES

ROOT = Path(__file__).resolve().parents[1]
PROJECTS = sorted((ROOT / "sample_projects").glob("*/*.yaml"))


def test_every_sample_project_is_listed_here():
    assert len(PROJECTS) >= 6  # seed office (3: method 2 on real weather), synthetic street, IFC house, CityJSON Rotterdam


@pytest.mark.parametrize("path", PROJECTS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_a_sample_says_what_it_is_and_why_it_fails(path):
    project = load_project(path)
    description = project.config.get("description", "")
    assert len(description) > 40, f"{path}: no description"
    if description.startswith("Fails by design"):
        assert "required" in description or "needed" in description, description  # says against what
    required = {k: v for k, v in vars(project.requirements).items() if v in ("minimum", "medium", "high")}
    for criterion in required:  # a required criterion has its section: never NOT ASSESSED by construction
        assert criterion in project.config, f"{path}: requires {criterion} but has no {criterion} section"


@pytest.mark.parametrize("name", sorted(SAMPLES))
def test_the_pinned_verdict_is_the_one_the_description_gives(name):
    report = json.loads(gzip.decompress((ROOT / "tests" / "golden" / f"{name}.json.gz").read_bytes()))
    doc = report["report.json"] if "report.json" in report else report
    doc = json.loads(doc) if isinstance(doc, str) else doc
    description = load_project(ROOT / SAMPLES[name]).config["description"]
    assert (doc["status"] == "fail") == description.startswith("Fails by design")
    assert doc["project"]["description"] == description
