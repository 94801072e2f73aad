"""Mutation tests (issue 39): the window and space matching (``scene/spaces.py``) and the hosts
(``scene/hosts.py``) on hand-built scenes: a window 2 x 1 m in the middle of a 0.3 m wall (glazing in
the plane y = -0.15, x in [1, 3], z in [1, 2]), spaces drawn on either side at distances worked out by
hand. Distances are printed to the centimetre, so the hand values are exact in the messages.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from en17037cli.errors import InputError
from en17037cli.io.mesh import Part, Space
from en17037cli.scene import hosts, spaces
from en17037cli.scene.model import INTERIOR, WINDOW, LeftOut, Scene, Window


def test_how_far_reads_by_hand():
    assert spaces._how_far(-0.5) == "inside the space, 0.50 m from its boundary"
    assert spaces._how_far(0.0) == "on the space's boundary"
    assert spaces._how_far(0.204) == "0.20 m from the space"


def rect_y(x0, x1, y, z0, z1):
    """Two triangles of the rectangle [x0, x1] x [z0, z1] in the plane y."""
    a, b, c, d = (x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)
    return [[a, b, c], [a, c, d]]


def wall_with_opening(y):
    """A wall face in the plane y around the opening x in [1, 3], z in [1, 2] (x in [-1, 5], z in [0, 3])."""
    return rect_y(-1, 1, y, 0, 3) + rect_y(3, 5, y, 0, 3) + rect_y(1, 3, y, 0, 1) + rect_y(1, 3, y, 2, 3)


GLAZING = np.array(rect_y(1.0, 3.0, -0.15, 1.0, 2.0), float)


def space(name, x0, x1, y0, y1, windows=(), kind="IfcSpace", problem=""):
    return Space(name.lower(), name, "", "S", np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], float), 0.0, 3.0,
                 windows=tuple(windows), kind=kind, problem=problem)


def scene(spaces_, host=(), key="W1", other=(), frame=False):
    """The window (host and key as given), the wall's two faces around its opening (part 0, id WALL),
    ``other`` faces (part 1, id X), with ``frame`` the window's own frame (part 2, id W1) at y = -0.1,
    and the glazing (part 3)."""
    faces = [(t, 0) for t in wall_with_opening(-0.3) + wall_with_opening(0.0)] + [(t, 1) for t in other]
    faces += [(t, 2) for t in (rect_y(0.9, 3.1, -0.1, 0.9, 1.0) if frame else [])]
    faces += [(t, 3) for t in GLAZING.tolist()]
    tris = np.array([f for f, _ in faces], float)
    part = np.array([p for _, p in faces])
    parts = [Part({"id": "WALL"}), Part({"id": "X"}), Part({"id": "W1"}), Part({"id": "G"}, window="W1")]
    layer = np.where(part == 3, WINDOW, INTERIOR).astype(np.int8)
    n = len(tris)
    w = Window("W", 0, np.arange(n - 2, n), GLAZING, np.array([0.0, 1.0, 0.0]), 2.0, key=key, host=tuple(host))
    return Scene(tris.reshape(-1, 3), np.arange(3 * n).reshape(n, 3), layer, np.ones(n, bool), parts, part,
                 spaces=[("m.ifc", s) for s in spaces_], origin=np.zeros(3), windows=[w])


A = (0.0, 4.0, 0.0, 5.0)  # the room behind the wall (its face y = 0), 0.15 from the glazing


def match(s, margin=0.5):
    return spaces.match_windows(s, margin)[0]


def test_a_window_between_two_spaces_opens_into_both_or_the_named_one():
    m = match(scene([space("A", *A), space("B", 0, 4, -5, -0.3)]))
    assert [(i, n.tolist(), why) for i, n, why in m.spaces] == [
        (0, [0.0, -1.0, 0.0], "100% of its glazing 0.15 m from the space"), (1, [0.0, 1.0, 0.0], "100% of its glazing 0.15 m from the space")]
    assert m.distance == {0: pytest.approx(0.15), 1: pytest.approx(0.15)} and m.why == "" and m.note == "" and m.open_depth == {}
    m = match(scene([space("A", *A), space("B", 0, 4, -5, -0.3, windows=["W1"])]))
    assert [(i, why) for i, _, why in m.spaces] == [
        (1, "100% of its glazing 0.15 m from the space; of the 2 spaces it opens onto, the one the model's space boundaries name")]
    m = match(scene([space("A", *A, windows=["W1"])]))
    assert [why for _, _, why in m.spaces] == ["100% of its glazing 0.15 m from the space; named by the model's space boundaries too"]


def test_the_host_limits_how_far_a_space_may_lie():
    # the wall reaches 0.15 m each side of the glazing (its frame at -0.1 too): 0.3 m deep, a space within 0.15 + 0.15
    s = scene([space("A", *A), space("B", 0, 4, -5, -0.6)], host=["WALL"], frame=True)
    assert hosts.host_depths(s, s.windows[0]) == pytest.approx((0.15, 0.15))
    m = match(s)
    assert [(i, why) for i, _, why in m.spaces] == [(0, "100% of its glazing 0.15 m from the space (its host 0.30 m deep)")]
    assert m.distance == {0: pytest.approx(0.15), 1: pytest.approx(0.45)}
    # on its own, B 0.45 m away: named by the boundaries (within the margin), else through the open opening
    m = match(scene([space("B", 0, 4, -5, -0.6, windows=["W1"])], host=["WALL"]))
    assert [(i, n.tolist(), why) for i, n, why in m.spaces] == [
        (0, [0.0, 1.0, 0.0], "named by the model's space boundaries, 100% of its glazing 0.45 m from the space (its host 0.30 m deep)")]
    m = match(scene([space("B", 0, 4, -5, -0.6)], host=["WALL"]))
    assert [why for _, _, why in m.spaces] == ["100% of its glazing 0.45 m from the space (its host 0.30 m deep), with nothing "
                                               "opaque between (a light well, a deep reveal)"]
    assert m.open_depth == {0: pytest.approx(0.45)}
    # a blind of another object in the way: not open; the nearest space is named with the reason
    m = match(scene([space("B", 0, 4, -5, -0.6)], host=["WALL"], other=rect_y(0, 4, -0.4, 0, 3)))
    assert m.spaces == [] and m.why == ("the nearest space, 'B', lies 0.45 m from its glazing, more than the 0.30 m its host "
                                        "allows (its host 0.30 m deep): it opens into no space of the model")
    # a frame of the window's own element in the way does not close it
    m = match(scene([space("B", 0, 4, -5, -0.6)], host=["WALL"], other=rect_y(0, 4, -0.4, 0, 3), key="X"))
    assert m.open_depth == {0: pytest.approx(0.45)}
    # the window's own frame alone (no host named): 0.05 m behind the glazing, so a space within 0.15 + 0.05
    s = scene([space("B", 0, 4, -5, -0.3)], frame=True)
    assert hosts.host_depths(s, s.windows[0]) == pytest.approx((0.05, 0.0))
    m = match(s)
    assert [why for _, _, why in m.spaces] == ["100% of its glazing 0.15 m from the space (its host 0.05 m deep)"]


def test_far_spaces_spaces_beside_and_none():
    m = match(scene([space("B", 0, 4, -5, -1.0, windows=["W1"])]))
    assert [(i, why) for i, _, why in m.spaces] == [
        (0, "named by the model's space boundaries; the space as drawn lies 0.85 m from its glazing (its volume does not "
            "reach the window: check the room's floor and windows)")]
    m = match(scene([space("C", 5, 8, -0.15, 5, windows=["W1"])]))
    assert [(i, n.tolist()) for i, n, _ in m.spaces] == [(0, [0.0, -1.0, 0.0])]
    assert "as drawn (its volume lies 2.00 m from the window, beside the glazing's normal)" in m.spaces[0][2]
    assert m.note == ("window 'W': in 'C', the space the model's boundaries name, though no ray from its glazing enters that "
                      "space as drawn (2.00 m away); nothing else places it")
    m = match(scene([space("B", 0, 4, -5, -1.0)]))  # unnamed and beyond the margin: not even a candidate
    assert m.spaces == [] and m.why.startswith("no space of the model lies within 0.5 m of its glazing")
    m = match(scene([space("C", 5, 8, -0.15, 5)]))
    assert m.spaces == [] and m.why == ("no space of the model lies within 0.5 m of its glazing on either side (spaces missing "
                                        "from the model, or the window outside every storey's spaces)")
    assert match(scene([space("A", *A, problem="no floor")])).spaces == []


def test_a_window_over_a_space_drawn_to_its_suspended_ceiling_names_the_space_below():
    # the glazing spans z 1-2 m; the space in front of it (y 0-5) is drawn from -2 m up to 0.9 m, as a
    # space drawn up to a suspended ceiling under a clerestory: no ray from the glazing enters it, and the
    # reason names it, 1.00 - 0.90 = 0.10 m under the glazing
    low = Space("low", "Low", "", "S", np.array([(0, 0), (4, 0), (4, 5), (0, 5)], float), -2.0, 0.9)
    m = match(scene([low]))
    assert m.spaces == []
    assert m.why.startswith("its glazing starts 0.10 m above the top of the space 'Low' below it (a window over a space "
                            "drawn up to its suspended ceiling lights no room of the model); no space of the model lies "
                            "within 0.5 m of its glazing")
    # a space whose top is more than UNDER_M below, or one beside the window in plan, is not named
    deep = Space("deep", "Deep", "", "S", np.array([(0, 0), (4, 0), (4, 5), (0, 5)], float), -3.0, -1.05)
    assert match(scene([deep])).why.startswith("no space of the model")
    beside = Space("b", "Beside", "", "S", np.array([(5, 0), (8, 0), (8, 5), (5, 5)], float), -2.0, 0.9)
    assert match(scene([beside])).why.startswith("no space of the model")


def test_shares_insides_and_the_nearer_side():
    # samples on a 5 x 5 grid at x = 1.2 .. 2.8: a space over x >= 2.1 holds two columns (40 %), over x >= 2.5 one (20 %)
    m = match(scene([space("A", 2.1, 4, 0, 5)]))
    assert [why for _, _, why in m.spaces] == ["40% of its glazing 0.15 m from the space"]
    assert match(scene([space("A", 2.5, 4, 0, 5)])).spaces == []
    # a space drawn to the wall's middle: the glazing lies in it, 0.15 m from its boundary behind
    m = match(scene([space("A", 0, 4, -0.3, 5)]))
    assert [(n.tolist(), why) for _, n, why in m.spaces] == [([0.0, -1.0, 0.0], "100% of its glazing inside the space, 0.15 m from its boundary")]
    # one space on both sides (two boxes): the nearer side decides (0.10 m behind, 0.15 m in front)
    body = np.concatenate([spaces.extruded_body(np.array([(0, 0), (4, 0), (4, 5), (0, 5)], float), (), 0.0, 3.0),
                           spaces.extruded_body(np.array([(0, -5), (4, -5), (4, -0.25), (0, -0.25)], float), (), 0.0, 3.0)])
    two = Space("ab", "AB", "", "S", np.array([(0, -5), (4, -5), (4, 5), (0, 5)], float), 0.0, 3.0, body=body)
    m = match(scene([two]))
    assert [(n.tolist(), why) for _, n, why in m.spaces] == [([0.0, 1.0, 0.0], "100% of its glazing 0.10 m from the space")]


def test_extruded_body_and_ray_distances_by_hand():
    foot = np.array([(0, 0), (4, 0), (4, 3), (0, 3)], float)
    hole = np.array([(1, 1), (1, 2), (2, 2), (2, 1)], float)
    body = spaces.extruded_body(foot, (hole,), 1.0, 3.5)
    n = np.cross(body[:, 1] - body[:, 0], body[:, 2] - body[:, 0])
    area = 0.5 * np.linalg.norm(n, axis=1)
    flat = np.abs(n[:, 2]) > 0
    # floor and ceiling: (12 - 1) m2 each; sides: (14 + 4) m of outline x 2.5 m
    assert area[flat].sum() == pytest.approx(22.0) and area[~flat].sum() == pytest.approx(45.0)
    assert sorted(set(body[flat][:, :, 2].ravel().tolist())) == [1.0, 3.5]
    # a vertical ray from inside the solid part crosses the ceiling once; from inside the hole, none ahead inside
    t = spaces.ray_distances(np.array([[0.37, 2.71, 2.0], [1.5, 1.5, 2.0], [0.37, 2.71, 0.0]]), np.array([0.0, 0.0, 1.0]), body)
    assert sorted(t[0][np.isfinite(t[0])].tolist()) == [1.5] and not np.isfinite(t[1]).any()
    assert sorted(t[2][np.isfinite(t[2])].tolist()) == [1.0, 3.5]
    tri = np.array([[[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]])
    o = np.array([[0.2, 0.2, 0.0], [0.0, 0.5, 0.0], [0.6, 0.6, 0.0], [0.2, 0.2, 2.0], [0.2, 0.2, 1.0]])
    # inside; on an edge (counted); outside; behind; on the plane itself (t = 0 is not ahead)
    assert spaces.ray_distances(o, np.array([0.0, 0.0, 1.0]), tri)[:, 0].tolist() == [1.0, 1.0, np.inf, np.inf, np.inf]
    assert spaces.ray_distances(o[:1], np.array([1.0, 0.0, 0.0]), tri)[0, 0] == np.inf  # parallel to it


def test_glazing_samples_lie_on_the_panes_mean_plane():
    w = Window("W", 0, np.arange(2), GLAZING, np.array([0.0, 1.0, 0.0]), 2.0)
    s = spaces.glazing_samples(w)
    assert s.shape == (25, 3) and np.allclose(s[:, 1], -0.15)
    assert sorted(set(np.round(s[:, 0], 9).tolist())) == [1.2, 1.6, 2.0, 2.4, 2.8]
    assert sorted(set(np.round(s[:, 2], 9).tolist())) == [1.1, 1.3, 1.5, 1.7, 1.9]
    stepped = np.array(rect_y(1.0, 2.0, 0.0, 1.0, 2.0) + rect_y(2.0, 3.0, 0.1, 1.0, 2.0), float)
    w = Window("W", 0, np.arange(4), stepped, np.array([0.0, 1.0, 0.0]), 2.0)
    assert np.allclose(spaces.glazing_samples(w, 3)[:, 1], 0.05)  # the vertices' mean plane


def test_names_of_spaces():
    s = [Space("g1", "R1", "Kitchen", "S", np.zeros((3, 2)), 0, 3), Space("g2", "R1", "Kitchen", "S", np.zeros((3, 2)), 0, 3),
         Space("g3", "", "Hall", "S", np.zeros((3, 2)), 0, 3), Space("g4", "", "", "S", np.zeros((3, 2)), 0, 3),
         Space("g5", "B2", "", "S", np.zeros((3, 2)), 0, 3)]
    assert [spaces.room_name(x) for x in s] == ["Kitchen (R1)", "Kitchen (R1)", "Hall", "g4", "B2"]
    assert spaces.space_names(SimpleNamespace(spaces=[("f", x) for x in s])) == [
        "Kitchen (R1) [g1]", "Kitchen (R1) [g2]", "Hall", "g4", "B2"]


def test_rooms_from_spaces_errors_and_spaces_left_out():
    spec = SimpleNamespace(gbxml_spaces=None, ifc_spaces="Room*", windows=None, window_margin_m=0.5, index=3)
    s = scene([space("A", *A, kind="gbXML Space")])
    with pytest.raises(InputError, match=r"^rooms\[3\]\.ifc_spaces: the model has no IfcSpace; make a room of every region"):
        spaces.rooms_from_spaces(s, spec, "rooms[3]")
    s = scene([space("A", *A), space("B", 0, 4, -5, -0.3)])
    with pytest.raises(InputError, match=r"^rooms\[3\]\.ifc_spaces: 'Room\*' matches no IfcSpace; spaces: A, B$"):
        spaces.rooms_from_spaces(s, spec, "rooms[3]")
    g = SimpleNamespace(gbxml_spaces="*", ifc_spaces=None, windows=None, window_margin_m=0.5, index=0)
    s = scene([space("A", *A, kind="gbXML Space", problem="no outline", windows=["W1"]), space("C", 5, 8, 6, 9, kind="gbXML Space")])
    assert spaces.rooms_from_spaces(s, g, "rooms[0]") == []
    assert s.left_out == [LeftOut("A", "the space has no floor (no outline)", ("W",)), LeftOut("C", "no window opens into it")]
    s = scene([space("A", *A, kind="gbXML Space")])
    g.windows = ["X*"]
    assert spaces.rooms_from_spaces(s, g, "rooms[0]") == []
    assert s.left_out == [LeftOut("A", "none of its 1 window(s) matches rooms[0].windows")]


def test_windows_in_no_room_say_why():
    w = [Window(n, k, np.arange(2), GLAZING, np.array([0.0, 1.0, 0.0]), 2.0) for k, n in enumerate("PQRS")]
    m = [spaces.WindowSpaces(spaces=[(0, None, "")]), spaces.WindowSpaces(why="too far"),
         spaces.WindowSpaces(spaces=[(1, None, "")]), spaces.WindowSpaces(spaces=[(2, None, "")])]
    s = SimpleNamespace(windows=w, rooms=[SimpleNamespace(windows=[w[0]])], left_out=[LeftOut("B", "no floor")],
                        space_windows=m, spaces=[("f", space("A", *A)), ("f", space("B", *A)), ("f", space("C", *A))])
    assert spaces.windows_in_no_room(s) == [("Q", "too far"), ("R", "it opens into 'B': 'B' is left out (no floor)"),
                                            ("S", "it opens into 'C': no rooms[] entry picks 'C'")]
    s.space_windows = None
    assert spaces.windows_in_no_room(s)[0] == ("Q", "it bounds no room of the project")


# --- hosts.py -------------------------------------------------------------------------------------


def test_host_faces_parallel_near_and_the_windows_own():
    s = scene([], host=["WALL"], other=rect_y(0, 4, -0.4, 0, 3) + [[(1, -0.2, 1), (1, -0.1, 1), (1, -0.1, 2)]], frame=True)
    w = s.windows[0]
    faces = hosts.host_faces(s, w)
    # the wall's 16 faces and the window's own frame (2), not the other object's
    assert sorted(set(s.part[faces].tolist())) == [0, 2] and len(faces) == 18
    assert hosts.reveal_depth_from_host(s, w, np.array([2.0, -0.15, 1.5]), 1.0) == pytest.approx(0.15)
    # the room-side face at y = 0 is 0.15 behind the glazing along -n... for a normal pointing out of the room (-y)
    out = Window("W", 0, w.face_ids, GLAZING, np.array([0.0, -1.0, 0.0]), 2.0, key="W1", host=("WALL",))
    assert hosts.reveal_depth_from_host(s, out, np.array([2.0, -0.15, 1.5]), 1.0) == pytest.approx(0.15)
    assert hosts.reveal_depth_from_host(s, out, np.array([2.0, -0.15, 1.5]), 0.1) == 0.0  # deeper than allowed
    assert hosts.host_depths(s, out) == pytest.approx((0.15, 0.15))
    # no host, no key: nothing; a host with no faces near the glazing: None
    bare = Window("W", 0, w.face_ids, GLAZING, w.normal, 2.0)
    assert len(hosts.host_faces(s, bare)) == 0 and hosts.host_depths(s, bare) is None
    assert hosts.reveal_depth_from_host(s, bare, np.zeros(3), 1.0) is None
    far = Window("W", 0, w.face_ids, GLAZING + [0.0, 0.0, 10.0], w.normal, 2.0, host=("WALL",))
    assert len(hosts.host_faces(s, far)) == 0 and hosts.reveal_depth_from_host(s, far, np.zeros(3), 1.0) is None
    ghost = Window("W", 0, w.face_ids, GLAZING, w.normal, 2.0, host=("NOTHING",))
    assert len(hosts.host_faces(s, ghost)) == 0


def test_host_faces_within_reach_of_the_glazing_only():
    # the host's faces count within 0.3 m of the glazing's box along it and 1.5 m across it (+ 0.3)
    s = scene([], host=["X"], other=rect_y(3.25, 4, -1.9, 1, 2) + rect_y(3.35, 4, -1.0, 1, 2) + rect_y(1, 3, -2.0, 1, 2))
    faces = hosts.host_faces(s, s.windows[0])
    assert s.part[faces].tolist() == [1, 1] and faces.tolist() == [16, 17]  # the first face only: the others too far
    w = Window("W", 0, s.windows[0].face_ids, GLAZING, np.array([0.0, 1.0, 0.0]), 2.0, host=("X",))
    assert hosts.host_depths(s, w) == pytest.approx((0.0, 1.75))


def test_host_pieces_of_an_assembly_count_and_faces_at_an_angle_do_not():
    tilt = [[(1, -0.5, 1), (3, -0.5, 1), (3, -0.5 + 0.2, 2)]]  # 11 deg off the glazing's plane
    s = scene([], other=tilt + [[(1, -0.6, 1), (3, -0.6, 1), (3, -0.55, 2)]])
    s.parts[1] = Part({"id": "X"}, assembly="CW")
    w = Window("W", 0, s.windows[0].face_ids, GLAZING, np.array([0.0, 1.0, 0.0]), 2.0, host=("CW",))
    assert hosts.host_faces(s, w).tolist() == [16, 17]
    assert hosts.host_depths(s, w) == pytest.approx((0.0, 0.6 - 0.15))
