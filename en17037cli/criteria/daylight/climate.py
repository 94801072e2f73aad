"""Method 2 of clause 5.1: hourly illuminance over the daylight hours, split as method 1 is.

E(p, h) = Σ_k C_k(p) S_sky,k(h) + E_sun(p, h) + Σ_k R_k(p) S_all,k(h)

* direct sky: C_k, the sky seen straight through the glazing in each Reinhart patch k
  (``daylight.sky_subdivision``) for a unit radiance, ∫ cos θ τ(i) dω, by the sky component's exact
  integration (:func:`~.sky_component.sky_component`, each quadrature node put in its patch);
  S_sky: ``gendaymtx -s`` of the weather file (Perez all-weather sky without the sun);
* direct sun: the sun's direct normal illuminance (gendaymtx's sun, ``-d``, summed over its patches)
  times cos θ and τ(i), where a ray from the point to the sun's centre leaves through the room's
  glazing with nothing in the way (the view engine's first hits: the same exact visibility);
* reflected: R_k, daylight coefficients of the light reflected by any surface, by method 1's light
  paths (:mod:`.transport`: next-event estimation through the windows at every bounce): the samples
  that reach the sky count in their patch for a unit radiance, what is outside along a ray comes
  from ``rcontrib`` per patch (Russian roulette); S_all: ``gendaymtx`` with the sun in its patches
  (reflected sunlight, smooth).

Each of ``daylight.radiance.replicates`` sets of paths (``climate_rays`` per point) has its own
directions: the shares of hours are computed per replicate, and their means and 95 % intervals
reported (the direct parts are exact and the same in every replicate). The hours are the daylight hours of EN 17037 (the 4380 with the
highest diffuse horizontal illuminance, :meth:`~en17037cli.weather.epw.Weather.daylight_hours`).

References: A. McNeil (2013), The five-phase method for simulating complex fenestration with
Radiance; C. Reinhart (2001) sky subdivision; R. Perez et al. (1993), All-weather model for sky
luminance distribution, Solar Energy 50(3); I. Reda, A. Andreas (2004), Solar position algorithm.
"""
from __future__ import annotations

import numpy as np

from en17037cli.criteria.base import room_thresholds
from en17037cli.criteria.daylight import radiance
from en17037cli.criteria.daylight.assess import climate_shares, judge, mean_and_error
from en17037cli.criteria.daylight.gather import SEED, cosine_directions, rtrace_args, sampling_frame
from en17037cli.criteria.daylight.patches import patch_bin, patch_directions, patch_solid_angles, reinhart_bins
from en17037cli.criteria.daylight.results import DaylightResult
from en17037cli.criteria.daylight.sky import glass_transmittance
from en17037cli.criteria.view.rays import SKY, ViewRays
from en17037cli.project.settings import DaylightSettings
from en17037cli.scene.model import room_window_group
from en17037cli.standard import LEVELS

__all__ = ["climate_room", "patch_directions", "patch_sky_text", "reinhart_bins", "sky_matrix", "skies"]

#: Angular diameter of the sun [deg].
SUN_DIAMETER_DEG = 0.533


def patch_sky_text(sink=(0.0, 0.0, -1.0e5)) -> str:  # pragma: no mutate block
    """Sky and ground hemispheres of unit radiance: ``skyglow``, which ``rcontrib`` bins by direction
    into Reinhart patches (``reinhartb.cal``), and ``groundglow``, one bin (gendaymtx's row 0); and a
    black sphere at ``sink`` (:func:`sink_point`), where the rays that fill a record end."""
    x, y, z = sink
    return ("void glow skyglow\n0\n0\n4 1 1 1 0\n\nskyglow source skydome\n0\n0\n4 0 0 1 180\n\n"
            "void glow groundglow\n0\n0\n4 1 1 1 0\n\ngroundglow source grounddome\n0\n0\n4 0 0 -1 180\n\n"
            f"void plastic en17037_sink\n0\n0\n5 0 0 0 0 0\n\nen17037_sink sphere en17037_sink_ball\n0\n0\n4 {x:.6f} {y:.6f} {z:.6f} "
            f"{SINK_RADIUS_M}\n")


