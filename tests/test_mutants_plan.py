"""Mutation tests (issue 39): the exact plan sight angle (``criteria/view/plan.py``), piece by piece
against hand plans, closed forms and brute force (dense sampling of directions).
"""
from __future__ import annotations

import copy
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

from en17037cli.criteria.view import plan

TWO_PI = 2 * np.pi
U = 2.0**-53  # unit round-off of float64


# --- interval arithmetic on the circle, by hand ---------------------------------------------------


def test_arcs_by_hand():
    p = np.zeros((5, 2))
    a = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, -1.0], [2.0, 0.0], [1.0, -1e-300]])
    b = np.array([[0.0, 1.0], [1.0, 0.0], [1.0, 1.0], [-3.0, 0.0001], [1.0, 1.0]])
    start, end, r = plan.arcs(p, a, b)
    # a quarter turn either way round is [0, pi/2]; one across azimuth 0 is [7 pi/4, pi/4]; a segment
    # from azimuth 0 to just under pi (a turn of +pi - 3.3e-5) runs counter-clockwise from 0
    want_end3 = np.arctan2(0.0001, -3.0)
    assert start.tolist() == pytest.approx([0.0, 0.0, 7 * np.pi / 4, 0.0, 0.0], abs=1e-15)
    assert end.tolist() == pytest.approx([np.pi / 2, np.pi / 2, np.pi / 4, want_end3, np.pi / 4], abs=1e-15)
    # r: the distance to the nearer end
    assert r.tolist() == pytest.approx([1.0, 1.0, np.sqrt(2), 2.0, 1.0], abs=1e-15)
    # an end a hair below azimuth 0 wraps to 2 pi - 1e-300 = 2 pi in float64: it is given as 0, in [0, 2 pi)
    assert start[4] == 0.0
    s, e, _ = plan.arcs(np.zeros((1, 2)), np.array([[1.0, 1.0]]), np.array([[1.0, -1e-300]]))
    assert s[0] == pytest.approx(0.0, abs=0) and e[0] == pytest.approx(np.pi / 4)
    s, e, _ = plan.arcs(np.zeros((1, 2)), np.array([[0.0, -1.0]]), np.array([[1.0, -1e-300]]))
    assert s[0] == pytest.approx(3 * np.pi / 2) and e[0] == 0.0  # the end at 2 pi is 0 too
    # seen from another point: the offsets count, not the coordinates
    s, e, r = plan.arcs(np.array([[10.0, 20.0]]), np.array([[13.0, 24.0]]), np.array([[10.0, 25.0]]))
    assert (s[0], e[0], r[0]) == pytest.approx((np.arctan2(4, 3), np.pi / 2, 5.0))


def test_split_wrap_by_hand():
    pt = np.array([0, 1, 2, 3, 4])
    start = np.array([1.0, 5.0, 2.0, 5.0, 6.0])
    end = np.array([2.0, 1.0, 2.0, 0.0, 5.5])
    extra = np.array([10, 11, 12, 13, 14])
    p_, lo, hi, x = plan.split_wrap(pt, start, end, extra)
    # 2 is empty (dropped); 1, 3 and 4 cross azimuth 0: [5, 2 pi] + [0, 1], [5, 2 pi] (+ [0, 0], dropped),
    # [6, 2 pi] + [0, 5.5]; the second pieces after all the first ones
    assert p_.tolist() == [0, 1, 3, 4, 1, 4]
    assert lo.tolist() == [1.0, 5.0, 5.0, 6.0, 0.0, 0.0]
    assert hi.tolist() == [2.0, TWO_PI, TWO_PI, TWO_PI, 1.0, 5.5]
    assert x.tolist() == [10, 11, 13, 14, 11, 14]
    p_, lo, hi = plan.split_wrap(pt[:1], start[:1], end[:1])  # no extra arrays
    assert (p_.tolist(), lo.tolist(), hi.tolist()) == ([0], [1.0], [2.0])


def test_sweep_by_hand():
    # point 0: covers [0, 3] and [2, 5], cut by [1, 2.5]: [0, 1] and [2.5, 5]
    # point 1: covered and cut by the same [1, 2]: nothing
    # point 2: [0, 1] and [1, 2] touch: one piece [0, 2]
    # point 3: [0, 2] cut by [0, 1] and [1, 2]: nothing (no piece of zero length either)
    # point 4: a cut alone: nothing; point 5: two disjoint covers, [0.5, 1] and [3, 4]
    rows = [(0, 0.0, 3.0, 0), (0, 2.0, 5.0, 0), (0, 1.0, 2.5, 1),
            (1, 1.0, 2.0, 0), (1, 1.0, 2.0, 1),
            (2, 0.0, 1.0, 0), (2, 1.0, 2.0, 0),
            (3, 0.0, 2.0, 0), (3, 0.0, 1.0, 1), (3, 1.0, 2.0, 1),
            (4, 0.0, 6.0, 1), (5, 3.0, 4.0, 0), (5, 0.5, 1.0, 0)]
    pt, lo, hi, kind = (np.array(c) for c in zip(*rows))
    p_, lo_, hi_ = plan.sweep(pt, lo.astype(float), hi.astype(float), kind)
    assert list(zip(p_.tolist(), lo_.tolist(), hi_.tolist())) == [
        (0, 0.0, 1.0), (0, 2.5, 5.0), (2, 0.0, 2.0), (5, 0.5, 1.0), (5, 3.0, 4.0)]
    assert p_.dtype == np.int64
    empty = plan.sweep(np.zeros(0, np.int64), np.zeros(0), np.zeros(0), np.zeros(0, np.int64))
    assert [x.shape for x in empty] == [(0,), (0,), (0,)] and empty[0].dtype == np.int64


