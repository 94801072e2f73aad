"""A window no ray can leave through because its wall is not cut (issue 35, corpus mechanism 11).

Built from descriptions of what real exports did, never from one file: a one-room IFC house written
with ifcopenshell.api (:class:`en17037cli.samples.ifc.Builder`), 6 x 5 m inside 0.3 m walls, a
1.2 x 1.2 m south window (glass 6 mm in an 8 cm frame 2 cm into the wall), checked for sunlight on
21 March in Delft, and drawn in these ways:

* ``cut``: as a correct export writes it: an IfcOpeningElement through the wall, filled by the window;
* ``uncut``: no IfcOpeningElement at all, the wall whole, its faces 6 cm beyond the glass and 24 cm
  on the room's side (Vectorworks 2013): the wall is cut along the window's outline with reveals, a
  note says so, and the room gets the same hours as ``cut``;
* ``shallow``: the window fills an opening cut only 12 cm into the 30 cm wall (BlenderBIM): the
  rest of its host is cut the same way, the same hours again;
* ``neighbour``: ``cut``, with another building's wall (IfcWall) 1.5 m in front of the facade, 20 m
  wide and 10 m high: a real obstruction, a legitimate 0 h: the room FAILs, and the warning names
  that wall and how far it lies;
* ``lining``: ``cut``, with an uncut lining (IfcCovering) 3 cm thick on the wall's room-side face:
  not the window's host and not around its glass, so not cut; no ray passes within the wall's
  thickness: the room's verdict is withheld (never a FAIL resting on a modelling error) and the
  window is listed with the quarantined elements;
* ``shutter``: ``cut``, the window's own element holding an opaque panel 1 cm beyond its glass (an
  ArchiCAD 9 window): withheld too, the reason naming the window's own panel, not its wall.
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
from tests.ifc_box import box_shell

pytest.importorskip("ifcopenshell")
SUN = {"date": "03-21", "period": {"start": "03-21", "end": "03-21"}}
CENTRE, S, X, Z = (3.3, 0.0, 1.5), (0, -1, 0), (1, 0, 0), (0, 0, 1)


def glazed(b, st, name: str):
    """The south window's IfcWindow (frame and glass, as Builder.window draws them) with no relation to any wall."""
    from en17037cli.samples.ifc import FRAME_DEPTH_M, FRAME_M, GLASS_M

    n, u, v = np.array(S, float), np.array(X, float), np.array(Z, float)
    outer = np.array([(-0.6, -0.6), (0.6, -0.6), (0.6, 0.6), (-0.6, 0.6)])
    inner = outer * (0.6 - FRAME_M) / 0.6
    front = np.array(CENTRE) - 0.02 * n
    w = b.entity("IfcWindow", name)
    b.place(w, st)
    b.represent(w, [b.plate(outer, [inner], front, u, v, -n, FRAME_DEPTH_M),
                    b.plate(inner, [], front - (FRAME_DEPTH_M / 2 - GLASS_M / 2) * n, u, v, -n, GLASS_M)],
                styles=["frame", "glass"])
    return w


def _rect(x0, z0, x1, z1):
    return [(x0, z0), (x1, z0), (x1, z1), (x0, z1)]


#: The pane inside the window's 6 cm frame: 1.08 x 1.08 m about the window's centre [m, in its plane].
PANE = 0.54
#: case -> opaque parts of the window's own element 1 cm beyond its glass: (outline, holes) in its plane [m]
OWN_PARTS = {
    "shutter": [(_rect(-0.55, -0.55, 0.55, 0.55), [])],  # a panel over the whole pane: covers 100 %
    "frame_ahead": [(_rect(-0.6, -0.6, 0.6, 0.6), [_rect(-PANE, -PANE, PANE, PANE)])],  # a ring around the glass: 0 %
    "sash_rim": [(_rect(-0.57, -0.57, 0.57, 0.57), [_rect(-0.52, -0.52, 0.52, 0.52)])],  # over its 2 cm rim: 7.3 %
    "glazing_bars": [(_rect(-PANE, -0.02, PANE, 0.02), []), (_rect(-0.02, -PANE, 0.02, -0.02), []),
                     (_rect(-0.02, 0.02, 0.02, PANE), [])],  # a cross of 4 cm bars: 7.3 %
}


