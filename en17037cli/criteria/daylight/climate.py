"""Method 2 of clause 5.1: hourly illuminance over the daylight hours from daylight coefficients.

E = DC · S − DC_d · S_d + C_s · S_s (the five-phase split of the sun; McNeil 2013; Subramaniam 2017):

* DC: daylight coefficients of the reference plane's points to the Reinhart sky patches
  (``daylight.sky_subdivision``), ``rcontrib`` with the run's -ab/-ad; S: ``gendaymtx`` sky of the
  weather file with the sun spread into its patch (Perez all-weather model);
* DC_d, S_d: the same coefficients with every opaque face black and -ab 1 (light straight from the
  patches through the glazing) and the sun-only sky (``gendaymtx -d``): the sun's direct part as
  the patches smear it, taken out;
* C_s, S_s: sun coefficients, ``rcontrib -ab 0`` to a 0.533° sun at the centre of each Reinhart
  patch of ``daylight.sun_subdivision`` the year's suns fall in, and ``gendaymtx -5 0.533 -d`` of
  that subdivision: the sun's direct light, sharp.

The products are numpy matrix products (what ``dctimestep`` computes, without writing the
matrices out). The hours are the daylight hours of EN 17037 (the 4380 with the highest diffuse
horizontal illuminance, :meth:`~en17037cli.weather.epw.Weather.daylight_hours`).

References: A. McNeil (2013), The five-phase method for simulating complex fenestration with
Radiance; S. Subramaniam (2017), Daylighting simulations with Radiance using matrix-based methods,
LBNL; C. Reinhart (2001) sky subdivision; R. Perez et al. (1993), All-weather model for sky
luminance distribution, Solar Energy 50(3).
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.daylight import radiance
from en17037cli.criteria.daylight.assess import climate_shares, judge, mean_and_error
from en17037cli.criteria.daylight.results import DaylightResult
from en17037cli.project.settings import DaylightSettings
from en17037cli.standard import LEVELS

#: Angular diameter of the sun [deg].
SUN_DIAMETER_DEG = 0.533


def patch_sky_text() -> str:
    """Sky and ground hemispheres of unit radiance: ``skyglow``, which ``rcontrib`` bins by direction
    into Reinhart patches (``reinhartb.cal``), and ``groundglow``, one bin (gendaymtx's row 0)."""
    return ("void glow skyglow\n0\n0\n4 1 1 1 0\n\nskyglow source skydome\n0\n0\n4 0 0 1 180\n\n"
            "void glow groundglow\n0\n0\n4 1 1 1 0\n\ngroundglow source grounddome\n0\n0\n4 0 0 -1 180\n")


def reinhart_bins(mf: int) -> int:
    """Patches of the Reinhart subdivision MF, ground included: 1 + 144 MF² + 1 (145 + 1 for MF 1)."""
    return 144 * mf * mf + 2


def coefficients(octree, points: np.ndarray, mf: int, ab: int, ad: int, lw: float, modifier: str = "skyglow") -> np.ndarray:
    """Daylight coefficients of horizontal points [lx per unit radiance]: one rcontrib call for all the
    points. ``skyglow``: (n, bins) in gendaymtx's row order (the ground, then the Reinhart patches);
    any other modifier (the suns): (n, bins - 1), the patches only."""
    sky = reinhart_bins(mf) - 1
    width = sky + 1 if modifier == "skyglow" else sky
    if not len(points):
        return np.zeros((0, width))
    args = ["rcontrib", "-h", "-fdd", "-I+", *radiance.ambient_args(ab, ad, 0, lw), "-f", "reinhartb.cal", "-e", f"MF:{mf}",
            "-b", "rbin", "-bn", "Nrbins", "-m", modifier]
    if modifier == "skyglow":
        args += ["-b", "0", "-bn", "1", "-m", "groundglow"]
    raw = np.frombuffer(radiance.run([*args, octree.path.name], radiance.rays(points), cwd=octree.dir), dtype=np.float64)
    c = radiance.illuminance(raw.reshape(-1, 3)).reshape(len(points), width)
    return np.column_stack([c[:, sky:], c[:, :sky]]) if modifier == "skyglow" else c


def sky_matrix(wea: str, mf: int, north_deg: float, *extra: str) -> np.ndarray:
    """``gendaymtx`` of a .wea text: (bins, hours) radiance per patch [W/(sr m²), visible], the sky
    turned so that its north lies ``north_deg`` clockwise from the model's +y."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory(prefix="en17037-wea-") as d:
        (Path(d) / "site.wea").write_text(wea)
        raw = radiance.run(["gendaymtx", "-h", "-od", "-m", str(mf), "-r", f"{-north_deg:.6f}", *extra, "site.wea"], cwd=Path(d))
    m = np.frombuffer(raw, dtype=np.float64).reshape(reinhart_bins(mf), -1, 3)
    return m @ radiance.RGB_WEIGHTS


def skies(criterion, ctx, settings: DaylightSettings) -> dict:
    """The run's sky matrices over the daylight hours, made once: ``all``, ``sun`` (sun-only, sky
    subdivision) and ``sun_fine`` (sun-only, sun subdivision, 0.533° suns), and the hours."""
    if "daylight_skies" not in ctx.cache:
        from en17037cli.weather.epw import wea_text

        w = criterion.weather(ctx)
        hours = w.daylight_hours()
        wea = wea_text(w)
        north = ctx.scene.true_north_deg
        mf, ms = settings.sky_subdivision, settings.sun_subdivision
        ctx.cache["daylight_skies"] = {
            "hours": hours,
            "all": sky_matrix(wea, mf, north)[:, hours],
            "sun": sky_matrix(wea, mf, north, "-d")[:, hours],
            "sun_fine": sky_matrix(wea, ms, north, "-d", "-5", f"{SUN_DIAMETER_DEG}")[:, hours],
        }
    return ctx.cache["daylight_skies"]


def sun_octree(criterion, ctx, settings: DaylightSettings, sun_fine: np.ndarray):
    """The scene with a 0.533° sun of unit radiance at the centre of each sun-subdivision patch that
    a daylight hour's sun falls in (``light solar``, binned by direction)."""
    if "daylight_octree_sun" not in ctx.cache:
        active = np.flatnonzero(sun_fine[1:].max(axis=1) > 0)  # sky patches (row 0 is the ground)
        d = patch_directions(settings.sun_subdivision)[1 + active]
        text = "void light solar\n0\n0\n3 1 1 1\n\n" + "".join(
            f"solar source sun{i}\n0\n0\n4 {x:.6f} {y:.6f} {z:.6f} {SUN_DIAMETER_DEG}\n\n" for i, (x, y, z) in zip(active, d))
        refl = dict(settings.reflectance)
        ctx.cache["daylight_octree_sun"] = radiance.Octree(radiance.scene_text(ctx.scene, refl, settings.glazing_transmittance),
                                                          text)
    return ctx.cache["daylight_octree_sun"]


