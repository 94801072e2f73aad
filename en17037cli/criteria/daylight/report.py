"""The daylight criterion's part of report.json: per room and per point of the reference plane."""
from __future__ import annotations

from en17037cli import standard
from en17037cli.criteria.daylight.assess import targets
from en17037cli.criteria.daylight.results import DaylightResult
from en17037cli.project.settings import DaylightSettings
from en17037cli.report.numbers import json_limit, json_number, json_scores, json_xyz
from en17037cli.scene.model import Scene
from en17037cli.standard import LEVELS

#: How each figure is computed and what its error estimate means (repeated in the report), per method.
DAYLIGHT_METHODS = {
    "daylight_factor": (
        "EN 17037 method 1: daylight factor D = E / E_sky on the reference plane under the CIE standard overcast sky "
        "(L = L_z (1 + 2 sin γ) / 3; ground below the horizon at daylight.reflectance.ground), split as D = SC + R. "
        "SC, the sky component (light straight from the sky through the glazing, its angular transmittance "
        "Radiance's glass): exact visibility on the windows' gnomonic grids (frames, reveals, obstructions), cells "
        "integrated by Gauss-Legendre and split where the sky's edge crosses them (daylight.sky_component); its "
        "error is a bound. R, the externally and internally reflected components: light paths from each point "
        "(daylight.radiance.rays cosine-weighted stratified directions, more up to max_rays until the interval is within "
        "max(rel_tolerance R, abs_tolerance_pct) or D is clear of every threshold), bouncing off the room's grey "
        "Lambertian surfaces with Russian roulette, the light through the glazing taken at every bounce by directions "
        "aimed through the windows (the CIE sky by its formula, what is outside by Radiance rtrace); its error is the "
        "half-width of a 99 % confidence interval over the paths (statistical). Error of D = the bound plus the "
        "interval; D_T = E_T / E_v,d,med, D_TM = E_TM / E_v,d,med; error of a share = share of the points whose D "
        "lies within its error of the threshold"),
    "climate_based": (
        "EN 17037 method 2: hourly illuminance of the 4380 daylight hours (the half of the year with the highest "
        "diffuse horizontal illuminance in the weather file), split as method 1: the sky straight through the glazing "
        "per Reinhart patch of daylight.sky_subdivision by the sky component's exact integration, times gendaymtx's "
        "sky without the sun; the direct sun by a ray to its centre each hour through the glazing (exact visibility), "
        "its direct normal illuminance from gendaymtx; the reflected light from daylight coefficients of method 1's "
        "light paths (daylight.radiance.climate_rays per point and replicate; what is outside by Radiance rcontrib) "
        "times gendaymtx's sky with the sun; shares by daylight.aggregation; error of a share = half-width of the 95 % "
        "confidence interval over the replicates of the paths (the direct parts are exact)"),
}


def daylight_score(res: DaylightResult, level: int) -> dict:
    """Score in [0, 3] (beyond the standard): the level plus, toward the next level, the smaller of
    the two shares reached at it over the share needed (as :func:`standard.share_score`)."""
    if level >= 3:
        return json_scores(3.0)
    nxt = LEVELS[level + 1]
    frac = min(res.target_share[nxt] / standard.DAYLIGHT_SHARES["target"],
               res.minimum_share[nxt] / standard.DAYLIGHT_SHARES["minimum_target"], 1.0)
    return json_scores(min(3.0, level + frac))


def daylight_section(scene: Scene, res: DaylightResult, required: str, settings: DaylightSettings,
                     thresholds: standard.Thresholds) -> dict:
    """The ``daylight`` section of a room in report.json (see ``schemas/report.schema.json``)."""
    level = LEVELS[res.level]
    et, etm = targets(thresholds)
    pts = scene.to_world(res.points_local)
    points = []
    for i in range(len(pts)):  # formatting each point's record
        p: dict = {"point": json_xyz(pts[i])}
        if res.daylight_factor_pct is not None:
            p["daylight_factor_pct"] = json_number(res.daylight_factor_pct[i], 4)
            p["daylight_factor_error_pct"] = json_number(res.daylight_factor_err_pct[i], 4)
        if res.sky_component_pct is not None:
            p["sky_component_pct"] = json_number(res.sky_component_pct[i], 4)
            p["sky_component_bound_pct"] = json_number(res.sky_component_bound_pct[i], 5)
            p["reflected_pct"] = json_number(res.reflected_pct[i], 4)
            p["reflected_error_pct"] = json_number(res.reflected_err_pct[i], 4)
        if res.share_of_hours is not None:
            p["share_of_hours"] = {f"{lx:g}": json_number(v[i], 4) for lx, v in res.share_of_hours.items()}
            p["share_of_hours_error"] = {f"{lx:g}": json_number(v[i], 4) for lx, v in res.share_of_hours_err.items()}
        points.append(p)
    by_level = {}
    for name in LEVELS[1:]:
        entry = {"target_lx": et[name], "minimum_target_lx": etm[name],
                 "target_share": json_number(res.target_share[name], 4),
                 "target_share_error": json_number(res.target_share_err[name], 4),
                 "minimum_target_share": json_number(res.minimum_share[name], 4),
                 "minimum_target_share_error": json_number(res.minimum_share_err[name], 4)}
        if res.method == "daylight_factor":
            entry |= {"target_daylight_factor_pct": json_number(100.0 * et[name] / res.median_diffuse_lx, 4),
                      "minimum_target_daylight_factor_pct": json_number(100.0 * etm[name] / res.median_diffuse_lx, 4)}
        by_level[name] = entry
    limit = standard.daylight_limit(res.target_share, res.minimum_share, res.level, required, etm)
    df = res.daylight_factor_pct
    rad = {k: v for k, v in res.radiance.items() if not k.endswith("time_s")}
    out = {
        "level": level,
        "required": required,
        "status": standard.status(level, required),
        "method": res.method,
        "median_diffuse_lx": json_number(res.median_diffuse_lx, 1),
        "median_diffuse_source": res.median_source,
        "limiting": json_limit(limit),
        "score": daylight_score(res, res.level),
        "near_threshold": res.near_threshold,
        "levels": by_level,
        "required_shares": dict(standard.DAYLIGHT_SHARES),
        "error_estimates": {
            "max_share_error": json_number(max([*res.target_share_err.values(), *res.minimum_share_err.values()]), 4),
            "method": DAYLIGHT_METHODS[res.method],
            "radiance": rad,
        },
        "points": points,
    }
    if df is not None and len(df):
        out["error_estimates"]["max_daylight_factor_error_pct"] = json_number(float(res.daylight_factor_err_pct.max()), 4)
        out["median_daylight_factor_pct"] = json_number(float(_median(df)), 4)
    if res.sky_component_pct is not None and len(df):
        out["error_estimates"]["max_sky_component_bound_pct"] = json_number(float(res.sky_component_bound_pct.max()), 5)
        out["error_estimates"]["max_reflected_error_pct"] = json_number(float(res.reflected_err_pct.max()), 4)
        out["error_estimates"]["kinds"] = {"sky_component": "bound", "reflected": "99 % confidence interval"}
        out["error_estimates"]["sky_component"] = dict(settings.sky_component.__dict__)
    if res.method == "climate_based":
        out["aggregation"] = res.aggregation
        out["daylight_hours"] = res.hours
        out["error_estimates"]["max_share_of_hours_error"] = json_number(
            max((float(v.max()) for v in res.share_of_hours_err.values() if len(v)), default=0.0), 4)
    return out


def _median(x):
    import numpy as np

    return np.median(x)
