"""Mutation tests (issue 39): the daylight criterion's formulas (``criteria/daylight/``: sky, patches,
radiance's pure functions, assess) against hand values, closed forms and brute force.

Tolerances: 1e-12 on sums of a few terms; the sky component's midpoint rule against a brute-force
quadrature over the opening's area, 1e-4 relative (both O(h^2): 48^2 pieces, 3e-5 measured, against
400^2 cells); Radiance's glass transmissivity is given to 10 digits, which its division by
0.0036 tv makes 3e-7 at tv 0.1 (1.2e-7 measured).
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
import shapely

from en17037cli import standard
from en17037cli.criteria.daylight import assess, patches, radiance, sky
from en17037cli.errors import NotAssessable
from en17037cli.scene.model import GROUND, INTERIOR, LANDSCAPE, WINDOW
from en17037cli.standard import Thresholds

THRESHOLDS = Thresholds.from_dict(standard.THRESHOLDS)
R_NORMAL = ((1.52 - 1) / (1.52 + 1)) ** 2  # a pane's Fresnel reflectance at normal incidence


# --- patches.py -----------------------------------------------------------------------------------


def test_reinhart_layout_by_hand():
    assert patches.reinhart_bins(1) == 146 and patches.reinhart_bins(2) == 578
    assert patches.row_counts(1).tolist() == [30, 30, 24, 24, 18, 12, 6, 1]
    assert patches.row_counts(2).tolist() == [60, 60, 60, 60, 48, 48, 48, 48, 36, 36, 24, 24, 12, 12, 1]
    assert patches.row_width_deg(1) == 12.0 and patches.row_width_deg(2) == 90.0 / 14.5
    for mf in (1, 2):  # the patches tile the upper hemisphere: 2 pi sr
        assert patches.patch_solid_angles(mf).sum() == pytest.approx(2 * np.pi, rel=1e-12)
    om = patches.patch_solid_angles(1)
    s = math.sin
    assert om[0] == pytest.approx(2 * math.pi * s(math.radians(12)) / 30, rel=1e-12)
    assert om[138] == pytest.approx(2 * math.pi * (s(math.radians(84)) - s(math.radians(72))) / 6, rel=1e-12)
    assert om[144] == pytest.approx(2 * math.pi * (1 - s(math.radians(84))), rel=1e-12)


def _dir(alt, az):
    a, z = math.radians(alt), math.radians(az)
    return [math.sin(z) * math.cos(a), math.cos(z) * math.cos(a), math.sin(a)]


@pytest.mark.parametrize("alt, az, mf, patch", [
    (6.0, 0.0, 1, 0), (6.0, 5.9, 1, 0), (6.0, 6.1, 1, 1), (6.0, 85.0, 1, 7), (6.0, 90.0, 1, 8), (6.0, 353.9, 1, 29), (6.0, 354.1, 1, 0),
    (18.0, 0.0, 1, 30), (78.0, 60.0, 1, 139), (78.0, 29.0, 1, 138), (85.0, 200.0, 1, 144), (90.0, 0.0, 1, 144),
    (-5.0, 10.0, 1, -1), (0.0, 10.0, 1, -1), (3.0, 3.1, 2, 1), (3.0, 0.0, 2, 0), (7.0, 0.0, 2, 60), (87.0, 100.0, 2, 576)])
def test_patch_bin_by_hand(alt, az, mf, patch):
    # rows of 90 / (7 MF + 0.5) deg, patches centred on multiples of 360 / n clockwise from +y (north)
    assert int(patches.patch_bin(_dir(alt, az), mf)[0]) == patch


def test_patch_directions_are_the_centres():
    d = patches.patch_directions(1)
    assert d.shape == (146, 3)
    assert d[0].tolist() == [0.0, 0.0, -1.0] and d[-1].tolist() == [0.0, 0.0, 1.0]
    assert d[1] == pytest.approx(_dir(6.0, 0.0), abs=1e-12) and d[2] == pytest.approx(_dir(6.0, 12.0), abs=1e-12)
    assert d[31] == pytest.approx(_dir(18.0, 0.0), abs=1e-12) and d[140] == pytest.approx(_dir(78.0, 60.0), abs=1e-12)
    # a unit vector a rounding over 1 in z is the zenith's, one under -1 the ground's
    assert patches.patch_bin([[0.0, 0.0, 1.0000000000000002], [0.0, 0.0, -1.0000000000000002]], 1).tolist() == [144, -1]
    for mf in (1, 2):  # each centre lies in its own patch
        assert patches.patch_bin(patches.patch_directions(mf)[1:], mf).tolist() == list(range(144 * mf * mf + 1))


# --- sky.py ---------------------------------------------------------------------------------------


def test_cie_overcast_by_hand():
    assert sky.cie_overcast_luminance(np.array([0.0, math.pi / 6, math.pi / 2])).tolist() == pytest.approx(
        [1 / 3, 2 / 3, 1.0], abs=1e-15)
    assert float(sky.overcast_horizontal_illuminance(9)) == pytest.approx(7 * math.pi, rel=1e-15)


def test_subdivide_by_hand():
    t = np.array([[[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]])
    out = sky.subdivide(t, 2)
    got = sorted(sorted(map(tuple, x[:, :2].tolist())) for x in out)
    want = sorted(sorted(x) for x in ([(0, 0), (1, 0), (0, 1)], [(1, 0), (2, 0), (1, 1)], [(0, 1), (1, 1), (0, 2)],
                                      [(1, 0), (1, 1), (0, 1)]))
    assert got == want
    assert sky.subdivide(np.tile(t, (2, 1, 1)) + [[[0, 0, 0]], [[0, 0, 5.0]]], 3).shape == (18, 3, 3)
    assert sky.subdivide(t + [0, 0, 5.0], 3)[:, :, 2].tolist() == [[5.0] * 3] * 9


def _brute_sky_component(p, x0, x1, y0, y1, h, n=400, normal=(0.0, 0.0, 1.0)):
    """The horizontal opening [x0, x1] x [y0, y1] at height h, seen from p: 9 / (7 pi) sum of
    L(g) cos(theta) cos(theta_w) dA / r^2 over n x n cells (midpoint rule over the area)."""
    xs = x0 + (np.arange(n) + 0.5) * (x1 - x0) / n
    ys = y0 + (np.arange(n) + 0.5) * (y1 - y0) / n
    X, Y = np.meshgrid(xs, ys)
    d = np.stack([X - p[0], Y - p[1], np.full_like(X, h - p[2])], axis=-1)
    r = np.linalg.norm(d, axis=-1)
    u = d / r[..., None]
    dw = np.abs(u[..., 2]) * (x1 - x0) * (y1 - y0) / n / n / r**2
    cos_t = u @ np.asarray(normal)
    w = np.where((u[..., 2] > 0) & (cos_t > 0), (1 + 2 * u[..., 2]) / 3 * cos_t, 0.0)
    return float((w * dw).sum() * 9 / (7 * math.pi))


def test_sky_component_of_a_roof_opening_against_a_brute_force():
    tris = np.array([[[0.0, 0.0, 3.0], [2.0, 0.0, 3.0], [2.0, 1.0, 3.0]], [[0.0, 0.0, 3.0], [2.0, 1.0, 3.0], [0.0, 1.0, 3.0]]])
    pts = np.column_stack([np.linspace(-2.0, 4.0, 20), np.full(20, 0.4), np.full(20, 0.85)])  # 20: two blocks of 16
    got = sky.sky_component(pts, tris, 48)
    want = [_brute_sky_component(p, 0.0, 2.0, 0.0, 1.0, 3.0) for p in pts]
    assert got.tolist() == pytest.approx(want, rel=1e-4)
    # a receiving plane facing +x sees the part of the opening in front of it only (x > p_x)
    got = sky.sky_component(pts[[3, 10]], tris, 48, normal=(1.0, 0.0, 0.0))
    want = [_brute_sky_component(p, 0.0, 2.0, 0.0, 1.0, 3.0, normal=(1.0, 0.0, 0.0)) for p in pts[[3, 10]]]
    assert got.tolist() == pytest.approx(want, rel=2e-3)  # the plane cuts the pieces: a coarser midpoint rule
    # an opening below the point adds nothing
    assert sky.sky_component([[0.5, 0.5, 4.0]], tris).tolist() == [0.0]


def _pane(tn, c, n=1.52):
    """Radiance's glass by Snell and Fresnel written out: (transmittance, reflectance)."""
    ct = math.sqrt(1 - (1 - c * c) / (n * n))
    d = tn ** (1 / ct)
    t = r = 0.0
    for f in (((c - n * ct) / (c + n * ct)) ** 2, ((ct - n * c) / (ct + n * c)) ** 2):
        t += 0.5 * (1 - f) ** 2 * d / (1 - f * f * d * d)
        r += 0.5 * f * (1 + (1 - 2 * f) * d * d) / (1 - f * f * d * d)
    return t, r


