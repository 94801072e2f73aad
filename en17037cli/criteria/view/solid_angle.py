"""Solid angles of sky, landscape and ground seen through a room's windows, adaptively integrated.

Each window is sampled per viewpoint on its gnomonic grid (:mod:`~en17037cli.criteria.view.gnomonic`);
every grid vertex is one ray, shared by the four cells around it, classified by one opaque
first-hit query. Cells weigh their exact solid angle (the rectangle formula, or the clipped polygon
for windows that are not rectangles), so the weights of an unobstructed window add up to its exact
solid angle. Cells whose samples disagree, and cells crossed by the image of a frame edge that is
not on a grid line (:func:`~en17037cli.criteria.view.edges.edge_pieces`: a round frame, a diagonal member, a frame whose lines were
thinned), are mixed; mixed cells are split in four, up to ``refine_levels`` times, until each
layer's estimated error is within max(``solid_angle_rel_tolerance`` x its solid angle,
``solid_angle_abs_tolerance_sr``). Error estimate: half the solid angle of the cells still mixed.
Cells crossed by a frame edge's image are also sampled just beside it (:meth:`~en17037cli.criteria.view.cells.Cells.sample_probes`).
A split traces the middle of a side two split cells share once (:func:`~en17037cli.criteria.view.refine.split_cells`). The caller may
run several calls at once on the engine's threads (``parallel=False``): a point's values depend on
no other point.

The rays are :mod:`~en17037cli.criteria.view.sampler`'s, the cells and their weights
:mod:`~en17037cli.criteria.view.cells`', their refinement :mod:`~en17037cli.criteria.view.refine`'s
and the frame edges' images :mod:`~en17037cli.criteria.view.edges`'; this module integrates.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.view.cells import base_cells
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


def solid_angles(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, settings: ViewSettings,
                 parallel: bool = True) -> SolidAngles:
    """Solid angle of sky, landscape and ground seen through the room's windows from each point.

    Parameters
    ----------
    points : (p, 3) float [m], local frame
    parallel : trace on the engine's threads (False: in the calling thread, for a caller that runs
        one call per thread); the results are the same

    Returns
    -------
    SolidAngles, per point; with ``distance_m`` for the ``solid_angle`` distance method (the
    perpendicular distance (delta_1 - delta_0) r . n of Brembilla et al. (2021) eq. (1) over the
    leaving cells, weighted by solid angle)
    """
    p = len(points)
    out = {key: np.zeros(p) for key in ("sky", "landscape", "ground", "glazing", "err_sky", "err_landscape", "err_ground")}
    out["cells"] = np.zeros(p, dtype=int)
    P = patches(rg, points, np.radians(settings.angular_resolution_deg))
    with_dist = settings.distance_method == "solid_angle"
    sample = Sampler(view_rays, rg, points, P, with_dist, parallel)
    dist_rows, dist_w, dist_p = [], [], []
    cells = base_cells(sample, P) if len(P.pt) else None
    rel, abs_ = settings.solid_angle_rel_tolerance, settings.solid_angle_abs_tolerance_sr
    for level in range(settings.refine_levels + 1):
        if cells is None or len(cells.w) == 0:
            break
        pi, w, cls = P.pt[cells.patch], cells.w, cells.cls
        kinds = cells.kinds()
        mixed = ((kinds & (kinds - 1)) != 0) | cells.crossed()  # samples that disagree, or a frame edge's image
        mi = np.flatnonzero(mixed)
        count = cells.counter(mi)
        nvalid = np.maximum(count(), 1)  # of the mixed cells
        # share of each layer: 1 or 0 in a pure cell, the share of its samples in a mixed one
        share = {}
        for key, code in LAYER_CODES:
            s = (kinds == (1 << code)).astype(float)
            s[mi] = count(code) / nvalid
            share[key] = s
        # Error control: a point stops refining once every layer's estimated error (half the
        # solid angle of its mixed cells) is within max(rel * layer solid angle, abs).
        # (At the last level every cell is final.)
        last = level == settings.refine_levels
        done = np.ones(p, dtype=bool)
        pm, half_m, kinds_m = pi[mi], 0.5 * w[mi], kinds[mi]  # the mixed cells (the others add 0 to an error)
        for key, code in ([] if last else LAYER_CODES):
            est = out["err_" + key] + np.bincount(pm, half_m * ((kinds_m >> code) & 1), p)
            value = out[key] + np.bincount(pi, w * share[key], p)
            done &= est <= np.maximum(rel * value, abs_)
        final = slice(None) if last else np.flatnonzero(~mixed | done[pi])
        fm = slice(None) if last else np.flatnonzero(done[pm])  # the final ones among the mixed
        fp, fw = pi[final], w[final]
        out["glazing"] += np.bincount(fp, fw, p)
        out["cells"] += np.bincount(fp, minlength=p)
        for key, code in LAYER_CODES:
            out[key] += np.bincount(fp, fw * share[key][final], p)
            out["err_" + key] += np.bincount(pm[fm], half_m[fm] * ((kinds_m[fm] >> code) & 1), p)
        if with_dist:  # each valid sample of a final cell carries an equal share of its weight
            nv_all = np.maximum(cells.valid_counts(), 1)
            c = cls[:, final].T  # (cells, samples), in the cells' order
            ok = (c >= 0) & (c != BLOCKED)
            sw = (fw / nv_all[final])[:, None] * ok
            r, col = np.nonzero(sw > 0)
            dist_rows.append(cells.dist[:, final].T[r, col])
            dist_w.append(sw[r, col])
            dist_p.append(fp[r])
            is_final = np.zeros(len(w), dtype=bool)
            is_final[final] = True
            if cells.probe_dist is not None:  # and its probes'
                q = np.flatnonzero(is_final[cells.probe_cell] & (cells.probe_cls >= 0) & (cells.probe_cls != BLOCKED))
                qc = cells.probe_cell[q]
                dist_rows.append(cells.probe_dist[q])
                dist_w.append(w[qc] / nv_all[qc])
                dist_p.append(pi[qc])
        if not last:
            rest = np.ones(len(w), dtype=bool)
            rest[final] = False
            if not rest.any():
                break
            cells = split_cells(sample, cells, np.flatnonzero(rest), neighbours=level + 1 < settings.refine_levels)
    view_rays.engine.count_rays(sample.rays)
    dist = gap = None
    if with_dist:
        dist, gap = ragged_statistic(np.concatenate(dist_p) if dist_p else np.zeros(0, int),
                                     np.concatenate(dist_rows) if dist_rows else np.zeros(0),
                                     np.concatenate(dist_w) if dist_w else np.zeros(0), p, settings.distance_statistic)
    return SolidAngles(sr={k: out[k] for k, _ in LAYER_CODES}, err_sr={k: out["err_" + k] for k, _ in LAYER_CODES},
                       glazing_sr=out["glazing"], cells=out["cells"], distance_m=dist, distance_gap_m=gap)
