"""A window no ray from its glass can match to a space goes to the space its IfcRelSpaceBoundary
names, with a note (issue 35, corpus mechanism 4).

Built from a description of the case, never from one file: a one-room IFC model written with
ifcopenshell.api (:class:`en17037cli.samples.ifc.Builder`), 6 x 5 m inside 0.3 m walls, a south
window whose rays enter the room's space, and an east window (1.2 x 1.2 m, its centre 3.8 m along
the wall) that the file's space boundary gives the room, though the space is drawn short of it
(its volume stops at y = 2.5 m, as a space drawn to a partition the design later removed): no ray
along the east window's normal enters any space.
"""
from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from en17037cli.project import load_project
from en17037cli.scene import build_scene
from en17037cli.scene.spaces import windows_in_no_room
from tests.ifc_box import box_shell

pytest.importorskip("ifcopenshell")


def model(path: Path, name_east: bool) -> Path:
    b, st, walls = box_shell()
    room = b.space("R1", "Room", st, [(0.3, 0.3), (6.3, 0.3), (6.3, 2.5), (0.3, 2.5)], 0.0, 2.7)  # drawn short
    b.window("W south", st, walls[0], (3.3, 0.0, 1.5), (0, -1, 0), (1, 0, 0), 2.0, 1.4, spaces=[room])
    b.window("W east", st, walls[1], (6.6, 3.8, 1.5), (1, 0, 0), (0, 1, 0), 1.2, 1.2, spaces=[room] if name_east else [])
    return b.write(path)


def scene_of(tmp: Path, name_east: bool):
    ifc = model(tmp / "room.ifc", name_east)
    doc = {"version": 1, "name": "boundaries", "model": {"files": [{"path": str(ifc)}]},
           "location": {"timezone": "Europe/Amsterdam"}, "rooms": [{"ifc_spaces": "*"}], "sunlight": {"date": "03-21"},
           "requirements": {"view": "none", "sunlight": "minimum"}}
    p = tmp / "project.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return build_scene(load_project(p, []))


def test_the_space_a_boundary_names_takes_a_window_nothing_else_places(tmp_path):
    s = scene_of(tmp_path, name_east=True)
    (room,) = s.rooms
    assert sorted(w.name for w in room.windows) == ["W east", "W south"]
    east = next(w for w in room.windows if w.name == "W east")
    assert east.normal @ [1.0, 0.0, 0.0] == pytest.approx(1.0, abs=1e-9)  # facing out of the room, east
    assert "none of its rays enters the space" in room.window_reasons["W east"]
    # the gap between the glass's box and the space's: the glass (outer face) stands 2 cm + half the frame's
    # depth less half the glass's in from the wall's outer face, and starts one frame width in from the opening
    from en17037cli.samples.ifc import FRAME_DEPTH_M, FRAME_M, GLASS_M

    dx = 6.6 - 0.02 - (FRAME_DEPTH_M / 2 - GLASS_M / 2) - 6.3
    dy = (3.8 - 0.6 + FRAME_M) - 2.5
    (note,) = [n for n in s.notes if "W east" in n and "boundaries name" in n]
    assert f"({(dx ** 2 + dy ** 2) ** 0.5:.2f} m away)" in note, note
    assert windows_in_no_room(s) == []


def test_without_the_boundary_the_window_is_in_no_room(tmp_path):
    s = scene_of(tmp_path, name_east=False)
    assert [w.name for w in s.rooms[0].windows] == ["W south"]
    assert [n for n, _ in windows_in_no_room(s)] == ["W east"]
