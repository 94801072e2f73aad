"""Typed settings of the ``glare:`` section (EN 17037 clause 5.4), built from the resolved document.

Kept beside :mod:`en17037cli.project.settings` (which holds the other sections) so that module stays
small; :func:`glare_settings` is called by :mod:`en17037cli.project.load` like the other builders.
Units are in the field names; see the project schema and docs/glare.md for each key's meaning.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: Weekday numbers (Monday 0) of the ``usage.days`` words.
DAY_NAMES = ("mon", "tue", "wed", "thu", "fri", "sat", "sun")
#: The surfaces and defaults of ``reflectance`` (as daylight's, docs/daylight.md).
REFLECTANCE_DEFAULTS = {"floor": 0.2, "walls": 0.5, "ceiling": 0.7, "landscape": 0.2, "ground": 0.2}
#: Glazing transmittance where neither glare nor daylight gives one.
GLAZING_TV_DEFAULT = 0.7


@dataclass(frozen=True)
class Shading:
    """A movable shading device over the glazing (``glare.shading``), read as a neutral filter.

    transmittance : visible transmittance of the device for light through the glazing, in (0, 1]
    sun_transmittance : the share of the sun's disc seen through it (its normal-normal
        transmittance, EN 14501's tau_v,n-n), default ``transmittance``
    control : ``glare`` (deployed in the usage hours whose unshaded DGP exceeds the required
        level's limit) or ``always`` (deployed in every usage hour)
    """

    transmittance: float
    control: str = "glare"
    sun_transmittance: float | None = None


@dataclass(frozen=True)
class GlareRadiance:
    """Radiance settings of the vertical illuminance at the eye (rcontrib ``-I``): ambient bounces,
    divisions, weight limit, and independent replicates (their spread is the Monte Carlo error)."""

    ab: int = 5
    ad: int = 2048
    lw: float = 1e-4
    replicates: int = 4


@dataclass(frozen=True)
class GlareReference:
    """The reference check: evalglare on ``rpict -vta`` fisheyes of ``hours`` usage hours of the
    worst view, rendered at ``resolution_px`` square with ``-ab -ad -aa -ar``."""

    hours: int = 3
    resolution_px: int = 400
    ab: int = 2
    ad: int = 256
    aa: float = 0.25
    ar: int = 16


@dataclass(frozen=True)
class GlareSettings:
    """``glare:`` section (clause 5.4).

    weather : EPW file (resolved) or None (point-in-time checks only); weather_display : as written
    year : the calendar year whose weekdays the usage time counts
    usage_start_h, usage_end_h : usage time of day, local clock [h from midnight]
    usage_days : weekday numbers (Monday 0) of the usage time
    positions : None (``auto``) or (n, 4) float x, y, z [m, model frame], direction [deg, compass]
    times : point-in-time checks, ISO local date-times (``2026-12-21T12:00``)
    shading : the movable device, or None
    eye_height_m, facade_distance_m, directions : where ``auto`` puts the critical positions
    dgp_limits : level -> the DGP a level allows in all but the exceedance share of the usage hours
    """

    weather: Path | None
    weather_display: str | None
    year: int
    usage_start_h: float
    usage_end_h: float
    usage_days: tuple[int, ...]
    positions: np.ndarray | None
    times: tuple[str, ...]
    shading: Shading | None
    eye_height_m: float
    facade_distance_m: float
    directions: tuple[str, ...]
    source_threshold_cd_m2: float
    low_light_correction: bool
    dgp_limits: tuple[tuple[str, float], ...]
    glazing_transmittance: float
    reflectance: tuple[tuple[str, float], ...]
    sky_subdivision: int
    view_rays: int
    radiance: GlareRadiance
    reference: GlareReference

    def limits(self) -> dict[str, float]:
        """Level -> its DGP limit."""
        return dict(self.dgp_limits)

    @property
    def usage_words(self) -> str:
        """``08:00-18:00, Mon-Fri`` for the reports."""
        days = self.usage_days
        if days == (0, 1, 2, 3, 4):
            d = "Mon-Fri"
        elif days == tuple(range(7)):
            d = "every day"
        else:
            d = ", ".join(DAY_NAMES[k].capitalize() for k in days)
        return f"{hhmm(self.usage_start_h)}-{hhmm(self.usage_end_h)}, {d}"


def hhmm(hours: float) -> str:
    """``08:00`` from 8.0 [h]."""
    m = int(round(hours * 60))
    return f"{m // 60:02d}:{m % 60:02d}"


def clock_hours(text: str) -> float:
    """Hours from midnight of ``HH:MM`` (the schema checks the form) [h]."""
    h, m = text.split(":")
    return int(h) + int(m) / 60.0


def usage_days(days) -> tuple[int, ...]:
    """Weekday numbers of ``usage.days``: ``weekdays`` (Mon-Fri), ``all``, or a list of day names."""
    if days == "weekdays":
        return (0, 1, 2, 3, 4)
    if days == "all":
        return tuple(range(7))
    return tuple(sorted({DAY_NAMES.index(str(d).lower()[:3]) for d in days}))


def glare_settings(d: dict, directory: Path, daylight: dict | None = None) -> GlareSettings:
    """The typed settings of a resolved ``glare`` section; materials not given are daylight's
    (``daylight``: that resolved section, or None), else :data:`REFLECTANCE_DEFAULTS`."""
    w = d.get("weather")
    pos = d.get("positions", "auto")
    positions = None if pos == "auto" else np.array([[p["x"], p["y"], p["z"], p["direction_deg"]] for p in pos], dtype=float)
    sh = d.get("shading", "none")
    shading = None if sh == "none" else Shading(float(sh["transmittance"]), sh.get("control", "glare"),
                                                None if "sun_transmittance" not in sh else float(sh["sun_transmittance"]))
    refl = {**REFLECTANCE_DEFAULTS, **((daylight or {}).get("reflectance") or {}), **(d.get("reflectance") or {})}
    tv = d.get("glazing_transmittance", (daylight or {}).get("glazing_transmittance", GLAZING_TV_DEFAULT))
    u, rp, rf = d["usage"], d["radiance"], d["reference"]
    return GlareSettings(
        weather=None if w is None else (directory / w).resolve(), weather_display=w, year=int(d["year"]),
        usage_start_h=clock_hours(u["start"]), usage_end_h=clock_hours(u["end"]), usage_days=usage_days(u["days"]),
        positions=positions, times=tuple(d.get("times", ())), shading=shading, eye_height_m=float(d["eye_height_m"]),
        facade_distance_m=float(d["facade_distance_m"]), directions=tuple(d["directions"]),
        source_threshold_cd_m2=float(d["source_threshold_cd_m2"]), low_light_correction=bool(d["low_light_correction"]),
        dgp_limits=tuple((k, float(d["dgp_limits"][k])) for k in ("minimum", "medium", "high")),
        glazing_transmittance=float(tv), reflectance=tuple((k, float(refl[k])) for k in REFLECTANCE_DEFAULTS),
        sky_subdivision=int(d["sky_subdivision"]), view_rays=int(d["view_rays"]),
        radiance=GlareRadiance(int(rp["ab"]), int(rp["ad"]), float(rp["lw"]), int(rp["replicates"])),
        reference=GlareReference(int(rf["hours"]), int(rf["resolution_px"]), int(rf["ab"]), int(rf["ad"]), float(rf["aa"]),
                                 int(rf["ar"])))
