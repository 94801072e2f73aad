"""Daylight provision of a room: the reference plane, the values on it by either method, the shares of
Table A.1 and the room's level with their error estimates."""
from __future__ import annotations

import numpy as np

from en17037cli import standard
from en17037cli.criteria.daylight.results import DaylightResult
from en17037cli.criteria.view.viewpoints import grid_points
from en17037cli.errors import NotAssessable
from en17037cli.project.settings import DaylightSettings
from en17037cli.scene.model import Room
from en17037cli.standard import LEVELS, Thresholds

#: Two-sided 95 % quantiles of Student's t by degrees of freedom (1..30); the normal 1.96 beyond.
_T975 = (12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
         2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042)


def t975(dof: int) -> float:
    """Student's t quantile 0.975 for ``dof`` degrees of freedom (tables, e.g. NIST/SEMATECH e-Handbook 1.3.6.7.2)."""
    return _T975[dof - 1] if 1 <= dof <= len(_T975) else 1.96


def mean_and_error(replicates: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean over the last axis and the half-width of its 95 % confidence interval, t(0.975, r-1) s / sqrt(r).

    Parameters
    ----------
    replicates : (..., r) independent estimates of one quantity, r >= 2
    """
    r = replicates.shape[-1]
    m = replicates.mean(axis=-1)
    s = replicates.std(axis=-1, ddof=1) if r > 1 else np.zeros_like(m)
    return m, t975(r - 1) * s / np.sqrt(r)


def reference_plane(room: Room, settings: DaylightSettings) -> np.ndarray:
    """The grid on the reference plane (Annex A): the floor inset by ``wall_margin_m``, gridded as the
    view's (:func:`~en17037cli.criteria.view.viewpoints.grid_points`) with ``grid_spacing_m``, at
    ``reference_plane_m`` above the floor; (n, 3) [m, local]."""
    utilised = room.floor.buffer(-settings.wall_margin_m, join_style="mitre")
    if utilised.is_empty:
        raise NotAssessable(f"the reference plane (floor inset by daylight.wall_margin_m = {settings.wall_margin_m} m) is "
                            "empty; reduce the margin or check the floor")
    xy = grid_points(utilised, settings.grid_spacing_m, settings.grid_offset)
    return np.column_stack([xy, np.full(len(xy), room.floor_z + settings.reference_plane_m)])


def targets(thresholds: Thresholds) -> tuple[dict[str, float], dict[str, float]]:
    """Level -> target illuminance E_T and minimum target illuminance E_TM [lx] (Table A.1)."""
    t, m = thresholds.daylight_target_lx.as_dict(), thresholds.daylight_minimum_target_lx.as_dict()
    return t, m


def shares_from_points(passes: dict[str, np.ndarray]) -> dict[str, float]:
    """Level -> share of the points that pass (bool (n,) per level)."""
    return {k: float(np.mean(v)) if v.size else 0.0 for k, v in passes.items()}


def judge(target_share, minimum_share, target_err, minimum_err) -> tuple[int, bool]:
    """The level of Table A.1 and whether a share lies within its error estimate of the share needed
    at the level reached or the next one (the level could flip)."""
    level = standard.daylight_level(target_share, minimum_share)
    near = False
    for name in LEVELS[1:]:
        for share, err, need in ((target_share, target_err, standard.DAYLIGHT_SHARES["target"]),
                                 (minimum_share, minimum_err, standard.DAYLIGHT_SHARES["minimum_target"])):
            near |= bool(err[name] > 0 and abs(share[name] - need) <= err[name])
    return level, near


def daylight_factor_room(points: np.ndarray, sky, refl, median_lx: float, source: str,
                         thresholds: Thresholds, radiance: dict) -> DaylightResult:
    """Method 1 (clause 5.1, Annex A): D = E / E_sky on the grid under the CIE overcast sky; a level is
    met when D >= D_T = E_T / E_v,d,med on 50 % of the plane and D >= D_TM = E_TM / E_v,d,med on 95 %.

    D = SC + R: the sky component ``sky`` (:class:`~.sky_component.SkyComponent`: value and a bound)
    and the reflected components ``refl`` (:class:`~.gather.Reflected`: value and the half-width of a
    99 % interval), both fractions of the unobstructed horizontal illuminance. The error of D is the
    bound plus the interval.

    Parameters
    ----------
    points : (n, 3) [m]; median_lx : E_v,d,med [lx]
    """
    df = 100.0 * (sky.value + refl.value)
    err = 100.0 * (sky.bound + refl.error)
    et, etm = targets(thresholds)
    share, share_m, e_share, e_share_m = {}, {}, {}, {}
    for name in LEVELS[1:]:
        dt, dtm = 100.0 * et[name] / median_lx, 100.0 * etm[name] / median_lx
        share[name] = float(np.mean(df >= dt)) if len(df) else 0.0
        share_m[name] = float(np.mean(df >= dtm)) if len(df) else 0.0
        # error of a share: the points whose D lies within its error of the threshold could go either way
        # (none for a threshold of 0, which every point reaches: a practice that asks no minimum target)
        e_share[name] = float(np.mean(np.abs(df - dt) <= err)) if len(df) and dt > 0 else 0.0
        e_share_m[name] = float(np.mean(np.abs(df - dtm) <= err)) if len(df) and dtm > 0 else 0.0
    level, near = judge(share, share_m, e_share, e_share_m)
    return DaylightResult(method="daylight_factor", points_local=points, median_diffuse_lx=median_lx, median_source=source,
                          target_share=share, minimum_share=share_m, target_share_err=e_share, minimum_share_err=e_share_m,
                          level=level, near_threshold=near, radiance=radiance | {"rays": int(refl.rays.sum())},
                          daylight_factor_pct=df, daylight_factor_err_pct=err, sky_component_pct=100.0 * sky.value,
                          sky_component_bound_pct=100.0 * sky.bound, reflected_pct=100.0 * refl.value,
                          reflected_err_pct=100.0 * refl.error)


def share_above(e_lx: np.ndarray, threshold_lx: float) -> np.ndarray:
    """Share of the hours (last axis) each point's illuminance reaches ``threshold_lx`` (>=)."""
    return (e_lx >= threshold_lx).mean(axis=-1)


def upper_median(values: np.ndarray, fraction: float) -> float:
    """The value reached on at least ``fraction`` of the entries: the k-th largest, k = ceil(n fraction)."""
    v = np.sort(np.asarray(values, dtype=float))[::-1]
    if not v.size:
        return 0.0
    return float(v[max(1, int(np.ceil(v.size * fraction - 1e-9))) - 1])


def climate_shares(e_lx: np.ndarray, thresholds: Thresholds, aggregation: str) -> tuple[dict, dict, dict[float, np.ndarray]]:
    """Shares of the plane of Table A.1 from hourly illuminance (method 2), in either order.

    ``hours_first``: a point reaches an illuminance when it does on at least half of the daylight
    hours; the share of the plane is that of its points that do. ``points_first``: each hour, the
    share of the plane reaching it; the share that counts is the one reached on at least half of the
    hours (the upper median over the hours: a level's 50 % / 95 % is met on at least half of them
    exactly when it is).

    Parameters
    ----------
    e_lx : (n, h) [lx] illuminance of each point in each daylight hour

    Returns
    -------
    target_share, minimum_share : level -> share of the plane; share_of_hours : lx -> (n,)
    """
    et, etm = targets(thresholds)
    lux = sorted(set(et.values()) | set(etm.values()))
    per_point = {lx: share_above(e_lx, lx) for lx in lux}
    out = []
    for table in (et, etm):
        shares = {}
        for name in LEVELS[1:]:
            lx = table[name]
            if aggregation == "hours_first":
                shares[name] = float(np.mean(per_point[lx] >= standard.DAYLIGHT_HOURS_FRACTION - 1e-12)) if len(e_lx) else 0.0
            else:
                per_hour = (e_lx >= lx).mean(axis=0) if len(e_lx) else np.zeros(e_lx.shape[1])
                shares[name] = upper_median(per_hour, standard.DAYLIGHT_HOURS_FRACTION)
        out.append(shares)
    return out[0], out[1], per_point
