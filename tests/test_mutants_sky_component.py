"""Mutation tests (issue 46): the exact sky component (``criteria/daylight/sky_component.py``) on
scenes small enough to answer by hand or by a brute-force sum.

The reference is a midpoint sum of the CIE overcast luminance over the pane (cos θ cos_pane / r² dA,
one point at a time, no cells, no rays), as in ``tests/reference/test_sky_component_reference.py``;
300 x 210 pieces over a 2 x 1.4 m pane err by O(h²), under 1e-5 of the value at these points (the
reference's own measurement: 1.5e-6 at 400 x 300), added to the engine's bound as a tolerance.
What a tolerance setting must do is asserted on the engine's own results (a tolerance its unrefined
bound already meets refines nothing; a tighter one is met), never against stored numbers.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from en17037cli.criteria.daylight.sky import cie_overcast_luminance, glass_transmittance
from en17037cli.criteria.daylight.sky_component import SC_PER_SR, SkyTolerance, sky_component
from en17037cli.criteria.view.frames import RoomGeometry, window_frame
from en17037cli.criteria.view.rays import ViewRays
from en17037cli.raytrace import RayEngine
from en17037cli.scene.model import GROUND, INTERIOR, LANDSCAPE, WINDOW, Window

#: The midpoint reference's relative error (O(h²), 300 x 210 pieces: under 1e-5 measured at 400 x 300).
MIDPOINT_REL = 2e-5


def _quad_y(y, x0, x1, z0, z1):
    return [(x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)]


def _engine(polys: dict, layers: dict, normal=(0.0, -1.0, 0.0)):
    """Ray engine, view rays and room geometry of named quads: each name starting with ``glazing`` one
    window facing ``normal`` (in the order given); ``layers`` gives each other name's layer (INTERIOR:
    blocks; GROUND: ground; LANDSCAPE: landscape)."""
    tris, layer, wname = [], [], []
    for name, quads in polys.items():
        for q in quads:
            q = np.asarray(q, float)
            for k in range(1, len(q) - 1):
                tris.append([q[0], q[k], q[k + 1]])
                layer.append(WINDOW if name.startswith("glazing") else layers[name])
                wname.append(name)
    tris, layer, wname = np.array(tris), np.array(layer), np.array(wname)
    win = np.flatnonzero(layer == WINDOW)
    engine = RayEngine(tris.reshape(-1, 3), np.arange(3 * len(tris)).reshape(-1, 3),
                       {"opaque": layer != WINDOW, "win": win})
    names = [n for n in polys if n.startswith("glazing")]
    frames, wof = [], np.full(len(tris), -1)
    for i, n in enumerate(names):
        ids = np.flatnonzero(wname == n)
        frames.append(window_frame(Window(n, i, ids, tris[ids], np.asarray(normal, float), 0.0), i))
        wof[ids] = i
    rg = RoomGeometry(frames, wof, tris[win], wof[win], "win")
    return engine, ViewRays(engine, SimpleNamespace(layer=layer)), rg


def _midpoint(points, corner, edge_u, edge_v, tv, nu=300, nv=210, facade=None, plane=(0.0, 0.0, 1.0)):
    """Sky component [-] of ``points`` through the pane corner + s edge_u + t edge_v: the midpoint sum
    of ℓ(γ) cos θ τ(i) cos_pane / r² dA over nu x nv pieces, over 7 π / 9 (cos θ to the receiving
    ``plane``'s normal). With ``facade`` = (y, top), a facade in the plane y (y < 0, wider than all
    the pane's directions) up to z = top: it hides the part of a vertical pane in the plane y = 0
    below z = p_z + (top - p_z) p_y / (p_y - y), the rest of the pane is summed."""
    out = []
    for p in np.asarray(points, float):  # one point at a time
        c, ev = np.array(corner, float), np.array(edge_v, float)
        if facade is not None:
            y, top = facade
            cut = p[2] + (top - p[2]) * p[1] / (p[1] - y)
            lo = min(max(c[2], cut), c[2] + ev[2])
            ev[2] -= lo - c[2]
            c[2] = lo
        s, t = (np.arange(nu) + 0.5) / nu, (np.arange(nv) + 0.5) / nv
        S, T = np.meshgrid(s, t, indexing="ij")
        X = c + S[..., None] * edge_u + T[..., None] * ev
        normal = np.cross(edge_u, ev)
        area = np.linalg.norm(normal) / (nu * nv)
        normal /= max(np.linalg.norm(normal), 1e-300)
        r = X - p
        dist = np.linalg.norm(r, axis=-1)
        d = r / dist[..., None]
        cos_pane = np.abs(d @ normal)
        up = np.maximum(d[..., 2], 0.0)
        cos_t = np.maximum(d @ np.asarray(plane, float), 0.0) * (up > 0)
        f = cie_overcast_luminance(np.arcsin(up)) * cos_t * glass_transmittance(cos_pane, tv) * cos_pane / dist**2
        out.append(float(f.sum() * area / (7.0 * np.pi / 9.0)))
    return np.array(out)


#: A 2 x 1.4 m south pane (x in [-1, 1], z in [0.8, 2.2], in the plane y = 0, facing -y), the ground
#: outside it and a facade 6 m high 10 m away, which block: the cells across the facade's top are mixed.
PANE = {"glazing": [_quad_y(0.0, -1.0, 1.0, 0.8, 2.2)],
        "ground": [[(-200.0, -200.0, 0.0), (200.0, -200.0, 0.0), (200.0, 0.0, 0.0), (-200.0, 0.0, 0.0)]]}
STREET = dict(PANE, facade=[_quad_y(-10.0, -50.0, 50.0, 0.0, 6.0)])
FACADE = (-10.0, 6.0)
PANE_REF = (np.array([-1.0, 0.0, 0.8]), np.array([2.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.4]))
POINTS = np.array([[0.0, 1.0, 0.85], [1.5, 3.0, 0.85], [-0.5, 1.5, 1.2]])


def test_a_point_that_sees_no_window_has_no_sky_component():
    # a point outside, in front of the pane: no patch, nothing integrated; the bins (if asked) all zero
    engine, vr, rg = _engine(PANE, {"ground": INTERIOR})
    sc = sky_component(vr, rg, np.array([[0.0, -1.0, 1.0], [0.3, -2.0, 1.5]]), np.array([0.7]),
                       bins=lambda d: np.zeros(len(d), int), nbins=3)
    assert sc.value.tolist() == [0.0, 0.0] and sc.bound.tolist() == [0.0, 0.0]
    assert sc.cells.tolist() == [0, 0] and sc.cells.dtype.kind == "i"
    assert sc.patches.tolist() == [[0.0] * 3] * 2
    plain = sky_component(vr, rg, np.array([[0.0, -1.0, 1.0]]), np.array([0.7]))
    assert plain.patches is None and plain.cells.dtype.kind == "i"
    engine.close()


def test_unrefined_cells_lie_within_their_bound_of_the_brute_force():
    # refine_levels 0: the base cells alone, each weighed by the Gauss rule; the mixed ones across the
    # horizon bounded by max(share, 1 - share) of their integral
    engine, vr, rg = _engine(STREET, {"ground": INTERIOR, "facade": INTERIOR})
    ref = _midpoint(POINTS, *PANE_REF, 0.7, facade=FACADE)
    sc = sky_component(vr, rg, POINTS, np.array([0.7]), SkyTolerance(refine_levels=0))
    assert np.all(sc.value > 0.0) and np.all(sc.bound > 0.0)
    assert np.all(np.abs(sc.value - ref) <= sc.bound + MIDPOINT_REL * ref), np.column_stack([sc.value, ref, sc.bound])
    engine.close()


def test_a_tolerance_the_base_cells_meet_refines_nothing_and_a_tighter_one_is_met():
    engine, vr, rg = _engine(STREET, {"ground": INTERIOR, "facade": INTERIOR})
    ref = _midpoint(POINTS, *PANE_REF, 1.0, facade=FACADE)
    base = sky_component(vr, rg, POINTS, np.array([1.0]), SkyTolerance(refine_levels=0))
    for k, p in enumerate(POINTS):
        one = np.stack([p, [0.0, -1.0, 1.0]])  # and a point outside that sees no window, last
        # an absolute tolerance twice the unrefined bound: nothing is split, the same cells and numbers
        loose = sky_component(vr, rg, one, np.array([1.0]),
                              SkyTolerance(refine_levels=8, rel_tolerance=0.0, abs_tolerance=2.0 * base.bound[k]))
        assert loose.cells[0] == base.cells[k]
        assert loose.value[0] == pytest.approx(base.value[k], rel=1e-12)
        assert loose.bound[0] == pytest.approx(base.bound[k], rel=1e-12)
        # a quarter of it: the bound is brought within it (to 1 %: the cells that stay are chosen by their
        # midpoint weight, then weighed by the Gauss rule, which differs by O(h²): 2e-5 over, measured),
        # and the value within the bound of the brute force
        tight = sky_component(vr, rg, one, np.array([1.0]),
                              SkyTolerance(refine_levels=8, rel_tolerance=0.0, abs_tolerance=0.25 * base.bound[k]))
        assert tight.cells[0] > base.cells[k]
        assert tight.bound[0] <= 1.01 * 0.25 * base.bound[k]
        assert abs(tight.value[0] - ref[k]) <= tight.bound[0] + MIDPOINT_REL * ref[k]
        # the relative tolerance alone does the same
        rel = 0.25 * base.bound[k] / ref[k]
        by_rel = sky_component(vr, rg, one, np.array([1.0]), SkyTolerance(refine_levels=8, rel_tolerance=rel, abs_tolerance=0.0))
        assert by_rel.bound[0] <= 1.01 * rel * by_rel.value[0]
        assert by_rel.cells[0] > base.cells[k]
        for r in (loose, tight, by_rel):
            assert r.value[1] == 0.0 and r.bound[1] == 0.0 and r.cells[1] == 0
    engine.close()


def test_a_small_roof_light_seen_as_one_cell():
    # a 0.2 x 0.2 m roof light 3 m above the point, 3.8 deg across, at a 10 deg resolution: one base cell,
    # all sky and a whole rectangle, weighed by the Gauss rule at once
    h, a = 3.0, 0.1
    polys = {"glazing": [[(-a, -a, h), (a, -a, h), (a, a, h), (-a, a, h)]]}
    engine, vr, rg = _engine(polys, {}, normal=(0.0, 0.0, 1.0))
    sc = sky_component(vr, rg, np.zeros((1, 3)), np.array([1.0]), SkyTolerance(resolution_deg=10.0))
    want = _midpoint(np.zeros((1, 3)), np.array([-a, -a, h]), np.array([2 * a, 0.0, 0.0]), np.array([0.0, 2 * a, 0.0]), 1.0)
    assert sc.cells.tolist() == [1]
    # ∫ ℓ cos θ dω over the light: ≈ (1 + 2) / 3 x 1 x 0.04 / 9 sr x 9 / (7 π) = 0.04 / (7 π) (on axis)
    assert want[0] == pytest.approx(0.04 / (7 * np.pi), rel=0.01)
    assert abs(sc.value[0] - want[0]) <= sc.bound[0] + MIDPOINT_REL * want[0]
    engine.close()


def test_a_point_above_the_pane_sees_no_sky_and_has_no_bound():
    # from 3 m up, every direction through the pane (top at 2.2 m) points down: a plate outside is seen
    # across the ground, the cells on its outline mixed of ground and obstruction, none with sky in it
    polys = dict(PANE, plate=[_quad_y(-3.0, -0.3, 5.0, 0.0, 1.0)])
    engine, vr, rg = _engine(polys, {"ground": GROUND, "plate": INTERIOR})
    sc = sky_component(vr, rg, np.array([[0.0, 2.0, 3.0]]), np.array([0.7]), SkyTolerance(resolution_deg=2.0))
    assert sc.value.tolist() == [0.0] and sc.bound.tolist() == [0.0] and sc.cells[0] > 0
    engine.close()


def test_sky_component_per_steradian_constant():
    # the unobstructed horizontal illuminance of the CIE overcast sky is 7 π / 9 times its zenith luminance
    assert SC_PER_SR == pytest.approx(9.0 / (7.0 * np.pi), rel=1e-15)


# --- one cell, worked by hand -----------------------------------------------------------------------
#: A 0.2 x 0.2 m roof light 3 m above the origin, 3.8 deg across: one base cell at a 10 deg resolution.
#: An opaque square 1 m above it, outside its frame depth, hides the direction of one corner of the
#: cell (x, y >= 0.12 at z = 4: the corner (0.1, 0.1, 3) is seen at (0.133, 0.133, 4)) and not the
#: three others: a mixed cell whose samples say 3/4 sky.
ROOF = {"glazing": [[(-0.1, -0.1, 3.0), (0.1, -0.1, 3.0), (0.1, 0.1, 3.0), (-0.1, 0.1, 3.0)]],
        "bar": [[(0.12, 0.12, 4.0), (0.2, 0.12, 4.0), (0.2, 0.2, 4.0), (0.12, 0.2, 4.0)]]}


def _one_cell(rg):
    """The one cell's integral and error estimate (the module's Gauss rule, tested on its own against a
    dense midpoint rule) and the cell's unit-radiance integral ∫ cos θ dω by a brute-force sum."""
    from en17037cli.criteria.daylight.sky_component import cell_integrals

    t = np.arctan(0.1 / 3.0)
    f = rg.frames[0]
    axes = np.stack([f.u, f.v, f.n])[None]
    value, qerr = cell_integrals(axes, np.array([1.0]), np.array([[-t, t, -t, t]]))
    n = 400
    s = (np.arange(n) + 0.5) / n * 0.2 - 0.1
    X, Y = np.meshgrid(s, s, indexing="ij")
    r2 = X * X + Y * Y + 9.0
    unit = float((3.0 / np.sqrt(r2) * 3.0 / np.sqrt(r2) / r2).sum() * (0.2 / n) ** 2)  # cos θ cos_pane / r² dA
    return value[0], qerr[0], unit