def sky_matrix(wea: str, mf: int, north_deg: float, *extra: str) -> np.ndarray:  # pragma: no mutate block
    """``gendaymtx`` of a .wea text: (bins, hours) radiance per patch [W/(sr m²), visible], the sky
    turned so that its north lies ``north_deg`` clockwise from the model's +y."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory(prefix="en17037-wea-") as d:
        (Path(d) / "site.wea").write_text(wea)
        raw = radiance.run(["gendaymtx", "-h", "-od", "-m", str(mf), "-r", f"{-north_deg:.6f}", *extra, "site.wea"], cwd=Path(d))
    m = np.frombuffer(raw, dtype=np.float64).reshape(reinhart_bins(mf), -1, 3)
    return m @ radiance.RGB_WEIGHTS


def skies(criterion, ctx, settings: DaylightSettings) -> dict:  # pragma: no mutate block
    """The run's skies over the daylight hours, made once: ``sky`` (without the sun) and ``all``
    (with it) per patch, the sun's direct normal illuminance ``sun_lx`` [lx] and direction ``sun_dir``
    (model frame) per hour, and the ``hours``."""
    if "daylight_skies" not in ctx.cache:
        from en17037cli.weather.epw import wea_text

        w = criterion.weather(ctx)
        hours = w.daylight_hours()
        wea = wea_text(w)
        north = ctx.scene.true_north_deg
        mf = settings.sky_subdivision
        sun = sky_matrix(wea, mf, north, "-d")[:, hours]
        ctx.cache["daylight_skies"] = {
            "hours": hours,
            "sky": sky_matrix(wea, mf, north, "-s")[:, hours],
            "all": sky_matrix(wea, mf, north)[:, hours],
            # gendaymtx spreads the sun's radiance over patches keeping its flux: Σ S Ω is its normal irradiance
            "sun_lx": radiance.EFFICACY_LM_W * (patch_solid_angles(mf) @ sun[1:]),
            "sun_dir": sun_directions(w, hours, north),
        }
    return ctx.cache["daylight_skies"]


def sun_directions(w, hours: np.ndarray, north_deg: float) -> np.ndarray:
    """(h, 3) unit vectors towards the sun at the middle of each hour (EPW: hour h ends at h:00 local
    standard time), at the weather file's site, in the model frame (NREL SPA, no refraction: the
    weather's radiation is per hour, not per minute)."""
    import datetime

    from en17037cli.criteria.sunlight.solar_position import direction_vectors, solar_position

    leap = len(w.hour) == 8784
    year = 2024 if leap else 2025  # a typical year has no calendar: one of the right length
    jan1 = datetime.datetime(year, 1, 1, tzinfo=datetime.UTC).timestamp()
    first = np.cumsum([0, 31, 29 if leap else 28, 31, 30, 31, 30, 31, 31, 30, 31, 30])  # day of year of each month's 1st, - 1
    days = first[w.month[hours] - 1] + w.day[hours] - 1
    t = jan1 + days * 86400.0 + (w.hour[hours] - 0.5 - w.tz_hours) * 3600.0
    el, az = solar_position(t, w.latitude, w.longitude, w.elevation_m, refraction=False)
    return direction_vectors(el, az, north_deg)


def direct_sun(ctx, room, points: np.ndarray, tv: np.ndarray, sun_lx: np.ndarray, sun_dir: np.ndarray) -> np.ndarray:
    """(n, h) [lx]: the sun's direct illuminance on the horizontal points, E_dn cos θ τ(i), in the
    hours whose sun's centre the point sees through the room's glazing (one ray each)."""
    out = np.zeros((len(points), len(sun_lx)))
    up = np.flatnonzero((sun_dir[:, 2] > 0) & (sun_lx > 0))
    if not len(points) or not len(up):
        return out
    vr = ViewRays(ctx.engine, ctx.scene)
    window_of = np.full(len(ctx.scene.triangles), -1)
    for k, w in enumerate(room.windows):
        window_of[w.face_ids] = k
    for a in range(0, len(up), 512):  # hours in blocks: bounded memory, each block vectorised over points
        hb = up[a:a + 512]
        o = np.repeat(points, len(hb), axis=0)
        d = np.tile(sun_dir[hb], (len(points), 1))
        cls, wface, _, _, _ = vr.through_windows(room_window_group(room), o, d)
        k = window_of[np.maximum(wface, 0)]
        normals = np.array([w.normal for w in room.windows])[np.maximum(k, 0)]
        tau = glass_transmittance(np.abs(np.einsum("ij,ij->i", d, normals)), tv[np.maximum(k, 0)])
        e = np.where(cls == SKY, sun_lx[hb][None].repeat(len(points), 0).ravel() * d[:, 2] * tau, 0.0)
        out[:, hb] = e.reshape(len(points), len(hb))
    return out


