"""Spaces drawn over one another (issue 43): the one left without windows says why.

A Revit export held three IfcSpaces of one name with nearly one footprint: the windows went to one,
and the other two said "no window opens into it", which is not the reason. Built here: the one-room
IFC house of tests/ifc_box.py (a 1.2 m south window) with two spaces named 'Hall' '15': A inside
the walls, 6 x 5 m, 2.7 m high; B the same but reaching 0.15 m into the north wall, 6 x 5.15 m. B
shares 6 x 5 x 2.7 = 81 m3 of its 6 x 5.15 x 2.7 = 83.43 m3 with A (97.1 %), A all of its own
with B (100 %).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.project import load_project
from en17037cli.scene import build_scene
from en17037cli.scene.space_overlap import shared_share
from tests.ifc_box import box_shell

pytest.importorskip("ifcopenshell")

OUTLINES = {"A": [(0.3, 0.3), (6.3, 0.3), (6.3, 5.3), (0.3, 5.3)], "B": [(0.3, 0.3), (6.3, 0.3), (6.3, 5.45), (0.3, 5.45)]}
SHARE = {"A": 1.0, "B": 6 * 5 / (6 * 5.15)}  # of each one's volume, inside the other (same heights)


def project(tmp: Path) -> tuple[Path, dict]:
    """The project, and each space's GlobalId."""
    b, st, walls = box_shell()
    ids = {}
    for k in ("A", "B"):
        sp = b.space("15", "Hall", st, OUTLINES[k], 0.0, 2.7)
        sp.GlobalId = ids[k] = b.entity_id(f"space {k}")  # two spaces of one name: their own ids
        b.named_ids.append(sp.GlobalId)
    b.window("W", st, walls[0], (3.3, 0.0, 1.5), (0, -1, 0), (1, 0, 0), 1.2, 1.2)
    ifc = b.write(tmp / "hall.ifc")
    doc = {"version": 1, "name": "hall", "model": {"files": [{"path": str(ifc)}]},
           "location": {"latitude": 52.0, "longitude": 4.36, "timezone": "Europe/Amsterdam"},
           "rooms": [{"ifc_spaces": "*"}], "sunlight": {"date": "03-21"}, "requirements": {"view": "none", "sunlight": "minimum"}}
    p = tmp / "hall.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p, ids


def test_shared_volume_of_two_prisms():
    """The shares worked out in the module docstring."""
    from en17037cli.io.mesh import Space

    sp = {k: Space(k, "15", "Hall", "Ground", np.array(o, float), 0.0, 2.7) for k, o in OUTLINES.items()}
    assert shared_share(sp["B"], sp["A"]) == pytest.approx(SHARE["B"], abs=1e-12)
    assert shared_share(sp["A"], sp["B"]) == pytest.approx(1.0, abs=1e-12)
    lower = Space("C", "16", "Below", "Ground", sp["A"].footprint, -3.0, 0.0)  # stacked under A: no volume shared
    assert shared_share(lower, sp["A"]) == 0.0


def test_a_space_drawn_over_one_with_windows_says_so(tmp_path):
    p, ids = project(tmp_path)
    s = build_scene(load_project(p, []))
    (room,) = s.rooms
    (left,) = s.left_out
    assert [w.name for w in room.windows] == ["W"]
    (kept,) = [k for k, gid in ids.items() if room.name == f"Hall (15) [{gid}]"]  # one of the two has the window
    other = "B" if kept == "A" else "A"
    assert left.name == f"Hall (15) [{ids[other]}]"
    want = f"overlaps '{room.name}' by {SHARE[other]:.0%}: its windows went to that one"
    assert left.reason == want
    r = CliRunner().invoke(cli, ["validate", str(p)], catch_exceptions=False)
    assert r.exit_code == 0 and f"space '{left.name}': not a room of the check: {want}" in r.output
    CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / "out"), "--quiet", "--no-plots"], catch_exceptions=False)
    rep = json.loads((tmp_path / "out" / "report.json").read_text())
    assert rep["spaces_left_out"] == [{"name": left.name, "reason": want, "windows": []}]