def test_union_by_hand():
    p_, lo, hi = plan.union(np.array([1, 0, 1, 0]), np.array([0.0, 1.0, 0.5, 4.0]), np.array([1.0, 2.0, 2.0, 5.0]))
    assert list(zip(p_.tolist(), lo.tolist(), hi.tolist())) == [(0, 1.0, 2.0), (0, 4.0, 5.0), (1, 0.0, 2.0)]


def test_float_bound_by_hand():
    # 2 n (16 u s / r + 8 u pi), r below 1e-6 m taken as 1e-6, an infinite r (no interval) as 1 m
    n = np.array([0, 1, 3, 2, 1])
    r = np.array([1.0, 0.5, 1e-9, np.inf, 2e-6])
    got = plan.float_bound(n, r, 20.0)
    per_end = 16 * U * 20.0 / np.array([1.0, 0.5, 1e-6, 1.0, 2e-6]) + 8 * U * np.pi
    assert got.tolist() == pytest.approx((2 * n * per_end).tolist(), rel=1e-12, abs=0)
    assert got[1] == pytest.approx(2 * (640 * U + 8 * U * np.pi), rel=1e-12, abs=0)


# --- a box room's window (en17037cli.samples.BoxRoom): glazing x in [-1, 1] in y = 0, the room at y > 0 ---
# Local frame: the scene's origin is (0, 0, 1.5), so the glazing spans z in [-0.7, 0.7] and local z = 0 is
# the window's mid-height; the window's outward normal is -y. Azimuths from a point (x0, y0) by atan2.


@pytest.fixture(scope="module")
def box(tmp_path_factory):
    from en17037cli.samples import BoxRoom, box_room_project
    from tests.conftest import Built

    made = []

    def _box(**kw):
        b = Built(box_room_project(tmp_path_factory.mktemp("plan"), BoxRoom(**kw)))
        made.append(b)
        return b

    yield _box
    for b in made:
        b.engine.close()


def _az(x, y, x0, y0):
    return float(np.arctan2(y - y0, x - x0) % TWO_PI)


def _geometry(b, depth=0.5):
    from en17037cli.criteria.view.frames import room_geometry

    return room_geometry(b.scene, b.room, depth)


def _fin(x, y0, y1):
    """A vertical triangle in the plane x whose cut at z = 0 is exactly the segment (x, y0)-(x, y1)."""
    return [[x, y0, -1.0], [x, y0 + 2 * (y1 - y0), -1.0], [x, y0, 1.0]]


def _per_point(pt, lo, hi, n):
    """The union of the pieces per point, as lists of (lo, hi)."""
    p_, l_, h_ = plan.union(pt, lo, hi)
    return [np.column_stack([l_[p_ == i], h_[p_ == i]]).ravel().tolist() for i in range(n)]


def _flat(pairs):
    return [x for pair in pairs for x in pair]


def test_window_arcs_of_a_box_window(box):
    rg = _geometry(box())
    # (0, 1) at mid-height sees the glazing's cut from (-1, 0) to (1, 0); (0.5, 2): its own; behind the
    # window's plane (0, -1) and above the glazing (z = 1.0 > 0.7) nothing
    pts = np.array([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.5, 2.0, 0.0], [0.0, 1.0, 1.0]])
    pt, win, lo, hi, r = plan.window_arcs(rg, pts)
    assert set(win.tolist()) == {0}
    got = _per_point(pt, lo, hi, 4)
    assert got[0] == pytest.approx(_flat([(5 * np.pi / 4, 7 * np.pi / 4)]), abs=1e-14)
    assert got[1] == [] and got[3] == []
    assert got[2] == pytest.approx(_flat([(_az(-1, 0, 0.5, 2.0), _az(1, 0, 0.5, 2.0))]), abs=1e-14)
    # each triangle's cut ends at the glazing's edge and on its diagonal, which crosses z = 0 at x = 0
    # (either diagonal of the rectangle): from (0, 1) the nearer end is (0, 0), 1 m away; from (0.5, 2)
    # the nearer end of each piece is (0, 0) too, sqrt(0.25 + 4) m
    assert r[pt == 0].tolist() == pytest.approx([1.0, 1.0]) and r[pt == 2].tolist() == pytest.approx([np.sqrt(4.25)] * 2)