@pytest.mark.parametrize("tv", [0.7, 0.3, 0.9])
def test_glass_transmittance_and_reflectance_by_fresnel(tv):
    tn = float(radiance.glass_transmissivity(tv))
    c = np.array([1.0, 0.8, 0.5, 0.2, 0.05])
    want = np.array([_pane(tn, x) for x in c])
    assert sky.glass_transmittance(c, tv).tolist() == pytest.approx(want[:, 0].tolist(), rel=1e-12)
    assert sky.glass_reflectance(c, tv).tolist() == pytest.approx(want[:, 1].tolist(), rel=1e-12)
    assert float(sky.glass_transmittance(1.0, tv)) == pytest.approx(tv, abs=3e-7)  # tv at normal incidence
    assert float(sky.glass_transmittance(0.0, tv)) == pytest.approx(_pane(tn, 1e-9)[0], abs=1e-15)


def test_a_clear_pane_that_absorbs_nothing_reflects_what_it_does_not_transmit():
    tv = (1 - R_NORMAL) / (1 + R_NORMAL)  # tn = 1: no absorption, so rho + tau = 1 at every angle
    c = np.linspace(0.02, 1.0, 7)
    assert float(radiance.glass_transmissivity(tv)) == pytest.approx(1.0, abs=1e-8)
    assert (sky.glass_transmittance(c, tv) + sky.glass_reflectance(c, tv)).tolist() == pytest.approx([1.0] * 7, abs=1e-7)


