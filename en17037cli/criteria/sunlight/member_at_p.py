"""Point P behind a member of the window's own frame: a mullion or a transom at P.

EN 17037 Annex A.3 puts P on the room-side plane of the opening at the horizontal centre of the
window. A window of two panes has a mullion there: P sits behind it, and a bar a few centimetres
wide, seen from a few centimetres away, hides the sun for hours that the window lets in (ArchiCAD's
FZK-Haus: 2.70 h at P behind its 12 cm mullion, 5.12 h with P at either pane). The same window drawn
as two panes (two windows to a format that has no window object) had P at each pane. The rule the
standard states does not say what to do; its intent is the sun that enters through the window, so
the choice is a parameter, ``sunlight.point_p_behind_member``:

``pane_centres`` (default)
    P moves along the window's width (across a mullion; along its height where a transom lies at
    P's height) to the middle of the clear glass on each side of the member, and the window's sun is
    the sun seen from either point: what a window drawn as separate panes gets, and a few
    centimetres of member width or position do not change it.
``nearest_glass``
    P moves to the nearest clear glass on each side, :data:`CLEARANCE_M` beyond the member's edge;
    the sun seen from either point.
``as_drawn``
    P stays behind the member, which shades it.

Whatever the choice, the report gives the hours at P as drawn and at the nearest glass beside the
member, so the few centimetres the result rests on are visible in the check itself.

"Clear glass" at a point of the room-side plane: the straight line from it out along the window's
normal reaches the window's glazing with no face of the ``interior`` layer between (no member, no frame; the jambs'
reveals lie outside the glazing's outline). Sampled every :data:`STEP_M` along the line through P,
the edges of the clear runs found by bisection to :data:`EDGE_TOL_M`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.geometry import points_in_triangles, window_axes
from en17037cli.raytrace import RayEngine
from en17037cli.scene.model import Window

#: The choices of ``sunlight.point_p_behind_member`` (see the module docstring).
RULES = ("pane_centres", "nearest_glass", "as_drawn")
#: Samples along the line through P [m] ...
STEP_M = 0.005
#: ... and the edges of clear glass found to this [m].
EDGE_TOL_M = 1e-4
#: ``nearest_glass``: P lies this far beyond the member's edge [m].
CLEARANCE_M = 0.01


@dataclass(frozen=True)
class MemberAtP:
    """What lies in front of a point P, and where the glass beside it is.

    axis : (3,) the direction searched (the window's width, or its height for a transom)
    pane_centres, nearest_glass : (k, 3) [m] the points on each side (k = 1 or 2)
    """

    axis: np.ndarray
    pane_centres: np.ndarray
    nearest_glass: np.ndarray

    def points(self, rule: str, p: np.ndarray) -> np.ndarray:
        """(k, 3) [m]: the points whose sun is the window's under ``rule``."""
        return p[None, :] if rule == "as_drawn" else getattr(self, rule)


def clear_along(engine: RayEngine, window: Window, p: np.ndarray, reach: float, axis: np.ndarray,
                s: np.ndarray) -> np.ndarray:
    """(m,) bool: whether the points ``p + s * axis`` see the window's glazing straight out along its
    normal with no opaque face before it. ``reach`` [m]: the distance from P to the glazing's plane."""
    n = window.normal
    o = p[None, :] + s[:, None] * axis[None, :]
    d = np.broadcast_to(n, o.shape)
    _, t = engine.first_hit("interior", np.ascontiguousarray(o), np.ascontiguousarray(d))
    free = ~(t < reach - 1e-6)
    u, v = window_axes(n)
    on = o + reach * n
    inside = points_in_triangles(np.column_stack([on @ u, on @ v]), np.stack([window.triangles @ u, window.triangles @ v], axis=-1))
    return free & inside


def _edge(engine, window, p, reach, axis, s_blocked: float, s_clear: float) -> float:
    """The edge of the clear glass between a blocked and a clear position [m], by bisection."""
    a, b = s_blocked, s_clear
    while abs(b - a) > EDGE_TOL_M:  # ~6 steps from STEP_M
        m = 0.5 * (a + b)
        if clear_along(engine, window, p, reach, axis, np.array([m]))[0]:
            b = m
        else:
            a = m
    return b


def member_at_p(engine: RayEngine, window: Window, p: np.ndarray, reach: float) -> MemberAtP | None:
    """The member in front of ``p`` and the glass beside it, or None where P sees the glazing.

    Parameters
    ----------
    p : (3,) point P [m], local frame; reach : distance from P to the glazing's plane along its normal [m]
    """
    if clear_along(engine, window, p, reach, window_axes(window.normal)[0], np.zeros(1))[0]:
        return None
    u, v = window_axes(window.normal)
    rel = window.triangles.reshape(-1, 3) - p
    for axis in (u, v):  # across a mullion first, then across a transom
        lo, hi = float((rel @ axis).min()), float((rel @ axis).max())
        s = np.arange(np.floor(lo / STEP_M), np.ceil(hi / STEP_M) + 1) * STEP_M
        clear = clear_along(engine, window, p, reach, axis, s)
        if not clear.any():
            continue
        centres, nearest = [], []
        for side in (-1, 1):  # the glass left and right of the member (below and above)
            idx = np.flatnonzero(clear & (side * s > 0))
            if len(idx) == 0:
                continue
            first = idx[np.argmin(np.abs(s[idx]))]
            run = [first]  # the clear run nearest P, out to where it ends
            k = first + side
            while 0 <= k < len(s) and clear[k]:
                run.append(k)
                k += side
            near = _edge(engine, window, p, reach, axis, float(s[first - side]), float(s[first]))
            far_k = run[-1] + side
            far = _edge(engine, window, p, reach, axis, float(s[far_k]), float(s[run[-1]])) if 0 <= far_k < len(s) else float(s[run[-1]])
            centres.append(p + 0.5 * (near + far) * axis)
            nearest.append(p + (near + side * min(CLEARANCE_M, 0.5 * abs(far - near))) * axis)
        return MemberAtP(axis, np.array(centres), np.array(nearest))
    return None