def test_a_mixed_cell_weighs_its_sky_share_and_is_bounded_by_the_larger_part():
    engine, vr, rg = _engine(ROOF, {"bar": INTERIOR}, normal=(0.0, 0.0, 1.0))
    f, qerr, unit = _one_cell(rg)
    two = np.zeros((2, 3))
    # by the sign of x: the Gauss nodes of the middle column (x = 0) in bin 0, the two sides in 1 and 2
    bins = lambda d: np.where(d[:, 0] > 1e-9, 1, np.where(d[:, 0] < -1e-9, 2, 0))  # noqa: E731
    for tol in (SkyTolerance(resolution_deg=10.0, refine_levels=0),
                SkyTolerance(resolution_deg=10.0, refine_levels=8, abs_tolerance=1.0)):  # split, but within budget
        sc = sky_component(vr, rg, two, np.array([1.0]), tol, bins=bins, nbins=3)
        assert sc.cells.tolist() == [1, 1]
        # value: share f; bound: max(share, 1 - share) f + share x the Gauss rule's error estimate
        assert sc.value == pytest.approx([0.75 * f * SC_PER_SR] * 2, rel=1e-12)
        assert sc.bound == pytest.approx([(0.75 * f + 0.75 * qerr) * SC_PER_SR] * 2, rel=1e-12)
        # the bins: share x the unit-radiance integral; the sides alike (the cell is symmetric), the middle
        # column with the Gauss weight 8/9 of 2 (to 1e-3: the integrand varies by that across 3.8 deg)
        assert sc.patches.sum(axis=1) == pytest.approx([0.75 * unit] * 2, rel=1e-4)
        assert sc.patches[:, 1] == pytest.approx(sc.patches[:, 2], rel=1e-9)
        assert sc.patches[:, 0] == pytest.approx([0.75 * unit * 8 / 18] * 2, rel=1e-3)
    engine.close()


