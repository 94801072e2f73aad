"""Mutation tests (issue 39): which faces of an IFC element are glass (``io/ifc_glazing.py``): the
style rules on stand-in materials, the IFC relations on stand-in entities and the panes found from
geometry on hand-built windows (frames, plates, one solid of frame and glass).
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from en17037cli.io import ifc_glazing as g

NAN = float("nan")


class _Product:
    def __init__(self, cls):
        self.cls = cls

    def is_a(self, name=None):
        return self.cls if name is None else name == self.cls


@pytest.mark.parametrize("name, cls, default", [
    ("DefaultMaterial", "IfcWall", True), ("DefaultMaterial7", "IfcWall", True), ("IfcWindow", "IfcWindow", True),
    ("IfcWindow", "IfcDoor", False), ("IfcWindow frame", "IfcWindow", False), ("Glass", "IfcWindow", False),
    ("", "IfcWindow", False), (None, "IfcWindow", False), ("Ifc", "IfcWindow", False)])
def test_default_material_by_hand(name, cls, default):
    assert g.is_default_material(SimpleNamespace(name=name), _Product(cls)) is default


@pytest.mark.parametrize("t, name, glass", [
    (0.6, "frame", True), (0.5, "frame", True), (0.49, "Glass", False), (0.01, "x", False),
    (0.0, "Clear GLAS", True), (0.0, "steel", False), (NAN, "Verre clair", True), (NAN, "vetro", True),
    (NAN, "vidrio", True), (NAN, "Glazed unit", True), (NAN, "Vitrage", True), (NAN, "glazing", True),
    (NAN, "frame", None), (NAN, None, None)])
def test_glass_by_style_by_hand(t, name, glass):
    assert g.glass_by_style(SimpleNamespace(transparency=t, name=name)) is glass


def test_glass_by_style_without_a_transparency_attribute():
    assert g.glass_by_style(SimpleNamespace(name="frame")) is None
    assert g.glass_by_style(SimpleNamespace(name="glass")) is True
    assert g.glass_by_style(SimpleNamespace()) is None


@pytest.mark.parametrize("t, name, opaque", [
    (0.05, "panel", True), (0.099, None, True), (0.1, "panel", False), (0.0, "panel", False), (0.05, "Glass", False),
    (NAN, "panel", False), (0.7, "panel", False)])
def test_opaque_by_style_by_hand(t, name, opaque):
    assert g.opaque_by_style(SimpleNamespace(transparency=t, name=name)) is opaque


# --- the IFC relations ----------------------------------------------------------------------------


def _el(gid, cls="IfcWall"):
    return SimpleNamespace(GlobalId=gid, is_a=lambda name=None: cls if name is None else name in (cls, "IfcElement")
                           and cls != "IfcSpatial")


class _File:
    def __init__(self, **rels):
        self.rels = rels

    def by_type(self, kind):
        if kind not in self.rels:
            raise RuntimeError(kind)
        return self.rels[kind]


def test_hosts_by_hand():
    def fill(op_walls, el):
        op = None if op_walls is None else SimpleNamespace(VoidsElements=[SimpleNamespace(RelatingBuildingElement=w)
                                                                          for w in op_walls])
        return SimpleNamespace(RelatingOpeningElement=op, RelatedBuildingElement=el)

    f = _File(IfcRelFillsElement=[fill([_el("W2"), _el("W1")], _el("D1")), fill([_el("W1"), None], _el("D1")),
                                  fill(None, _el("D2")), fill([_el("W3")], None), fill([], _el("D3")), fill([None], _el("D4")),
                                  fill([_el("S1")], _el("D5"))])
    assert g.hosts(f) == {"D1": ("W1", "W2"), "D5": ("S1",)}
    op = SimpleNamespace(VoidsElements=None)
    assert g.hosts(_File(IfcRelFillsElement=[SimpleNamespace(RelatingOpeningElement=op, RelatedBuildingElement=_el("D"))])) == {}


def test_assemblies_by_hand():
    cw, roof, zone = _el("CW", "IfcCurtainWall"), _el("R", "IfcRoof"), _el("Z", "IfcSpatial")
    agg = [SimpleNamespace(RelatingObject=cw, RelatedObjects=[_el("P1", "IfcPlate"), _el("P2", "IfcPlate"), zone]),
           SimpleNamespace(RelatingObject=None, RelatedObjects=[_el("P3")]),
           SimpleNamespace(RelatingObject=zone, RelatedObjects=[_el("P4")]),
           SimpleNamespace(RelatingObject=roof, RelatedObjects=None)]
    nests = [SimpleNamespace(RelatingObject=roof, RelatedObjects=[_el("P1"), _el("S1", "IfcSlab")])]
    out = g.assemblies(_File(IfcRelAggregates=agg, IfcRelNests=nests))
    assert out == {"P1": ("CW", "IfcCurtainWall"), "P2": ("CW", "IfcCurtainWall"), "S1": ("R", "IfcRoof")}
    assert g.assemblies(_File(IfcRelAggregates=agg)) == {"P1": ("CW", "IfcCurtainWall"), "P2": ("CW", "IfcCurtainWall")}


# --- panes from geometry --------------------------------------------------------------------------


def box(x0, x1, y0, y1, z0, z1):
    """A closed box: 8 shared vertices, 12 triangles."""
    v = np.array([(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return v, np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])


def ring(o, i, y0, y1):
    """A square frame as one solid: outer [0, o]^2 and inner [i, o - i]^2 in x, z, from y0 to y1."""
    sq = lambda a, b: [(a, a), (b, a), (b, b), (a, b)]  # noqa: E731
    pts = sq(0.0, o) + sq(i, o - i)
    v = np.array([(x, y, z) for y in (y0, y1) for x, z in pts], float)
    tris = []
    for k in range(4):
        n = (k + 1) % 4
        for base in (0, 8):  # the front and back rings
            tris += [(base + k, base + n, base + 4 + n), (base + k, base + 4 + n, base + 4 + k)]
        for a, b in ((k, n), (4 + k, 4 + n)):  # the outer and inner sides
            tris += [(a, b, 8 + b), (a, 8 + b, 8 + a)]
    return v, np.array(tris)


def join(*meshes):
    vs, fs, off = [], [], 0
    for v, f in meshes:
        vs.append(v)
        fs.append(f + off)
        off += len(v)
    return np.concatenate(vs), np.concatenate(fs)


Y = np.array([0.0, 1.0, 0.0])


def test_a_thin_plate_is_a_pane_a_thick_block_by_its_faces_and_a_frame_not():
    v, f = box(0, 1, 0, 0.01, 0, 1)
    assert g.pane_faces(v, f, Y).all() and g.pane_faces(v, f, 2 * Y).all()
    v, f = box(0, 1, 0, 0.2, 0, 1)  # thicker than 0.1 m: its two big faces are levels that fill the outline
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    assert g.pane_faces(v, f, Y).tolist() == (np.abs(n[:, 1]) > 0).tolist()
    v, f = ring(1.0, 0.3, 0.0, 0.05)  # a frame: its faces hold a hole
    assert not g.pane_faces(v, f, Y).any()


def test_the_pane_inside_a_frame_of_bars():
    bars = [box(0, 1, 0, 0.06, 0, 0.05), box(0, 1, 0, 0.06, 0.95, 1), box(0, 0.05, 0, 0.06, 0.05, 0.95),
            box(0.95, 1, 0, 0.06, 0.05, 0.95)]
    v, f = join(*bars, box(0.05, 0.95, 0.02, 0.03, 0.05, 0.95))
    assert g.pane_faces(v, f, Y).tolist() == [False] * 48 + [True] * 12


def test_a_plate_that_does_not_fill_its_outline_is_not_a_pane():
    plus = [box(x, x + 1, 0, 0.01, z, z + 1) for x, z in ((1, 0), (0, 1), (1, 1), (2, 1), (1, 2))]
    v, f = join(*plus)  # 5 of the 7 m2 of its convex hull
    assert not g.pane_faces(v, f, Y).any()
    ell = [box(x, x + 1, 0, 0.01, z, z + 1) for x, z in ((0, 0), (1, 0), (0, 1))]
    v, f = join(*ell)  # 3 of 3.5 m2
    assert g.pane_faces(v, f, Y).all()
    v, f = box(0, 1, 0, 0.01, 0, 1)  # in a wall at 45 deg to every face: no face parallel to the wall
    assert not g.pane_faces(v, f, np.array([0.7, 0.0, 0.7])).any()


def test_principal_normal_by_hand():
    v, f = box(0, 2, 0, 0.05, 0, 1)
    assert np.allclose(g.principal_normal(v[f]), [0, 1, 0])
    u, w, n = np.array([1.0, 0, 0]), np.array([0, 0.8, -0.6]), np.array([0, 0.6, 0.8])
    pv = v @ np.column_stack([u, n, w]).T  # the plate turned: its big faces normal to (0, 0.6, 0.8)
    assert np.allclose(g.principal_normal(pv[f]), n)
    assert np.allclose(g.principal_normal(-pv[f]), n)


def test_fill_and_panes_of_a_frame_with_no_glass():
    v, f = ring(1.0, 0.2, 0.0, 0.05)
    u, w = np.array([1.0, 0, 0]), np.array([0, 0, -1.0])
    area, hull, holes = g._fill(v[f], u, w)
    assert area == pytest.approx(1 - 0.36, abs=1e-5) and hull == pytest.approx(1.0, abs=1e-5) and holes == 1
    panes = g.frame_opening_panes(v, f, Y)
    a = 0.5 * np.linalg.norm(np.cross(panes[:, 1] - panes[:, 0], panes[:, 2] - panes[:, 0]), axis=1)
    assert a.sum() == pytest.approx(0.36, abs=1e-9) and np.allclose(panes[..., 1], 0.025)
    assert panes[..., 0].min() == pytest.approx(0.2) and panes[..., 2].max() == pytest.approx(0.8)
    assert g.frame_opening_panes(*ring(1.0, 0.3, 0.0, 0.05), Y) is None  # a hole of 16 % of the outline: not a sash
    v2, f2 = join(ring(1.0, 0.2, 0.0, 0.05), (ring(1.0, 0.2, 0.0, 0.05)[0] + [1.0, 0.0, 0.0], ring(1.0, 0.2, 0.0, 0.05)[1]))
    panes = g.frame_opening_panes(v2, f2, Y)
    a = 0.5 * np.linalg.norm(np.cross(panes[:, 1] - panes[:, 0], panes[:, 2] - panes[:, 0]), axis=1)
    assert a.sum() == pytest.approx(0.72, abs=1e-9)  # two sashes side by side: two openings
    v, f = box(0, 1, 0, 0.05, 0, 1)
    assert g.frame_opening_panes(v, f, Y) is None
