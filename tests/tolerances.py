"""Fixed tolerances of the tests, each with its reason, and the two-sided check of error estimates.

A test never takes its tolerance from the engine's own error estimate: a loss of precision would
then widen the estimate and pass. Error estimates are checked on both sides instead
(:func:`check_estimate`): they must cover the true error, and not exceed it by more than a
stated factor.
"""
from __future__ import annotations

import numpy as np

#: Horizontal sight angle [deg] at the defaults: at most two transitions bisected to
#: ``view.angle_tolerance_deg`` (1e-4 deg) each, plus the fan's two end insets of half that.
SIGHT_ANGLE_DEG = 3e-4
#: Smallest sight-angle error a float64 closed form resolves [deg]: the plan method's error bound
#: is round-off (about 1e-12 deg), the closed forms' own round-off about 1e-13 deg.
SIGHT_ANGLE_ROUNDOFF_DEG = 1e-11
#: Solid angle of a layer [sr] at the defaults (1 deg cells, 3 refinements), as docs/accuracy.md's
#: accuracy section states it: within max(1 %, 1e-3 sr) at the tested points (measured).
def solid_angle_sr(exact: float) -> float:
    return max(0.01 * exact, 1e-3)


#: Largest solid-angle error estimate at the defaults [sr] (docs/accuracy.md's table: half the solid
#: angle of the cells still mixed, at most 5.5e-3 sr on the box room and the seed office).
SOLID_ANGLE_ESTIMATE_MAX_SR = 5.5e-3
#: Cells tile a window exactly: their weights add up to its solid angle but for round-off [sr].
TILING_SR = 1e-9
#: Outside distance [m] across a 25-60 m street: float32 ray distances carry ~1e-5 m.
DISTANCE_M = 1e-3
#: Sun hours of one day against a brute force sampled every second [s]: at most four changes of
#: visibility a day, each located by the engine to ``sunlight.tolerance_s`` (1 s) and by the brute
#: force to its 1 s step.
HOURS_VS_BRUTE_FORCE_S = 8.0
#: An error estimate may be at most this many times the largest true error it covers.
ESTIMATE_FACTOR = 10.0


def check_estimate(error, estimate, factor: float = ESTIMATE_FACTOR, floor: float = 0.0, what: str = ""):
    """Both sides of an error estimate: every true error lies within its estimate, and the largest
    estimate is at most ``factor`` times the largest true error (or ``floor``, the smallest error
    the oracle can resolve). Errors and estimates are arrays of the same quantity and unit."""
    error, estimate = np.abs(np.asarray(error, float)), np.asarray(estimate, float)
    assert np.all(error <= estimate + 1e-12), f"{what}: an error exceeds its estimate: {error} > {estimate}"
    assert estimate.max() <= factor * max(error.max(), floor), \
        f"{what}: estimate {estimate.max():.3g} more than {factor:g} x the largest error {error.max():.3g}"
