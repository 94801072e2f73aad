"""Every file of ../shared/data/real-models through ``validate`` and ``check`` as a user runs them:
the console command in its own process, the defaults (pictures on), the project of the README's
"From BIM" section (every IfcSpace or gbXML Space a room; a city model the context of the box room
set down in it; ``scripts/bim_corpus.py`` writes them). Exit 0 or 1, never 2 or 3; report.json valid
against its schema; every picture the report names is on disk (issue 43: AC11-Institute stopped
with exit 3 on a GlobalId's ``$`` in a picture's label, and nothing here ran the pictures).

Marked ``real_models`` (``pytest -m real_models`` runs these alone; CI runs them with the rest).
Skipped, with the reason, where ../shared/data/real-models is absent (a clone on its own).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest

from en17037cli.schemas import load_schema

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT.parent / "shared" / "data" / "real-models"
sys.path.insert(0, str(ROOT / "scripts"))
from bim_corpus import citygml_project, kind_of, project_for  # noqa: E402

pytestmark = [pytest.mark.real_models,
              pytest.mark.skipif(not MODELS.is_dir(), reason=f"{MODELS} is absent: the real models are not checked")]
FILES = sorted(p for p in MODELS.iterdir() if kind_of(p)) if MODELS.is_dir() else []


def en17037(*args) -> subprocess.CompletedProcess:
    env = dict(os.environ, COLUMNS="120")
    return subprocess.run([sys.executable, "-m", "en17037cli", *map(str, args)], capture_output=True, text=True, env=env,
                          timeout=1500)


@pytest.mark.parametrize("model", FILES, ids=[p.name for p in FILES])
def test_validate_and_check_with_the_defaults(model, tmp_path):
    pytest.importorskip("ifcopenshell")
    pytest.importorskip("matplotlib")
    kind = kind_of(model)
    if kind in ("citygml", "cityjson"):
        project, _, _ = citygml_project(model, tmp_path, kind)
    else:
        project = project_for(model, tmp_path, 52.0, 5.0, kind)
    v = en17037("validate", project)
    assert v.returncode == 0, (v.stdout[-2000:], v.stderr[-2000:])
    out = tmp_path / "report"
    bim = ("--bcf", tmp_path / "issues.bcf", "--ifc-out", tmp_path / "results.ifc") if kind == "ifc" else ()
    c = en17037("check", project, "--out", out, "-q", *bim)
    assert c.returncode in (0, 1), c.stderr[-3000:]
    report = json.loads((out / "report.json").read_text(encoding="utf-8"))
    jsonschema.validate(report, load_schema("report"))
    assert report["rooms"], "no room was checked"
    html = (out / "report.html").read_text(encoding="utf-8")
    figures = sorted((out / "figures").glob("*.png")) if (out / "figures").is_dir() else []
    assert figures or "<svg" in html, "the report has no picture"
    if bim:
        back_into_the_bim(model, report, tmp_path / "issues.bcf", tmp_path / "results.ifc")


def back_into_the_bim(model: Path, report: dict, bcf: Path, ifc: Path) -> None:
    """The BCF validates against buildingSMART's BCF 2.1 schemas and selects only the file's
    IfcSpaces and glazed elements; the written IFC carries EN17037_Results on each room's space."""
    import io
    import re
    import zipfile

    import ifcopenshell
    import ifcopenshell.util.element as ue
    import xmlschema

    xsd = Path(__file__).parent / "data" / "bcf-2.1"
    markup, visinfo = (xmlschema.XMLSchema(str(xsd / f"{n}.xsd")) for n in ("markup", "visinfo"))
    f = ifcopenshell.open(str(model))
    with zipfile.ZipFile(bcf) as z:
        for name in z.namelist():
            if name.endswith(".bcf"):
                markup.validate(io.BytesIO(z.read(name)))
            elif name.endswith(".bcfv"):
                visinfo.validate(io.BytesIO(z.read(name)))
                for gid in re.findall(r'IfcGuid="([^"]+)"', z.read(name).decode("utf-8")):
                    assert f.by_guid(gid).is_a() in ("IfcSpace", "IfcWindow", "IfcDoor", "IfcPlate") or \
                        any(f.by_guid(gid).is_a(c) for c in ("IfcWindow", "IfcDoor", "IfcPlate")), gid
        topics = {n.split("/")[0] for n in z.namelist() if n.endswith("/markup.bcf")}
    try:  # and IfcOpenShell's BCF library (bcf-client, the test extra) reads every topic of it
        from bcf.v2.bcfxml import BcfXml
    except ImportError:
        BcfXml = None
    if BcfXml is not None:
        with BcfXml.load(bcf) as b:
            assert set(b.topics) == topics
            assert all(h.topic.title and len(h.viewpoints) == 1 for h in b.topics.values())
    out = ifcopenshell.open(str(ifc))
    rooms = {r["source"]["ids"][0]: r for r in report["rooms"] if r["source"]["format"] == "ifc"}
    for gid, room in rooms.items():
        assert ue.get_psets(out.by_guid(gid))["EN17037_Results"]["Status"] == room["status"]
