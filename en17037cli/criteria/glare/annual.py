"""The annual method: the DGP of every usage hour at each view, from daylight coefficients with the
sun apart (an enhanced simplified DGP, Wienold 2009, whose image is replaced by rays: the imageless
idea of Jones 2019).

For a view (eye, direction f) and a usage hour h with sky S (gendaymtx -s, patches), sun S_s
(gendaymtx -d, spread into its patches) and the sun's direct normal illuminance E_n:

* E_v = DC · (S + S_s) - DC_d · S_s + E_n τ(θ) cos(sun, f) [seen]: DC the eye's daylight
  coefficients (rcontrib -I, every bounce), DC_d their direct part (the sky and ground seen from
  the eye through the glazing, from the rays below) and the last term the sun's disc itself, seen
  or not as clause 5.3 sees it (:meth:`~en17037cli.criteria.sunlight.visibility.SunVisibility.
  seen_along` from the eye, the SPA sun at the hour's middle) through glass of transmittance τ at
  its angle of incidence (:func:`~.dgp.glass_transmission`) — the five-phase split of the daylight
  criterion, with the sun exact;
* glare sources: the directions of an even set of rays from the eye (``view_rays`` over the
  sphere, 4 π / n sr each) that see the sky or the ground hemisphere through the glazing, with
  luminance 179 T_i S[patch_i] (T_i the panes' transmission, rcontrib -ab 0), and the sun's disc,
  E_n τ / ω_sun over ω_sun = 6.8e-5 sr; each brighter than ``source_threshold_cd_m2`` adds
  L² ω / P² with P its position index (:func:`~.dgp.position_index`). Sunlit surfaces and the
  landscape are not sources (they count in E_v).

The sum over the rays is found without an hours x rays matrix: the rays of a patch, sorted by T,
with the running sum of T² / P², answer "which rays of patch b exceed the threshold in hour h" by a
binary search (:meth:`ViewModel.glare_sum`). A shading device is a neutral filter of transmittance
t: E_v and every luminance scale by t (the sun's disc by the device's own ``sun_transmittance``,
its normal-normal transmittance), the sources found again.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from en17037cli.criteria.glare import engine
from en17037cli.criteria.glare.dgp import (
    MAX_POSITION_INDEX as MAX_P,
)
from en17037cli.criteria.glare.dgp import (
    SUN_SOLID_ANGLE_SR,
    dgp,
    glass_transmission,
    position_index,
    reinhart_bin,
)
from en17037cli.criteria.glare.usage import UsageHours, usage_hours

#: Luminous efficacy of Radiance's radiance units [lm/W].
K = 179.0


@dataclass
class Climate:
    """The usage hours of a run and their sky: sky (bins, h) and sun (bins, h) radiance [W sr⁻¹ m⁻²],
    the sun's direct normal illuminance e_n (h,) [lx], its direction (h, 3) in the model frame and
    whether it is above the horizon (h,)."""

    usage: UsageHours
    sky: np.ndarray
    sun: np.ndarray
    e_n: np.ndarray
    sun_dir: np.ndarray
    sun_up: np.ndarray


class _Air:
    """The refraction settings of the sun's position (the sunlight section's where present)."""

    pressure_mbar, temperature_c, refraction = 1013.25, 12.0, True


def climate(weather, location, settings, north_deg: float, sunlight=None) -> Climate:  # pragma: no mutate block
    """The usage hours of ``weather`` (see :mod:`.usage`) with their skies and sun."""
    from en17037cli.criteria.sunlight.solar_position import direction_vectors
    from en17037cli.criteria.sunlight.visibility import SunPath
    from en17037cli.weather.epw import wea_text

    s = settings
    use = usage_hours(weather.month, weather.day, weather.hour, weather.tz_hours, location.timezone, s.year,
                      s.usage_start_h, s.usage_end_h, s.usage_days)
    wea = wea_text(weather)
    g = dict(s.reflectance)["ground"]
    sky = engine.sky_matrix(wea, s.sky_subdivision, north_deg, g, "sky")[:, use.rows]
    sun = engine.sky_matrix(wea, s.sky_subdivision, north_deg, g, "sun")[:, use.rows]
    e_n = K * engine.reinhart_solid_angles(s.sky_subdivision) @ sun  # the sun's energy, kept by the spreading
    path = SunPath(location, cast(object, sunlight or _Air()))  # type: ignore[arg-type]
    elev, azim = path(use.unix_mid)
    return Climate(use, sky, sun, e_n, direction_vectors(elev, azim, north_deg), (elev > 0) & (e_n > 0))


@dataclass
class EyeRays:
    """The rays from one eye that see the sky or the ground hemisphere through the glazing:
    directions (n, 3), transmission T (n,), the sky bin each sees (gendaymtx's row; 0 the ground),
    the solid angle each stands for [sr] and the window of the room each leaves through (its index;
    the number of windows where none)."""

    dirs: np.ndarray
    t: np.ndarray
    bin: np.ndarray
    omega: float
    window: np.ndarray | None = None


def eye_rays(octrees, octree: str, eyes, n: int, mf: int, windows=None) -> list[EyeRays]:
    """The :class:`EyeRays` of each eye (k, 3) from ``n`` directions over the sphere, all traced in one
    rcontrib call (the octree read once); ``windows``: (ray engine, the room) to find the window each
    ray leaves through, else every ray is one opening's."""
    from en17037cli.criteria.glare.dgp import sphere_directions

    eyes = np.asarray(eyes, dtype=float).reshape(-1, 3)
    d = sphere_directions(n)
    t_sky, t_ground = engine.view_transmission(octrees, octree, np.repeat(eyes, n, axis=0), np.tile(d, (len(eyes), 1)))
    bins = reinhart_bin(d, mf)  # in the model frame, as rcontrib bins: gendaymtx -r turns the sky onto them
    out = []
    for k, eye in enumerate(eyes):  # a few eyes per room
        ts, tg = t_sky[k * n:(k + 1) * n], t_ground[k * n:(k + 1) * n]
        seen = (ts > 0) | (tg > 0)
        b = np.where(tg[seen] > 0, 0, bins[seen])
        win = np.zeros(int(seen.sum()), dtype=int)
        if windows is not None and len(win):
            from en17037cli.scene.model import room_window_group

            eng, room = windows
            face, _ = eng.first_hit(room_window_group(room), np.broadcast_to(eye, (len(win), 3)), d[seen])
            lookup = np.full(int(np.concatenate([w.face_ids for w in room.windows]).max()) + 2, len(room.windows))
            for j, w in enumerate(room.windows):  # a few windows
                lookup[w.face_ids] = j
            win = lookup[np.where(face >= 0, face, len(lookup) - 1)]  # no window of the room: the last group
        out.append(EyeRays(d[seen], (ts + tg)[seen], b, 4.0 * np.pi / n, win))
    return out


def sun_through_glazing(engine_, scene, room, eye, clim: Climate, window_tn: np.ndarray) -> np.ndarray:
    """The share of the sun's direct normal light reaching the eye each usage hour: 0 where the
    sun is not seen from the eye (clause 5.3's visibility: through a window of the room, no face
    that blocks the sun on the way), else the glass's transmission at its angle of incidence on the
    window it is seen through (the first window, in the room's order, whose plane it crosses).

    Returns
    -------
    (h,) float in [0, 1)
    """
    from en17037cli.criteria.sunlight.visibility import SunVisibility
    from en17037cli.scene.model import room_window_group

    d = clim.sun_dir
    out = np.zeros(len(d))
    done = ~clim.sun_up
    for w, tn in zip(room.windows, window_tn):  # a few windows per room, each vectorised over the hours
        vis = SunVisibility(engine_, np.asarray(eye)[None, :], np.asarray(w.normal)[None, :], room_window_group(room),
                            None, None, scene.true_north_deg)  # type: ignore[arg-type]
        seen = vis.seen_along(d, ~done)
        out[seen] = np.where(tn >= 1.0, 1.0, glass_transmission(tn, d[seen] @ np.asarray(w.normal)))
        done |= seen
    return out


class ViewModel:
    """Everything the DGP of one view needs, hour by hour (see the module docstring).

    ev : (replicates, h) vertical illuminance at the eye [lx]; e_sun : (h,) the sun's disc's part of
    it; l_sun, p_sun : (h,) the sun's luminance through the glazing [cd/m²] (0 where not in view)
    and its position index

    The rays of one opening brighter than the threshold are one glare source, as evalglare merges
    neighbouring pixels: their mean luminance, their solid angle, the position index at their
    centroid in the fisheye's (angular) picture plane, where evalglare takes it. The rays are sorted
    by (opening, sky bin, T); running sums of ω, T ω and the picture coordinates give, for each
    opening, bin and hour, the sums over the rays above the threshold by one binary search.
    """

    def __init__(self, rays: EyeRays, dc: np.ndarray, view_dir, clim: Climate, sun_share: np.ndarray, threshold: float,
                 low_light: bool):
        from en17037cli.criteria.glare.dgp import view_frame

        f = np.asarray(view_dir, dtype=float)
        cos = rays.dirs @ f
        front = cos > 1e-9
        t, b, d = rays.t[front], rays.bin[front], rays.dirs[front]
        g = np.zeros(len(t), dtype=int) if rays.window is None else rays.window[front]
        nb = clim.sky.shape[0]
        self.groups = int(g.max()) + 1 if len(g) else 1
        cell = g * nb + b
        order = np.lexsort((t, cell))
        self.t, self.cell = t[order], cell[order]
        self.key = self.cell + 0.5 * self.t
        _, r, u = view_frame(f)
        th = np.arccos(np.clip(cos[front], -1.0, 1.0))
        k = np.where(th > 1e-9, th / np.maximum(np.sin(th), 1e-12), 1.0)  # the angular fisheye's radius is the angle
        a, c = (d @ r) * k, (d @ u) * k
        w = rays.omega
        # running sums, in sorted order, of ω, T ω, a ω, c ω (a leading 0)
        self.cums = np.vstack([np.zeros((1, 4)), np.cumsum(np.column_stack([np.full(len(t), w), t * w, a * w, c * w])[order],
                                                             axis=0)])
        # the (opening, bin) cells that hold rays, in sorted order, and where each ends; openings contiguous
        self.cells, first = np.unique(self.cell, return_index=True)
        self.end = np.append(first[1:], len(self.cell))
        self.cell_bin = self.cells % nb
        group = self.cells // nb
        self.group_start = np.flatnonzero(np.concatenate([[True], group[1:] != group[:-1]])) if len(group) else group
        self.f, self.frame = f, (r, u)
        self.omega, self.sky, self.threshold, self.low_light = w, clim.sky, threshold, low_light
        dc_direct = K * np.bincount(b, weights=t * cos[front] * w, minlength=nb)
        cos_sun = clim.sun_dir @ f
        self.in_view = (sun_share > 0) & (cos_sun > 0)
        self.e_sun = clim.e_n * sun_share * np.maximum(cos_sun, 0.0) * self.in_view  # the sun's disc alone
        self.ev = np.maximum(dc @ (clim.sky + clim.sun) - dc_direct @ clim.sun, 0.0) + self.e_sun  # (replicates, h)
        self.l_sun = np.where(self.in_view, clim.e_n * sun_share / SUN_SOLID_ANGLE_SR, 0.0)
        self.p_sun = np.where(self.in_view, np.nan_to_num(position_index(clim.sun_dir, f), nan=1.0), 1.0)

    def glare_sum(self, hours: np.ndarray, scale: float = 1.0, sun_scale: float | None = None) -> np.ndarray:
        """Σ L² ω / P² over the sources in ``hours`` (indices) with every luminance times ``scale``, the
        sun's disc times ``sun_scale`` (default ``scale``): each opening's rays above the threshold one
        source (see the class docstring), the sun's disc another."""
        sky_sum = np.zeros(len(hours))
        if len(self.cells):
            s = K * scale * self.sky[self.cell_bin][:, hours]  # (cells, k) luminance per unit transmission
            with np.errstate(divide="ignore"):
                need = np.where(s > 0, self.threshold / np.where(s > 0, s, 1.0), np.inf)  # T a ray needs to be a source
            pos = np.minimum(np.searchsorted(self.key, self.cells[:, None] + 0.5 * np.minimum(need, 1.0), side="right"),
                             self.end[:, None])
            part = self.cums[self.end][:, None, :] - self.cums[pos]  # (cells, k, 4): ω, T ω, a ω, c ω above the threshold
            part[..., 1] *= s  # T ω -> L ω
            src = np.add.reduceat(part, self.group_start, axis=0)  # (openings, k, 4)
            om, lum = src[..., 0], src[..., 1]
            with np.errstate(invalid="ignore", divide="ignore"):
                a, c = src[..., 2] / om, src[..., 3] / om
                rad = np.hypot(a, c)
                direction = (np.cos(rad)[..., None] * self.f + (np.sin(rad) / np.where(rad > 0, rad, 1.0))[..., None]
                             * (a[..., None] * self.frame[0] + c[..., None] * self.frame[1]))
                p = np.nan_to_num(position_index(direction.reshape(-1, 3), self.f), nan=MAX_P).reshape(om.shape)
                sky_sum = np.where(om > 0, lum**2 / np.where(om > 0, om, 1.0) / p**2, 0.0).sum(axis=0)
        ls = self.l_sun[hours] * (scale if sun_scale is None else sun_scale)
        sun_sum = np.where(ls > self.threshold, ls**2 * SUN_SOLID_ANGLE_SR / self.p_sun[hours] ** 2, 0.0)
        return sky_sum + sun_sum

    def dgp(self, hours: np.ndarray | None = None, scale: float = 1.0, sun_scale: float | None = None) -> np.ndarray:
        """(replicates, k) DGP of ``hours`` (default all) behind a device that passes ``scale`` of the
        light and ``sun_scale`` (default ``scale``) of the sun's disc seen through it."""
        hours = np.arange(self.ev.shape[1]) if hours is None else hours
        ss = scale if sun_scale is None else sun_scale
        ev = (self.ev[:, hours] - self.e_sun[hours]) * scale + self.e_sun[hours] * ss
        return dgp(ev, self.glare_sum(hours, scale, ss)[None, :], self.low_light)
