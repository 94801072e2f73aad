"""Typed results of the view criterion: per point, per eye height, per room."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

import numpy as np

#: The view layers of EN 17037 clause 5.2, in report order.
LAYER_NAMES = ("sky", "landscape", "ground")


def concat(items: list):
    """One dataclass of per-point arrays from chunks of the same type (dicts of arrays and None kept)."""
    first = items[0]
    out: dict[str, Any] = {}
    for f in dataclasses.fields(first):
        vals = [getattr(i, f.name) for i in items]
        if vals[0] is None:
            out[f.name] = None
        elif isinstance(vals[0], dict):
            out[f.name] = {k: np.concatenate([v[k] for v in vals]) for k in vals[0]}
        else:
            out[f.name] = np.concatenate(vals)
    return type(first)(**out)


@dataclass(kw_only=True)
class OutsideDistance:
    """Per point: outside distance and its resolution estimate [m], where this method measures it.

    distance_m, distance_gap_m : (p,) float [m], or None where the project's distance method is
    the other one (``solid_angle`` is measured with the solid angles, ``horizontal`` with the fan)
    """

    distance_m: np.ndarray | None = None
    distance_gap_m: np.ndarray | None = None


@dataclass
class SolidAngles(OutsideDistance):
    """Per point: solid angle of each layer seen through the room's windows and its error estimate [sr].

    sr, err_sr : layer name -> (p,) float [sr]: the estimate and the exact mode's error estimate
        (half the solid angle of the mixed cells holding the layer)
    glazing_sr : (p,) float [sr], the windows' geometric solid angle
    cells : (p,) int, final cells of the integration
    lo_sr, hi_sr : layer name -> (p,) float [sr]: the interval the layer's solid angle lies in at
        the sampling's resolution (the cells wholly of the layer; plus every mixed cell that can
        hold it), which holds the estimate of any finer refinement (None: not traced)
    decided : (p,) bool, whether the point's layers level is decided by the intervals (None: not known)
    undecided : layer name -> (p,) bool, whether its interval still holds the layer threshold
        (visible or not is then the estimate's answer, as in the exact mode; None: not known)
    """

    sr: dict[str, np.ndarray]
    err_sr: dict[str, np.ndarray]
    glazing_sr: np.ndarray
    cells: np.ndarray
    lo_sr: dict[str, np.ndarray] | None = None
    hi_sr: dict[str, np.ndarray] | None = None
    decided: np.ndarray | None = None
    undecided: dict[str, np.ndarray] | None = None


@dataclass
class SightAngles(OutsideDistance):
    """Per point: horizontal sight angle and its error bound [deg].

    transitions : (p,) int, changes between leaving and blocked located by bisection
    rays : (p,) int, rays traced for the fan
    """

    angle_deg: np.ndarray
    angle_err_deg: np.ndarray
    transitions: np.ndarray
    rays: np.ndarray


@dataclass
class ViewPoints:
    """Everything known about each viewpoint of one eye height.

    distance_m : (p,) float [m], outside distance by the project's method (+inf: unobstructed,
        NaN: no direction leaves); distance_gap_m its resolution estimate
    visible : layer name -> (p,) bool
    level_by_criterion : criterion -> (p,) int level index (see standard.VIEW_CRITERIA)
    level : (p,) int, the point's view level; near : (p,) bool, within its error of a threshold
    """

    solid: SolidAngles
    sight: SightAngles
    distance_m: np.ndarray
    distance_gap_m: np.ndarray
    visible: dict[str, np.ndarray]
    level_by_criterion: dict[str, np.ndarray]
    level: np.ndarray
    near: np.ndarray

    def __len__(self) -> int:
        return len(self.level)


@dataclass
class EyeHeightResult:
    """The viewpoints of one eye height and the room's levels from them.

    points_local : (p, 3) float [m]
    level_by_criterion : criterion -> level index reached by the area fraction of the points
    share_by_level : criterion (and ``view``) -> level name -> share of points reaching it
    """

    eye_height_m: float
    points_local: np.ndarray
    values: ViewPoints | None
    level: int
    level_by_criterion: dict[str, int]
    share_by_level: dict[str, dict[str, float]]


@dataclass
class ViewResult:
    """The view result of one room: per eye height, and the room's level (the lowest of them).

    layers_unassessable : why the view layers cannot be judged on this model (it has no landscape:
        :func:`~en17037cli.criteria.view.no_landscape`), or None; then the room's view is not
        assessable, whatever its sight angle and distance, which are still reported
    """

    eye_heights: list[EyeHeightResult]
    level: int
    notes: list[str] = field(default_factory=list)
    layers_unassessable: str | None = None
