"""Which viewpoints refine their solid angles further: ``view.refine`` (``decided`` or ``exact``).

The standard asks a level of each viewpoint and a level of each room, not the solid angles to the
last digit. At every level of refinement each point has, per layer, an interval [lo, hi] of its
solid angle (:class:`~en17037cli.criteria.view.solid_angle.Measure`): the estimate of any finer
refinement lies inside it. A layer is *visible* when its solid angle exceeds
``view.layer_threshold_sr`` (:func:`~en17037cli.standard.layer_visible`); that is decided once
lo > threshold (with a threshold of 0, once a ray has hit the layer: every finer level keeps that
ray) or hi <= threshold. The point's layers level (EN 17037 Table A.5,
:func:`~en17037cli.standard.level_from_layers`) is decided once it is the same with every
undecided layer seen and with none seen; the room's (the highest level reached by
``view.area_fraction`` of the points, :func:`~en17037cli.standard.room_level`) once the shares of
the points' lowest and highest possible levels give the same level.

``decided``: a point goes on while the exact mode would (:attr:`Measure.exact_done`: its error
estimate above max(``solid_angle_rel_tolerance`` x value, ``solid_angle_abs_tolerance_sr``) and
fewer than ``refine_levels`` splits) and either its level is undecided and its room's too, or an
interval is wider than 2 x ``view.tolerance`` x the windows' solid angle at the point. So its
cells are always those of the exact mode stopped earlier: the exact mode's estimate lies in the
reported interval, and every level the decided mode reports as decided is the exact mode's.
``view.tolerance: 0`` is the exact mode. ``exact``: a point goes on while the exact mode would.
"""
from __future__ import annotations

import numpy as np

from en17037cli import standard
from en17037cli.criteria.view.results import LAYER_NAMES
from en17037cli.project.settings import ViewSettings


def visibility_bounds(m, threshold_sr: float) -> tuple[dict, dict]:
    """(surely, possibly): per layer, (p,) bool, whether the layer is visible at every finer level
    (lo above the threshold, or with a threshold of 0 a ray that hit it), and whether it can be
    (hi above the threshold).

    Parameters
    ----------
    m : :class:`~en17037cli.criteria.view.solid_angle.Measure` (or anything with ``lo``, ``hi``,
        ``seen`` dicts of (p,) arrays [sr] and bool)
    threshold_sr : the layer threshold [sr] (``view.layer_threshold_sr``)
    """
    surely, possibly = {}, {}
    for k in LAYER_NAMES:
        surely[k] = m.lo[k] > threshold_sr
        if threshold_sr == 0:  # any positive solid angle: the ray that hit it is a corner of every finer cell
            surely[k] = surely[k] | m.seen[k]
        possibly[k] = surely[k] | (m.hi[k] > threshold_sr)
    return surely, possibly


def level_bounds(surely: dict, possibly: dict) -> tuple[np.ndarray, np.ndarray]:
    """(lowest, highest) layers level of each point (EN 17037 Table A.5) its undecided layers allow."""
    lo = standard.level_from_layers(surely["sky"], surely["landscape"], surely["ground"])
    hi = standard.level_from_layers(possibly["sky"], possibly["landscape"], possibly["ground"])
    return lo, hi


def room_decided(level_lo: np.ndarray, level_hi: np.ndarray, area_fraction: float) -> bool:
    """Whether the room's layers level (the highest reached by ``area_fraction`` of the points) is
    the same whatever its undecided points turn out to be: it is monotone in every point's level."""
    return standard.room_level(level_lo, area_fraction)[0] == standard.room_level(level_hi, area_fraction)[0]


def too_wide(m, tolerance: float) -> np.ndarray:
    """(p,) bool: an interval wider than 2 x ``tolerance`` x the windows' solid angle at the point
    (``view.tolerance``: the largest half-width of an interval, a fraction of that solid angle)."""
    width = np.max([m.hi[k] - m.lo[k] for k in LAYER_NAMES], axis=0)
    return width > 2.0 * tolerance * m.glazing


def go_on(m, settings: ViewSettings) -> np.ndarray:
    """(p,) bool: the points whose mixed cells are split at the next level (see the module)."""
    more = ~m.exact_done
    if settings.refine == "exact" or settings.distance_method == "solid_angle":
        return more  # the solid angle's distance statistic is not bounded here: refined as in the exact mode
    lo, hi = level_bounds(*visibility_bounds(m, settings.layer_threshold_sr))
    open_ = (lo != hi) & (not room_decided(lo, hi, settings.area_fraction))
    return more & (open_ | too_wide(m, settings.tolerance))
