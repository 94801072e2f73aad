"""The horizontal sight angle in plan (``view.sight_angle_method: plan``) against closed forms and a
brute force, and ``view.mullions_block``.

Box room (en17037cli.samples.BoxRoom): glazing x in [-1, 1] in the plane y = 0, reveals of depth t
(the wall's thickness) from y = 0 to y = t, room at y > t; a mullion is an opaque plate at
y = MULLION_GAP (room side), x in [xm - w/2, xm + w/2]. The closed forms below take the azimuths
of the edges that bound the view with atan2, by hand.
"""
from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from en17037cli.criteria.view.frames import room_geometry
from en17037cli.criteria.view.sight_angle import horizontal
from en17037cli.samples import MULLION_GAP, BoxRoom

#: Plan against a closed form [deg]: both are float64 arithmetic on the same few coordinates
#: (a few units of round-off in 1e-16 rad); 1e-6 deg is the issue's target, far above both.
EXACT_DEG = 1e-6
#: The closed form's own round-off [deg], for checking the engine's error bound against it.
CLOSED_FORM_ROUNDOFF_DEG = 1e-12
WIDTH = 0.05  # BoxRoom's mullion width [m]
_EXAMPLE = itertools.count()  # a project directory per hypothesis example


def closed_form_deg(x0: float, y0: float, reveal: float, mullions=(), width: float = WIDTH) -> float:
    """Sight angle [deg] of the box room from (x0, y0): the window's interval between its tighter
    jamb edges (inner y = t or outer y = 0), minus each mullion plate's shadow within it."""
    def az(x, y):
        return np.arctan2(y - y0, x - x0)  # seen from the room (y0 > t), every edge lies in (-pi, 0)

    right = min(az(1.0, reveal), az(1.0, 0.0))  # +x side: the smaller azimuth is the tighter edge
    left = max(az(-1.0, reveal), az(-1.0, 0.0))
    total = right - left
    for xm in mullions:
        s0, s1 = az(xm - width / 2, MULLION_GAP), az(xm + width / 2, MULLION_GAP)
        total -= max(0.0, min(s1, right) - max(s0, left))
    return float(np.degrees(total))


def sight(b, pts_world, **view):
    """SightAngles of world points (n, 3) [m] with view settings replaced."""
    vs = dataclasses.replace(b.view_cfg, **view)
    rg = room_geometry(b.scene, b.room, vs.frame_depth_m)
    return horizontal(b.view_rays, rg, b.scene.to_local(np.asarray(pts_world, float)), vs)


def gap_point(y0: float, gap_deg: float, reveal: float, x_edge: float) -> float:
    """x0 at depth y0 from which the gap between a mullion's edge (x_edge, MULLION_GAP) and the right
    jamb's inner edge (1, reveal) subtends ``gap_deg``; by bisection on the closed form."""
    def gap(x0):
        return np.degrees(np.arctan2(reveal - y0, 1.0 - x0) - np.arctan2(MULLION_GAP - y0, x_edge - x0))

    lo, hi = 1.0, 1.99  # the gap closes as the point moves out to the line through both edges
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if gap(mid) > gap_deg else (lo, mid)
    return 0.5 * (lo + hi)


def test_a_005_deg_gap_between_mullion_and_jamb_is_exact(build):
    """A mullion 0.2 m from the jamb, seen from where the gap between them subtends 0.05 deg (half
    the fan's 0.1 deg step): the plan sight angle matches the closed form to 1e-6 deg. (The fan,
    view.sight_angle_method: fan, misses the gap from (1.71, 1.3, 1.7): 0.05 deg off, estimate 2e-4.)"""
    t, xm = 0.3, 0.775  # the mullion's right edge at x = 0.8, 0.2 m from the jamb
    b = build(BoxRoom(wall_thickness=t, mullions=(xm,)))
    pts = []
    for y0, z in ((t + 0.8, 1.2), (t + 1.0, 1.7), (t + 1.2, 1.2)):
        x0 = gap_point(y0, 0.05, t, xm + WIDTH / 2)
        if x0 < 1.95:  # inside the room (x < 2) with room to spare
            pts.append((x0, y0, z))
    assert len(pts) >= 2
    r = sight(b, pts)
    for i, (x0, y0, _) in enumerate(pts):
        exact = closed_form_deg(x0, y0, t, (xm,))
        gap = np.degrees(np.arctan2(t - y0, 1.0 - x0) - np.arctan2(MULLION_GAP - y0, xm + WIDTH / 2 - x0))
        assert abs(gap - 0.05) < 1e-9  # the point sees the gap under 0.05 deg (bisection to 1e-12 deg)
        assert abs(r.angle_deg[i] - exact) <= EXACT_DEG, (pts[i], r.angle_deg[i], exact)
        assert abs(r.angle_deg[i] - exact) <= r.angle_err_deg[i] + CLOSED_FORM_ROUNDOFF_DEG  # the bound covers it
        assert r.angle_err_deg[i] <= 1e-9  # round-off, not sampling


