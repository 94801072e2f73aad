"""Vectorised bisection of true/false transitions: where along a bracket a predicate changes.

The view engine locates where a horizontal ray stops leaving through a window (in azimuth), the
sunlight engine where the sun appears or disappears (in time); both bracket every transition
between two samples and halve all brackets at once.
"""
from __future__ import annotations

from collections.abc import Callable

import numpy as np


def bisect_transitions(predicate: Callable[[np.ndarray, np.ndarray], np.ndarray], key: np.ndarray, lo: np.ndarray,
                       hi: np.ndarray, state_lo: np.ndarray, *, iterations: int | None = None,
                       max_width: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Shrink brackets [lo, hi] around the points where ``predicate`` changes value.

    Each round evaluates the predicate at every bracket's midpoint, once for all brackets, and
    keeps the half in which the value still changes. Stops after ``iterations`` rounds, or once
    every bracket is at most ``max_width`` wide (whichever is given; both: the first reached).

    Parameters
    ----------
    predicate : callable (key (k,), x (k,) float) -> (k,) bool
        The quantity under test at ``x`` for the item ``key`` (a viewpoint, say); ``key`` is
        passed through unchanged.
    key : (k,) any
    lo, hi : (k,) float, brackets in the predicate's unit (rad, s)
    state_lo : (k,) bool, the predicate's value at ``lo``
    iterations : int, optional
    max_width : float, optional, in the brackets' unit

    Returns
    -------
    lo, hi : (k,) float, the final brackets; the transition lies inside each
    """
    if iterations is None and max_width is None:
        raise ValueError("bisect_transitions: give iterations or max_width")
    done = 0
    while len(lo):
        if iterations is not None and done >= iterations:
            break
        if max_width is not None and np.max(hi - lo) <= max_width:
            break
        mid = 0.5 * (lo + hi)
        same = predicate(key, mid) == state_lo
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
        done += 1
    return lo, hi
