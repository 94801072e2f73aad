"""An IfcWindow's pane from the window itself (issue 35, corpus mechanisms 3 and 5).

Built from descriptions of what real exports did, never from one file: a one-room IFC model written
with ifcopenshell.api (:class:`en17037cli.samples.ifc.Builder`), 6 x 5 m inside 0.3 m walls, and
windows whose file says nothing of their glass (no transparent style, no glass name), so that the
pane has to be found in their geometry:

* ``roof light``: a 0.6 x 0.6 m roof light with no host (no IfcRelFillsElement), modelled as a
  frame ring 0.15 m deep with no glass (a deep curb: its sides are larger than its faces), named
  by the room's space boundary: one horizontal pane filling the ring's 0.5 x 0.5 m hole, in the
  room; not the ring's sides taken for panes (a Revit 2020 IFC4 export);
* ``lintel``: a 2.26 x 2.37 m window whose opening is cut in a 13 cm lintel above it (its host,
  wider than it is high, so its faces lie mostly flat): one vertical pane in the window's own
  plane; not the frame's top and bottom taken for panes in the lintel's (an Autodesk ADT export);
* ``bars``: a window modelled as a frame and two flat glazing bars across it, no glass: the bars
  are too small to be its panes (6 % of its outline); the four openings they leave are;
* ``bare``: an IfcWindow with no geometry at all whose IfcOpeningElement is cut in the wall: an
  unglazed pane of the opening's outline at the wall's mid-plane, with a note; one with neither
  geometry nor opening is named (an Allplan export with every window's Representation unset).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from en17037cli.errors import InputError
from en17037cli.project import load_project
from en17037cli.scene import build_scene

pytest.importorskip("ifcopenshell")
WALL = 0.3
SQUARE = lambda h: np.array([(-h, -h), (h, -h), (h, h), (-h, h)])  # noqa: E731  (a square of half side h [m])


def boundary(b, space, element) -> None:
    """An IfcRelSpaceBoundary between ``space`` and ``element``, as exporters write them."""
    b.f.create_entity("IfcRelSpaceBoundary", GlobalId=b.entity_id(f"boundary {element.Name} {space.Name}"),
                      RelatingSpace=space, RelatedBuildingElement=element, PhysicalOrVirtualBoundary="PHYSICAL",
                      InternalOrExternalBoundary="EXTERNAL")


def opening(b, name: str, element, outline_uv, origin, u, v, n, depth: float):
    """An IfcOpeningElement of ``outline_uv`` in the plane (origin, u, v), extruded ``depth`` along n, voiding ``element``."""
    op = b.entity("IfcOpeningElement", f"Opening {name}")
    b.place(op)
    b.represent(op, [b.plate(outline_uv, [], origin, u, v, n, depth)])
    b.api.run("feature.add_feature", b.f, feature=op, element=element)
    return op


def model(path: Path, case: str) -> Path:
    """Write the one-room model with the window of ``case`` (see the module docstring)."""
    from en17037cli.samples.ifc import Builder

    b = Builder("IFC4")
    b.styles["glass"] = b.styles["frame"]  # the file says nothing of the glass: no transparency, no glass name
    st = b.storey("Ground", 0.0)
    b.locate(52.0, 4.36, 0.0)
    height = 2.5 if case == "lintel" else 2.7
    foot = [(0, 0), (6.6, 0), (6.6, 5.6), (0, 5.6)]
    b.slab("Floor", st, foot, -0.2, 0.2)
    roof = b.slab("Roof", st, foot, height, 0.2)
    for k, (p, q) in enumerate(zip(foot, foot[1:] + foot[:1])):  # east, north, west; the south wall per case
        if k:
            b.wall(f"Wall {k}", st, *p, *q, 0.0, height)
    room = b.space("R1", "Room", st, [(WALL, WALL), (6.3, WALL), (6.3, 5.3), (WALL, 5.3)], 0.0, height)
    S, X, Y, Z = (0, -1, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)
    if case == "lintel":  # the south wall in three pieces: a 13 cm lintel over the window between two piers
        b.wall("Wall west pier", st, 0.0, 0.0, 1.87, 0.0, 0.0, height)
        b.wall("Wall east pier", st, 4.13, 0.0, 6.6, 0.0, 0.0, height)
        lintel = b.wall("Lintel", st, 1.87, 0.0, 4.13, 0.0, 2.37, 0.13)
        b.window("W lintel", st, lintel, (3.0, 0.0, 1.185), S, X, 2.26, 2.37, spaces=[room])
        return b.write(path)
    south = b.wall("Wall 0", st, 0.0, 0.0, 6.6, 0.0, 0.0, height)
    if case == "roof light":  # the roof is cut, but the window fills no opening: no host
        opening(b, "roof light", roof, SQUARE(0.3), (3.3, 2.8, height - 0.1), X, Y, Z, 0.4)
        w = b.entity("IfcWindow", "Roof light")
        b.place(w, st)
        b.represent(w, [b.plate(SQUARE(0.3), [SQUARE(0.25)], (3.3, 2.8, height + 0.05), X, Y, Z, 0.15)], style="frame")
        boundary(b, room, w)
    elif case == "bars":  # a frame 1.2 x 1.2 m and two flat bars 4 cm wide, 1 cm deep, across its opening
        op = opening(b, "bars", south, SQUARE(0.6), (3.3, 0.02, 1.5), X, Z, (0, 1, 0), WALL + 0.04)
        w = b.entity("IfcWindow", "W bars")
        b.place(w, st)
        front = np.array([3.3, 0.04, 1.5])  # the frame's outer face, 4 cm into the wall
        bar_v = np.array([(-0.02, -0.54), (0.02, -0.54), (0.02, 0.54), (-0.02, 0.54)])
        items = [b.plate(SQUARE(0.6), [SQUARE(0.54)], front, X, Z, (0, 1, 0), 0.08),
                 b.plate(bar_v, [], front + (0, 0.035, 0), X, Z, (0, 1, 0), 0.01),
                 b.plate(bar_v[:, ::-1], [], front + (0, 0.035, 0), X, Z, (0, 1, 0), 0.01)]
        b.represent(w, items, style="frame")
        b.api.run("feature.add_filling", b.f, opening=op, element=w)
    elif case in ("bare", "bare only"):  # no Representation; the first one's opening is cut in the south wall
        if case == "bare":
            b.window("W south", st, south, (1.5, 0.0, 1.5), S, X, 1.0, 1.2, spaces=[room])
            op = opening(b, "bare", south, SQUARE(0.6), (4.3, -0.02, 1.5), X, Z, (0, 1, 0), WALL + 0.04)
            w = b.entity("IfcWindow", "W bare")
            b.place(w, st)
            b.api.run("feature.add_filling", b.f, opening=op, element=w)
        b.place(b.entity("IfcWindow", "W nowhere"), st)
    return b.write(path)


def scene_of(tmp: Path, case: str):
    ifc = model(tmp / f"{case.replace(' ', '_')}.ifc", case)
    doc = {"version": 1, "name": case, "model": {"files": [{"path": str(ifc)}]}, "location": {"timezone": "Europe/Amsterdam"},
           "rooms": [{"ifc_spaces": "*"}], "sunlight": {"date": "03-21"}, "requirements": {"view": "none", "sunlight": "minimum"}}
    p = tmp / "project.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return build_scene(load_project(p, []))


def test_a_roof_light_with_no_host_gets_one_horizontal_pane_in_its_room(tmp_path):
    s = scene_of(tmp_path, "roof light")
    (w,) = s.rooms[0].windows
    assert len(s.windows) == 1 and w.name == "Roof light"
    assert w.normal[2] == pytest.approx(1.0, abs=1e-9)  # horizontal, facing up out of the room: not the ring's sides
    assert w.area_m2 == pytest.approx(0.25, rel=1e-6)  # the ring's 0.5 x 0.5 m hole


def test_a_window_hosted_by_a_lintel_keeps_its_own_plane(tmp_path):
    s = scene_of(tmp_path, "lintel")
    assert s.quarantined == []
    (w,) = s.rooms[0].windows
    assert len(s.windows) == 1 and w.name == "W lintel"
    assert w.normal @ np.array([0.0, -1.0, 0.0]) == pytest.approx(1.0, abs=1e-9)  # vertical, facing out (south)
    assert w.area_m2 == pytest.approx((2.26 - 0.12) * (2.37 - 0.12), rel=1e-6)  # the glass inside the 6 cm frame
    assert any("host's faces around them lie in another plane" in n and "W lintel" in n for n in s.notes), s.notes


def test_flat_glazing_bars_are_not_panes_the_openings_they_leave_are(tmp_path):
    s = scene_of(tmp_path, "bars")
    (w,) = s.rooms[0].windows
    assert len(s.windows) == 1 and w.name == "W bars"
    bars = 2 * 0.04 * 1.08 - 0.04 ** 2  # two 4 cm bars across the 1.08 m hole, crossing once
    assert w.area_m2 == pytest.approx(1.08 ** 2 - bars, rel=1e-6)
    assert w.normal @ np.array([0.0, -1.0, 0.0]) == pytest.approx(1.0, abs=1e-9)


def test_a_window_without_geometry_takes_its_openings_outline(tmp_path):
    s = scene_of(tmp_path, "bare")
    w = next(x for x in s.windows if x.name == "W bare")
    assert w.area_m2 == pytest.approx(1.2 * 1.2, rel=1e-6)  # the opening's outline, no frame
    y = w.triangles[..., 1] + s.origin[1]
    assert np.allclose(y, WALL / 2, atol=1e-9)  # at the wall's mid-plane
    assert sorted(x.name for x in s.rooms[0].windows) == ["W bare", "W south"]
    assert any("no geometry whose IfcOpeningElement is cut" in n and "W bare" in n for n in s.notes), s.notes
    assert any("W nowhere" in x and "no geometry and no opening" in x for x in s.warnings), s.warnings


def test_a_model_whose_only_window_has_no_geometry_names_it(tmp_path):
    with pytest.raises(InputError, match=r"no face is on the 'window' layer.*W nowhere.*no IfcOpeningElement"):
        scene_of(tmp_path, "bare only")


def test_a_deep_window_falls_back_on_its_overall_size_then_its_host():
    """A 0.54 x 0.94 m window 0.40 m deep (linings through a thick wall) is not clearly thin across
    any axis (0.40 / 0.54 = 0.74 > THIN_RATIO): its OverallWidth x OverallHeight tell its plane; a
    host confirms nothing against it; without the sizes the host's plane is taken."""
    import trimesh

    from en17037cli.io.ifc_windows import THIN_RATIO, window_plane

    box = trimesh.creation.box(extents=(0.40, 0.54, 0.94))  # depth along x, width along y, height along z
    v, f = np.asarray(box.vertices), np.asarray(box.faces)
    assert 0.40 / 0.54 > THIN_RATIO
    lintel = np.array([0.0, 0.0, 1.0])  # a host whose faces lie flat
    p = window_plane(v, f, np.eye(3), (0.54, 0.94), lintel)
    assert abs(p.normal @ [1.0, 0.0, 0.0]) == pytest.approx(1.0) and p.host_disagrees and "OverallWidth" in p.how
    p = window_plane(v, f, np.eye(3), None, np.array([1.0, 0.0, 0.0]))
    assert abs(p.normal @ [1.0, 0.0, 0.0]) == pytest.approx(1.0) and p.how == "its host's faces" and not p.host_disagrees
    thin = trimesh.creation.box(extents=(0.08, 2.26, 2.37))  # clearly thin: its own geometry wins over a flat host
    p = window_plane(np.asarray(thin.vertices), np.asarray(thin.faces), np.eye(3), None, lintel)
    assert abs(p.normal @ [1.0, 0.0, 0.0]) == pytest.approx(1.0) and "thinnest" in p.how and p.host_disagrees