@pytest.mark.parametrize("t", [0.0, 0.2])
def test_two_50_mm_mullions_block_or_not(build, t):
    """Two 50 mm mullions: with view.mullions_block true their shadows are cut out exactly; with
    false the opening is measured between its reveals."""
    mullions = (-0.35, 0.35)
    b = build(BoxRoom(wall_thickness=t, mullions=mullions, depth=8.0))
    pts = [(0.0, t + 7.2, 1.2), (0.6, t + 5.7, 1.7), (-0.8, t + 6.7, 1.2), (0.3, t + 1.7, 1.2), (1.5, t + 0.8, 1.7)]
    blocked, open_ = sight(b, pts), sight(b, pts, mullions_block=False)
    for i, (x0, y0, _) in enumerate(pts):
        with_m, without = closed_form_deg(x0, y0, t, mullions), closed_form_deg(x0, y0, t)
        assert with_m < without - 0.1  # the mullions matter from every point
        assert abs(blocked.angle_deg[i] - with_m) <= EXACT_DEG, (i, blocked.angle_deg[i], with_m)
        assert abs(open_.angle_deg[i] - without) <= EXACT_DEG, (i, open_.angle_deg[i], without)


def test_mullions_block_false_with_the_fan_is_an_input_error(build):
    """The fan's rays stop at a mullion: the project must say plan to leave mullions out."""
    from en17037cli.errors import InputError

    with pytest.raises(InputError, match="view.mullions_block: false needs view.sight_angle_method: plan"):
        build(BoxRoom(), overrides=["view.sight_angle_method=fan", "view.mullions_block=false"])


def brute_force_deg(x0: float, y0: float, reveal: float, mullions, block: bool, n: int = 200_001) -> tuple[float, float]:
    """Sight angle [deg] by a fan of n rays over the half-plane towards the window, each intersected
    with the plan's segments in numpy (independent of the engine); returns (angle, step) [deg].

    A ray leaves when it crosses the glazing (y = 0, |x| <= 1) before any opaque segment: the
    reveals (x = +-1, 0 <= y <= t), the wall's inner face (y = t, 1 <= |x| <= 2) and the mullion
    plates (y = MULLION_GAP)."""
    step = np.pi / n
    th = -np.pi + (np.arange(n) + 0.5) * step  # midpoints over (-pi, 0): towards y < y0
    d = np.stack([np.cos(th), np.sin(th)], axis=1)
    segs = []
    if reveal > 0:
        segs += [((1.0, 0.0), (1.0, reveal)), ((-1.0, 0.0), (-1.0, reveal)),
                 ((1.0, reveal), (2.0, reveal)), ((-2.0, reveal), (-1.0, reveal))]
    if block:
        segs += [((xm - WIDTH / 2, MULLION_GAP), (xm + WIDTH / 2, MULLION_GAP)) for xm in mullions]

    def hit(a, b):
        """Distance along each ray to the segment a-b (inf where missed), by Cramer's rule."""
        p = np.array([x0, y0])
        a, b = np.asarray(a), np.asarray(b)
        e = b - a
        den = d[:, 0] * (-e[1]) - d[:, 1] * (-e[0])
        rhs = a - p
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (rhs[0] * (-e[1]) - rhs[1] * (-e[0])) / den
            u = (d[:, 0] * rhs[1] - d[:, 1] * rhs[0]) / den
        return np.where((np.abs(den) > 0) & (t > 0) & (u >= 0) & (u <= 1), t, np.inf)

    t_glass = hit((-1.0, 0.0), (1.0, 0.0))
    t_opaque = np.min([hit(a, b) for a, b in segs], axis=0) if segs else np.full(n, np.inf)
    leaves = np.isfinite(t_glass) & (t_glass < t_opaque)
    return float(np.degrees(leaves.sum() * step)), float(np.degrees(step))


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_plan_matches_a_brute_force_fan_of_segments(build, data):
    """Random viewpoints, mullion positions and reveals: plan equals a fan of 200,001 2D rays in
    the test, within the fan's resolution."""
    t = data.draw(st.sampled_from([0.0, 0.15, 0.3]), label="wall thickness")
    k = data.draw(st.integers(0, 3), label="mullions")
    slots = data.draw(st.lists(st.integers(0, 17), min_size=k, max_size=k, unique=True), label="slots")
    jitter = data.draw(st.floats(0.0, 0.04), label="jitter")
    mullions = tuple(sorted(-0.9 + 0.1 * s + jitter for s in slots))  # 10 cm apart at least: 5 cm plates never overlap
    block = data.draw(st.booleans(), label="mullions_block")
    pts = [(data.draw(st.floats(-1.9, 1.9), label="x"), data.draw(st.floats(t + 0.05, t + 5.9), label="y"),
            data.draw(st.sampled_from([1.2, 1.7]), label="z")) for _ in range(3)]
    b = build(BoxRoom(wall_thickness=t, mullions=mullions), sub=f"h{next(_EXAMPLE)}")
    r = sight(b, pts, mullions_block=block)
    for i, (x0, y0, _) in enumerate(pts):
        brute, step = brute_force_deg(x0, y0, t, mullions, block)
        # each change of leaves / blocked along the brute force's fan is off by at most half a
        # step: at most 2 jamb edges and 2 per mullion
        allowed = (2 + 2 * len(mullions)) * step / 2 + 1e-9
        assert abs(r.angle_deg[i] - brute) <= allowed, (pts[i], r.angle_deg[i], brute, allowed)