def test_open_openings_and_opaque_glazing():
    c = np.array([1.0, 0.3])
    assert sky.glass_transmittance(c, 1.0).tolist() == [1.0, 1.0] and sky.glass_reflectance(c, 1.0).tolist() == [0.0, 0.0]
    assert sky.glass_transmittance(c, 0.999).tolist() == [1.0, 1.0]
    assert sky.glass_transmittance(c, 0.0).tolist() == [0.0, 0.0]
    assert sky.glass_transmittance(c, np.array([0.7, 1.0]))[1] == 1.0


def test_transmittance_table_and_its_error():
    sky.transmittance_table.cache_clear()
    c, t, err = sky.transmittance_table(0.7)
    assert len(c) == 4097 and c[0] == 0.0 and c[-1] == 1.0 and c[1] == pytest.approx(1 / 4096, rel=1e-12)
    assert t.tolist() == sky.glass_transmittance(c, 0.7).tolist()
    # the error is twice the largest gap between the formula and the chords at the midpoints
    x = np.linspace(0.0, 1.0, 200001)
    gap = np.max(np.abs(np.interp(x, c, t) - sky.glass_transmittance(x, 0.7)))
    # the fine grid comes within (2 x 2.5e-6 / 2.4e-4)^2 = 4e-4 of each midpoint's gap
    assert err / 2 == pytest.approx(gap, rel=1e-3) and err < 1e-4


# --- radiance.py (the pure functions) -------------------------------------------------------------


def test_glass_transmissivity_inverts_the_normal_transmittance():
    tn = radiance.glass_transmissivity(np.array([0.0, 0.1, 0.5, 0.88]))
    assert tn[0] == 0.0
    tv = tn[1:] * (1 - R_NORMAL) ** 2 / (1 - R_NORMAL**2 * tn[1:] ** 2)
    assert tv.tolist() == pytest.approx([0.1, 0.5, 0.88], abs=3e-7)


def test_illuminance_by_hand():
    got = radiance.illuminance([[1.0, 1.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]])
    assert got.tolist() == pytest.approx([179.0, 179 * 0.265, 179 * 0.670, 179 * 0.13], rel=1e-12)


