"""Typed results of the glare check (clause 5.4) of one room."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from en17037cli.criteria.glare.positions import View


@dataclass
class ViewResult:
    """The annual method at one position and view direction.

    dgp : (h,) DGP of every usage hour as the occupant sees it (shading deployed where it is)
    dgp_unshaded : (h,) the same without the shading device
    ev_lx : (h,) vertical illuminance at the eye, unshaded [lx]
    sun_in_view : (h,) bool, the sun's disc seen through the glazing within the 180 deg field of view
    shaded : (h,) bool, the shading device deployed
    dgp_5pct : DGP exceeded in 5 % of the usage hours (standard.dgp_exceeded of ``dgp``)
    dgp_5pct_err : its Monte Carlo error (95 % interval of the replicates' values)
    hours_over : limit -> usage hours with DGP above it
    """

    view: View
    dgp: np.ndarray
    dgp_unshaded: np.ndarray
    ev_lx: np.ndarray
    sun_in_view: np.ndarray
    shaded: np.ndarray
    dgp_5pct: float
    dgp_5pct_err: float
    hours_over: dict[float, int]
    level: int


@dataclass
class MomentResult:
    """A point-in-time check at one view: DGP and E_v from evalglare on its fisheye.

    picture : (rows, cols) luminance [cd/m²] of the fisheye, for the report's picture
    """

    time: str
    view: View
    sky: str
    dgp: float
    ev_lx: float
    picture: np.ndarray | None = None


@dataclass
class ReferenceHour:
    """One usage hour of the reference check: the annual method against evalglare on a fisheye."""

    local_time: str
    dgp_fast: float
    dgp_evalglare: float
    ev_fast_lx: float
    ev_evalglare_lx: float


@dataclass
class GlareResult:
    """Clause 5.4 for one room.

    views : the annual method at each position and direction ([] without a weather file)
    level : the room's level: the lowest of its views' (None: not assessable without weather)
    worst : index of the view with the highest DGP exceeded in 5 % of the hours
    usage_local : (h,) datetime64[m] start of each usage hour on the local clock
    reference : the reference check's hours at the worst view
    transmittance_needed : the largest shading transmittance (control: glare, a neutral filter) at
        which the room reaches its required level, None where it already does or none tried does
    transmittance_needed_sun_hidden : the same for a device through which the sun's disc is not seen
    """

    views: list[ViewResult]
    level: int | None
    worst: int | None
    usage_local: np.ndarray
    usage_hours: int
    method: dict
    moments: list[MomentResult] = field(default_factory=list)
    reference: list[ReferenceHour] = field(default_factory=list)
    reference_s: float = 0.0
    level_reference: int | None = None  # the level with every hour's DGP moved by the reference's mean difference
    transmittance_needed: float | None = None
    transmittance_needed_sun_hidden: float | None = None
    transmittance_tried: tuple[float, ...] = ()
    sun_in_view_hours: int = 0
    notes: list[str] = field(default_factory=list)
    unassessable: str | None = None
    near_threshold: bool = False
    error_dgp: float = 0.0
    time_s: dict = field(default_factory=dict)
