"""Protection from glare (5.4), its parts against independent values: the 5 % rule and the levels by
hand, the usage hours counted on a calendar, the DGP formula at evalglare's own figures, the
position index against evalglare's, the Reinhart binning and the glass against Radiance, and the
vertical illuminance at the eye under the CIE overcast sky against its closed form."""
from __future__ import annotations

import math

import numpy as np
import pytest

from en17037cli import standard
from en17037cli.criteria.glare.dgp import dgp, glass_transmission, position_index, reinhart_bin, sphere_directions
from en17037cli.criteria.glare.usage import count_usage_hours, usage_hours

pytest.importorskip("pyradiance")


def test_five_percent_rule_by_hand():
    # 100 hours: 5 may exceed the limit, so the DGP "exceeded in 5 %" is the 6th largest
    series = np.full(100, 0.30)
    series[:5] = [0.9, 0.8, 0.7, 0.6, 0.5]
    series[5] = 0.42
    assert standard.dgp_exceeded(series) == pytest.approx(0.42)
    assert int(standard.glare_level(0.42)) == 1  # at most 0.45 (minimum), above 0.40 (medium)
    # six hours above 0.45 in 100: more than 5 % -> not even minimum
    series[5] = 0.46
    assert int(standard.glare_level(standard.dgp_exceeded(series))) == 0
    # exactly at a limit is within it (compared with <=); 0.35 on 96 hours and 0.9 on 4 -> high
    s = np.array([0.9] * 4 + [0.35] * 96)
    assert standard.dgp_exceeded(s) == 0.35 and int(standard.glare_level(0.35)) == 3
    # 2610 usage hours: 130 may exceed (5 % of 2610 is 130.5)
    s = np.zeros(2610)
    s[:130] = 1.0
    assert standard.dgp_exceeded(s) == 0.0
    s[130] = 1.0
    assert standard.dgp_exceeded(s) == 1.0
    # hours over each limit, by hand
    assert standard.glare_level(np.array([0.5, 0.44, 0.39, 0.30])).tolist() == [0, 1, 2, 3]
    assert math.isnan(float(standard.dgp_exceeded(np.zeros(0))))


def _calendar(year: int):
    """month, day, hour (1..24) of every hour of ``year`` as an EPW lists them."""
    days = np.arange(np.datetime64(f"{year}-01-01"), np.datetime64(f"{year + 1}-01-01"))
    month = days.astype("datetime64[M]").astype(int) % 12 + 1
    day = (days - days.astype("datetime64[M]")).astype(int) + 1
    return np.repeat(month, 24), np.repeat(day, 24), np.tile(np.arange(1, 25), len(days))


@pytest.mark.parametrize("year, weekdays", [(2026, 261), (2024, 262), (2027, 261)])
def test_usage_hours_weekdays_8_to_18(year, weekdays):
    # 2026 starts on a Thursday: 52 weeks and one day (a Thursday) -> 261 weekdays; 2024 (leap) starts
    # on a Monday: 52 weeks and two days (Mon, Tue) -> 262; 10 hours a day
    assert count_usage_hours(year, 8.0, 18.0, (0, 1, 2, 3, 4)) == 10 * weekdays
    m, d, h = _calendar(year)
    u = usage_hours(m, d, h, 0.0, "UTC", year, 8.0, 18.0, (0, 1, 2, 3, 4))
    assert len(u) == 10 * weekdays
    first = str(u.local_start[0])
    assert first.endswith("08:00") and np.datetime64(first[:10]).astype(int) % 7 not in (2, 3)  # not a weekend day
    # Amsterdam keeps summer time: the usage hours stay 08:00 to 18:00 on the clock, so in July the first
    # is the EPW's 07:00-08:00 standard-time row (hour 8) and the count is the same
    u = usage_hours(m, d, h, 1.0, "Europe/Amsterdam", year, 8.0, 18.0, (0, 1, 2, 3, 4))
    assert len(u) == 10 * weekdays
    july = np.flatnonzero(m[u.rows] == 7)[0]
    assert h[u.rows[july]] == 8 and str(u.local_start[july]).endswith("08:00")
    jan = np.flatnonzero(m[u.rows] == 1)[0]
    assert h[u.rows[jan]] == 9


def test_usage_hours_of_a_leap_year_file_in_a_common_year():
    m, d, h = _calendar(2024)  # 8784 rows with 29 February
    u = usage_hours(m, d, h, 0.0, "UTC", 2026, 8.0, 18.0, tuple(range(7)))
    assert len(u) == 365 * 10 and not np.any((m[u.rows] == 2) & (d[u.rows] == 29))


