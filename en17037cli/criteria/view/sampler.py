"""The rays of the solid angle's cells: from each patch's viewpoint through gnomonic coordinates
(X, Y) of its window (:mod:`~en17037cli.criteria.view.gnomonic`), each classified by one opaque
first-hit query (:meth:`Sampler.trace`). The cells that own the samples are
:mod:`~en17037cli.criteria.view.cells`; the integration is :mod:`~en17037cli.criteria.view.solid_angle`.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.view.frames import RoomGeometry
from en17037cli.criteria.view.gnomonic import Patches
from en17037cli.criteria.view.rays import BLOCKED, LANDSCAPE_HIT, ViewRays


class Sampler:
    """Traces rays from patches' viewpoints through gnomonic coordinates (X, Y) of their windows (or
    their angles, calling it).

    ``parallel``: trace each call's rays on the engine's threads (False: in the calling thread, for
    a caller that already runs one :func:`solid_angles` per thread). The rays :meth:`trace` traces
    add up in :attr:`rays` (its caller counts them into the engine); a call counts its own.
    """

    def __init__(self, view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, P: Patches, with_distance: bool,
                 parallel: bool = True):
        self.view_rays, self.rg, self.P = view_rays, rg, P
        self.points32 = points.astype(np.float32)
        self.U, self.V, self.N = rg.frame_array("u"), rg.frame_array("v"), rg.frame_array("n")
        self.rect = rg.frame_array("is_rectangle")
        self.with_distance = with_distance
        self.parallel = parallel
        self.groups = ["opaque"] if len(rg.frames) == 1 else ["opaque", rg.group]
        view_rays.engine.prepare(self.groups)  # built here, not by two threads at once
        self.per_ray = sum(view_rays.engine.embree_scene(g)[0] is not None for g in self.groups)
        self.rays = 0

    def __call__(self, patch: np.ndarray, A: np.ndarray, B: np.ndarray):
        """:meth:`trace` at gnomonic angles (alpha, beta) [rad] of the patches; the rays counted in the engine."""
        rays = self.rays
        out = self.trace(patch, np.tan(A), np.tan(B))
        self.view_rays.engine.count_rays(self.rays - rays)
        self.rays = rays
        return out

    def trace(self, patch: np.ndarray, X: np.ndarray, Y: np.ndarray):
        """Class of each sample at gnomonic coordinates X = tan(alpha), Y = tan(beta) of its patch
        (-1: outside the window's outline) and perpendicular distance [m] beyond the glazing.

        A sample counts for its window when no opaque face and no nearer window of the room lie
        before the glazing; then :meth:`~en17037cli.criteria.view.rays.ViewRays.outside_class` classifies it.

        Returns
        -------
        cls : (m,) int8; dist : (m,) float [m] (+inf unless landscape), or None without distances
        """
        P, rg = self.P, self.rg
        idx = None
        if not self.rect.all():
            w = P.win[patch]
            inside = self.rect[w].copy()
            for f in rg.frames:  # outline test for windows that are not rectangles
                sel = np.flatnonzero((w == f.index) & ~f.is_rectangle)
                if len(sel):
                    ps = patch[sel]
                    inside[sel] = f.on_glazing(P.x0[ps] + P.d[ps] * X[sel], P.y0[ps] + P.d[ps] * Y[sel])
            idx = np.flatnonzero(inside)
            patch, X, Y = patch[idx], X[idx], Y[idx]
        n = len(patch)
        c = np.empty(n, dtype=np.int8)
        dist = np.empty(n) if self.with_distance else None
        engine, vr = self.view_rays.engine, self.view_rays
        one = len(rg.frames) == 1

        def chunk(a: int, b: int) -> None:  # the rays of [a, b): directions, queries, classes, in one thread
            pa = patch[a:b]
            x, y = X[a:b], Y[a:b]
            secant = np.sqrt(1.0 + x * x + y * y)
            inv = 1.0 / secant
            dirs = np.empty((b - a, 3), dtype=np.float32)  # Embree's precision, built column by column
            if one:
                for k in range(3):  # the three coordinates
                    dirs[:, k] = (x * self.U[0, k] + y * self.V[0, k] + self.N[0, k]) * inv
            else:
                w = P.win[pa]
                for k in range(3):
                    dirs[:, k] = (x * self.U[w, k] + y * self.V[w, k] + self.N[w, k]) * inv
            t_w = P.d[pa] * secant  # distance to the glazing plane [m]
            origins = self.points32[P.pt[pa]]
            f_o, t_o = engine.first_hit_chunk("opaque", origins, dirs)
            cc = vr.outside_class(f_o, dirs)
            cc[t_o <= t_w] = BLOCKED
            if not one:  # a direction counts once, through the nearest window of the room
                f_g, t_g = engine.first_hit_chunk(rg.group, origins, dirs)
                nearer = (f_g >= 0) & (rg.window_of_face[np.maximum(f_g, 0)] != w) & (t_g < t_w * (1 - 1e-6))
                cc[nearer] = BLOCKED
            c[a:b] = cc
            if dist is not None:
                dist[a:b] = np.where(cc == LANDSCAPE_HIT, (t_o - t_w) / secant, np.inf)

        engine.map_chunks(chunk, n, parallel=self.parallel)
        self.rays += n * self.per_ray
        if idx is not None:
            full_c = np.full(len(inside), -1, dtype=np.int8)
            full_c[idx] = c
            c = full_c
            if dist is not None:
                full_d = np.full(len(inside), np.inf)
                full_d[idx] = dist
                dist = full_d
        return c, dist
