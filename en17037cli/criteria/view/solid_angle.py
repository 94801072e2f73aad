"""Solid angles of sky, landscape and ground seen through a room's windows, one refinement level at a time.

Each window is sampled per viewpoint on its gnomonic grid (:mod:`~en17037cli.criteria.view.gnomonic`);
every grid vertex is one ray, shared by the four cells around it, classified by one opaque
first-hit query. Cells weigh their exact solid angle (the rectangle formula, or the clipped polygon
for windows that are not rectangles), so the weights of an unobstructed window add up to its exact
solid angle. Cells whose samples disagree, and cells crossed by the image of a frame edge that is
not on a grid line (:func:`~en17037cli.criteria.view.edges.edge_pieces`: a round frame, a diagonal member, a frame whose lines were
thinned), are mixed; a mixed cell may be split in four (:func:`~en17037cli.criteria.view.refine.split_cells`),
at most ``refine_levels`` times. Cells crossed by a frame edge's image are also sampled just
beside it (:meth:`~en17037cli.criteria.view.cells.Cells.sample_probes`).

:class:`Integration` holds the cells of one chunk of viewpoints and steps through the levels:
:meth:`Integration.measure` gives, per point, the estimate of each layer (pure cells whole, a mixed
cell by the share of its samples), its exact mode error estimate (half the solid angle of the mixed
cells holding the layer) and its **interval** [lo, hi]: lo the cells wholly of the layer, hi plus
every mixed cell that can hold it (one with a sample of it, or whose directions the layer can
take: sky only at or above the horizon, ground or landscape that lie wholly below the eye only
below it). Refinement only
ever splits a mixed cell into children inside it, so the interval of a coarser level contains the
estimate and the interval of every finer one. :meth:`Integration.advance` splits the mixed cells
of the points the caller names and makes the rest final; which points go on is the caller's
decision (:mod:`~en17037cli.criteria.view.decide`): in ``view.refine: exact`` every point whose
error estimate is above max(``solid_angle_rel_tolerance`` x value, ``solid_angle_abs_tolerance_sr``)
(today's method), in ``decided`` only those whose verdict or tolerance still needs it.
:func:`solid_angles` is the exact mode on one chunk.

The rays are :mod:`~en17037cli.criteria.view.sampler`'s, the cells and their weights
:mod:`~en17037cli.criteria.view.cells`', their refinement :mod:`~en17037cli.criteria.view.refine`'s
and the frame edges' images :mod:`~en17037cli.criteria.view.edges`'; this module integrates.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.criteria.view.cells import _kind_bits, base_cells
from en17037cli.criteria.view.distance import ragged_statistic
from en17037cli.criteria.view.frames import RoomGeometry
from en17037cli.criteria.view.gnomonic import patches
from en17037cli.criteria.view.rays import BLOCKED, GROUND_HIT, LANDSCAPE_HIT, SKY, ViewRays
from en17037cli.criteria.view.refine import split_cells
from en17037cli.criteria.view.results import SolidAngles
from en17037cli.criteria.view.sampler import Sampler
from en17037cli.project.settings import ViewSettings

#: Sample classes that are layers, with their report keys.
LAYER_CODES = (("sky", SKY), ("landscape", LANDSCAPE_HIT), ("ground", GROUND_HIT))
#: The class of a pure cell from its kinds (a single bit): log2, and 4 (no class) for 0.
_CLASS_OF_KINDS = np.array([4 if k == 0 else k.bit_length() - 1 for k in range(256)], dtype=np.int64)
#: A direction this close to the horizontal (the z of its unnormalised vector, [-]) may be classed
#: either side of it by the float32 ray tracer: both sky and ground stay possible there.
HORIZON_SLACK = 1e-6


@dataclass
class Measure:
    """Per point of a chunk, at the current level (arrays (p,); dicts by layer name).

    est : the estimate [sr] (pure cells whole, a mixed cell by the share of its samples)
    err : the exact mode's error estimate [sr] (half the solid angle of the mixed cells holding the layer)
    lo, hi : the interval [sr]: the cells wholly of the layer; plus every mixed cell that can hold it
    seen : a corner sample of the layer (a ray that hit it, inherited by every finer level)
    glazing : the windows' solid angle [sr]; mixed : (p,) int, the point's mixed cells now
    exact_done : whether ``view.refine: exact`` stops the point here (or it has no mixed cell)
    """

    est: dict
    err: dict
    lo: dict
    hi: dict
    seen: dict
    glazing: np.ndarray
    mixed: np.ndarray
    exact_done: np.ndarray


class Integration:
    """The solid angles of one chunk of viewpoints, refined one level at a time (:meth:`measure`,
    :meth:`advance`, :meth:`result`); the caller decides which points go on.

    Parameters
    ----------
    points : (p, 3) float [m], local frame
    parallel : trace on the engine's threads (False: in the calling thread, for a caller that runs
        one integration per thread); the results are the same
    """

    def __init__(self, view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, settings: ViewSettings,
                 parallel: bool = True):
        p = self.p = len(points)
        self.settings, self.view_rays, self.rg = settings, view_rays, rg
        self.level = 0
        zeros = lambda: np.zeros(p)  # noqa: E731
        # what the final cells add up to: estimate, error estimate, interval, corner witnesses
        self.acc = {key: zeros() for key in ("sky", "landscape", "ground", "glazing", "err_sky", "err_landscape", "err_ground",
                                             "lo_sky", "lo_landscape", "lo_ground", "hi_sky", "hi_landscape", "hi_ground")}
        self.final_cells = np.zeros(p, dtype=int)
        self.seen = {key: np.zeros(p, dtype=bool) for key, _ in LAYER_CODES}
        self.with_dist = settings.distance_method == "solid_angle"
        self.dist_rows: list = []
        self.dist_w: list = []
        self.dist_p: list = []
        P = self.P = patches(rg, points, np.radians(settings.angular_resolution_deg))
        self.sample = Sampler(view_rays, rg, points, P, self.with_dist, parallel)
        # the layers a direction can take: ground or landscape faces above the eye can be seen upwards
        self.ground_up = points[:, 2] <= view_rays.ground_top_z + HORIZON_SLACK
        self.landscape_up = points[:, 2] <= view_rays.landscape_top_z + HORIZON_SLACK
        self.zdir = (rg.frame_array("u")[:, 2], rg.frame_array("v")[:, 2], rg.frame_array("n")[:, 2])
        self.cells = base_cells(self.sample, P) if len(P.pt) else None
        self._classify()
        if self.cells is not None:  # the pure cells are final at once: only the mixed ones are kept
            self._finalize(np.flatnonzero(~self._mixed))
            self._keep(self._mixed)

    # -- the current cells -------------------------------------------------------------------------
    def _classify(self) -> None:
        """Kinds, mixedness, each layer's share and possibility of the current cells."""
        c = self.cells
        if c is None or len(c.w) == 0:
            self.cells = None
            return
        self._pi = self.P.pt[c.patch]
        kinds = self._kinds = c.kinds()
        self._corners = np.bitwise_or.reduce(_kind_bits(c.cls[:4]), axis=0)  # the classes of its corner rays
        mixed = self._mixed = ((kinds & (kinds - 1)) != 0) | c.crossed()  # samples that disagree, or a frame edge's image
        mi = self._mi = np.flatnonzero(mixed)
        count = c.counter(mi)
        nvalid = np.maximum(count(), 1)  # of the mixed cells
        self._share, self._possible = {}, {}
        z = self._direction_z(mi)
        for key, code in LAYER_CODES:
            s = (kinds == (1 << code)).astype(float)  # 1 or 0 in a pure cell, the share of its samples in a mixed one
            s[mi] = count(code) / nvalid
            self._share[key] = s
            able = ((kinds[mi] >> code) & 1).astype(bool)  # a mixed cell can hold a layer one of its samples saw ...
            if key == "sky":  # ... or one its directions can take: sky only at or above the horizon,
                able |= z[1] >= -HORIZON_SLACK
            elif key == "ground":  # ground below it (or anywhere, from under a ground face's top)
                able |= (z[0] <= HORIZON_SLACK) | self.ground_up[self._pi[mi]]
            else:  # landscape likewise: from above every landscape face only below the horizon
                able |= (z[0] <= HORIZON_SLACK) | self.landscape_up[self._pi[mi]]
            self._possible[key] = able

    def _direction_z(self, sel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(lowest, highest) z of the unnormalised directions X u + Y v + n over cells ``sel`` [-]:
        linear in the gnomonic coordinates (X, Y), so its extremes over a cell lie at its corners."""
        if len(sel) == 0:
            return np.zeros(0), np.zeros(0)
        X0, X1, Y0, Y1 = self.cells.tans(sel)
        w = self.P.win[self.cells.patch[sel]]
        uz, vz, nz = (a[w] for a in self.zdir)
        lo = np.minimum(X0 * uz, X1 * uz) + np.minimum(Y0 * vz, Y1 * vz) + nz
        hi = np.maximum(X0 * uz, X1 * uz) + np.maximum(Y0 * vz, Y1 * vz) + nz
        return lo, hi

    def _finalize(self, sel: np.ndarray) -> None:
        """Add cells ``sel`` (indices of the current ones) to what the final cells add up to."""
        if self.cells is None or len(sel) == 0:
            return
        c, p = self.cells, self.p
        fp, fw = self._pi[sel], c.w[sel]
        self.acc["glazing"] += np.bincount(fp, fw, p)
        self.final_cells += np.bincount(fp, minlength=p)
        mixed = self._mixed[sel]
        # pure cells: all of a cell's weight to its one class (one bincount over point x class)
        pure = ~mixed
        if pure.any():
            by_class = np.bincount(fp[pure] * 8 + _CLASS_OF_KINDS[self._kinds[sel[pure]]], fw[pure], 8 * p).reshape(p, 8)
            for key, code in LAYER_CODES:
                for acc in (key, "lo_" + key, "hi_" + key):
                    self.acc[acc] += by_class[:, code]
        if mixed.any():  # mixed cells: the share of their samples, the error estimate, the interval's upper end
            at = np.full(len(c.w), -1, np.int64)
            at[self._mi] = np.arange(len(self._mi))
            msel = sel[mixed]
            ms = at[msel]  # as indices into the mixed cells
            mp, mw, mk = fp[mixed], fw[mixed], self._kinds[msel]
            for key, code in LAYER_CODES:
                self.acc[key] += np.bincount(mp, mw * self._share[key][msel], p)
                self.acc["hi_" + key] += np.bincount(mp, mw * self._possible[key][ms], p)
                self.acc["err_" + key] += np.bincount(mp, 0.5 * mw * ((mk >> code) & 1), p)
        corners = self._corners[sel]
        for key, code in LAYER_CODES:
            self.seen[key] |= np.bincount(fp, (corners >> code) & 1, p) > 0
        if self.with_dist:  # each valid sample of a final cell carries an equal share of its weight
            nv_all = np.maximum(c.valid_counts(), 1)
            cl = c.cls[:, sel].T  # (cells, samples), in the cells' order
            ok = (cl >= 0) & (cl != BLOCKED)
            sw = (fw / nv_all[sel])[:, None] * ok
            r, col = np.nonzero(sw > 0)
            self.dist_rows.append(c.dist[:, sel].T[r, col])
            self.dist_w.append(sw[r, col])
            self.dist_p.append(fp[r])
            if c.probe_dist is not None:  # and its probes'
                is_final = np.zeros(len(c.w), dtype=bool)
                is_final[sel] = True
                q = np.flatnonzero(is_final[c.probe_cell] & (c.probe_cls >= 0) & (c.probe_cls != BLOCKED))
                qc = c.probe_cell[q]
                self.dist_rows.append(c.probe_dist[q])
                self.dist_w.append(c.w[qc] / nv_all[qc])
                self.dist_p.append(self._pi[qc])

    def _keep(self, mask: np.ndarray) -> None:
        """Keep only the current cells in ``mask`` (bool), with their classification."""
        if self.cells is None:
            return
        if mask.all():
            return
        sel = np.flatnonzero(mask)
        at = np.full(len(self.cells.w), -1, np.int64)
        at[self._mi] = np.arange(len(self._mi))
        msel = at[sel[self._mixed[sel]]]
        self.cells = self.cells.take(sel).compact()
        if len(sel) == 0:
            self.cells = None
            return
        self._pi, self._kinds, self._mixed, self._corners = self._pi[sel], self._kinds[sel], self._mixed[sel], self._corners[sel]
        self._mi = np.flatnonzero(self._mixed)
        self._share = {k: v[sel] for k, v in self._share.items()}
        self._possible = {k: v[msel] for k, v in self._possible.items()}

    # -- the interface -----------------------------------------------------------------------------
    def measure(self) -> Measure:
        """Per point: estimate, error estimate, interval and witnesses of each layer, from the final
        cells and the current ones (every current cell is mixed), and the exact mode's stop."""
        p, settings = self.p, self.settings
        est, err, lo, hi, seen = {}, {}, {}, {}, {}
        glazing = self.acc["glazing"].copy()
        mixed = np.zeros(p, dtype=int)
        if self.cells is not None:
            c, pi = self.cells, self._pi
            glazing += np.bincount(pi, c.w, p)
            mixed = np.bincount(pi[self._mi], minlength=p)
        for key, code in LAYER_CODES:
            est[key], err[key] = self.acc[key].copy(), self.acc["err_" + key].copy()
            lo[key], hi[key] = self.acc["lo_" + key].copy(), self.acc["hi_" + key].copy()
            seen[key] = self.seen[key].copy()
            if self.cells is not None:
                mi, pm, wm = self._mi, pi[self._mi], c.w[self._mi]
                est[key] += np.bincount(pi, c.w * self._share[key], p)
                err[key] += np.bincount(pm, 0.5 * wm * ((self._kinds[mi] >> code) & 1), p)
                hi[key] += np.bincount(pm, wm * self._possible[key], p)
                seen[key] |= np.bincount(pi, (self._corners >> code) & 1, p) > 0
        done = mixed == 0
        if self.level < settings.refine_levels:  # today's error control: every layer within max(rel x value, abs)
            ok = np.ones(p, dtype=bool)
            for key, _ in LAYER_CODES:
                ok &= err[key] <= np.maximum(settings.solid_angle_rel_tolerance * est[key], settings.solid_angle_abs_tolerance_sr)
            done |= ok
        else:
            done[:] = True
        return Measure(est, err, lo, hi, seen, glazing, mixed, done)

    def advance(self, go: np.ndarray) -> bool:
        """Split the mixed cells of the points in ``go`` ((p,) bool) in four; make every other cell
        final. Returns whether any cell is left to measure."""
        if self.cells is None:
            return False
        split = go[self._pi] & (self.level < self.settings.refine_levels)
        self._finalize(np.flatnonzero(~split))
        rest = np.flatnonzero(split)
        if len(rest) == 0:
            self.cells = None
            return False
        self.level += 1
        self.cells = split_cells(self.sample, self.cells, rest, neighbours=self.level < self.settings.refine_levels)
        self._classify()
        if self.cells is not None:  # the children that came out pure are final at once
            self._finalize(np.flatnonzero(~self._mixed))
            self._keep(self._mixed)
        return self.cells is not None

    def result(self, bounds: bool = True) -> SolidAngles:
        """The per-point solid angles of the final cells (every current cell made final first);
        the rays traced are counted into the engine."""
        if self.cells is not None:
            self._finalize(np.arange(len(self.cells.w)))
            self.cells = None
        self.view_rays.engine.count_rays(self.sample.rays)
        self.sample.rays = 0
        dist = gap = None
        if self.with_dist:
            dist, gap = ragged_statistic(np.concatenate(self.dist_p) if self.dist_p else np.zeros(0, int),
                                         np.concatenate(self.dist_rows) if self.dist_rows else np.zeros(0),
                                         np.concatenate(self.dist_w) if self.dist_w else np.zeros(0), self.p,
                                         self.settings.distance_statistic)
        a = self.acc
        return SolidAngles(sr={k: a[k] for k, _ in LAYER_CODES}, err_sr={k: a["err_" + k] for k, _ in LAYER_CODES},
                           glazing_sr=a["glazing"], cells=self.final_cells, distance_m=dist, distance_gap_m=gap,
                           lo_sr={k: a["lo_" + k] for k, _ in LAYER_CODES} if bounds else None,
                           hi_sr={k: a["hi_" + k] for k, _ in LAYER_CODES} if bounds else None)


def solid_angles(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, settings: ViewSettings,
                 parallel: bool = True) -> SolidAngles:
    """Solid angle of sky, landscape and ground seen through the room's windows from each point,
    refined as ``view.refine: exact`` does (every point until its error estimate meets the
    tolerance or ``refine_levels``).

    Parameters
    ----------
    points : (p, 3) float [m], local frame
    parallel : trace on the engine's threads (False: in the calling thread)

    Returns
    -------
    SolidAngles, per point; with ``distance_m`` for the ``solid_angle`` distance method (the
    perpendicular distance (delta_1 - delta_0) r . n of Brembilla et al. (2021) eq. (1) over the
    leaving cells, weighted by solid angle)
    """
    it = Integration(view_rays, rg, points, settings, parallel)
    while it.advance(~it.measure().exact_done):
        pass
    return it.result()
