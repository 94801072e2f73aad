"""The view's solid angles as the fast core computes them (issue 38): small tasks on the engine's
threads, every ray of a split traced once, window outlines queried from several threads, and the
automatic plan's wall guard cut only where it must be. Each answer is compared with the same
computation done the plain way (one call, one thread, every ray traced; the full overlay): the
numbers must be the same bit for bit, not within a tolerance."""
from __future__ import annotations

import threading

import numpy as np
import pytest
import shapely
from conftest import Built

from en17037cli.criteria.view import assess as view_assess
from en17037cli.criteria.view import refine
from en17037cli.criteria.view.frames import WindowFrame, room_geometry
from en17037cli.criteria.view.sampler import Sampler
from en17037cli.raytrace import RayEngine
from en17037cli.samples import BoxRoom, box_room_project

#: Viewpoints in the box room [m, world]: near the window, deep, off to the sides.
POINTS = np.array([[x, y, z] for x in (-1.5, -0.4, 0.3, 1.6) for y in (0.6, 1.7, 3.2, 5.1) for z in (1.2, 1.7)])


@pytest.fixture
def mullion_room(tmp_path):
    """Two mullions and a 0.3 m reveal, the outside distance from the solid angles: frame lines,
    two-sided sample columns, refinement along the buildings' edges and distances per sample."""
    path = box_room_project(tmp_path / "p", BoxRoom(wall_thickness=0.3, mullions=(-0.35, 0.35)), sunlight=None,
                            view={"distance_method": "solid_angle"})
    b = Built(path)
    yield b
    b.engine.close()


def _solid(b: Built, engine: RayEngine, cells_per_task: int, monkeypatch) -> tuple[np.ndarray, int]:
    from en17037cli.criteria.view.rays import ViewRays

    monkeypatch.setattr(view_assess, "CELLS_PER_TASK", cells_per_task)
    rg = room_geometry(b.scene, b.room, b.view_cfg.frame_depth_m)
    before = engine.rays_traced
    v = view_assess.assess_points(ViewRays(engine, b.scene), rg, b.scene.to_local(POINTS), b.view_cfg, b.thresholds)
    s = v.solid
    cols = [s.sr[k] for k in ("sky", "landscape", "ground")] + [s.err_sr[k] for k in ("sky", "landscape", "ground")]
    return np.column_stack(cols + [s.glazing_sr, s.cells, s.distance_m, s.distance_gap_m]), engine.rays_traced - before


def test_tasks_and_threads_change_no_bit(mullion_room, monkeypatch):
    """One task on one thread against tasks of a few points on two threads: every solid angle,
    error estimate, cell count and distance the same bits, and the same rays counted (a point's
    values depend on nothing but the point: chunks split no point's cells)."""
    b = mullion_room
    one = RayEngine(b.scene.vertices, b.scene.triangles, b.scene.ray_groups(), threads=1)
    two = RayEngine(b.scene.vertices, b.scene.triangles, b.scene.ray_groups(), threads=2)
    try:
        plain, rays_plain = _solid(b, one, 10**9, monkeypatch)
        tasks, rays_tasks = _solid(b, two, 2_000, monkeypatch)
    finally:
        one.close()
        two.close()
    assert len(view_assess.chunks(room_geometry(b.scene, b.room, 0.0), b.scene.to_local(POINTS), b.view_cfg, 2_000)) > 4
    assert np.array_equal(plain, tasks, equal_nan=True)
    assert rays_plain == rays_tasks > 0


def test_no_ray_of_a_split_is_traced_twice(mullion_room, monkeypatch):
    """The middle of a side two split cells share is one ray (traced for one, taken by the other),
    and the answers are those of tracing it twice (``_twins`` switched off)."""
    b = mullion_room
    repeats = []
    original = Sampler.trace

    def spy(self, patch, X, Y):
        key = np.unique(np.column_stack([patch, X, Y]), axis=0)
        repeats.append(len(patch) - len(key))
        return original(self, patch, X, Y)

    monkeypatch.setattr(Sampler, "trace", spy)
    once, rays_once = _solid(b, b.engine, 10**9, monkeypatch)
    assert max(repeats) == 0
    monkeypatch.setattr(refine, "_twins", lambda *a: (np.zeros(0, np.int64), np.zeros(0, np.int64)))
    repeats.clear()
    twice, rays_twice = _solid(b, b.engine, 10**9, monkeypatch)
    assert max(repeats) > 0  # the plain way repeats rays ...
    assert rays_once < 0.95 * rays_twice  # ... at least 5 % of them here
    assert np.array_equal(once, twice, equal_nan=True)


def l_shaped_frame() -> WindowFrame:
    """An L-shaped pane (not convex: shapely answers for it), 2 x 2 m less its upper right 1 x 1 m."""
    tri = np.array([[[0, 0], [2, 0], [2, 1]], [[0, 0], [2, 1], [1, 1]], [[0, 0], [1, 1], [1, 2]], [[0, 0], [1, 2], [0, 2]]],
                   float)
    return WindowFrame(0, "L", np.zeros(3), np.array([1.0, 0, 0]), np.array([0, 0, 1.0]), np.array([0, -1.0, 0]), tri,
                       0.0, 2.0, 0.0, 2.0, False, np.arange(4))