def house(path: Path, case: str) -> Path:
    b, st, walls = box_shell()
    room = b.space("R1", "Room", st, [(0.3, 0.3), (6.3, 0.3), (6.3, 5.3), (0.3, 5.3)], 0.0, 2.7)
    if case in ("cut", "neighbour", "lining"):
        b.window("W", st, walls[0], CENTRE, S, X, 1.2, 1.2, spaces=[room])
    elif case in OWN_PARTS:  # the window's own opaque parts 1 cm beyond its glass's outer face
        from en17037cli.samples.ifc import FRAME_DEPTH_M, GLASS_M

        w = b.window("W", st, walls[0], CENTRE, S, X, 1.2, 1.2, spaces=[room])
        rep = w.Representation.Representations[0]
        glass_y = 0.02 + FRAME_DEPTH_M / 2 - GLASS_M / 2
        parts = [b.plate(np.array(outer), [np.array(h) for h in holes], (CENTRE[0], glass_y - 0.01, CENTRE[2]), X, Z,
                         (0, -1, 0), 0.005) for outer, holes in OWN_PARTS[case]]
        rep.Items = list(rep.Items) + parts
        for panel in parts:
            b.api.run("style.assign_item_style", b.f, item=panel, style=b.styles["frame"])
    elif case == "uncut":
        glazed(b, st, "W")
    elif case == "shallow":  # the opening from the outer face 12 cm into the wall: the window's frame fits in it
        op = b.entity("IfcOpeningElement", "Opening W")
        b.place(op)
        outline = np.array([(-0.6, -0.6), (0.6, -0.6), (0.6, 0.6), (-0.6, 0.6)])
        b.represent(op, [b.plate(outline, [], np.array(CENTRE) + (0, -0.02, 0), X, Z, (0, 1, 0), 0.14)])
        b.api.run("feature.add_feature", b.f, feature=op, element=walls[0])
        b.api.run("feature.add_filling", b.f, opening=op, element=glazed(b, st, "W"))
    if case in ("neighbour", "frame_ahead", "sash_rim", "glazing_bars"):
        b.wall("Neighbour", st, 16.0, -1.5, -10.0, -1.5, 0.0, 10.0)  # thickness to its left: south, away from the house
    if case == "lining":
        lining = b.entity("IfcCovering", "Lining")
        b.place(lining, st)
        b.represent(lining, [b.prism([(0.3, 0.3), (6.3, 0.3), (6.3, 0.33), (0.3, 0.33)], 0.0, 2.7)])
    return b.write(path)


def project(tmp: Path, case: str) -> Path:
    ifc = house(tmp / f"{case}.ifc", case)
    doc = {"version": 1, "name": case, "model": {"files": [{"path": str(ifc)}]}, "location": {"timezone": "Europe/Amsterdam"},
           "rooms": [{"ifc_spaces": "*"}], "sunlight": SUN, "requirements": {"view": "none", "sunlight": "minimum"}}
    p = tmp / f"{case}.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p


def check(p: Path, out: Path) -> tuple[int, dict]:
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(out), "--quiet", "--no-plots"], catch_exceptions=False)
    return r.exit_code, json.loads((out / "report.json").read_text())


