"""One odd element costs that element, never the model (issue 35).

Built from descriptions of what real exports did, never from one file: a two-room IFC house
written with ifcopenshell.api (:class:`en17037cli.samples.ifc.Builder`), rooms A (west) and B
(east) behind a south wall, each with a 2.0 x 1.4 m south window, and then:

* ``uncut``: an IfcWindow whose glass lies on the east wall's outer face of room B with no opening
  cut for it (a glazed door a Revit export drew on its wall): it is quarantined (taken as opaque,
  named with its wall and the two project-file remedies), room A is assessed as before, room B is
  assessed without it and its verdict withheld (never a pass), and following the advice gives B
  its verdict back;
* ``panel``: an IfcWindow 3 m wide whose only style is an opal panel of transparency 0.01 filling no
  opening on room A's west wall (an ArchiCAD wall panel classed as a window): not glazing at all,
  so nothing lies on its wall, and no verdict is withheld;
* ``slab_door``: a glazed IfcDoor lying flat on a terrace's slab (a door an export placed in the
  wrong plane): quarantined, a window of no room: every room keeps its verdict.
"""
from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.errors import InputError
from en17037cli.project import load_project
from en17037cli.scene import build_scene
from en17037cli.schemas import load_schema

pytest.importorskip("ifcopenshell")
SUN = {"date": "03-21", "period": {"start": "03-21", "end": "03-21"}}


def house(path: Path, *, uncut: bool = False, panel: bool = False, slab_door: bool = False, only_uncut: bool = False) -> Path:
    """Write the two-room house (see the module docstring)."""
    from en17037cli.samples.ifc import Builder

    b = Builder("IFC4")
    st = b.storey("Ground", 0.0)
    b.locate(52.0, 4.36, 0.0)
    foot = [(0, 0), (12.3, 0), (12.3, 5.6), (0, 5.6)]
    b.slab("Floor", st, foot, -0.2, 0.2)
    roof = b.slab("Roof", st, foot, 2.7, 0.2)
    walls = [b.wall(f"Wall {k}", st, *p, *q, 0.0, 2.7) for k, (p, q) in enumerate(zip(foot, foot[1:] + foot[:1]))]
    b.wall("Partition", st, 6.3, 0.3, 6.3, 5.3, 0.0, 2.7)
    a = b.space("A", "Room A", st, [(0.3, 0.3), (6.0, 0.3), (6.0, 5.3), (0.3, 5.3)], 0.0, 2.7)
    bb = b.space("B", "Room B", st, [(6.3, 0.3), (12.0, 0.3), (12.0, 5.3), (6.3, 5.3)], 0.0, 2.7)
    b.styles["opal"] = b.surface_style("Opal polycarbonate", (0.95, 0.95, 0.95), 0.01)
    if not only_uncut:
        b.window("W A", st, walls[0], (3.15, 0.0, 1.5), (0, -1, 0), (1, 0, 0), 2.0, 1.4, spaces=[a])
        b.window("W B", st, walls[0], (9.15, 0.0, 1.5), (0, -1, 0), (1, 0, 0), 2.0, 1.4, spaces=[bb])
    pane = np.array([(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)])
    if uncut or only_uncut:  # glass on room B's east wall, outer face, no opening
        w = b.entity("IfcWindow", "W uncut")
        b.place(w, st)
        b.represent(w, [b.plate(pane, [], (12.3, 2.8, 1.5), (0, 1, 0), (0, 0, 1), (-1, 0, 0), 0.006)], style="glass")
    if panel:  # a 3 x 2 m opal panel on room A's west wall, classed as a window
        w = b.entity("IfcWindow", "Panel")
        b.place(w, st)
        big = np.array([(-1.5, -1.0), (1.5, -1.0), (1.5, 1.0), (-1.5, 1.0)])
        b.represent(w, [b.plate(big, [], (0.0, 2.8, 1.4), (0, -1, 0), (0, 0, 1), (-1, 0, 0), 0.02)], style="opal")
    if slab_door:  # a glazed door lying on a terrace slab's upper face, east of the house
        b.slab("Terrace", st, [(13, 0), (16, 0), (16, 5.6), (13, 5.6)], -0.2, 0.2)
        d = b.entity("IfcDoor", "Door on the terrace")
        b.place(d, st)
        b.represent(d, [b.plate(pane, [], (14.5, 2.8, 0.0), (1, 0, 0), (0, 1, 0), (0, 0, 1), 0.006)], style="glass")
    del roof
    return b.write(path)