def test_rays_and_replicate_divisions():
    raw = np.frombuffer(radiance.rays(np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]), (0.0, 1.0, 0.0), 2)).reshape(-1, 6)
    assert raw.tolist() == [[1, 2, 3, 0, 1, 0], [4, 5, 6, 0, 1, 0]] * 2
    assert np.frombuffer(radiance.rays([[1.0, 2.0, 3.0]])).tolist() == [1, 2, 3, 0, 0, 1]
    assert radiance.replicate_divisions(512, 3) == [529, 576, 625]
    assert radiance.replicate_divisions(256, 2) == [256, 289] and radiance.replicate_divisions(0, 2) == [1, 4]


def _scene(tris, layers, rooms=(), optics=None):
    v = np.asarray(tris, float).reshape(-1, 3)
    return SimpleNamespace(vertices=v, triangles=np.arange(len(v)).reshape(-1, 3), layer=np.asarray(layers), rooms=list(rooms),
                           optics=optics)


def _flat(z, up=True, x=0.0):
    a, b, c = (x, 0.0, z), (x + 1.0, 0.0, z), (x, 1.0, z)
    return [a, b, c] if up else [a, c, b]


def test_surface_kinds_by_hand():
    room = SimpleNamespace(floor=shapely.box(0, 0, 4, 4), floor_z=0.0, ceiling_z=3.0)
    high = SimpleNamespace(floor=shapely.box(10, 0, 14, 4), floor_z=0.0, ceiling_z=float("inf"))
    t44 = math.radians(44.0)  # a face tilted 44 deg from horizontal: its normal is 44 deg from vertical, flat
    tilted = [(20, 0, 0), (21, 0, 0), (20, math.cos(t44), math.sin(t44))]
    tris = [_flat(0.0), _flat(0.0, up=False), _flat(3.0), _flat(3.0, up=False), _flat(1.5), _flat(1.5, up=False),
            _flat(0.03), _flat(2.97, up=True), [(0, 0, 0), (1, 0, 0), (0, 0, 1)], tilted, _flat(0.0, x=5.0),
            _flat(3.0, x=10.5), _flat(0.0), _flat(0.0), _flat(0.0)]
    layers = [INTERIOR] * 12 + [LANDSCAPE, GROUND, WINDOW]
    kinds = radiance.surface_kinds(_scene(tris, layers, [room, high]))
    # floor level: floor either way; ceiling level: ceiling either way; between: by the normal; walls; the
    # tilted face is flat (its normal within 45 deg of vertical); outside every floor: by the normal; a room
    # with no ceiling has no ceiling level; landscape 3, ground 4, glazing 5
    assert kinds.tolist() == [0, 0, 2, 2, 0, 2, 0, 2, 1, 0, 0, 0, 3, 4, 5]
    steep = [(20, 0, 0), (21, 0, 0), (20, math.cos(math.radians(46.0)), math.sin(math.radians(46.0)))]
    assert radiance.surface_kinds(_scene([steep], [INTERIOR])).tolist() == [1]


def test_face_optics_defaults_and_layer_rules():
    tris = [[(0, 0, 0), (1, 0, 0), (0, 0, 1)], _flat(0.0, x=9.0), _flat(0.0), _flat(0.0), _flat(0.0), _flat(0.0)]
    layers = [INTERIOR, INTERIOR, LANDSCAPE, GROUND, WINDOW, WINDOW]
    refl = {"floor": 0.2, "walls": 0.5, "ceiling": 0.7, "landscape": 0.3, "ground": 0.1}
    kind, value = radiance.face_optics(_scene(tris, layers), refl, 0.6)
    assert kind.tolist() == [1, 0, 3, 4, 5, 5] and value.tolist() == [0.5, 0.2, 0.3, 0.1, 0.6, 0.6]
    optics = np.array([[0.9, np.nan], [np.nan, np.nan], [np.nan, 0.4], [0.05, np.nan], [0.8, 0.45], [np.nan, np.nan]])
    _, value = radiance.face_optics(_scene(tris, layers, optics=optics), refl, 0.6)
    # a rule's reflectance for opaque faces, its transmittance for glazing, the default where it gives none
    assert value.tolist() == [0.9, 0.2, 0.3, 0.05, 0.45, 0.6]


# --- assess.py ------------------------------------------------------------------------------------