def test_window_outlines_answer_alike_from_threads():
    """Eight threads asking an L-shaped pane's outline at once (its prepared polygon and STR trees
    build their indexes on first use) get the answers one thread gets."""
    rng = np.random.default_rng(7)
    x0, y0 = rng.uniform(-0.5, 2.5, (2, 4000))
    x1, y1 = x0 + rng.uniform(0, 0.3, 4000), y0 + rng.uniform(0, 0.3, 4000)

    def ask(f):
        return (f.on_glazing(x0, y0), *f.classify_boxes(x0, x1, y0, y1), *f.triangle_pairs(x0, x1, y0, y1),
                f.meets_glazing(x0, y0, x1, y1))

    want = ask(l_shaped_frame())
    shared = l_shaped_frame()
    got: list = [None] * 8
    start = threading.Barrier(8)

    def work(k):
        start.wait()
        got[k] = [ask(shared) for _ in range(5)]

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for answers in got:
        for a in answers:
            assert all(np.array_equal(p, q) for p, q in zip(a, want))


def _bridges_full(lower, segs, upper):
    """The plan's bridges as they were made before (issue 38): every segment overlaid with the whole guard."""
    from en17037cli.scene.section import SNAP_M

    gaps = shapely.line_merge(shapely.union_all(shapely.difference(shapely.linestrings(upper), lower.buffer(SNAP_M))))
    pieces = [g for g in shapely.get_parts(gaps) if g.geom_type == "LineString" and g.length > 10 * SNAP_M]
    a, v = segs[:, 0], segs[:, 1] - segs[:, 0]
    vlen = np.linalg.norm(v, axis=1)
    out = []
    for piece in pieces:
        c = np.asarray(piece.coords)[[0, -1]]
        d = (c[1] - c[0]) / max(piece.length, 1e-12)
        parallel = np.abs(d[0] * v[:, 1] - d[1] * v[:, 0]) < 0.02 * vlen
        ok = True
        for end in c:
            t = np.clip(np.einsum("kj,kj->k", end - a, v) / np.maximum(vlen ** 2, 1e-24), 0.0, 1.0)
            dist = np.linalg.norm(a + t[:, None] * v - end, axis=1)
            on_line = np.abs((end - a)[:, 0] * v[:, 1] - (end - a)[:, 1] * v[:, 0]) < 2 * SNAP_M * vlen
            ok &= bool(np.any(parallel & on_line & (dist < 2 * SNAP_M)))
        if ok:
            out.append(shapely.LineString([c[0] - 3 * SNAP_M * d, c[1] + 3 * SNAP_M * d]))
    return out


def test_bridges_are_the_full_overlays():
    """The plan's bridges with the guard cut only where a segment crosses its outline are those of
    the overlay of every segment with the whole guard, coordinate for coordinate (the seed office's
    storey, both cuts: segments inside the guard, clear of it and across it)."""
    from pathlib import Path

    from en17037cli.project import load_project
    from en17037cli.scene import build_scene
    from en17037cli.scene import section as sec

    root = Path(__file__).resolve().parents[1]
    scene = build_scene(load_project(root / "sample_projects" / "seed-office" / "project.yaml", []))
    floor_z = scene.rooms[0].floor_z  # local
    segs = sec._segments(scene, floor_z + sec.CUT_HEIGHT_M)
    lower = shapely.union_all(shapely.linestrings(segs))
    guard = lower.buffer(sec.SNAP_M)
    found = 0
    for h in sec.BRIDGE_HEIGHTS_M:
        upper = sec._segments(scene, floor_z + h)
        lines = shapely.linestrings(upper)
        inside, clear = shapely.within(lines, guard), ~shapely.intersects(lines, guard)
        assert inside.any() and (~inside & ~clear).any()
        fast, full = sec._bridges(lower, segs, upper), _bridges_full(lower, segs, upper)
        assert len(fast) == len(full)
        assert all(np.array_equal(np.asarray(p.coords), np.asarray(q.coords)) for p, q in zip(fast, full))
        found += len(full)
    assert found > 0  # the wall under the window's sill closes the plan


def test_sampler_called_with_angles_counts_its_rays(mullion_room):
    """``Sampler(...)(patch, alpha, beta)`` (the angles, as before issue 38) answers as ``trace`` at
    their tangents and counts its rays in the engine; ``trace`` leaves the counting to its caller."""
    from en17037cli.criteria.view.gnomonic import patches
    from en17037cli.criteria.view.rays import ViewRays

    b = mullion_room
    rg = room_geometry(b.scene, b.room, b.view_cfg.frame_depth_m)
    pts = b.scene.to_local(POINTS[:6])
    P = patches(rg, pts, np.radians(1.0))
    s = Sampler(ViewRays(b.engine, b.scene), rg, pts, P, True)
    rng = np.random.default_rng(3)
    patch = rng.integers(0, len(P), 500)
    A, B = rng.uniform(P.a0[patch], P.a1[patch]), rng.uniform(P.b0[patch], P.b1[patch])
    before = b.engine.rays_traced
    c1, d1 = s(patch, A, B)
    assert b.engine.rays_traced - before == 500 * s.per_ray and s.rays == 0
    c2, d2 = s.trace(patch, np.tan(A), np.tan(B))
    assert b.engine.rays_traced - before == 500 * s.per_ray and s.rays == 500 * s.per_ray
    assert np.array_equal(c1, c2) and np.array_equal(d1, d2)
    assert len(np.unique(c1)) > 1