def test_window_arcs_keep_a_point_just_in_front_and_drop_one_on_the_plane(box):
    from en17037cli.criteria.view.gnomonic import MIN_PLANE_DISTANCE_M

    rg = _geometry(box())
    d = MIN_PLANE_DISTANCE_M
    pts = np.array([[0.0, 2 * d, 0.0], [0.0, d, 0.0], [0.0, 0.5 * d, 0.0]])
    pt, _, lo, hi, _ = plan.window_arcs(rg, pts)
    assert sorted(set(pt.tolist())) == [0]  # in front by more than MIN_PLANE_DISTANCE_M only


def test_shadow_arcs_split_at_the_windows_line_by_hand(box):
    """From (0, 1) at mid-height: a fin at x = 0.5 wholly beyond the glazing's line (y from -0.5 to -0.2)
    casts a shadow only when ``interior``; a fin at x = -0.5 across the line (y from 0.3 to -0.3) blocks
    with its part on the room's side whatever its layer, and with its part beyond when ``interior``."""
    from en17037cli.scene.model import INTERIOR, LANDSCAPE

    rg = _geometry(box())
    pts = np.array([[0.0, 1.0, 0.0]])
    tri = np.array([_fin(0.5, -0.5, -0.2), _fin(-0.5, 0.3, -0.3)])
    beyond = (_az(0.5, -0.5, 0, 1), _az(0.5, -0.2, 0, 1))
    inner = (_az(-0.5, 0.3, 0, 1), _az(-0.5, 0.0, 0, 1))
    whole = (_az(-0.5, 0.3, 0, 1), _az(-0.5, -0.3, 0, 1))
    pt, win, lo, hi, r = plan.shadow_arcs(rg, pts, tri, np.array([INTERIOR, INTERIOR]))
    assert set(win.tolist()) == {0} and set(pt.tolist()) == {0}
    assert _per_point(pt, lo, hi, 1)[0] == pytest.approx(_flat([whole, beyond]), abs=1e-14)
    # r: each piece's nearer end: (-0.5, 0.3) and the crossing (-0.5, 0) for the two parts of the second
    # fin, (0.5, -0.2) for the first
    assert sorted(r.tolist()) == pytest.approx(sorted([np.hypot(0.5, 0.7), np.hypot(0.5, 1.0), np.hypot(0.5, 1.2)]))
    pt, win, lo, hi, r = plan.shadow_arcs(rg, pts, tri, np.array([LANDSCAPE, LANDSCAPE]))
    assert _per_point(pt, lo, hi, 1)[0] == pytest.approx(_flat([inner]), abs=1e-14)
    assert r.tolist() == pytest.approx([np.hypot(0.5, 0.7)])
    # the fin the other way round (from beyond to the room's side) is the same
    tri2 = np.array([_fin(-0.5, -0.3, 0.3)])
    pt, _, lo, hi, _ = plan.shadow_arcs(rg, pts, tri2, np.array([LANDSCAPE]))
    assert _per_point(pt, lo, hi, 1)[0] == pytest.approx(_flat([inner]), abs=1e-14)
    pt, _, lo, hi, _ = plan.shadow_arcs(rg, pts, tri2, np.array([INTERIOR]))
    assert _per_point(pt, lo, hi, 1)[0] == pytest.approx(_flat([whole]), abs=1e-14)
    # an opaque segment lying in the glazing's line, (0.2, 0)-(0.6, 0), is on the room's side: it blocks
    # whatever its layer; with a mullion-like plate parallel to the line (0.02 m inside), no warning of a
    # division by zero (0 / 0 in the line, x / 0 parallel to it) reaches the user
    in_line = np.array([[[0.2, 0.0, -1.0], [1.0, 0.0, -1.0], [0.2, 0.0, 1.0]],
                        [[-0.3, 0.02, -1.0], [-0.1, 0.02, -1.0], [-0.3, 0.02, 1.0]]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pt, _, lo, hi, _ = plan.shadow_arcs(rg, pts, in_line, np.array([LANDSCAPE, LANDSCAPE]))
    plate = (_az(-0.3, 0.02, 0, 1), _az(-0.2, 0.02, 0, 1))
    assert _per_point(pt, lo, hi, 1)[0] == pytest.approx(_flat([plate, (_az(0.2, 0.0, 0, 1), _az(0.6, 0.0, 0, 1))]), abs=1e-14)
    # a room without windows: empty arrays of the right types
    out = plan.shadow_arcs(SimpleNamespace(frames=[]), pts, tri, np.array([INTERIOR, INTERIOR]))
    assert [x.shape for x in out] == [(0,)] * 5 and [x.dtype for x in out] == [np.int64, np.int64, float, float, float]
    # nothing cut at the point's height: empty arrays of the right types
    out = plan.shadow_arcs(rg, np.array([[0.0, 1.0, 5.0]]), tri, np.array([INTERIOR, INTERIOR]))
    assert [x.shape for x in out] == [(0,)] * 5 and out[0].dtype == np.int64 and out[1].dtype == np.int64


def test_visible_intervals_of_a_box_room_by_hand(box):
    """A wall 0.3 m thick (reveals from y = 0 to 0.3) and a 50 mm mullion at x = 0.3, 0.02 m inside the
    glazing: from (0, 1.3) at mid-height the view is the window between its tighter jamb edges, minus the
    mullion's shadow (the closed form of tests/reference/test_sight_angle_plan.py)."""
    b = box(wall_thickness=0.3, mullions=(0.3,))
    rg = _geometry(b)
    x0, y0 = 0.0, 1.3
    pts = np.array([[x0, y0, 0.0], [x0, y0, 5.0]])  # the second above the room: nothing
    pt, lo, hi, faces, bound = plan.visible_intervals(b.scene, rg, pts, 0.5)
    left = max(_az(-1.0, 0.3, x0, y0), _az(-1.0, 0.0, x0, y0))  # the tighter jamb edges (here the outer ones)
    right = min(_az(1.0, 0.3, x0, y0), _az(1.0, 0.0, x0, y0))
    assert left == _az(-1.0, 0.0, x0, y0) and right == _az(1.0, 0.0, x0, y0)
    m0, m1 = _az(0.275, 0.02, x0, y0), _az(0.325, 0.02, x0, y0)
    assert pt.tolist() == [0, 0]
    assert np.column_stack([lo, hi]).ravel().tolist() == pytest.approx(_flat([(left, m0), (m1, right)]), abs=1e-13)
    # the bound: 2 pieces; the nearest end of any interval is where the glazing's diagonal crosses z = 0,
    # (0, 0), 1.3 m away (the mullion's diagonal crosses at (0.3, 0.02), 1.31 m; every other cut end is
    # further); the largest coordinate that of the faces that took part
    assert bound[1] == 0.0
    r = 1.3
    scale = max(np.abs(b.scene.vertices[b.scene.triangles[faces]][..., :2]).max(), 1.3)
    assert bound[0] == pytest.approx(2 * 2 * (16 * U * scale / r + 8 * U * np.pi), rel=1e-12, abs=0)
    # mullions_block False leaves the mullion (a member inside the opening) out
    pt, lo, hi, faces2, _ = plan.visible_intervals(b.scene, rg, pts, 0.5, members_block=False)
    assert faces2.tolist() == faces.tolist()
    assert pt.tolist() == [0] and [lo[0], hi[0]] == pytest.approx([left, right], abs=1e-13)


def _faces_where(b, pred):
    """Opaque faces whose corners (k, 3, 3) [m] satisfy ``pred``."""
    from en17037cli.scene.model import WINDOW

    faces = np.flatnonzero(b.scene.layer != WINDOW)
    corners = b.scene.vertices[b.scene.triangles[faces]]
    return faces[[bool(pred(c)) for c in corners]]


def test_near_faces_by_hand(box):
    """Points (0, 1) and (1.5, 0.8) at mid-height, the box room without reveals (local z = 0 is world 1.5 m):
    with a margin of 0.2 m the box is x in [-1.2, 1.7], y in [-0.2, 1.2], z = 0: only the two pieces of the
    facade beside the window (x <= -1 and x >= 1 in y = 0, from floor to ceiling) meet it. With 0.5 m
    (x up to 2.0) the east wall x = 2 comes in; from higher points (z = 1, world 2.5) the piece above the
    window (z from 2.2 to 3) too."""
    b = box()
    rg = _geometry(b)
    pts = np.array([[0.0, 1.0, 0.0], [1.5, 0.8, 0.0]])
    beside = _faces_where(b, lambda c: np.all(c[:, 1] == 0) and (np.all(c[:, 0] >= 1) or np.all(c[:, 0] <= -1)))
    east = _faces_where(b, lambda c: np.all(c[:, 0] == 2.0))
    above = _faces_where(b, lambda c: np.all(c[:, 1] == 0) and np.all(c[:, 2] >= 0.7) and np.all(np.abs(c[:, 0]) <= 1))
    assert len(beside) == 4 and len(east) == 2 and len(above) == 2
    assert sorted(plan.near_faces(b.scene, rg, pts, 0.2).tolist()) == sorted(beside.tolist())
    assert sorted(plan.near_faces(b.scene, rg, pts, 0.5).tolist()) == sorted(np.r_[beside, east].tolist())
    high = pts + [0.0, 0.0, 1.0]
    assert sorted(plan.near_faces(b.scene, rg, np.r_[pts, high], 0.2).tolist()) == sorted(np.r_[beside, above].tolist())
    # a point far out in the street widens the box over the ground, but the ground lies at z = -1.5, below it
    far = np.array([[-30.0, -30.0, 0.0]])
    got = plan.near_faces(b.scene, rg, far, 0.0)
    assert not np.isin(_faces_where(b, lambda c: np.all(c[:, 2] == -1.5)), got).any()


def test_face_boxes_round_outwards_and_are_kept_per_scene(box):
    b = box(wall_thickness=0.3)  # 0.3 m is no float32: the boxes must still hold every corner
    faces, lo, hi = plan.face_boxes(b.scene)
    from en17037cli.scene.model import WINDOW

    assert faces.tolist() == np.flatnonzero(b.scene.layer != WINDOW).tolist()
    corners = b.scene.vertices[b.scene.triangles[faces]]  # (f, 3, 3) float64
    assert lo.dtype == hi.dtype == np.float32 and lo.shape == (3, len(faces)) and hi.shape == (3, len(faces))
    assert np.all(lo.astype(float) < corners.min(axis=1).T) and np.all(hi.astype(float) > corners.max(axis=1).T)
    # by at most 2 float32 ulps (one to round to float32, one outwards)
    span = np.spacing(np.abs(corners).max(axis=1).T.astype(np.float32)).astype(float)
    assert np.all(corners.min(axis=1).T - lo <= 2 * span) and np.all(hi - corners.max(axis=1).T <= 2 * span)
    assert plan.face_boxes(b.scene)[1] is lo  # computed once per scene


def test_opening_members_by_hand(box):
    """The mullion plate (0.02 m inside the glazing, over the opening) is a member; the reveals and the
    facade around the opening lie on the outline's edge or outside it and are not. Within 0.01 m of the
    window's plane the mullion is not near enough; at exactly 0.02 m it is."""
    b = box(wall_thickness=0.3, mullions=(0.3,))
    rg = _geometry(b)
    from en17037cli.scene.model import WINDOW

    faces = np.flatnonzero(b.scene.layer != WINDOW)
    mullion = _faces_where(b, lambda c: np.all(c[:, 1] == 0.02))
    assert len(mullion) == 2
    assert faces[plan.opening_members(b.scene, rg, faces, 0.5)].tolist() == sorted(mullion.tolist())
    assert faces[plan.opening_members(b.scene, rg, faces, 0.02)].tolist() == sorted(mullion.tolist())
    assert not plan.opening_members(b.scene, rg, faces, 0.01).any()
    assert plan.opening_members(b.scene, rg, faces[:0], 0.5).shape == (0,)


def test_visible_intervals_in_blocks_are_those_of_the_whole(box, monkeypatch):
    """Points at two heights split into blocks (by MAX_PAIRS / POINT_BLOCK, or by MAX_CUTS): the same
    pieces, with each block's point numbers shifted back to the whole's, and the same bounds."""
    b = box(wall_thickness=0.3, mullions=(-0.35, 0.35))
    rg = _geometry(b)
    xs = np.array([-1.5, -0.6, 0.0, 0.4, 1.1, 1.7, 0.2])
    pts = np.column_stack([xs, 0.5 + 0.6 * np.arange(7), np.where(np.arange(7) % 2, 0.3, -0.2)])
    whole = plan.visible_intervals(b.scene, rg, pts, 0.5)
    assert sorted(set(whole[0].tolist())) == list(range(7))  # every point sees out
    monkeypatch.setattr(plan, "MAX_PAIRS", 0)
    monkeypatch.setattr(plan, "POINT_BLOCK", 3)
    blocks = plan.visible_intervals(b.scene, rg, pts, 0.5)
    monkeypatch.setattr(plan, "MAX_PAIRS", 10**9)
    n_faces = len(whole[3])
    monkeypatch.setattr(plan, "MAX_CUTS", 2 * max(n_faces, len(rg.triangles)))  # 2 heights x faces > MAX_CUTS
    cuts = plan.visible_intervals(b.scene, rg, pts, 0.5)
    for got in (blocks, cuts):
        assert got[0].tolist() == whole[0].tolist()
        assert got[1].tolist() == whole[1].tolist() and got[2].tolist() == whole[2].tolist()
        assert got[3].tolist() == whole[3].tolist()
        assert got[4].tolist() == pytest.approx(whole[4].tolist(), rel=1e-12, abs=0)


class _Scene:
    """The attributes of a scene that face_boxes, near_faces and opening_members read (weakly referable)."""

    def __init__(self, tris):
        tris = np.asarray(tris, float)
        self.vertices = tris.reshape(-1, 3)
        self.triangles = np.arange(len(self.vertices)).reshape(-1, 3)
        self.layer = np.ones(len(tris), np.int8)  # interior: opaque


def test_face_boxes_of_triangles_whose_corners_are_each_the_extreme():
    # each corner in turn the lowest and the highest on some axis
    tris = [[[0.1, 5.3, 2.2], [1.3, 0.7, 9.1], [4.9, 2.9, 0.3]],
            [[7.7, 0.3, 5.5], [0.2, 8.8, 1.1], [3.3, 4.4, 9.9]],
            [[2.5, 1.5, 0.5], [9.5, 3.5, 7.5], [0.5, 0.25, 8.5]]]
    faces, lo, hi = plan.face_boxes(_Scene(tris))
    c = np.array(tris)
    assert faces.tolist() == [0, 1, 2]
    want_lo = np.nextafter(c.min(axis=1).T.astype(np.float32), np.float32(-np.inf))
    want_hi = np.nextafter(c.max(axis=1).T.astype(np.float32), np.float32(np.inf))
    assert lo.dtype == np.float32 and hi.dtype == np.float32
    assert lo.tolist() == want_lo.tolist() and hi.tolist() == want_hi.tolist()


def test_face_boxes_cache_keeps_live_scenes_and_drops_gone_ones():
    import gc

    a, b = _Scene([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]), _Scene([[[0, 0, 1], [1, 0, 1], [0, 1, 1]]])
    la, lb = plan.face_boxes(a)[1], plan.face_boxes(b)[1]
    assert plan.face_boxes(a)[1] is la and plan.face_boxes(b)[1] is lb  # both kept
    assert la[2, 0] < 0 < lb[2, 0]  # and each its own
    c = _Scene([[[0, 0, 2], [1, 0, 2], [0, 1, 2]]])
    plan.face_boxes(c)
    key = id(c)
    del c
    gc.collect()
    plan.face_boxes(a)  # a hit: no clean-up yet
    plan.face_boxes(_Scene([[[0, 0, 3], [1, 0, 3], [0, 1, 3]]]))  # a miss cleans up the scenes gone
    assert key not in plan._FACE_BOXES or plan._FACE_BOXES[key][0]() is not None


def _up(v):
    return float(np.nextafter(np.float32(v), np.float32(np.inf)))


def _down(v):
    return float(np.nextafter(np.float32(v), np.float32(-np.inf)))


def test_near_faces_touching_the_box_are_in():
    """Window cut x in [1, 2] (y = 1), one point (1.5, 1.5) at z = 1.25, no margin: the box is x in [1, 2],
    y in [1, 1.5], z = 1.25. A face whose box, rounded outwards to float32, touches it on one side is in;
    one a float32 step further is out."""
    window = SimpleNamespace(triangles=np.array([[[1.0, 1.0, 1.0], [2.0, 1.0, 1.0], [1.0, 1.0, 2.0]]]))
    pts = np.array([[1.5, 1.5, 1.25]])
    east, west, north, south, above, below = _up(2.0), _down(1.0), _up(1.5), _down(1.0), _up(1.25), _down(1.25)
    tris = [[[east, 1.2, 1.0], [3.0, 1.2, 1.5], [east, 1.3, 1.5]],        # 0: east, touching x = 2
            [[0.0, 1.2, 1.0], [west, 1.2, 1.5], [west, 1.3, 1.5]],        # 1: west, touching x = 1
            [[1.2, north, 1.0], [1.3, 3.0, 1.5], [1.2, north, 1.5]],      # 2: north, touching y = 1.5
            [[1.2, 0.0, 1.0], [1.3, south, 1.5], [1.2, south, 1.5]],      # 3: south, touching y = 1
            [[1.2, 1.2, above], [1.3, 1.2, 3.0], [1.2, 1.3, above]],      # 4: above, touching z = 1.25
            [[1.2, 1.2, 0.0], [1.3, 1.2, below], [1.2, 1.3, below]],      # 5: below, touching z = 1.25
            [[_up(east), 1.2, 1.0], [3.0, 1.2, 1.5], [_up(east), 1.3, 1.5]]]  # 6: east, one step off
    assert sorted(plan.near_faces(_Scene(tris), window, pts, 0.0).tolist()) == [0, 1, 2, 3, 4, 5]


def test_opening_members_by_hand_off_the_origin(box):
    """Faces of our own 0.02 m inside the box's glazing (x in [-1, 1], local z in [-0.7, 0.7]): a plate over
    the opening's edge whose centroid lies outside it, a triangle enclosing the whole opening (no edge
    over it), a plate wholly beside the opening, a reveal in the jamb's plane (on the outline's edge), and
    a plate 0.3 m in front of it. Then the same with the window's frame and the faces moved 3 m along the
    window (the frame's origin off the local origin)."""
    rg = _geometry(box())
    f = rg.frames[0]
    y = 0.02
    z0, z1 = -0.7, 0.7
    tris = np.array([[[0.95, y, z0], [1.7, y, z0], [1.7, y, z1]],        # 0: edge plate, centroid x = 1.45
                     [[-4.0, y, -3.0], [4.0, y, -3.0], [0.0, y, 5.0]],    # 1: encloses the opening
                     [[1.1, y, z0], [1.5, y, z0], [1.5, y, z1]],          # 2: beside
                     [[1.0, 0.0, z0], [1.0, 0.3, z0], [1.0, 0.3, z1]],    # 3: the jamb's reveal
                     [[-0.2, 0.3, z0], [0.2, 0.3, z0], [0.2, 0.3, z1]]])  # 4: over the opening, 0.3 m in
    want = [True, True, False, False, False]
    for shift in (0.0, 3.0):
        moved = copy.copy(f)
        moved.origin = f.origin + shift * f.u
        rg1 = SimpleNamespace(frames=[moved])
        scene = _Scene(tris + shift * f.u)
        assert plan.opening_members(scene, rg1, np.arange(5), 0.1).tolist() == want
        assert plan.opening_members(scene, rg1, np.array([0]), 0.1).tolist() == [True]  # a single face
        assert plan.opening_members(scene, rg1, np.array([4]), 0.3).tolist() == [True]  # within 0.3 m
    # a room whose first window is far from every face: the next one still counts
    far = copy.copy(f)
    far.origin = f.origin + 10.0 * f.n
    two = SimpleNamespace(frames=[far, f])
    assert plan.opening_members(_Scene(tris), two, np.arange(5), 0.1).tolist() == want
    # and a second window in the same plane 5 m along: the faces lie near it but are none of its members,
    # which leaves them members of the first
    beside = copy.copy(f)
    beside.origin = f.origin + 5.0 * f.u
    two = SimpleNamespace(frames=[f, beside])
    assert plan.opening_members(_Scene(tris), two, np.arange(5), 0.1).tolist() == want


def test_visible_intervals_with_given_faces_and_the_bound_by_hand(box, monkeypatch):
    """A narrow window x in [-0.4, 0.4] and a mullion plate x in [0.075, 0.125], 0.02 m inside it, from
    (0, 0.5) at local height 0.6 (the glazing reaches 0.7, the plate 0.8). With only the plate's faces given:
    the window's cut minus the plate's shadow, 2 pieces, the nearest end the plate's (0.075, 0.02); with no
    face given, the window's cut whole. The round-off bound 2 n (16 u s / r + 8 u pi) with s the largest
    plan coordinate of the points (0.5), the faces taking part or the window (0.4)."""
    b = box(window_x=(-0.4, 0.4), mullions=(0.1,))
    assert b.scene.origin[:2].tolist() == [0.0, 0.0]
    rg = _geometry(b)
    plate = _faces_where(b, lambda c: np.all(c[:, 1] == 0.02))
    p = np.array([[0.0, 0.5, 0.6]])
    w0, w1 = _az(-0.4, 0.0, 0, 0.5), _az(0.4, 0.0, 0, 0.5)
    m0, m1 = _az(0.075, 0.02, 0, 0.5), _az(0.125, 0.02, 0, 0.5)

    def bound(n, s, r):
        return 2 * n * (16 * U * s / r + 8 * U * np.pi)

    pt, lo, hi, faces, bd = plan.visible_intervals(b.scene, rg, p, 0.5, faces=plate)
    assert faces.tolist() == plate.tolist() and pt.tolist() == [0, 0]
    assert np.column_stack([lo, hi]).ravel().tolist() == pytest.approx([w0, m0, m1, w1], abs=1e-13)
    assert bd[0] == pytest.approx(bound(2, 0.5, np.hypot(0.075, 0.48)), rel=1e-12, abs=0)
    pt, lo, hi, faces, bd = plan.visible_intervals(b.scene, rg, p, 0.5, faces=plate[:0])
    assert faces.tolist() == [] and pt.tolist() == [0] and [lo[0], hi[0]] == pytest.approx([w0, w1], abs=1e-13)
    # the window's nearest cut end: where its diagonal crosses z = 0.6, x = +-0.4 (2 * 1.3 / 1.4 - 1)
    assert bd[0] == pytest.approx(bound(1, 0.5, np.hypot(0.4 * (2 * 1.3 / 1.4 - 1), 0.5)), rel=1e-12, abs=0)
    # from (0, 0.3) the window (0.4) is the largest coordinate; with the faces near the points, the
    # facade beside the window (x to 2)
    p3 = np.array([[0.0, 0.3, 0.6]])
    bd = plan.visible_intervals(b.scene, rg, p3, 0.5, faces=plate)[4]
    assert bd[0] == pytest.approx(bound(2, 0.4, np.hypot(0.075, 0.28)), rel=1e-12, abs=0)
    near = plan.near_faces(b.scene, rg, p3, 0.5)
    assert np.abs(b.scene.vertices[b.scene.triangles[near]][..., :2]).max() == 2.0
    bd2 = plan.visible_intervals(b.scene, rg, p3, 0.5)[4]
    assert bd2[0] == pytest.approx(bound(2, 2.0, np.hypot(0.075, 0.28)), rel=1e-12, abs=0)
    # the given faces hold in blocks of points too, and so does view.mullions_block false
    monkeypatch.setattr(plan, "MAX_PAIRS", 0)
    monkeypatch.setattr(plan, "POINT_BLOCK", 1)
    two = np.r_[p, p]
    pt, lo, hi, faces, _ = plan.visible_intervals(b.scene, rg, two, 0.5, faces=plate[:0])
    assert faces.tolist() == [] and pt.tolist() == [0, 1] and lo.tolist() == pytest.approx([w0, w0], abs=1e-13)
    pt, lo, hi, _, _ = plan.visible_intervals(b.scene, rg, two, 0.5, members_block=False, faces=plate)
    assert pt.tolist() == [0, 1] and hi.tolist() == pytest.approx([w1, w1], abs=1e-13)


def test_visible_intervals_cut_at_most_max_cuts_at_once(box, monkeypatch):
    """Viewpoints at several heights go in blocks so that no call cuts more than MAX_CUTS (plane, triangle)
    pairs, counting the opaque faces and the window's triangles; the pieces are those of one call."""
    calls = []
    real = plan.cut_triangles

    def spy(tri, zs):
        calls.append(len(tri) * len(np.atleast_1d(zs)))
        return real(tri, zs)

    monkeypatch.setattr(plan, "cut_triangles", spy)
    for kw, faces_of in (({"wall_thickness": 0.3, "mullions": (0.0,)}, None),
                         ({"window_split": 10}, lambda b: _faces_where(b, lambda c: np.all(c[:, 1] == 0))[:2])):
        b = box(**kw)
        rg = _geometry(b)
        for heights in (2, 5):
            pts = np.column_stack([np.linspace(-0.5, 0.5, 5), np.linspace(0.6, 2.0, 5),
                                   np.linspace(-0.5, 0.5, heights)[np.arange(5) % heights]])
            faces = plan.near_faces(b.scene, rg, pts, 0.5) if faces_of is None else faces_of(b)
            m = max(len(faces), len(rg.triangles))
            monkeypatch.setattr(plan, "MAX_CUTS", 10**9)
            whole = plan.visible_intervals(b.scene, rg, pts, 0.5, faces=faces)
            for cuts in (m, 2 * m):
                monkeypatch.setattr(plan, "MAX_CUTS", cuts)
                calls.clear()
                got = plan.visible_intervals(b.scene, rg, pts, 0.5, faces=faces)
                assert max(calls) <= cuts and len(calls) >= 2 * (heights // (cuts // m))
                assert got[0].tolist() == whole[0].tolist() and got[1].tolist() == whole[1].tolist()
                assert got[2].tolist() == whole[2].tolist()


def test_visible_intervals_go_in_blocks_of_points_above_max_pairs(box, monkeypatch):
    b = box(wall_thickness=0.3)
    rg = _geometry(b)
    pts = np.column_stack([np.linspace(-0.5, 0.5, 7), np.full(7, 1.0), np.zeros(7)])
    faces = plan.near_faces(b.scene, rg, pts, 0.5)
    seen = []
    real = plan.shadow_arcs
    monkeypatch.setattr(plan, "shadow_arcs", lambda rg_, points, *a: seen.append(len(points)) or real(rg_, points, *a))
    monkeypatch.setattr(plan, "POINT_BLOCK", 3)
    monkeypatch.setattr(plan, "MAX_PAIRS", 7 * len(faces) - 1)  # one pair too many: blocks of 3
    plan.visible_intervals(b.scene, rg, pts, 0.5)
    assert seen == [3, 3, 1]
    seen.clear()
    monkeypatch.setattr(plan, "MAX_PAIRS", 7 * len(faces))  # exactly the limit: one call
    plan.visible_intervals(b.scene, rg, pts, 0.5)
    assert seen == [7]


def test_shadow_arcs_of_a_turned_and_moved_window(tmp_path):
    """The fins of test_shadow_arcs_split_at_the_windows_line_by_hand with the whole model turned 30 deg
    counter-clockwise (the window's normal off the axes): every azimuth turns by 30 deg. Then the
    window, the points and the fins moved together by (3, -2, 0.5) m (the frame's origin off the local
    origin): the same shadows."""
    import dataclasses

    from en17037cli.samples import BoxRoom, box_room_project
    from en17037cli.scene.model import INTERIOR, LANDSCAPE
    from tests.conftest import Built

    b = Built(box_room_project(tmp_path / "turned", BoxRoom(), rotate_deg=30.0))
    try:
        rg = _geometry(b)
    finally:
        b.engine.close()
    c, s_ = np.cos(np.radians(30.0)), np.sin(np.radians(30.0))
    rot = np.array([[c, -s_, 0.0], [s_, c, 0.0], [0.0, 0.0, 1.0]])
    # the OBJ's 9 decimals move the turned corners by up to 5e-10 m: azimuths from 1 m off by ~1e-9 rad
    assert rg.frames[0].n == pytest.approx(rot @ [0.0, -1.0, 0.0], abs=1e-9)
    assert np.abs(rg.frames[0].origin).max() < 1e-12  # the scene's origin is the window's centre
    pts = np.array([[0.0, 1.0, 0.0]]) @ rot.T
    fins = np.array([_fin(0.5, -0.5, -0.2), _fin(-0.5, 0.3, -0.3)]) @ rot.T
    turn = np.radians(30.0)
    beyond = (_az(0.5, -0.5, 0, 1) + turn, _az(0.5, -0.2, 0, 1) + turn)
    inner = (_az(-0.5, 0.3, 0, 1) + turn, _az(-0.5, 0.0, 0, 1) + turn)
    whole = (_az(-0.5, 0.3, 0, 1) + turn, _az(-0.5, -0.3, 0, 1) + turn)
    shift = np.array([3.0, -2.0, 0.5])
    moved_frame = copy.copy(rg.frames[0])
    moved_frame.origin = rg.frames[0].origin + shift
    moved = dataclasses.replace(rg, frames=[moved_frame], triangles=rg.triangles + shift)
    for layer, want in ((INTERIOR, [whole, beyond]), (LANDSCAPE, [inner])):
        here = plan.shadow_arcs(rg, pts, fins, np.array([layer, layer]))
        assert _per_point(here[0], here[2], here[3], 1)[0] == pytest.approx(_flat(want), abs=1e-8), layer
        there = plan.shadow_arcs(moved, pts + shift, fins + shift, np.array([layer, layer]))
        assert _per_point(there[0], there[2], there[3], 1)[0] == pytest.approx(_per_point(here[0], here[2], here[3], 1)[0], abs=1e-12)

