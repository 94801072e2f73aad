"""View-out engine (EN 17037 clause 5.2): sight angle, outside distance and view layers.

For each viewpoint:

* **Solid angles.** Each window triangle is subdivided, per viewpoint, until every cell
  subtends at most ``angular_resolution_deg`` (cost scales with the windows' solid angle); a
  ray through each cell's centroid and vertices classifies it (blocked / sky / landscape /
  ground, :func:`~en17037cli.raytrace.trace_through_windows`); cells whose four samples disagree
  are split, up to ``refine_levels`` times, until the point's estimated error of every layer is
  within max(``solid_angle_rel_tolerance`` x its solid angle, ``solid_angle_abs_tolerance_sr``). Each cell weighs its exact solid angle (Van Oosterom and
  Strackee 1983), so the weights of an unobstructed planar window add up to its exact solid
  angle. Error estimate: half the solid angle of the cells still mixed after refinement.
* **Horizontal sight angle.** A horizontal fan at eye height, ``horizontal_resolution_deg``
  apart; every change between "leaves through a window" and "blocked" is located by bisection
  to ``angle_tolerance_deg``. Error estimate: the remaining bracket widths, summed (a bound).
* **Outside distance.** ``horizontal`` (default): over the leaving horizontal directions, the
  distance from the glazing plane to the first ``landscape`` face, measured horizontally and
  perpendicular to the window; ``solid_angle``: the perpendicular distance (delta_1 - delta_0)
  r . n of Brembilla et al. (2021) eq. (1) over the leaving cells, weighted by solid angle.
  Unobstructed directions count as +inf; ground never obstructs.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli import standard
from en17037cli.errors import InputError
from en17037cli.raytrace import BLOCKED, GLAZING_OFFSET_M, GROUND_HIT, LANDSCAPE_HIT, SKY, trace_through_windows
from en17037cli.view_math import base_cells, cell_samples, cell_weights, grid_points, split4, weighted_statistic

#: Points per chunk (bounds memory: cells of all points in a chunk are held at once).
POINT_CHUNK = 16


@dataclass
class RoomGeometry:
    """Per-room lookups: which faces are this room's windows and their outward normals."""

    is_room_window: np.ndarray  # (n_faces,) bool
    normal: np.ndarray  # (n_faces, 3) outward unit normal of the window a face belongs to
    triangles: np.ndarray  # (k, 3, 3) all window triangles of the room [m]


def room_geometry(scene, room) -> RoomGeometry:
    n = len(scene.triangles)
    is_w = np.zeros(n, dtype=bool)
    normal = np.zeros((n, 3))
    tris = []
    for w in room.windows:
        is_w[w.face_ids] = True
        normal[w.face_ids] = w.normal
        tris.append(w.triangles)
    return RoomGeometry(is_w, normal, np.concatenate(tris))


def viewpoints(scene, room, view_cfg: dict, explicit) -> tuple[list, list]:
    """Viewpoints of a room grouped by eye height.

    Returns
    -------
    groups : list of (eye_height_m, (n, 3) float local [m])
    notes : list of str
    """
    notes = []
    if explicit is not None:
        pts = scene.to_local(np.asarray(explicit, dtype=float))
        heights = np.round(pts[:, 2] - room.floor_z, 3)
        groups = [(float(h), pts[heights == h]) for h in np.unique(heights)]
    else:
        utilised = room.floor.buffer(-view_cfg["wall_margin_m"], join_style="mitre")
        if utilised.is_empty:
            raise InputError(f"rooms '{room.name}': the utilised area (floor inset by view.wall_margin_m = {view_cfg['wall_margin_m']} m) is empty; reduce the margin")
        xy = grid_points(utilised, view_cfg["grid_spacing_m"])
        groups = [(float(h), np.column_stack([xy, np.full(len(xy), room.floor_z + h)])) for h in view_cfg["eye_heights_m"]]
    out = []
    for h, p in groups:
        p = p.copy()
        moved = 0
        for w in room.windows:  # per window, vectorised over points
            c = w.centroid
            s = (p - c) @ w.normal
            close = np.abs(s) < GLAZING_OFFSET_M
            if np.any(close):
                p[close] -= (s[close] + GLAZING_OFFSET_M)[:, None] * w.normal
                moved += int(close.sum())
        if moved:
            notes.append(f"room '{room.name}': {moved} viewpoints at eye height {h} m lay on a glazing plane and were moved {GLAZING_OFFSET_M * 1000:.0f} mm into the room")
        out.append((h, p))
    return out, notes