def path_coefficients(S, octree, points: np.ndarray, mf: int, rays: int, replicate: int, args: list[str],
                      frame: np.ndarray, sink: np.ndarray) -> np.ndarray:
    """(n, bins) daylight coefficients of the reflected light [per unit radiance of a patch], gendaymtx's
    order (the ground first): ``rays`` light paths per point (:func:`~.transport.trace_paths`), their
    next-event samples that reached the sky put in the sky's patches, their requests (what is outside
    along a ray) answered by ``rcontrib`` per patch, in batches."""
    from en17037cli.criteria.daylight.transport import trace_paths

    width = reinhart_bins(mf)
    if not len(points):
        return np.zeros((0, width))
    n = max(1, int(round(np.sqrt(rays))))
    k = n * n
    rng = np.random.default_rng([SEED, 1000 + replicate])
    d = cosine_directions(len(points), n, rng, frame).reshape(-1, 3)
    _, req, _ = trace_paths(S, np.repeat(points, k, axis=0), d, S.window_rays, [SEED, 1000 + replicate, 1])
    owner = lambda path: path // k  # noqa: E731  (paths are numbered point by point)
    dc = np.zeros((len(points), width))
    sd, sw, sp = req.arrays("sky")
    b = patch_bin(sd, mf)
    ok = b >= 0
    np.add.at(dc, (owner(sp[ok]), 1 + b[ok]), sw[ok])
    o, dd, w, path = req.arrays()
    if len(o):
        o, dd, w0, owner_of = _equal_weights(o, dd, w, owner(path), rng)
        dc += w0 * _record_sums(octree, o, dd, owner_of, len(points), mf, args, sink, S.engine.threads)
    return dc / k


def _equal_weights(o, d, w, point, rng):
    """The requests with one weight W0 (their mean), without bias: a request of weight w < W0 is kept
    with probability w / W0, one of w >= W0 becomes floor(w / W0) copies and one more with the
    probability of the rest (Russian roulette and splitting, Arvo and Kirk 1990); sorted by point.
    Returns origins, directions, W0 and each one's point."""
    w0 = float(w.mean())
    m = np.floor(w / w0).astype(np.int64) + (rng.random(len(w)) < (w / w0) % 1.0)
    idx = np.repeat(np.arange(len(w)), m)
    idx = idx[np.argsort(point[idx], kind="stable")]
    return o[idx], d[idx], w0, point[idx]