def test_a_square_window_nearly_as_deep_as_wide_takes_the_closest_match_of_its_overall_size():
    """A 0.60 x 0.60 m window 0.54 m deep (Renga Architecture: linings through a 0.54 m wall) matches
    its OverallWidth x OverallHeight across its depth exactly and across its width within 10 % (0.54
    against 0.60): the exact match is its plane, so the pane in it is found; the first candidate
    that matched (its placement's x axis, across its width) found no pane and left it opaque."""
    import trimesh

    from en17037cli.io.ifc_windows import THIN_RATIO, panes_from_geometry, window_plane

    frame = trimesh.creation.box(extents=(0.60, 0.54, 0.60))  # width along x, depth along y (the wall), height z
    pane = trimesh.creation.box(extents=(0.50, 0.01, 0.50))  # the glass, a thin plate in the wall's plane
    both = trimesh.util.concatenate([frame, pane])
    v, f = np.asarray(both.vertices), np.asarray(both.faces)
    assert 0.54 / 0.60 > THIN_RATIO  # not clearly thin across any axis
    p = window_plane(v, f, np.eye(3), (0.60, 0.60), np.array([0.0, 1.0, 0.0]))
    assert abs(p.normal @ [0.0, 1.0, 0.0]) == pytest.approx(1.0) and "OverallWidth" in p.how and not p.host_disagrees
    glass, opening, _ = panes_from_geometry(v, f, p.normal)
    assert glass.any() and opening is None
    p = window_plane(v, f, np.eye(3), (0.60, 1.80), np.array([0.0, 1.0, 0.0]))  # no side matches: the host
    assert abs(p.normal @ [0.0, 1.0, 0.0]) == pytest.approx(1.0)