def solid_angles(engine, rg: RoomGeometry, points: np.ndarray, cfg: dict) -> dict:
    """Solid angle of sky, landscape and ground seen through the room's windows from each point.

    Returns a dict of (p,) arrays [sr]: ``sky``, ``landscape``, ``ground``, ``glazing`` (the
    windows' geometric solid angle), ``err_sky``/``err_landscape``/``err_ground``, and for the
    ``solid_angle`` distance method ``distance`` [m] and ``distance_gap`` [m]; ``cells`` (p,) int.
    """
    p = len(points)
    res = np.radians(cfg["angular_resolution_deg"])
    k = len(rg.triangles)
    pi0 = np.repeat(np.arange(p), k)
    tri0 = np.tile(rg.triangles, (p, 1, 1))
    pi, cells = base_cells(points, pi0, tri0, res)
    out = {key: np.zeros(p) for key in ("sky", "landscape", "ground", "glazing", "err_sky", "err_landscape", "err_ground")}
    out["cells"] = np.zeros(p, dtype=int)
    dist_rows, dist_w, dist_p = [], [], []
    keys = (("sky", SKY), ("landscape", LANDSCAPE_HIT), ("ground", GROUND_HIT))
    for level in range(cfg["refine_levels"] + 1):
        if len(cells) == 0:
            break
        w = cell_weights(points, pi, cells)
        o, d = cell_samples(points, pi, cells)
        cls, wface, odist, gdist = trace_through_windows(engine, o, d)
        cls = np.where((wface >= 0) & rg.is_room_window[np.maximum(wface, 0)], cls, BLOCKED).reshape(-1, 4)
        mixed = np.any(cls != cls[:, :1], axis=1)
        # Error control: a point stops refining once every layer's estimated error (half the
        # solid angle of its mixed cells) is within max(rel * layer solid angle, abs).
        done = np.ones(p, dtype=bool)
        for key, code in keys:
            est = out["err_" + key] + np.bincount(pi, 0.5 * w * (mixed & np.any(cls == code, axis=1)), p)
            value = out[key] + np.bincount(pi, w * (cls[:, 0] == code), p)
            done &= est <= np.maximum(cfg["solid_angle_rel_tolerance"] * value, cfg["solid_angle_abs_tolerance_sr"])
        last = level == cfg["refine_levels"]
        final = np.ones(len(cells), dtype=bool) if last else (~mixed | done[pi])
        fp, fw, fc = pi[final], w[final], cls[final, 0]
        out["glazing"] += np.bincount(fp, fw, p)
        out["cells"] += np.bincount(fp, minlength=p)
        for key, code in keys:
            out[key] += np.bincount(fp, fw * (fc == code), p)
            unsure = mixed[final] & np.any(cls[final] == code, axis=1)
            out["err_" + key] += np.bincount(fp, 0.5 * fw * unsure, p)
        if cfg["distance_method"] == "solid_angle":
            c0 = np.flatnonzero(final)
            leave = fc != BLOCKED
            dd = d.reshape(-1, 4, 3)[c0, 0]
            n = rg.normal[np.maximum(wface.reshape(-1, 4)[c0, 0], 0)]
            t_o, t_g = odist.reshape(-1, 4)[c0, 0], gdist.reshape(-1, 4)[c0, 0]
            perp = np.where(fc == LANDSCAPE_HIT, (t_o - t_g) * np.einsum("ij,ij->i", dd, n), np.inf)
            dist_rows.append(perp[leave])
            dist_w.append(fw[leave])
            dist_p.append(fp[leave])
        if not last:
            split = ~final
            pi, cells = np.repeat(pi[split], 4), split4(cells[split])
    if cfg["distance_method"] == "solid_angle":
        vals, wts = _pad_rows(np.concatenate(dist_p) if dist_p else np.zeros(0, int),
                              np.concatenate(dist_rows) if dist_rows else np.zeros(0),
                              np.concatenate(dist_w) if dist_w else np.zeros(0), p)
        out["distance"], out["distance_gap"] = weighted_statistic(vals, wts, cfg["distance_statistic"])
    return out