def patch_directions(mf: int) -> np.ndarray:
    """(bins, 3) unit directions of the Reinhart patch centres (bin 0, the ground: straight down),
    from ``reinhart.cal``'s layout: rows of 30, 30, 24, 24, 18, 12, 6 patches (x MF each), 12°/MF
    of altitude each, starting due north and going clockwise seen from above (towards +x, east),
    then the zenith cap."""
    tnaz = np.repeat(np.array([30, 30, 24, 24, 18, 12, 6]) * mf, mf)
    rowalt = 90.0 / (7 * mf + 0.5)
    out = [np.array([0.0, 0.0, -1.0])]
    for r, n in enumerate(tnaz):
        alt = np.radians((r + 0.5) * rowalt)
        az = np.radians(np.arange(n) * 360.0 / n)
        out.append(np.column_stack([np.sin(az) * np.cos(alt), np.cos(az) * np.cos(alt), np.full(n, np.sin(alt))]))
    out.append(np.array([0.0, 0.0, 1.0]))
    return np.vstack(out)


def climate_room(criterion, ctx, points: np.ndarray, settings: DaylightSettings, median: float, source: str,
                 params: dict) -> DaylightResult:
    """Method 2 for one room (see the module docstring): per replicate of the daylight coefficients
    the hourly illuminance and the shares of Table A.1; their means and 95 % intervals."""
    sk = skies(criterion, ctx, settings)
    p = settings.radiance
    mf = settings.sky_subdivision
    sun_c = coefficients(sun_octree(criterion, ctx, settings, sk["sun_fine"]), points, settings.sun_subdivision, 0, 512,
                         p.lw, "solar")
    direct_sun = sun_c @ sk["sun_fine"][1:]  # (n, h)
    per_rep = []
    for k_ad in radiance.replicate_divisions(p.ad, p.replicates):  # a few calls per room, each for every point
        dc = coefficients(criterion.octree(ctx, "sky"), points, mf, p.ab, k_ad, p.lw)
        dcd = coefficients(criterion.octree(ctx, "black"), points, mf, 1, k_ad, p.lw)
        e = dc @ sk["all"] - dcd @ sk["sun"] + direct_sun
        per_rep.append(np.maximum(e, 0.0))
    thresholds = ctx.project.thresholds
    shares = [climate_shares(e, thresholds, settings.aggregation) for e in per_rep]
    lux = sorted(shares[0][2])
    soh = {lx: mean_and_error(np.stack([s[2][lx] for s in shares], axis=-1)) for lx in lux}
    t_share, t_err, m_share, m_err = {}, {}, {}, {}
    for name in LEVELS[1:]:
        t_share[name], t_err[name] = (float(x) for x in mean_and_error(np.array([s[0][name] for s in shares])))
        m_share[name], m_err[name] = (float(x) for x in mean_and_error(np.array([s[1][name] for s in shares])))
    level, near = judge(t_share, m_share, t_err, m_err)
    return DaylightResult(method="climate_based", points_local=points, median_diffuse_lx=median, median_source=source,
                          target_share=t_share, minimum_share=m_share, target_share_err=t_err, minimum_share_err=m_err,
                          level=level, near_threshold=near, radiance=params | {"sky_subdivision": mf,
                                                                               "sun_subdivision": settings.sun_subdivision},
                          illuminances_lx=tuple(lux), share_of_hours={lx: v[0] for lx, v in soh.items()},
                          share_of_hours_err={lx: v[1] for lx, v in soh.items()}, aggregation=settings.aggregation,
                          hours=int(len(sk["hours"])))