def test_with_no_tolerance_the_mixed_cell_is_split_to_the_last_level():
    engine, vr, rg = _engine(ROOF, {"bar": INTERIOR}, normal=(0.0, 0.0, 1.0))
    _, _, unit = _one_cell(rg)
    two = np.zeros((2, 3))
    bins = lambda d: np.zeros(len(d), int)  # noqa: E731
    want = _midpoint(two[:1], np.array([-0.1, -0.1, 3.0]), np.array([0.2, 0.0, 0.0]), np.array([0.0, 0.2, 0.0]), 1.0,
                     nu=400, nv=400)[0]
    hidden = _midpoint(two[:1], np.array([0.09, 0.09, 3.0]), np.array([0.01, 0.0, 0.0]), np.array([0.0, 0.01, 0.0]), 1.0,
                       nu=40, nv=40)[0]  # the corner (0.09, 0.1]² the square hides (x, y >= 0.12 x 3 / 4)
    for levels in (1, 3):
        sc = sky_component(vr, rg, two, np.array([1.0]), SkyTolerance(resolution_deg=10.0, refine_levels=levels,
                                                                     rel_tolerance=0.0, abs_tolerance=0.0), bins=bins, nbins=1)
        # every level splits the cells the square's outline crosses (the cell's corner): 1 + 3 per level
        assert sc.cells.tolist() == [1 + 3 * levels] * 2
        assert np.all(np.abs(sc.value - (want - hidden)) <= sc.bound + MIDPOINT_REL * want)
        assert sc.patches[:, 0] == pytest.approx(unit * sc.value / want, rel=1e-3)
    engine.close()


