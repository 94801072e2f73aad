"""The sky component of the daylight factor, exact: the CIE overcast sky integrated over what each
point sees of the sky through its room's glazing, with a bound on the error. No sampling noise.

SC(p) = 9 / (7 π) ∫ ℓ(γ) cos θ τ(i) dω over the directions from p that leave through a window and
reach the sky (:data:`~en17037cli.criteria.view.rays.SKY`), where ℓ(γ) = (1 + 2 sin γ) / 3 is the
CIE overcast luminance relative to the zenith's (:func:`~.sky.cie_overcast_luminance`), θ the
angle to the reference plane's normal (+z: cos θ = sin γ), τ(i) the glazing's transmittance at the
incidence angle i (:func:`~.sky.glass_transmittance`, Radiance's ``glass``; 1 for an open
opening) and 7 π L_z / 9 the unobstructed horizontal illuminance.

The directions are those of the view engine (:mod:`en17037cli.criteria.view.solid_angle`): each
window is seen on its gnomonic grid, every grid vertex is one ray classified by one opaque
first-hit query (frames, reveals, mullions, obstructions, the ground), cells whose samples
disagree or that a frame edge's image crosses are mixed and split in four. Here each cell weighs
the integral of the smooth integrand over it instead of its solid angle: tensor Gauss-Legendre in
the gnomonic angles (3 x 3 nodes; its difference from the midpoint rule, the centre node, as its
error: far above the Gauss rule's own). A cell that the samples say is all sky adds its integral; a
mixed cell adds its sky share of it, and at most the larger of its share and its complement times
its integral to the bound (the sky in it lies between none and all of it). A cell of a window that
is not a rectangle, cut by its outline, weighs its exact clipped solid angle times the integrand's
mean, with the integrand's range over it times that solid angle added to the bound. Only cells
with sky in them and a sky edge or an outline across them are split, and of those only the ones
whose bound does not fit an equal share of a quarter of what the point's tolerance leaves: until the
point's bound is within max(``rel_tolerance`` x SC, ``abs_tolerance``), or ``refine_levels``.

What the bound assumes is what the view engine assumes: inside a cell whose samples agree nothing
changes (obstructions narrower than a cell between its samples are not seen; frame edges are on
grid lines or refined). Everything else in it is arithmetic.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.criteria.daylight.sky import transmittance_table
from en17037cli.criteria.view.cells import base_cells
from en17037cli.criteria.view.frames import RoomGeometry
from en17037cli.criteria.view.gnomonic import patches
from en17037cli.criteria.view.rays import SKY, ViewRays
from en17037cli.criteria.view.refine import split_cells
from en17037cli.criteria.view.sampler import Sampler
from en17037cli.geometry import offset_rectangle_solid_angle

#: The sky component per steradian of a direction with integrand 1 [1/sr]: 1 / (7 π / 9), the
#: unobstructed horizontal illuminance of the CIE overcast sky over its zenith luminance.
SC_PER_SR = 9.0 / (7.0 * np.pi)

@dataclass(frozen=True)
class SkyTolerance:
    """How finely the sky component is integrated.

    resolution_deg : largest angular size of a base cell [deg]
    refine_levels : times a mixed cell may be split in four
    rel_tolerance : a point's bound is within this fraction of its sky component ...
    abs_tolerance : ... or within this [-] (a fraction of the unobstructed sky: 5e-5 is 0.005 % D)
    frame_depth_m : opaque faces this close to a window's plane are its frame (grid lines) [m]
    """

    resolution_deg: float = 1.0
    refine_levels: int = 8
    rel_tolerance: float = 0.005
    abs_tolerance: float = 5e-5
    frame_depth_m: float = 0.5


@dataclass
class SkyComponent:
    """Per point: ``value`` [-] (fraction of the unobstructed horizontal illuminance), ``bound`` [-]
    (|value - exact| <= bound, see the module docstring), ``cells`` (cells integrated)."""

    value: np.ndarray
    bound: np.ndarray
    cells: np.ndarray
    #: (p, bins) [sr]: ∫ cos θ τ(i) dω of the sky seen through the glazing in each bin of directions
    #: (a sky patch), when asked for: the direct daylight coefficients of unit-radiance patches
    patches: np.ndarray | None = None


def _integrand(axes: np.ndarray, tv: np.ndarray, X: np.ndarray, Y: np.ndarray, normal: np.ndarray):
    """ℓ(γ) cos θ τ(i) per steradian and the gnomonic Jacobian dω / (dα dβ) on the grid of
    gnomonic coordinates X = tan α (m, k) by Y = tan β (m, k) of cells whose windows have axes
    ``axes`` (m, 3, 3: u, v, n) and transmittance ``tv`` (m,); 0 below the horizon.

    The direction of (X, Y) is (X u + Y v + n) / s, s = sqrt(1 + X² + Y²), in the window's frame (n
    its outward normal), so cos i = 1 / s and dω = (1 + X²) (1 + Y²) / s³ dα dβ.

    Returns
    -------
    g : (m, k, k) [-]; jac : (m, k, k) [sr / rad²]
    """
    Xg, Yg = X[:, :, None], Y[:, None, :]
    X2, Y2 = Xg * Xg, Yg * Yg
    inv = 1.0 / np.sqrt(1.0 + X2 + Y2)  # cos i
    pz = axes[:, :, 2]  # (m, 3): u, v, n on +z
    up = np.maximum((Xg * pz[:, 0, None, None] + Yg * pz[:, 1, None, None] + pz[:, 2, None, None]) * inv, 0.0)  # sin γ
    if normal[0] == 0.0 and normal[1] == 0.0 and normal[2] == 1.0:
        cos_t = up  # a horizontal plane: θ is the zenith angle
    else:
        pn = axes @ normal
        cos_t = np.maximum((Xg * pn[:, 0, None, None] + Yg * pn[:, 1, None, None] + pn[:, 2, None, None]) * inv, 0.0)
    tau = np.empty_like(inv)
    for t in np.unique(tv):  # a few glazing types; each vectorised
        k = tv == t
        c, v, _ = transmittance_table(float(t))
        tau[k] = np.interp(inv[k], c, v)
    g = (1.0 + 2.0 * up) * (1.0 / 3.0) * cos_t * tau * (up > 0)
    return g, (1.0 + X2) * (1.0 + Y2) * inv * inv * inv


_GX, _GW = np.polynomial.legendre.leggauss(3)
_WEIGHTS = np.outer(_GW, _GW)


def cell_integrals(axes: np.ndarray, tv: np.ndarray, G: np.ndarray, normal=(0.0, 0.0, 1.0), extremes: bool = False):
    """Integral of the sky-component integrand over cells [α0, α1] x [β0, β1] (``G``'s first four
    columns [rad]) of windows with ``axes`` (m, 3, 3) and transmittance ``tv`` (m,), by 3 x 3
    Gauss-Legendre in (α, β), with its difference from the midpoint rule (the centre node) as an
    error estimate: far above the Gauss rule's own error on these smooth integrands (the rules err
    by O(h²) and O(h⁶) on cells of side h).

    Returns
    -------
    value, qerr : (m,) [sr]; with ``extremes``, also gmin, gmax : (m,) [-], the integrand per
    steradian at the nodes
    """
    ha, hb = 0.5 * (G[:, 1] - G[:, 0]), 0.5 * (G[:, 3] - G[:, 2])
    X = np.tan(0.5 * (G[:, 0] + G[:, 1])[:, None] + ha[:, None] * _GX[None])
    Y = np.tan(0.5 * (G[:, 2] + G[:, 3])[:, None] + hb[:, None] * _GX[None])
    g, jac = _integrand(axes, tv, X, Y, np.asarray(normal, float))
    f = g * jac
    value = np.einsum("mij,ij->m", f, _WEIGHTS) * ha * hb
    qerr = np.abs(value - 4.0 * f[:, 1, 1] * ha * hb)
    if extremes:
        return value, qerr, g.min(axis=(1, 2)), g.max(axis=(1, 2))
    return value, qerr


def sky_component(view_rays: ViewRays, rg: RoomGeometry, points: np.ndarray, tv: np.ndarray,
                  tol: SkyTolerance = SkyTolerance(), normal=(0.0, 0.0, 1.0), bins=None, nbins: int = 0) -> SkyComponent:
    """The sky component of ``points`` (p, 3) [m, local] through the room's windows (see the module
    docstring), as a fraction of the unobstructed horizontal illuminance under the CIE overcast sky.

    Parameters
    ----------
    tv : (windows,) normal-hemispherical transmittance of each window of ``rg`` (1: open)
    normal : the receiving plane's unit normal (+z: the reference plane)
    bins : optional, a function of unit directions (m, 3) giving their bin (0 .. nbins - 1, -1: none):
        the cells' integrals of cos θ τ(i) (unit radiance) are also summed per bin, each quadrature
        node into the bin of its direction (:attr:`SkyComponent.patches`)
    """
    p = len(points)
    value, bound = np.zeros(p), np.zeros(p)
    ncell = np.zeros(p, dtype=int)
    binned = np.zeros((p, nbins)) if bins is not None else None
    P = patches(rg, points, np.radians(tol.resolution_deg))
    if not len(P.pt):
        return SkyComponent(value, bound, ncell, binned)
    sample = Sampler(view_rays, rg, points, P, False)
    cells = base_cells(sample, P)
    tv = np.asarray(tv, float)
    axes = np.stack([np.stack([f.u, f.v, f.n]) for f in rg.frames])  # (windows, 3, 3)
    abs_raw = tol.abs_tolerance / SC_PER_SR
    for level in range(tol.refine_levels + 1):  # a few levels; each vectorised over cells
        if len(cells.w) == 0:
            break
        pi = P.pt[cells.patch]
        kinds = cells.kinds()
        has_sky = ((kinds >> SKY) & 1) > 0  # cells with no sky sample add nothing
        mixed = ((kinds & (kinds - 1)) != 0) | cells.crossed()
        share = (kinds == (1 << SKY)).astype(float)
        mi = np.flatnonzero(mixed)
        count = cells.counter(mi)
        share[mi] = count(SKY) / np.maximum(count(), 1)
        # only cells with sky in them and a sky edge or a window outline across them get finer; they
        # are weighed by their midpoint to decide, by the Gauss rule only if they stay
        split = has_sky & (mixed | ~cells.full) if level < tol.refine_levels else np.zeros(len(share), bool)
        f, qerr = np.zeros(len(share)), np.zeros(len(share))
        now = np.flatnonzero(has_sky & ~split)
        f[now], qerr[now] = _weigh(axes, tv, P, cells, now, normal, gauss=True)
        cand = np.flatnonzero(split)
        f[cand], qerr[cand] = _weigh(axes, tv, P, cells, cand, normal, gauss=False)
        # the sky part of a mixed cell lies in [0, f]: its estimate share f errs by at most max(share, 1 - share) f
        own = np.where(mixed & has_sky, np.maximum(share, 1.0 - share) * f, 0.0) + share * qerr
        value += np.bincount(pi, share * f, p)
        fixed = bound + np.bincount(pi[~split], own[~split], p)
        budget = np.maximum(tol.rel_tolerance * value, abs_raw) - fixed
        stay = cand[_within_budget(pi[cand], own[cand], budget)]
        split[stay] = False
        if len(stay):  # candidates that stay final after all: weighed by the Gauss rule
            value -= np.bincount(pi[stay], share[stay] * f[stay], p)
            f[stay], qerr[stay] = _weigh(axes, tv, P, cells, stay, normal, gauss=True)
            own[stay] = np.where(mixed[stay], np.maximum(share[stay], 1.0 - share[stay]) * f[stay], 0.0) + share[stay] * qerr[stay]
            value += np.bincount(pi[stay], share[stay] * f[stay], p)
        # what is not split is final: its value is counted; the cells split count again as their children
        value -= np.bincount(pi[split], (share * f)[split], p)
        bound += np.bincount(pi[~split], own[~split], p)
        ncell += np.bincount(pi[~split], minlength=p)
        if binned is not None:
            fin = np.flatnonzero(~split & (share > 0))
            binned += _node_bins(axes, tv, P, cells, fin, share[fin], bins, nbins, np.asarray(normal, float), p)
        if not split.any():
            break
        cells = split_cells(sample, cells, np.flatnonzero(split), neighbours=level + 1 < tol.refine_levels)
    return SkyComponent(value * SC_PER_SR, bound * SC_PER_SR, ncell, binned)


def _node_bins(axes, tv, P, cells, fin, share, bins, nbins: int, normal, p: int) -> np.ndarray:
    """(p, nbins) [sr]: the unit-radiance integrals cos θ τ(i) dω of cells ``fin`` (times their sky
    ``share``), each of their 3 x 3 Gauss nodes put in the bin of its direction."""
    out = np.zeros(p * nbins)
    if not len(fin):
        return out.reshape(p, nbins)
    G = cells.bounds(fin)[0].T
    win = P.win[cells.patch[fin]]
    ha, hb = 0.5 * (G[:, 1] - G[:, 0]), 0.5 * (G[:, 3] - G[:, 2])
    X = np.tan(0.5 * (G[:, 0] + G[:, 1])[:, None] + ha[:, None] * _GX[None])
    Y = np.tan(0.5 * (G[:, 2] + G[:, 3])[:, None] + hb[:, None] * _GX[None])
    ax = axes[win]
    g, jac = _integrand(ax, tv[win], X, Y, normal)
    s = np.sqrt(1.0 + X[:, :, None] ** 2 + Y[:, None, :] ** 2)
    d = (X[:, :, None, None] * ax[:, None, None, 0] + Y[:, None, :, None] * ax[:, None, None, 1] + ax[:, None, None, 2]) / s[..., None]
    lum = (1.0 + 2.0 * np.maximum(d[..., 2], 0.0)) / 3.0
    w = g / lum * jac * _WEIGHTS[None] * (ha * hb)[:, None, None]  # unit radiance
    part = ~cells.full[fin]
    if part.any():  # cut by a window outline that is not a rectangle: scaled to the part inside
        rect = _rect_solid_angle(G)
        w = np.where(part[:, None, None], w * (cells.w[fin] / np.maximum(rect, 1e-300))[:, None, None], w)
    b = bins(d.reshape(-1, 3))
    pt = np.repeat(P.pt[cells.patch[fin]], 9)
    ok = b >= 0
    out += np.bincount(pt[ok] * nbins + b[ok], (w * share[:, None, None]).ravel()[ok], p * nbins)
    return out.reshape(p, nbins)


def _weigh(axes, tv, P, cells, idx, normal, gauss: bool):
    """(value, error) [sr] of cells ``idx``: the 3 x 3 Gauss rule with its error estimate
    (:func:`cell_integrals`), or the midpoint rule alone (error 0: an estimate to decide by); a cell
    cut by a window outline that is not a rectangle scaled to its exact part inside, the integrand's
    range over it times that part added to the error."""
    if not len(idx):
        return np.zeros(0), np.zeros(0)
    win = P.win[cells.patch[idx]]
    G = cells.bounds(idx)[0].T
    if gauss:
        fs, qs = cell_integrals(axes[win], tv[win], G, normal)
    else:
        ha, hb = 0.5 * (G[:, 1] - G[:, 0]), 0.5 * (G[:, 3] - G[:, 2])
        g, jac = _integrand(axes[win], tv[win], np.tan(0.5 * (G[:, 0] + G[:, 1]))[:, None],
                            np.tan(0.5 * (G[:, 2] + G[:, 3]))[:, None], np.asarray(normal, float))
        fs, qs = 4.0 * (g * jac)[:, 0, 0] * ha * hb, np.zeros(len(idx))
    part = ~cells.full[idx]  # clipped to a window outline that is not a rectangle: scaled to the part inside
    if part.any():
        w, rect = cells.w[idx], _rect_solid_angle(G)
        scale = np.where(rect > 0, w / np.maximum(rect, 1e-300), 0.0)
        fs = np.where(part, fs * scale, fs)
        if gauss:
            _, _, gmin, gmax = cell_integrals(axes[win], tv[win], G, normal, extremes=True)
            qs = np.where(part, qs * scale + w * (gmax - gmin), qs)
    return fs, qs


def _rect_solid_angle(G: np.ndarray) -> np.ndarray:
    """Exact solid angle [sr] of cells [α0, α1] x [β0, β1] of the gnomonic plane (G's columns 0-3 [rad])."""
    return offset_rectangle_solid_angle(*(np.tan(G[:, i]) for i in range(4)))


def _within_budget(pt: np.ndarray, own: np.ndarray, budget: np.ndarray) -> np.ndarray:
    """Which of the cells that could be split (of points ``pt``, error bounds ``own``) stay as they
    are: every one of a point whose cells' bounds all fit its ``budget`` (what its tolerance leaves
    beside the rest), else those whose bound is within an equal share of a quarter of the budget
    (so that what is kept over all levels stays within it, and the split cells' children get the
    rest)."""
    n = np.bincount(pt, minlength=len(budget))
    total = np.bincount(pt, own, len(budget))
    return (total[pt] <= budget[pt]) | (own <= 0.25 * budget[pt] / np.maximum(n[pt], 1))


def window_transmittance(scene, room, reflectance: dict, glazing_tv: float) -> np.ndarray:
    """(windows,) normal-hemispherical transmittance of each of ``room``'s windows: its faces' (a
    layer rule's ``transmittance``, else ``glazing_tv``), area-weighted where its faces differ."""
    from en17037cli.criteria.daylight.radiance import face_optics
    from en17037cli.geometry import triangle_normals

    _, value = face_optics(scene, reflectance, glazing_tv)
    out = []
    for w in room.windows:  # a few windows
        ids = np.asarray(w.face_ids)
        _, area = triangle_normals(scene.vertices[scene.triangles[ids]])
        out.append(float(np.average(value[ids], weights=np.maximum(area, 1e-300))))
    return np.array(out)
