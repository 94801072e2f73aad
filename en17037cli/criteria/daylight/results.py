"""Typed result of the daylight provision criterion (clause 5.1) for one room."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class DaylightResult:
    """The reference plane's points, their values and error estimates, and the room's level.

    method : ``daylight_factor`` or ``climate_based``
    points_local : (n, 3) float [m], the grid on the reference plane
    median_diffuse_lx, median_source : E_v,d,med [lx] and where it came from
    daylight_factor_pct, daylight_factor_err_pct : (n,) [%], method 1 (None for method 2): D = SC + R
        and its error, the sky component's bound plus the reflected part's 99 % interval
    sky_component_pct, sky_component_bound_pct : (n,) [%], method 1: the sky component (exact) and
        the bound on its error
    reflected_pct, reflected_err_pct : (n,) [%], method 1: the reflected components (Radiance) and the
        half-width of their 99 % confidence interval
    illuminances_lx : the distinct target illuminances of Table A.1, ascending [lx]
    share_of_hours, share_of_hours_err : lx -> (n,) share of the daylight hours each point reaches
        that illuminance, and its error estimate, method 2 (None for method 1)
    target_share, minimum_share : level -> share of the plane reaching its target (minimum target)
        illuminance by the method's rule (method 2: by ``aggregation``)
    target_share_err, minimum_share_err : level -> error estimate of those shares
    level : level index; near_threshold : a share lies within its error of the share needed
    """

    method: str
    points_local: np.ndarray
    median_diffuse_lx: float
    median_source: str
    target_share: dict[str, float]
    minimum_share: dict[str, float]
    target_share_err: dict[str, float]
    minimum_share_err: dict[str, float]
    level: int
    near_threshold: bool
    radiance: dict
    daylight_factor_pct: np.ndarray | None = None
    daylight_factor_err_pct: np.ndarray | None = None
    sky_component_pct: np.ndarray | None = None
    sky_component_bound_pct: np.ndarray | None = None
    reflected_pct: np.ndarray | None = None
    reflected_err_pct: np.ndarray | None = None
    illuminances_lx: tuple[float, ...] = ()
    share_of_hours: dict[float, np.ndarray] | None = None
    share_of_hours_err: dict[float, np.ndarray] | None = None
    aggregation: str | None = None
    hours: int = 0
    notes: list[str] = field(default_factory=list)