def test_student_t_and_the_mean_of_replicates():
    assert assess.t975(1) == 12.706 and assess.t975(2) == 4.303 and assess.t975(30) == 2.042
    assert assess.t975(31) == 1.96 and assess.t975(0) == 1.96
    m, e = assess.mean_and_error(np.array([[1.0, 2.0, 3.0], [2.0, 2.0, 2.0]]))
    assert m.tolist() == [2.0, 2.0] and e.tolist() == pytest.approx([4.303 / math.sqrt(3), 0.0], rel=1e-12)
    m, e = assess.mean_and_error(np.array([[4.0], [5.0]]))
    assert m.tolist() == [4.0, 5.0] and e.tolist() == [0.0, 0.0]


def test_reference_plane_is_the_floor_inset_at_its_height(monkeypatch):
    seen = {}

    def grid(poly, spacing, offset):
        seen.update(area=poly.area, bounds=poly.bounds, spacing=spacing, offset=offset)
        return np.array([[1.0, 1.0], [2.0, 1.0]])

    monkeypatch.setattr(assess, "grid_points", grid)
    floor = shapely.Polygon([(0, 0), (4, 0), (4, 2), (2, 2), (2, 4), (0, 4)])  # an L: its inner corner stays square
    room = SimpleNamespace(floor=floor, floor_z=1.5)
    s = SimpleNamespace(wall_margin_m=0.5, grid_spacing_m=0.3, grid_offset=0.25, reference_plane_m=0.85)
    assert assess.reference_plane(room, s).tolist() == [[1.0, 1.0, 2.35], [2.0, 1.0, 2.35]]
    assert seen == {"area": pytest.approx(5.0, abs=1e-12), "bounds": (0.5, 0.5, 3.5, 3.5), "spacing": 0.3, "offset": 0.25}
    with pytest.raises(NotAssessable, match=r"daylight.wall_margin_m = 2.0 m\) is empty"):
        assess.reference_plane(room, SimpleNamespace(**{**vars(s), "wall_margin_m": 2.0}))


def test_shares_and_judge_by_hand():
    assert assess.targets(THRESHOLDS) == ({"minimum": 300.0, "medium": 500.0, "high": 750.0},
                                          {"minimum": 100.0, "medium": 300.0, "high": 500.0})
    assert assess.shares_from_points({"a": np.array([True, False, True, True]), "b": np.zeros(0, bool)}) == {"a": 0.75, "b": 0.0}
    t = {"minimum": 0.75, "medium": 0.625, "high": 0.125}
    m = {"minimum": 0.96875, "medium": 0.9, "high": 0.25}
    zero = dict.fromkeys(t, 0.0)
    assert assess.judge(t, m, zero, zero) == (1, False)
    assert assess.judge(t, m, {**zero, "medium": 0.125}, zero) == (1, True)  # 0.625 is 0.125 from 0.5
    assert assess.judge(t, m, {**zero, "medium": 0.124}, zero) == (1, False)
    assert assess.judge(t, m, zero, {**zero, "medium": 0.05}) == (1, True)  # 0.90 is 0.05 from 0.95
    assert assess.judge(t, m, zero, {**zero, "minimum": 0.01}) == (1, False)
    assert assess.judge(t, m, {**zero, "high": 0.4}, zero) == (1, True)
    assert assess.judge({**t, "medium": 0.5}, m, zero, zero) == (1, False)  # on the share needed, with no error