def test_an_all_sky_whole_cell_is_never_split():
    # the roof light without the square: one cell, all sky, a whole rectangle: final at level 0 whatever
    # the tolerance, its Gauss value and error estimate
    polys = {"glazing": ROOF["glazing"]}
    engine, vr, rg = _engine(polys, {}, normal=(0.0, 0.0, 1.0))
    f, qerr, _ = _one_cell(rg)
    sc = sky_component(vr, rg, np.zeros((1, 3)), np.array([1.0]),
                       SkyTolerance(resolution_deg=10.0, refine_levels=3, rel_tolerance=0.0, abs_tolerance=0.0))
    assert sc.cells.tolist() == [1]
    assert sc.value[0] == pytest.approx(f * SC_PER_SR, rel=1e-12)
    assert sc.bound[0] == pytest.approx(qerr * SC_PER_SR, rel=1e-12)
    engine.close()


def test_cells_with_no_sky_are_never_split():
    # a landscape wall 5 m out fills the pane's whole view, a plate 3 m out stands in front of it: the
    # cells on the plate's outline are mixed (obstruction and landscape, above the horizon) but hold no
    # sky: nothing to integrate, nothing to bound, nothing split
    polys = dict(PANE, plate=[_quad_y(-3.0, -0.5, 0.5, 0.0, 3.0)], hill=[_quad_y(-5.0, -100.0, 100.0, 0.0, 100.0)])
    engine, vr, rg = _engine(polys, {"ground": INTERIOR, "plate": INTERIOR, "hill": LANDSCAPE})
    pts = np.array([[0.0, 1.0, 1.5], [0.3, 2.0, 1.2]])
    base = sky_component(vr, rg, pts, np.array([0.7]), SkyTolerance(refine_levels=0))
    sc = sky_component(vr, rg, pts, np.array([0.7]), SkyTolerance(refine_levels=3, rel_tolerance=0.0, abs_tolerance=0.0))
    for r in (base, sc):
        assert r.value.tolist() == [0.0, 0.0] and r.bound.tolist() == [0.0, 0.0]
    assert sc.cells.tolist() == base.cells.tolist()
    engine.close()