def _pad_rows(row: np.ndarray, values: np.ndarray, weights: np.ndarray, p: int):
    """Scatter ragged (row, value, weight) triples into (p, kmax) arrays padded with weight 0."""
    order = np.argsort(row, kind="stable")
    row, values, weights = row[order], values[order], weights[order]
    counts = np.bincount(row, minlength=p)
    kmax = max(int(counts.max()) if len(counts) else 0, 1)
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    col = np.arange(len(row)) - start[row]
    V = np.full((p, kmax), np.nan)
    W = np.zeros((p, kmax))
    V[row, col] = values
    W[row, col] = weights
    return V, W


def horizontal(engine, rg: RoomGeometry, points: np.ndarray, cfg: dict) -> dict:
    """Horizontal sight angle and horizontal outside distance from each point.

    Returns a dict of (p,) arrays: ``angle_deg``, ``angle_err_deg``, ``transitions`` and, for the
    ``horizontal`` distance method, ``distance`` [m] and ``distance_gap`` [m].
    """
    p = len(points)
    m = int(round(360.0 / cfg["horizontal_resolution_deg"]))
    step = 2 * np.pi / m
    theta = np.arange(m) * step

    def leaves(pt_idx, angles):
        d = np.column_stack([np.cos(angles), np.sin(angles), np.zeros(len(angles))])
        cls, wface, _, gdist = trace_through_windows(engine, points[pt_idx], d)
        ok = (cls != BLOCKED) & (wface >= 0) & rg.is_room_window[np.maximum(wface, 0)]
        return ok, wface, gdist, d

    pidx = np.repeat(np.arange(p), m)
    ang = np.tile(theta, p)
    leave, wface, gdist, dirs = leaves(pidx, ang)
    L = leave.reshape(p, m)
    Ln = np.roll(L, -1, axis=1)
    trans = np.flatnonzero((L != Ln).reshape(-1))
    lo = ang[trans].copy()
    hi = lo + step
    s_lo = leave[trans]
    tol = np.radians(cfg["angle_tolerance_deg"])
    n_iter = int(np.ceil(np.log2(step / tol))) if tol < step else 0
    for _ in range(n_iter):  # bisection: all transitions of all points at once
        mid = 0.5 * (lo + hi)
        lm, _, _, _ = leaves(pidx[trans], mid)
        same = lm == s_lo
        lo = np.where(same, mid, lo)
        hi = np.where(same, hi, mid)
    x = 0.5 * (lo + hi)
    part = np.where(s_lo, x - ang[trans], ang[trans] + step - x)  # leaving length inside the interval [rad]
    full = (L & Ln).reshape(-1) * step
    weight = 0.5 * full + 0.5 * np.roll(full.reshape(p, m), 1, axis=1).reshape(-1)
    target = np.where(s_lo, trans, (trans // m) * m + (trans % m + 1) % m)  # sample owning the partial length
    np.add.at(weight, target, part)
    angle = (full.reshape(p, m).sum(axis=1) + np.bincount(trans // m, part, p))
    out = {
        "angle_deg": np.degrees(angle),
        # full bracket width: a bound even where float32 rays blur the bracket ends
        "angle_err_deg": np.degrees(np.bincount(trans // m, hi - lo, p)),
        "transitions": np.bincount(trans // m, minlength=p),
    }
    if cfg["distance_method"] == "horizontal":
        idx = np.flatnonzero(leave)
        _, t_l = engine.first_hit("landscape", points[pidx[idx]], dirs[idx])
        n = rg.normal[wface[idx]]
        nh = n.copy()
        nh[:, 2] = 0.0
        nh /= np.maximum(np.linalg.norm(nh, axis=1, keepdims=True), 1e-12)
        dist = np.full(p * m, np.nan)
        dist[idx] = (t_l - gdist[idx]) * np.einsum("ij,ij->i", dirs[idx], nh)
        out["distance"], out["distance_gap"] = weighted_statistic(dist.reshape(p, m), weight.reshape(p, m), cfg["distance_statistic"])
    return out


def assess_points(engine, rg: RoomGeometry, points: np.ndarray, cfg: dict, thresholds: dict, progress=None) -> dict:
    """Every per-point quantity, level and error estimate for one set of viewpoints (vectorised)."""
    parts = []
    for a in range(0, len(points), POINT_CHUNK):  # chunks bound memory; each chunk is vectorised
        chunk = points[a:a + POINT_CHUNK]
        sa = solid_angles(engine, rg, chunk, cfg)
        hz = horizontal(engine, rg, chunk, cfg)
        parts.append({**sa, **{("h_" + k): v for k, v in hz.items()}})
        if progress:
            progress(len(chunk))
    r = {k: np.concatenate([q[k] for q in parts]) for k in parts[0]} if parts else {}
    if not parts:
        return {}
    if cfg["distance_method"] == "horizontal":
        dist, gap = r["h_distance"], r["h_distance_gap"]
    else:
        dist, gap = r["distance"], r["distance_gap"]
    thr = cfg["layer_threshold_sr"]
    visible = {k: r[k] > thr for k in ("sky", "landscape", "ground")}
    lv_angle = standard.level_from_value(r["h_angle_deg"], thresholds["horizontal_sight_angle_deg"])
    lv_dist = standard.level_from_value(np.where(np.isnan(dist), -np.inf, dist), thresholds["outside_distance_m"])
    lv_layers = standard.level_from_layers(visible["sky"], visible["landscape"], visible["ground"])
    level = np.minimum(np.minimum(lv_angle, lv_dist), lv_layers)
    near = (
        standard.near_threshold(r["h_angle_deg"], r["h_angle_err_deg"], thresholds["horizontal_sight_angle_deg"])
        | standard.near_threshold(dist, gap, thresholds["outside_distance_m"])
        | np.any([standard.near_threshold(r[k], r["err_" + k], [thr]) for k in ("sky", "landscape", "ground")], axis=0)
    )
    r.update(distance=dist, distance_gap=gap, visible=visible, level_angle=lv_angle, level_distance=lv_dist,
             level_layers=lv_layers, level=level, near=near)
    return r


def assess_room(engine, scene, room, cfg: dict, thresholds: dict, explicit=None, progress=None, planned=None) -> dict:
    """View result of one room: per eye height, per point values, shares and levels.

    ``planned`` is the room's :func:`viewpoints` result when the caller already made it (to size a
    progress bar); otherwise the viewpoints are made here.

    Returns
    -------
    dict with ``eye_heights`` (list of dicts holding numpy arrays), ``level`` (str), ``notes``.
    """
    rg = room_geometry(scene, room)
    groups, notes = planned if planned is not None else viewpoints(scene, room, cfg, explicit)
    eye = []
    for h, pts in groups:  # one pass per eye height (two by default)
        r = assess_points(engine, rg, pts, cfg, thresholds, progress)
        lv = {}
        share = {}
        for crit, key in (("horizontal_sight_angle", "level_angle"), ("outside_distance", "level_distance"),
                          ("layers", "level_layers"), ("view", "level")):
            level, sh = standard.room_level(r.get(key, []), cfg["area_fraction"])
            lv[crit] = level
            share[crit] = sh
        eye.append({"eye_height_m": h, "points_local": pts, "values": r,
                    "level": min(lv["horizontal_sight_angle"], lv["outside_distance"], lv["layers"]),
                    "level_by_criterion": {k: lv[k] for k in ("horizontal_sight_angle", "outside_distance", "layers")},
                    "share_by_level": share})
    level = min(e["level"] for e in eye) if eye else 0
    return {"eye_heights": eye, "level": level, "notes": notes}