@pytest.fixture(scope="module")
def cut(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("cut")
    return check(project(tmp, "cut"), tmp / "out")


@pytest.mark.parametrize("case", ["uncut", "shallow"])
def test_a_window_in_an_uncut_wall_gets_its_opening_cut(tmp_path, case, cut):
    code0, ref = cut
    assert code0 == 0 and ref["rooms"][0]["sunlight"]["status"] == "pass"
    p = project(tmp_path, case)
    s = build_scene(load_project(p, []))
    (note,) = [n for n in s.notes if "set in a wall the file does not cut" in n]
    assert "IfcWindow 'W'" in note and "IfcWall 'Wall 0'" in note
    (w,) = s.rooms[0].windows
    assert w.name == "W" and len(w.host) == 1  # the wall it is cut in is its host now (point P on its room-side face)
    code, rep = check(p, tmp_path / "out")
    assert code == 0 and rep["quarantined"] == [] and not any("no ray" in x for x in rep["warnings"])
    got, want = rep["rooms"][0]["sunlight"], ref["rooms"][0]["sunlight"]
    assert got["status"] == "pass"
    assert got["windows"][0]["point_p_m"] == pytest.approx(want["windows"][0]["point_p_m"], abs=1e-6)
    # the same building as a correct export, to the exact method's bracketing (sunlight.tolerance_s, 1 s) at each end
    assert got["hours_h"] == pytest.approx(want["hours_h"], abs=4 / 3600)


def test_an_obstruction_outside_is_a_legitimate_zero(tmp_path):
    code, rep = check(project(tmp_path, "neighbour"), tmp_path / "out")
    sun = rep["rooms"][0]["sunlight"]
    assert code == 1 and sun["status"] == "fail" and sun["hours_h"] == 0.0 and rep["quarantined"] == []
    (warning,) = [x for x in rep["warnings"] if "no ray from the room leaves" in x]
    # the glass's outer face lies 2 cm + (8 - 0.6) / 2 cm inside the wall's outer face, the neighbour 1.5 m beyond it
    assert "on IfcWall 'Neighbour'" in warning and f"lies {1.5 + 0.02 + 0.037:.1f} m out" in warning
    assert "an obstruction, not a wall left uncut" in warning


def test_a_window_blocked_within_its_walls_thickness_withholds_the_verdict(tmp_path):
    code, rep = check(project(tmp_path, "lining"), tmp_path / "out")
    sun = rep["rooms"][0]["sunlight"]
    assert code == 1 and sun["status"] == "not_assessable" and sun["level"] is None  # never a FAIL on a modelling error
    assert sun["hours_h"] == 0.0 and "lets no ray through" in sun["reason"]
    (q,) = rep["quarantined"]
    assert q["rooms"] == ["Room (R1)"] and q["element"] == "window 'W'" and "IfcCovering 'Lining'" in q["reason"]
    assert "verdict withheld" in q["action"] and "layer: interior}" in q["advice"]
    # the lining's face lies 2 cm + 3.7 cm + ... : the glass (outer face) 5.7 cm into the 30 cm wall, the lining at its room face
    assert f"lies {0.3 - 0.057:.2f} m in front of its glazing" in q["reason"]


def test_a_window_covered_by_its_own_panel_withholds_the_verdict_naming_it(tmp_path):
    code, rep = check(project(tmp_path, "shutter"), tmp_path / "out")
    sun = rep["rooms"][0]["sunlight"]
    assert code == 1 and sun["status"] == "not_assessable"
    (q,) = rep["quarantined"]
    assert "its own element IfcWindow 'W'" in q["reason"] and "lies 0.01 m beyond its glazing" in q["reason"]
    assert "wall" not in q["reason"]


#: The share of the pane (1.08 x 1.08 m) each case's own parts cover, worked out by hand.
COVER = {"shutter": 1.0, "frame_ahead": 0.0, "sash_rim": 1 - 1.04 ** 2 / 1.08 ** 2,
         "glazing_bars": (1.08 * 0.04 + 2 * 0.04 * 0.52) / 1.08 ** 2}


@pytest.mark.parametrize("case", list(OWN_PARTS))
def test_what_a_windows_own_parts_cover_of_its_pane(tmp_path, case):
    """Seen along the pane's normal: the shutter covers all of it, the ring around it nothing, the
    sash over its rim and the glazing bars 7.3 % (the window's own 8 cm frame, its hole the pane's
    outline, adds nothing)."""
    from en17037cli.preflight import own_cover

    s = build_scene(load_project(project(tmp_path, case), []))
    (w,) = s.rooms[0].windows
    assert own_cover(s, w, 1.0, 0.6) == pytest.approx(COVER[case], abs=1e-9)
    assert own_cover(s, w, -1.0, 0.6) == 0.0  # nothing of it on the room's side


@pytest.mark.parametrize("case", ["frame_ahead", "sash_rim", "glazing_bars"])
def test_a_windows_own_frame_or_bars_ahead_of_its_glass_are_no_shutter(tmp_path, case):
    """A frame, a sash over the glass's rim, glazing bars 1 cm beyond the glass, and a neighbour's
    wall 1.5 m out that stops every ray: the neighbour is what stops them (a legitimate 0 h, the
    room FAILs), and the window is not quarantined as covered by its own panel (before: the bars,
    over 5 of the 9 points the check looks through, were taken for one)."""
    code, rep = check(project(tmp_path, case), tmp_path / "out")
    sun = rep["rooms"][0]["sunlight"]
    assert rep["quarantined"] == [] and code == 1 and sun["status"] == "fail" and sun["hours_h"] == 0.0
    (warning,) = [x for x in rep["warnings"] if "no ray from the room leaves" in x]
    assert "on IfcWall 'Neighbour'" in warning and f"lies {1.5 + 0.02 + 0.037:.1f} m out" in warning