def test_an_interior_fin_beyond_the_frame_depth_is_found_by_the_rays(build, tmp_path):
    """A fin of the building (interior layer) 1 to 3 m in front of the glazing, beyond
    view.frame_depth_m: plan does not cut it, the fan's rays find it and bisect its edges."""
    import tolerances as tol

    b0 = build(BoxRoom(), sub="fin")
    obj = b0.project.directory / "model.obj"
    text = obj.read_text()
    n = sum(1 for line in text.splitlines() if line.startswith("v "))
    fin = [(0.6, -1.0, 0.0), (0.6, -3.0, 0.0), (0.6, -3.0, 3.0), (0.6, -1.0, 3.0)]
    obj.write_text(text + "o room\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in fin)
                   + "f " + " ".join(str(n + i + 1) for i in range(4)) + "\n")
    from conftest import Built

    b = Built(b0.project.path)
    pts = [(0.0, 3.0, 1.2), (-0.5, 2.0, 1.7)]
    r = sight(b, pts)
    for i, (x0, y0, _) in enumerate(pts):
        az0, az1 = np.arctan2(-3.0 - y0, 0.6 - x0), np.arctan2(-1.0 - y0, 0.6 - x0)  # the fin's shadow
        left, right = np.arctan2(-y0, -1.0 - x0), np.arctan2(-y0, 1.0 - x0)  # the window's interval
        exact = np.degrees(right - left - max(0.0, min(az1, right) - max(az0, left)))
        assert exact < closed_form_deg(x0, y0, 0.0) - 1.0  # the fin matters
        # two edges bisected to 1e-4 deg by the rays
        assert abs(r.angle_deg[i] - exact) <= tol.SIGHT_ANGLE_DEG, (i, r.angle_deg[i], exact)
        assert abs(r.angle_deg[i] - exact) <= r.angle_err_deg[i] + CLOSED_FORM_ROUNDOFF_DEG
        assert r.angle_err_deg[i] >= 1e-5  # the error is the rays' brackets here, not round-off


def test_plan_counts_its_pieces_and_traces_no_bisection_ray(build):
    """Two mullions inside the window's interval: three visible pieces, six ends, all from plan;
    the rays are the fan's samples over the window's interval, ceil(width / res) + 1, and none is
    a bisection ray (nothing beyond view.frame_depth_m blocks)."""
    res = 0.2
    b = build(BoxRoom(depth=8.0, mullions=(-0.35, 0.35)), view={"horizontal_resolution_deg": res})
    pts = [(0.0, 7.5, 1.2), (0.6, 6.0, 1.7), (-0.8, 7.0, 1.2)]
    r = sight(b, pts)
    assert r.transitions.tolist() == [6, 6, 6]
    width = np.array([closed_form_deg(x, y, 0.0) for x, y, _ in pts])  # the window's interval
    assert r.rays.tolist() == (np.ceil(width / res - 1e-9) + 1).astype(int).tolist()
    assert np.all(r.angle_err_deg <= 1e-9)  # round-off only