def test_a_vertical_receiving_plane():
    # the receiving plane faces the pane (normal -y): cos θ = -d_y, smooth over the pane's directions
    engine, vr, rg = _engine(STREET, {"ground": INTERIOR, "facade": INTERIOR})
    ref = _midpoint(POINTS, *PANE_REF, 0.7, facade=FACADE, plane=(0.0, -1.0, 0.0))
    sc = sky_component(vr, rg, POINTS, np.array([0.7]), normal=(0.0, -1.0, 0.0))
    assert np.all(np.abs(sc.value - ref) <= sc.bound + MIDPOINT_REL * ref), np.column_stack([sc.value, ref, sc.bound])
    # and it differs from the horizontal plane's by more than both bounds
    flat = sky_component(vr, rg, POINTS, np.array([0.7]))
    assert np.all(np.abs(flat.value - sc.value) > flat.bound + sc.bound)
    engine.close()


def test_a_cell_is_split_when_its_midpoint_weight_exceeds_the_budget():
    # the mixed roof-light cell (3/4 sky): it is decided by its midpoint weight, 4 ha hb g(0) with g = 1
    # on the light's axis (ℓ(90 deg) = 1, cos θ = 1, τ = 1 open), i.e. (2 atan(1/30))²; its own bound
    # 3/4 of that: it stays if the tolerance holds it, else it is split in four
    engine, vr, rg = _engine(ROOF, {"bar": INTERIOR}, normal=(0.0, 0.0, 1.0))
    own = 0.75 * (2.0 * np.arctan(1.0 / 30.0)) ** 2 * SC_PER_SR
    for factor, cells in ((1.0005, 1), (0.9995, 4)):
        tol = SkyTolerance(resolution_deg=10.0, refine_levels=1, rel_tolerance=0.0, abs_tolerance=factor * own)
        assert sky_component(vr, rg, np.zeros((1, 3)), np.array([1.0]), tol).cells.tolist() == [cells]
    # the relative tolerance against the value so far, 3/4 of the midpoint weight (the bound is all of it)
    for factor, cells in ((1.0005, 1), (0.9995, 4)):
        tol = SkyTolerance(resolution_deg=10.0, refine_levels=1, rel_tolerance=factor, abs_tolerance=0.0)
        assert sky_component(vr, rg, np.zeros((1, 3)), np.array([1.0]), tol).cells.tolist() == [cells]
    engine.close()