def test_dgp_formula_at_evalglares_figures():
    # evalglare 3.06 -d on a hand-built picture: E_v 1839.133319 lx, one source of 5000.8125 cd/m², 0.3405170155 sr,
    # position index 2.107473 -> DGP 0.303666 (its output, 6 decimals)
    assert float(dgp(1839.133319, 5000.8125**2 * 0.3405170155 / 2.107473**2)) == pytest.approx(0.303666, abs=1e-6)
    assert float(dgp(3000.0, 0.0)) == pytest.approx(5.87e-5 * 3000 + 0.159)
    # low-light correction (Wienold 2009), below 1000 lx only
    raw = float(dgp(300.0, 1e6))
    assert float(dgp(300.0, 1e6, low_light_correction=True)) == pytest.approx(raw * math.exp(3.2) / (1 + math.exp(3.2)))
    assert float(dgp(1200.0, 1e6, low_light_correction=True)) == float(dgp(1200.0, 1e6))
    assert float(dgp(0.0, 5.0)) == 0.0 and float(dgp(1e6, 1e30)) == 1.0


def test_position_index_guth_and_iwata_by_hand():
    f = np.array([0.0, 1.0, 0.0])
    assert position_index([[0.0, 1.0, 0.0]], f)[0] == pytest.approx(1.0)  # on the line of sight
    # straight up from the line of sight by sigma: tau = 0; Guth: exp((35.2 - 1.22) sigma / 1000 + 21 sigma² / 1e5)
    s = 30.0
    d = [0.0, math.cos(math.radians(s)), math.sin(math.radians(s))]
    assert position_index([d], f)[0] == pytest.approx(math.exp(33.98e-3 * s + 21e-5 * s * s))
    # below: Iwata, R = tan(phi) = tan 30 deg = 0.577 (< 0.6: factor 0.8)
    d = [0.0, math.cos(math.radians(30)), -math.sin(math.radians(30))]
    assert position_index([d], f)[0] == pytest.approx(1 + 0.8 * math.tan(math.radians(30)), rel=1e-4)
    assert np.isnan(position_index([[0.0, -1.0, 0.0]], f)[0])  # behind the eye


def test_sphere_directions_are_unit_and_even():
    d = sphere_directions(20000)
    assert np.allclose(np.linalg.norm(d, axis=1), 1.0)
    # an even lattice: the share of directions in a cap is the cap's share of the sphere, 2 pi (1 - cos a) / 4 pi
    for a in (10.0, 45.0, 90.0):
        share = np.mean(d @ [0.3, 0.4, np.sqrt(0.75)] > math.cos(math.radians(a)))
        assert share == pytest.approx((1 - math.cos(math.radians(a))) / 2, abs=2e-3)


# --- against Radiance ------------------------------------------------------------------------

@pytest.fixture(scope="module")
def empty_octrees():
    from en17037cli.criteria.glare import engine

    o = engine.Octrees("void plastic m\n0\n0\n5 0 0 0 0 0\n\nm polygon t\n0\n0\n9 0 0 -1000 0.01 0 -1000 0 0.01 -1000\n")
    yield o
    o.close()