def project(tmp: Path, ifc: Path, **extra) -> Path:
    doc = {"version": 1, "name": "two rooms", "model": {"files": [{"path": str(ifc), **extra.pop("file", {})}]},
           "location": {"timezone": "Europe/Amsterdam"}, "rooms": [{"ifc_spaces": "*"}],
           "sunlight": SUN, "requirements": {"view": "none", "sunlight": "minimum"}, **extra}
    p = tmp / "project.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p


def check(p: Path, out: Path) -> tuple[int, dict]:
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(out), "--quiet", "--no-plots"], catch_exceptions=False)
    return r.exit_code, json.loads((out / "report.json").read_text()) if (out / "report.json").exists() else {}


def test_a_window_drawn_on_its_wall_is_quarantined_and_its_room_withheld(tmp_path):
    base_code, base = check(project(tmp_path, house(tmp_path / "h0.ifc")), tmp_path / "o0")
    assert [r["sunlight"]["status"] for r in base["rooms"]] == ["pass", "pass"] and base_code == 0
    assert base["quarantined"] == []
    p = project(tmp_path, house(tmp_path / "h.ifc", uncut=True))
    s = build_scene(load_project(p, []))
    assert {r.name: [w.name for w in r.windows] for r in s.rooms} == {"Room A (A)": ["W A"], "Room B (B)": ["W B"]}
    assert "W uncut" not in [w.name for w in s.windows]
    (q,) = s.quarantined
    assert q.rooms == ("Room B (B)",) and q.action == "taken as opaque" and "lies on IfcWall 'Wall 1'" in q.reason
    code, rep = check(p, tmp_path / "o1")
    assert code == 1
    rooms = {r["name"]: r for r in rep["rooms"]}
    assert rooms["Room A (A)"]["sunlight"] == base["rooms"][0]["sunlight"]  # every other room exactly as before
    b = rooms["Room B (B)"]["sunlight"]
    assert b["status"] == "not_assessable" and b["level"] is None and "W uncut" in b["reason"]
    assert b["reason"].endswith("without them it reaches " + base["rooms"][1]["sunlight"]["level"])
    assert b["hours_h"] == base["rooms"][1]["sunlight"]["hours_h"]  # the figures are still there
    jsonschema.validate(rep, load_schema("report"))  # a withheld section: level null, not_assessable, its figures
    (entry,) = rep["quarantined"]
    assert entry["rooms"] == ["Room B (B)"] and "layer: interior}" in entry["advice"] and "exclude: ['" in entry["advice"]
    assert any(w.startswith("quarantined: window 'W uncut'") for w in rep["warnings"])
    # the advice, as written, gives room B its verdict back
    key = entry["advice"].split("{id: '")[1].split("'")[0]
    p2 = project(tmp_path, house(tmp_path / "h.ifc", uncut=True), file={"layers": [{"id": key, "layer": "interior"}]})
    code2, rep2 = check(p2, tmp_path / "o2")
    assert code2 == 0 and rep2["quarantined"] == [] and rep2["rooms"][1]["sunlight"]["status"] == "pass"


def test_an_opal_panel_classed_as_a_window_is_no_glazing(tmp_path):
    p = project(tmp_path, house(tmp_path / "h.ifc", panel=True))
    s = build_scene(load_project(p, []))
    assert sorted(w.name for w in s.windows) == ["W A", "W B"] and s.quarantined == []
    assert any("nearly opaque" in w and "Panel" in w for w in s.warnings), s.warnings
    assert all(r.withheld is None for r in s.rooms)


def test_a_door_lying_on_a_slab_is_a_window_of_no_room(tmp_path):
    p = project(tmp_path, house(tmp_path / "h.ifc", slab_door=True))
    s = build_scene(load_project(p, []))
    (q,) = s.quarantined
    assert q.rooms == () and "Door on the terrace" in q.element and "IfcSlab 'Terrace'" in q.reason
    code, rep = check(p, tmp_path / "o")
    assert code == 0 and [r["sunlight"]["status"] for r in rep["rooms"]] == ["pass", "pass"]
    assert any("it is a window of no room" in w for w in rep["warnings"])


def test_a_model_whose_every_window_lies_on_its_wall_is_an_input_error(tmp_path):
    """Nothing left to assess: one line naming the window, the wall and the remedies, exit 2."""
    p = project(tmp_path, house(tmp_path / "h.ifc", only_uncut=True))
    with pytest.raises(InputError, match=r"window 'W uncut' .* lies on IfcWall 'Wall 1' .*layer: interior\}"):
        build_scene(load_project(p, []))