def _record_sums(octree, o, d, point, n: int, mf: int, args: list[str], sink: np.ndarray, processes: int = 1) -> np.ndarray:  # pragma: no mutate block
    """(n, bins) per point, the sum over its rays of what ``rcontrib`` gives each patch (gendaymtx's
    order), in records of :data:`RECORD` rays (``-c``: a record is their mean), each point's last
    record filled with rays that start inside a black sphere at ``sink`` (:func:`sink_point`)."""
    width = reinhart_bins(mf)
    count = np.bincount(point, minlength=n)
    records = -(-count // RECORD)
    slot = np.arange(len(point)) - np.repeat(np.cumsum(count) - count, count)  # index of each ray within its point
    orig = np.tile(sink, (int(records.sum()) * RECORD, 1))
    dirs = np.tile([0.0, 0.0, 1.0], (len(orig), 1))
    pos = (np.cumsum(records) - records)[point] * RECORD + slot
    orig[pos], dirs[pos] = o, d
    cmd = ["rcontrib", "-h", "-fdd", "-c", str(RECORD), *args, "-f", "reinhartb.cal", "-e", f"MF:{mf}", "-b", "rbin",
           "-bn", "Nrbins", "-m", "skyglow", "-b", "0", "-bn", "1", "-m", "groundglow", octree.path.name]
    rays_in = np.ascontiguousarray(np.column_stack([orig, dirs]), dtype=np.float64).reshape(-1, RECORD, 6)
    # contiguous shares of the records, as many whatever the machine's cores (each program's own random
    # sequence: the same shares give the same numbers), run up to ``processes`` at once
    parts = np.array_split(np.arange(len(rays_in)), max(1, min(8, len(rays_in) // 64)))

    def one(idx):
        return radiance.run(cmd, rays_in[idx].tobytes(), cwd=octree.dir)

    if len(parts) > 1 and processes > 1:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(min(processes, len(parts))) as pool:
            out_raw = b"".join(pool.map(one, parts))
    else:
        out_raw = b"".join(one(idx) for idx in parts)
    raw = np.frombuffer(out_raw, dtype=np.float64).reshape(-1, width, 3)
    c = RECORD * (raw @ radiance.RGB_WEIGHTS)  # the sum of each record's rays
    c = np.column_stack([c[:, width - 1:], c[:, :width - 1]])
    out = np.zeros((n, width))
    np.add.at(out, np.repeat(np.arange(n), records), c)
    return out


#: Rays per rcontrib record (``-c``): the output is a record's mean per patch, so a point's rays are
#: sent in records of this many, its last one filled up with rays that end on black.
RECORD = 64


def sink_point(scene) -> np.ndarray:
    """Where the rays that fill a record start: the centre of a black sphere of :data:`SINK_RADIUS_M`
    10 m below the model's lowest point, under the middle of its extent [m, local]; a ray from the
    model meets it only by passing 10 m under the whole model (never, under a ground)."""
    lo, hi = scene.vertices.min(axis=0), scene.vertices.max(axis=0)
    return np.array([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), lo[2] - 10.0])


#: Radius of the black sphere the filling rays start in [m].
SINK_RADIUS_M = 0.5


def climate_room(criterion, ctx, room, points: np.ndarray, settings: DaylightSettings, median: float, source: str,
                 params: dict) -> DaylightResult:  # pragma: no mutate block
    """Method 2 for one room (see the module docstring): the direct parts once, the reflected part per
    replicate; per replicate the hourly illuminance and the shares of Table A.1; their means and 95 %
    intervals."""
    sk = skies(criterion, ctx, settings)
    p = settings.radiance
    mf = settings.sky_subdivision
    sc = criterion.sky(ctx, room, points, bins=lambda d: patch_bin(d, mf), nbins=reinhart_bins(mf) - 1)
    tv = criterion.window_tv(ctx, room)
    e_direct = radiance.EFFICACY_LM_W * (sc.patches @ sk["sky"][1:]) + direct_sun(ctx, room, points, tv, sk["sun_lx"],
                                                                                  sk["sun_dir"])
    octree = criterion.octree(ctx, "sky")
    S = criterion.paths_scene(ctx, room)
    args = rtrace_args(criterion.gather_settings(ctx))
    frame = sampling_frame(room.windows[0].normal)
    per_rep = []
    for r in range(p.replicates):  # a few path sets per room, each for every point
        dc = path_coefficients(S, octree, points, mf, p.climate_rays, r, args, frame, sink_point(ctx.scene))
        per_rep.append(np.maximum(e_direct + radiance.EFFICACY_LM_W * (dc @ sk["all"]), 0.0))
    thresholds = room_thresholds(ctx.project, room)
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
                          level=level, near_threshold=near,
                          radiance={k: v for k, v in params.items() if k in ("ab", "ad", "as", "lw", "window_rays")}
                          | {"replicates": p.replicates, "climate_rays": p.climate_rays, "sky_subdivision": mf},
                          illuminances_lx=tuple(lux), share_of_hours={lx: v[0] for lx, v in soh.items()},
                          share_of_hours_err={lx: v[1] for lx, v in soh.items()}, aggregation=settings.aggregation,
                          hours=int(len(sk["hours"])))