@pytest.mark.parametrize("mf", [1, 2])
def test_reinhart_bin_is_rcontribs(empty_octrees, mf):
    from en17037cli.criteria.daylight import radiance
    from en17037cli.criteria.glare import engine

    rng = np.random.default_rng(mf)
    d = rng.normal(size=(2000, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    d[:, 2] = np.abs(d[:, 2])
    oc = empty_octrees.with_sky(engine.PATCH_SKY)
    args = ["rcontrib", "-h", "-fdd", "-ab", "0", "-lw", "1e-6", "-f", "reinhartb.cal", "-e", f"MF:{mf}", "-b", "rbin", "-bn",
            "Nrbins", "-m", "skyglow", oc]
    raw = np.frombuffer(radiance.run(args, engine.rays(np.zeros(3), d), cwd=empty_octrees.dir)).reshape(len(d), -1, 3)
    assert np.array_equal(raw[:, :, 0].argmax(axis=1) + 1, reinhart_bin(d, mf))  # gendaymtx's rows: 0 is the ground


def test_glass_transmission_is_radiances_glass():
    from en17037cli.criteria.daylight import radiance
    from en17037cli.criteria.glare import engine

    tn = float(radiance.glass_transmissivity(0.7))
    o = engine.Octrees(f"void glass g\n0\n0\n3 {tn} {tn} {tn}\n\ng polygon p\n0\n0\n12 -100 -100 1 100 -100 1 100 100 1 -100 100 1\n")
    oc = o.with_sky("void glow skyglow\n0\n0\n4 1 1 1 0\n\nskyglow source skydome\n0\n0\n4 0 0 1 180\n")
    th = np.radians(np.arange(0.0, 86.0, 5.0))
    d = np.column_stack([np.sin(th), np.zeros_like(th), np.cos(th)])
    got = np.frombuffer(radiance.run(["rtrace", "-h", "-fdd", "-ab", "0", "-lw", "1e-6", oc], engine.rays(np.zeros(3), d),
                                     cwd=o.dir)).reshape(-1, 3)[:, 0]
    o.close()
    # rtrace works in float; the formula is the same one
    assert np.allclose(glass_transmission(tn, np.cos(th)), got, atol=1e-6)
    assert float(glass_transmission(tn, 1.0)) == pytest.approx(0.7, abs=1e-6)


def _reinhart_centres(mf: int) -> np.ndarray:
    """Directions of the Reinhart patch centres (reinhart.cal's layout), zenith cap last."""
    rings = np.repeat(np.array([30, 30, 24, 24, 18, 12, 6]) * mf, mf)
    a = 90.0 / (7 * mf + 0.5)
    out = []
    for r, n in enumerate(rings):
        alt, az = np.radians((r + 0.5) * a), np.radians(np.arange(n) * 360.0 / n)
        out.append(np.column_stack([np.sin(az) * np.cos(alt), np.cos(az) * np.cos(alt), np.full(n, np.sin(alt))]))
    return np.vstack([*out, [[0.0, 0.0, 1.0]]])


def test_vertical_illuminance_under_cie_overcast_closed_form(empty_octrees):
    """E_v on a vertical plane facing +y, unobstructed, under the CIE overcast sky L = Lz (1 + 2 sin g) / 3
    with a ground of reflectance r: the sky's half in front gives Lz (pi / 6 + 4 / 9), the ground (uniform,
    r E_h / pi, E_h = 7 pi Lz / 9) gives r E_h / 2 (Moon and Spencer 1942; integrated by hand)."""
    from en17037cli.criteria.daylight.sky import cie_overcast_luminance
    from en17037cli.criteria.glare import engine

    oc = empty_octrees.with_sky(engine.PATCH_SKY)
    lz, rho = 1000.0, 0.2
    exact = lz * (math.pi / 6 + 4 / 9) + rho * (7 * math.pi * lz / 9) / 2
    for mf, tol in ((1, 0.01), (2, 0.005)):  # the sky held uniform over each patch: 0.35 % (MF 1), 0.09 % (MF 2) measured
        dc = engine.eye_coefficients(empty_octrees, oc, np.zeros((1, 3)), np.array([[0.0, 1.0, 0.0]]), mf, 1, 8192, 1e-5, 4)
        c = _reinhart_centres(mf)
        sky = np.concatenate([[rho * 7 * lz / 9], lz * cie_overcast_luminance(np.arcsin(c[:, 2]))]) / 179.0
        assert (dc[:, 0, :] @ sky).mean() == pytest.approx(exact, rel=tol)


@pytest.mark.parametrize("north", [0.0, 40.0, -115.0])
def test_skies_turn_to_the_models_north_as_the_spa_sun(north):
    """The model's true north ``north`` deg clockwise from +y: the patch gendaymtx -d puts the sun in
    (-r), gendaylit's sun turned by xform, and the NREL SPA's sun in the model frame agree."""
    from en17037cli.criteria.glare import engine
    from en17037cli.criteria.sunlight.solar_position import direction_vectors, solar_position
    from en17037cli.project.glare_settings import GLAZING_TV_DEFAULT  # noqa: F401  (the settings module imports alone)

    # 21 March 2026 at 10:30 and 2 July at 15:30 local standard time (UTC+1), Delft
    wea = ("place test\nlatitude 52.0\nlongitude -4.36\ntime_zone -15\nsite_elevation 0.0\nweather_data_file_units 1\n"
           "3 21 10.500 600.0 100.0\n7 2 15.500 500.0 150.0\n")
    sun = engine.sky_matrix(wea, 2, north, 0.2, "sun")
    unix = np.array([np.datetime64("2026-03-21T09:30"), np.datetime64("2026-07-02T14:30")]).astype("datetime64[s]").astype(float)
    elev, azim = solar_position(unix, 52.0, 4.36)
    spa = direction_vectors(elev, azim, north)
    assert np.array_equal(np.argmax(sun, axis=0), reinhart_bin(spa, 2))  # the sun's patch (MF 2: 5 deg wide)
    for k, (mo, d, h) in enumerate(((3, 21, 10.5), (7, 2, 15.5))):
        text = engine.sky_text("gendaylit", mo, d, h, 52.0, 4.36, 15.0, north, 0.2, 600.0, 100.0).split()
        i = text.index("source")
        sun_dir = np.array([float(x) for x in text[i + 5:i + 8]])  # solar source sun 0 0 4 dx dy dz 0.533
        # gendaylit's own solar position (Radiance's sun.c: an approximate solar time) is 0.74 deg off the SPA here
        assert np.degrees(np.arccos(np.clip(sun_dir @ spa[k], -1, 1))) < 1.0