def test_daylight_factor_room_by_hand():
    # median 10 000 lx: D_T 3 / 5 / 7.5 %, D_TM 1 / 3 / 5 %; D = 100 (SC + R), its error 100 (bound + interval)
    sc = SimpleNamespace(value=np.array([0.05, 0.02, 0.005, 0.0]), bound=np.array([0.0, 0.001, 0.0, 0.0]))
    refl = SimpleNamespace(value=np.array([0.03, 0.015, 0.004, 0.009]), error=np.array([0.0, 0.0, 0.0005, 0.0]),
                           rays=np.array([10, 20, 30, 40]))
    r = assess.daylight_factor_room(np.zeros((4, 3)), sc, refl, 10000.0, "weather", THRESHOLDS, {"ab": 3})
    assert r.daylight_factor_pct.tolist() == pytest.approx([8.0, 3.5, 0.9, 0.9], abs=1e-12)
    assert r.daylight_factor_err_pct.tolist() == pytest.approx([0.0, 0.1, 0.05, 0.0], abs=1e-12)
    assert r.target_share == {"minimum": 0.5, "medium": 0.25, "high": 0.25}
    assert r.minimum_share == {"minimum": 0.5, "medium": 0.5, "high": 0.25}
    # within its error of D_TM (1 %): the third point (0.9 +- 0.05 is not); of D_T 3 %: none (3.5 - 0.1)
    assert r.target_share_err == {"minimum": 0.0, "medium": 0.0, "high": 0.0}
    assert r.minimum_share_err == {"minimum": 0.0, "medium": 0.0, "high": 0.0}
    assert r.level == 0 and r.near_threshold is False and r.radiance == {"ab": 3, "rays": 100}
    assert r.sky_component_pct.tolist() == pytest.approx([5.0, 2.0, 0.5, 0.0]) and r.median_source == "weather"
    assert r.reflected_err_pct.tolist() == pytest.approx([0.0, 0.0, 0.05, 0.0])
    assert r.sky_component_bound_pct.tolist() == pytest.approx([0.0, 0.1, 0.0, 0.0])
    assert r.reflected_pct.tolist() == pytest.approx([3.0, 1.5, 0.4, 0.9])
    # a point exactly at D_TM's error: 0.95 +- 0.05 reaches 1 %
    sc.bound = np.array([0.0, 0.0, 0.0005, 0.0])
    r = assess.daylight_factor_room(np.zeros((4, 3)), sc, refl, 10000.0, "weather", THRESHOLDS, {})
    assert r.minimum_share_err["minimum"] == 0.25
    e = assess.daylight_factor_room(np.zeros((0, 3)), SimpleNamespace(value=np.zeros(0), bound=np.zeros(0)),
                                    SimpleNamespace(value=np.zeros(0), error=np.zeros(0), rays=np.zeros(0, int)), 1e4, "x",
                                    THRESHOLDS, {})
    assert e.target_share == {"minimum": 0.0, "medium": 0.0, "high": 0.0} and e.level == 0


def test_upper_median_and_shares_of_hours_by_hand():
    assert assess.share_above(np.array([[100.0, 300.0, 299.9, 500.0]]), 300.0).tolist() == [0.5]
    assert assess.upper_median([0.1, 0.9, 0.5, 0.3], 0.5) == 0.5  # the 2nd largest of 4
    assert assess.upper_median([0.1, 0.9, 0.5], 0.5) == 0.5  # the 2nd largest of 3 (ceil 1.5)
    assert assess.upper_median([0.1, 0.9, 0.5, 0.3], 0.75) == 0.3 and assess.upper_median([0.2], 1.0) == 0.2
    assert assess.upper_median([], 0.5) == 0.0 and assess.upper_median([0.4, 0.8], 0.0) == 0.8
    # 2 points x 4 hours; hours first: a point counts where it reaches the level on >= half the hours
    e = np.array([[600.0, 600.0, 0.0, 0.0], [800.0, 0.0, 0.0, 0.0]])
    t, m, per = assess.climate_shares(e, THRESHOLDS, "hours_first")
    assert per[500.0].tolist() == [0.5, 0.25] and sorted(per) == [100.0, 300.0, 500.0, 750.0]
    assert t == {"minimum": 0.5, "medium": 0.5, "high": 0.0} and m == {"minimum": 0.5, "medium": 0.5, "high": 0.5}
    t, m, _ = assess.climate_shares(e, THRESHOLDS, "points_first")
    # per hour the share reaching 500 lx: 1, 0.5, 0, 0: reached on half the hours: 0.5
    assert t == {"minimum": 0.5, "medium": 0.5, "high": 0.0} and m["high"] == 0.5
    t, _, _ = assess.climate_shares(np.zeros((0, 4)), THRESHOLDS, "points_first")
    assert t == {"minimum": 0.0, "medium": 0.0, "high": 0.0}
    t, _, _ = assess.climate_shares(np.zeros((0, 4)), THRESHOLDS, "hours_first")
    assert t == {"minimum": 0.0, "medium": 0.0, "high": 0.0}