def test_a_receiving_plane_facing_down_gets_no_sky():
    engine, vr, rg = _engine(PANE, {"ground": INTERIOR})
    sc = sky_component(vr, rg, POINTS, np.array([0.7]), normal=(0.0, 0.0, -1.0))
    assert sc.value.tolist() == [0.0] * 3 and sc.bound.tolist() == [0.0] * 3
    engine.close()


def test_each_window_weighs_by_its_own_glass():
    from en17037cli.criteria.daylight.sky_component import cell_integrals

    axes = np.array([[[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]] * 2)  # a south pane's u, v, n
    G = np.array([[-0.3, 0.2, 0.1, 0.4]] * 2)
    both, qb = cell_integrals(axes, np.array([0.7, 1.0]), G)
    for k, tv in enumerate((0.7, 1.0)):
        one, q1 = cell_integrals(axes[k:k + 1], np.array([tv]), G[k:k + 1])
        assert both[k] == pytest.approx(one[0], rel=1e-14) and qb[k] == pytest.approx(q1[0], rel=1e-14)
    assert both[0] < 0.9 * both[1]  # clear glass of tv 0.7 lets through less than an open opening


def _triangle_solid_angle(a, b, c):
    """Solid angle [sr] of the triangle a, b, c seen from the origin (Van Oosterom & Strackee 1983)."""
    la, lb, lc = (np.linalg.norm(x) for x in (a, b, c))
    num = abs(np.dot(a, np.cross(b, c)))
    den = la * lb * lc + np.dot(a, b) * lc + np.dot(a, c) * lb + np.dot(b, c) * la
    return 2.0 * np.arctan2(num, den)


def test_a_cell_cut_by_the_outline_weighs_its_part_inside():
    # a triangular roof light 3 m up, one base cell (10 deg): the cell's Gauss integral scaled by the
    # triangle's solid angle over the cell's (the outline's bounding rectangle), and its bound the
    # scaled error estimate plus the integrand's range at the nodes times the triangle's solid angle
    from en17037cli.criteria.daylight.sky_component import cell_integrals

    tri = np.array([(-0.2, -0.1, 3.0), (0.2, -0.1, 3.0), (0.05, 0.1, 3.0)])  # acute: one bounding rectangle
    polys = {"glazing": [tri]}
    engine, vr, rg = _engine(polys, {}, normal=(0.0, 0.0, 1.0))
    f = rg.frames[0]
    d = float(f.origin @ f.n)  # the point at the origin, the light's plane at this distance along n
    x0, y0 = -(f.origin @ f.u), -(f.origin @ f.v)
    G = np.array([[np.arctan((f.xmin - x0) / d), np.arctan((f.xmax - x0) / d),
                   np.arctan((f.ymin - y0) / d), np.arctan((f.ymax - y0) / d)]])
    X0, X1, Y0, Y1 = np.tan(G[0])
    # the rectangle's solid angle by its corners: two triangles, each by the closed form
    corners = [d * f.n + X * d * f.u + Y * d * f.v for X, Y in ((X0, Y0), (X1, Y0), (X1, Y1), (X0, Y1))]
    rect = _triangle_solid_angle(corners[0], corners[1], corners[2]) + _triangle_solid_angle(corners[0], corners[2], corners[3])
    w = _triangle_solid_angle(*tri)
    assert 0.4 < w / rect < 0.6
    for normal in ((0.0, 0.0, 1.0), (0.6, 0.0, 0.8)):
        axes = np.stack([f.u, f.v, f.n])[None]
        val, qerr, gmin, gmax = cell_integrals(axes, np.array([1.0]), G, normal, extremes=True)
        sc = sky_component(vr, rg, np.zeros((1, 3)), np.array([1.0]), SkyTolerance(resolution_deg=10.0, refine_levels=0),
                           normal=normal)
        assert sc.cells.tolist() == [1]
        assert sc.value[0] == pytest.approx(val[0] * w / rect * SC_PER_SR, rel=1e-9)
        assert sc.bound[0] == pytest.approx((qerr[0] * w / rect + w * (gmax[0] - gmin[0])) * SC_PER_SR, rel=1e-9)
    engine.close()


def test_the_budget_is_what_the_tolerance_leaves_beside_the_final_cells():
    # two roof lights side by side: one clear (all sky, final at once: its bound, the Gauss rule's error
    # estimate q, is spent), one under the square (mixed: 3/4 of its midpoint weight m to decide by). The
    # mixed one stays if q + 3/4 m fits the tolerance, else it is split
    from en17037cli.criteria.daylight.sky_component import cell_integrals

    clear = [(0.5, -0.1, 3.0), (0.7, -0.1, 3.0), (0.7, 0.1, 3.0), (0.5, 0.1, 3.0)]
    engine, vr, rg = _engine(dict(ROOF, glazing2=[clear]), {"bar": INTERIOR}, normal=(0.0, 0.0, 1.0))
    f = rg.frames[1]
    d = float(f.origin @ f.n)
    x0, y0 = -(f.origin @ f.u), -(f.origin @ f.v)
    G = np.array([[np.arctan((f.xmin - x0) / d), np.arctan((f.xmax - x0) / d),
                   np.arctan((f.ymin - y0) / d), np.arctan((f.ymax - y0) / d)]])
    _, q = cell_integrals(np.stack([f.u, f.v, f.n])[None], np.array([1.0]), G)
    m = 0.75 * (2.0 * np.arctan(1.0 / 30.0)) ** 2
    for extra, cells in ((0.5, 1 + 4), (1.5, 1 + 1)):
        tol = SkyTolerance(resolution_deg=10.0, refine_levels=1, rel_tolerance=0.0, abs_tolerance=(m + extra * q[0]) * SC_PER_SR)
        assert sky_component(vr, rg, np.zeros((1, 3)), np.array([1.0, 1.0]), tol).cells.tolist() == [cells]
    engine.close()