# --- assess.py: the shares on their thresholds (issue 46) -------------------------------------------


def _df_room(df_pct, err_pct, median_lx, thresholds=THRESHOLDS):
    sc = SimpleNamespace(value=np.asarray(df_pct, float) / 100.0, bound=np.asarray(err_pct, float) / 100.0)
    n = len(df_pct)
    refl = SimpleNamespace(value=np.zeros(n), error=np.zeros(n), rays=np.zeros(n, int))
    return assess.daylight_factor_room(np.zeros((n, 3)), sc, refl, median_lx, "weather", thresholds, {})


def test_daylight_factor_shares_count_a_point_exactly_on_a_threshold():
    # median 12 800 lx: D_T 2.34375 / 3.90625 / 5.859375 %, D_TM 0.78125 / 2.34375 / 3.90625 % (exact in binary)
    r = _df_room([2.34375, 0.78125, 3.90625, 5.859375], [0.0] * 4, 12800.0)
    assert r.target_share == {"minimum": 0.75, "medium": 0.5, "high": 0.25}
    assert r.minimum_share == {"minimum": 1.0, "medium": 0.75, "high": 0.5}
    # no error: only a point exactly on a threshold lies within its error of it
    assert r.target_share_err == {"minimum": 0.25, "medium": 0.25, "high": 0.25}
    assert r.minimum_share_err == {"minimum": 0.25, "medium": 0.25, "high": 0.25}
    # four times the median: D_T 0.5859375 %, D_TM 0.1953125 % (below 1 %)
    r = _df_room([0.5859375, 0.1953125, 10.0], [0.0] * 3, 51200.0)
    assert r.target_share_err["minimum"] == pytest.approx(1 / 3) and r.minimum_share_err["minimum"] == pytest.approx(1 / 3)
    # an empty plane: every share and error 0 (no mean of nothing)
    e = _df_room([], [], 12800.0)
    for d in (e.target_share, e.minimum_share, e.target_share_err, e.minimum_share_err):
        assert d == {"minimum": 0.0, "medium": 0.0, "high": 0.0}


def test_a_threshold_of_zero_has_no_error_share():
    # a practice that asks no minimum target (D_TM 0 at the minimum level): every point reaches it, none is
    # within its error of it, even a point of D = 0 with no error
    th = {k: dict(v) for k, v in standard.THRESHOLDS.items()}
    th["daylight_minimum_target_lx"]["minimum"] = 0.0
    th["daylight_target_lx"]["minimum"] = 0.0
    r = _df_room([0.0, 1.0], [0.0, 0.0], 12800.0, Thresholds.from_dict(th))
    assert r.minimum_share["minimum"] == 1.0 and r.minimum_share_err["minimum"] == 0.0
    assert r.target_share["minimum"] == 1.0 and r.target_share_err["minimum"] == 0.0


def test_judge_near_the_minimum_level_alone():
    zero = {"minimum": 0.0, "medium": 0.0, "high": 0.0}
    t = {"minimum": 0.55, "medium": 0.1, "high": 0.0}
    m = {"minimum": 0.99, "medium": 0.2, "high": 0.0}
    assert assess.judge(t, m, {**zero, "minimum": 0.1}, zero) == (1, True)  # 0.55 is 0.05 from 0.5
    assert assess.judge(t, m, zero, {**zero, "minimum": 0.05}) == (1, True)  # 0.99 is 0.04 from 0.95
    assert assess.judge(t, m, {**zero, "minimum": 0.04}, zero) == (1, False)


def test_two_replicates_have_an_interval():
    m, e = assess.mean_and_error(np.array([[1.0, 3.0]]))
    assert m.tolist() == [2.0] and e.tolist() == pytest.approx([12.706 * math.sqrt(2.0) / math.sqrt(2.0)], rel=1e-12)


def test_points_first_counts_an_hour_exactly_at_the_illuminance():
    # two points, two hours; 500 lx exactly is reached
    e = np.array([[500.0, 0.0], [500.0, 750.0]])
    t, m, _ = assess.climate_shares(e, THRESHOLDS, "points_first")
    assert t == {"minimum": 1.0, "medium": 1.0, "high": 0.5} and m == {"minimum": 1.0, "medium": 1.0, "high": 1.0}
