"""Rooms from the spaces a model defines (IfcSpace, gbXML Space; any reader's
:class:`~en17037cli.io.mesh.Space`): one room per space a project's ``ifc_spaces`` /
``gbxml_spaces`` glob picks among the spaces of that kind, each with the windows that open into it.

Windows are matched to spaces by geometry first, over every space of the model at once
(:func:`match_windows`): a window opens into the space whose boundary its glazing lies on, within
the thickness of the wall it is cut in. From points spread over the glazing, rays run along the
glazing's normal to each side; a ray *enters* a space where it crosses the space's body from
outside (or starts just inside it: the glazing on the boundary); a side's space is the first one
its rays enter, for at least :data:`MIN_SPACE_SHARE` of them, within the host's depth on that side
+ :data:`SPACE_GAP_M` (the host wall, or roof and a roof light's curb, from ``Part.host``), or within
``window_margin_m`` where the model names no host. The room is on that side: the window's outward
normal points away from it. A roof light counts like a wall window (its rays run down into the
stair or hall below), and a window lying inside a space's volume (a roof space above the roof)
does not open into that space.

The model's own space boundaries (``Space.windows``: IfcRelSpaceBoundary) confirm and settle:
where a window opens into several spaces by geometry and the boundaries name some of them, those
are its spaces; where the geometry finds none within the host's depth but a boundary names a space
within ``window_margin_m``, that space has it; where nothing else places the window (its rays enter
the space farther away, or not at all: a space drawn beside it), the spaces the boundaries name
have it, with a note. Boundaries never remove a window the geometry gives (they are often
incomplete). A window in no space is listed by ``validate`` with the reason.

A reader's :class:`Space` needs: ``id`` (unique), ``name`` / ``long_name`` (reports), ``footprint``
(and ``holes``) in the mesh frame [m] with ``floor_z`` and ``top_z``, or ``problem`` saying why it
has none; ``body`` (closed triangles) where the format has the volume (else the footprint is
extruded from ``floor_z`` to ``top_z``); ``windows``: the ``Part.window`` keys its boundaries name,
or () where the format has no boundaries.
"""
from __future__ import annotations

import fnmatch
from dataclasses import dataclass, field, replace

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.mesh import Space
from en17037cli.project.settings import RoomSpec
from en17037cli.scene.hosts import host_depths
from en17037cli.scene.model import WINDOW, LeftOut, Room, Scene, Window
from en17037cli.scene.rooms import make_room
from en17037cli.scene.space_overlap import overlap_reason
from en17037cli.scene.windows import glazing_grid

#: A space counts as the one a window opens into when it lies this far beyond the host's depth at most [m]
#: (finishes, a space drawn short of the wall's face).
SPACE_GAP_M = 0.15
#: Share of a window's sample rays that must first enter a space for the window to open into it.
MIN_SPACE_SHARE = 0.25
#: Samples across and up the glazing (a grid, inset, kept on the glazing).
SAMPLES = 5
#: Rays start this far off the glazing's plane [m].
START_OFFSET_M = 2e-3


@dataclass
class WindowSpaces:
    """The spaces one window opens into: (space index, outward normal, reason) each; ``why`` says
    why there is none."""

    spaces: list[tuple[int, np.ndarray, str]] = field(default_factory=list)
    why: str = ""
    #: space -> [m] the open path from the glazing to it, where the window opens into it that way
    open_depth: dict[int, float] = field(default_factory=dict)
    #: space -> [m] how far from the glazing its rays enter it (negative: the glazing lies inside it)
    distance: dict[int, float] = field(default_factory=dict)
    #: a note for the report where only the model's space boundaries place the window, else ""
    note: str = ""


def room_name(space: Space) -> str:
    """How reports name a space: 'LongName (Name)', or whichever of them it has, or its GlobalId."""
    if space.long_name and space.name:
        return f"{space.long_name} ({space.name})"
    return space.long_name or space.name or space.id


def space_names(scene: Scene) -> list[str]:
    """The room name of each space of ``scene`` (:func:`room_name`), made unique: spaces named alike
    (exports do that) get their GlobalIds, ``'Room (R1) [2O2Fr$t4X7Zf8NOew3FLQD]'``."""
    names = [room_name(s) for _, s in scene.spaces]
    return [f"{n} [{s.id}]" if names.count(n) > 1 else n for n, (_, s) in zip(names, scene.spaces)]


def extruded_body(footprint: np.ndarray, holes, z0: float, z1: float) -> np.ndarray:
    """(k, 3, 3) [m]: the closed prism of a floor outline (with holes) from ``z0`` to ``z1``; the
    outline is ear-clipped with its holes (mapbox-earcut)."""
    import mapbox_earcut

    rings = [np.asarray(footprint, dtype=float)[:, :2]] + [np.asarray(h, dtype=float)[:, :2] for h in holes]
    xy = np.concatenate(rings)
    ends = np.cumsum([len(r) for r in rings]).astype(np.uint32)
    flat = xy[mapbox_earcut.triangulate_float64(xy, ends).reshape(-1, 3)]
    bottom = np.concatenate([flat, np.full(flat.shape[:2] + (1,), z0)], axis=-1)
    top = np.concatenate([flat, np.full(flat.shape[:2] + (1,), z1)], axis=-1)
    sides = []
    for ring in [np.asarray(footprint)] + [np.asarray(h) for h in holes]:
        a, b = ring, np.roll(ring, -1, axis=0)
        lo_a, lo_b = np.column_stack([a, np.full(len(a), z0)]), np.column_stack([b, np.full(len(b), z0)])
        hi_a, hi_b = np.column_stack([a, np.full(len(a), z1)]), np.column_stack([b, np.full(len(b), z1)])
        sides += [np.stack([lo_a, lo_b, hi_b], axis=1), np.stack([lo_a, hi_b, hi_a], axis=1)]
    return np.concatenate([bottom, top, *sides])


def ray_distances(origins: np.ndarray, d: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(s, t) [m]: distance along the unit direction ``d`` from each origin (s, 3) to each
    triangle (t, 3, 3) it crosses ahead, +inf where it misses (Moller and Trumbore 1997,
    doi:10.1080/10867651.1997.10487468)."""
    v0, e1, e2 = tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    tv = origins[:, None, :] - v0[None]
    u = np.einsum("stk,tk->st", tv, p) * inv
    q = np.cross(tv, e1[None])
    v = (q @ d) * inv
    t = np.einsum("stk,tk->st", q, e2) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
    return np.where(hit, t, np.inf)


def glazing_samples(window: Window, n: int = SAMPLES) -> np.ndarray:
    """Up to n x n points [m] on the glazing: a grid over its extent in its plane, inset by half a
    step, kept where it lies on the glazing (else the triangles' centroids)."""
    grid = glazing_grid(window, n)
    if not len(grid):
        return window.triangles.mean(axis=1)
    plane = window.triangles.reshape(-1, 3) @ window.normal  # a stepped pane: the points on its mean plane
    return grid + (plane.mean() - window.centroid @ window.normal) * window.normal


def _entries(samples: np.ndarray, d: np.ndarray, bodies: list[np.ndarray], allowed: float) -> np.ndarray:
    """(s, b) [m]: how far along ``d`` from each sample the ray enters each body: 0 where the
    sample lies on the body's boundary (just inside on this side, outside on the other); minus the
    depth where the glazing lies inside the body no deeper than ``allowed`` [m] from its boundary
    behind (a space drawn to a curtain wall's middle); +inf where it does not enter (misses, or
    starts deeper inside). Inside or not: parity of the crossings ahead."""
    out = np.full((len(samples), len(bodies)), np.inf)
    ahead, behind = samples + START_OFFSET_M * d, samples - START_OFFSET_M * d
    for j, tri in enumerate(bodies):  # a handful of candidate spaces per window
        t = ray_distances(ahead, d, tri)
        crossings = np.isfinite(t).sum(axis=1)
        inside = crossings % 2 == 1
        back = ray_distances(behind, -d, tri)
        inside_behind = np.isfinite(back).sum(axis=1) % 2 == 1
        depth = back.min(axis=1) + START_OFFSET_M  # to the boundary behind the glazing, where it lies inside
        first = t.min(axis=1) + START_OFFSET_M
        out[:, j] = np.select([inside & ~inside_behind, inside & inside_behind & (depth <= allowed), ~inside & (crossings > 0)],
                              [0.0, -depth, first], np.inf)
    return out


def match_windows(scene: Scene, margin_m: float) -> list[WindowSpaces]:
    """The spaces each window of ``scene`` opens into (see the module docstring), over every space
    of the model; ``margin_m`` [m]: how far a space may lie from a window with no host, and from
    one whose host says less where the model's boundaries name the space."""
    spaces = [s for _, s in scene.spaces]
    bodies, boxes = [], []
    for s in spaces:  # local frame; a space without a floor has no body to match
        if s.problem:
            bodies.append(None)
            boxes.append(None)
            continue
        body = (s.body if s.body is not None else extruded_body(s.footprint, s.holes, s.floor_z, s.top_z)) - scene.origin
        bodies.append(body)
        boxes.append((body.reshape(-1, 3).min(axis=0), body.reshape(-1, 3).max(axis=0)))
    named = {}
    for i, s in enumerate(spaces):
        for key in s.windows:
            named.setdefault(key, set()).add(i)
    has = np.array([b is not None for b in boxes], bool)
    blo = np.array([b[0] if b is not None else np.full(3, np.inf) for b in boxes]).reshape(-1, 3)
    bhi = np.array([b[1] if b is not None else np.full(3, -np.inf) for b in boxes]).reshape(-1, 3)
    wlo, whi = scene.window_boxes()
    out = []
    for k, w in enumerate(scene.windows):  # one small ray test per window and side
        lo, hi = wlo[k] - margin_m, whi[k] + margin_m
        near = has & np.all(blo <= hi, axis=1) & np.all(bhi >= lo, axis=1)
        for i in named.get(w.key, ()) if w.key else ():  # the spaces the file's boundaries name, wherever drawn
            near[i] = has[i]
        cand = [int(i) for i in np.flatnonzero(near)]
        out.append(_match_one(scene, w, cand, [bodies[i] for i in cand], named.get(w.key, set()) if w.key else set(),
                              margin_m, spaces))
        if not out[-1].spaces and not out[-1].distance:  # no space met on either side: what lies under it, if any
            under = has & np.all(blo[:, :2] <= whi[k, :2] + margin_m, axis=1) & np.all(bhi[:, :2] >= wlo[k, :2] - margin_m, axis=1) \
                & (bhi[:, 2] <= wlo[k, 2] + 1e-6) & (bhi[:, 2] >= wlo[k, 2] - UNDER_M)
            if under.any():
                i = max(np.flatnonzero(under), key=lambda j: (bhi[j, 2], -j))
                out[-1].why = (f"its glazing starts {wlo[k, 2] - bhi[i, 2]:.2f} m above the top of the space "
                               f"'{room_name(spaces[i])}' below it (a window over a space drawn up to its suspended "
                               "ceiling lights no room of the model); " + out[-1].why)
    return out


#: A space whose top lies up to this far under a window in no space is named as the one below it [m].
UNDER_M = 2.0


def _match_one(scene: Scene, w: Window, cand: list[int], bodies: list, named: set, margin_m: float, spaces) -> WindowSpaces:
    n = np.asarray(w.normal, float)
    depths = host_depths(scene, w)
    samples = glazing_samples(w)
    found: dict[int, tuple[float, float, float, float]] = {}  # space -> (side, share, distance, allowed)
    for side, depth in ((1.0, None if depths is None else depths[0]), (-1.0, None if depths is None else depths[1])):
        if not cand:
            break
        allowed = margin_m if depth is None else min(depth + SPACE_GAP_M, margin_m)
        e = _entries(samples, side * n, bodies, allowed)
        first = np.argmin(e, axis=1)
        dist = e[np.arange(len(samples)), first]
        for j in np.unique(first[np.isfinite(dist)]):
            sel = (first == j) & np.isfinite(dist)
            share, how_far = float(sel.mean()), float(np.median(dist[sel]))
            if share >= MIN_SPACE_SHARE and (cand[j] not in found or abs(how_far) < abs(found[cand[j]][2])):
                found[cand[j]] = (side, share, how_far, allowed)
    wall = "" if depths is None else f" (its host {depths[0] + depths[1]:.2f} m deep)"
    strict = {i: f for i, f in found.items() if abs(f[2]) <= f[3]}
    res = WindowSpaces(distance={i: f[2] for i, f in found.items()})
    if len(strict) > 1 and named & set(strict):  # the model's boundaries settle which of them
        picked = {i: strict[i] for i in strict if i in named}
        for i, (side, share, dist, _) in picked.items():
            res.spaces.append((i, -side * n, f"{share:.0%} of its glazing {_how_far(dist)}{wall}; of the "
                               f"{len(strict)} spaces it opens onto, the one the model's space boundaries name"))
        return res
    for i, (side, share, dist, _) in strict.items():
        res.spaces.append((i, -side * n, f"{share:.0%} of its glazing {_how_far(dist)}{wall}"
                           + ("; named by the model's space boundaries too" if i in named else "")))
    if res.spaces:
        return res
    loose = {i: f for i, f in found.items() if i in named and abs(f[2]) <= margin_m}
    for i, (side, share, dist, _) in loose.items():
        res.spaces.append((i, -side * n, f"named by the model's space boundaries, {share:.0%} of its glazing "
                           f"{_how_far(dist)}{wall}"))
    if res.spaces:
        return res
    for i, (side, share, dist, _) in found.items():  # a light well, a deep reveal: nothing opaque on the way
        if 0 < dist <= margin_m and open_share(scene, w, samples, side * n, dist) >= MIN_SPACE_SHARE:
            res.spaces.append((i, -side * n, f"{share:.0%} of its glazing {_how_far(dist)}{wall}, with nothing "
                               "opaque between (a light well, a deep reveal)"))
            res.open_depth[i] = dist
    if res.spaces:
        return res
    far = {i: f for i, f in found.items() if i in named}
    for i, (side, _share, dist, _) in far.items():  # the file's own link, where the space's drawn volume is off
        res.spaces.append((i, -side * n, f"named by the model's space boundaries; the space as drawn lies "
                           f"{abs(dist):.2f} m from its glazing{wall} (its volume does not reach the window: check "
                           "the room's floor and windows)"))
    if res.spaces:
        return res
    for j, i in enumerate(cand):  # the file's own link where no ray enters the space at all (drawn beside the window)
        if i in named and i not in found:
            body = bodies[j].reshape(-1, 3)
            side = 1.0 if (body.mean(axis=0) - w.centroid) @ n >= 0 else -1.0
            gap = float(np.linalg.norm(np.maximum(0.0, np.maximum(body.min(axis=0) - w.triangles.reshape(-1, 3).max(axis=0),
                                                                 w.triangles.reshape(-1, 3).min(axis=0) - body.max(axis=0)))))
            res.spaces.append((i, -side * n, f"named by the model's space boundaries, though none of its rays enters the space "
                               f"as drawn (its volume lies {gap:.2f} m from the window, beside the glazing's normal): check "
                               "the room's floor and windows"))
            res.note = (f"window '{w.name}': in '{room_name(spaces[i])}', the space the model's boundaries name, though no ray "
                        f"from its glazing enters that space as drawn ({gap:.2f} m away); nothing else places it")
    if res.spaces:
        return res
    if found:
        i, (side, share, dist, allowed) = min(found.items(), key=lambda kv: kv[1][2])
        res.why = (f"the nearest space, '{room_name(spaces[i])}', lies {dist:.2f} m from its glazing, more than the "
                   f"{allowed:.2f} m its host allows{wall}: it opens into no space of the model")
    else:
        res.why = (f"no space of the model lies within {margin_m:g} m of its glazing on either side (spaces missing "
                   "from the model, or the window outside every storey's spaces)")
    return res


def open_share(scene: Scene, w: Window, samples: np.ndarray, d: np.ndarray, dist: float) -> float:
    """Share of the rays from ``samples`` along ``d`` that meet no opaque face within ``dist`` [m]
    (the window's own element not counted): the window opens into what lies that far along an
    open path (a roof light over a light well down to the hall's ceiling opening)."""
    if "tri_boxes" not in scene.cache:  # every face's bounding box, once per scene
        tri = scene.vertices[scene.triangles]
        scene.cache["tri_boxes"] = (tri.min(axis=1), tri.max(axis=1))
    tlo, thi = scene.cache["tri_boxes"]
    ends = samples + d * dist
    lo, hi = np.minimum(samples, ends).min(axis=0) - 1e-6, np.maximum(samples, ends).max(axis=0) + 1e-6
    faces = np.flatnonzero(np.all((tlo <= hi) & (thi >= lo), axis=1) & (scene.layer != WINDOW))
    if w.key is not None and len(faces):
        mine = np.array([scene.parts[p].attrs.get("id") == w.key for p in scene.part[faces]], bool)
        faces = faces[~mine]
    if len(faces) == 0:
        return 1.0
    t = ray_distances(samples + START_OFFSET_M * d, d, scene.vertices[scene.triangles[faces]])
    return float(np.mean(t.min(axis=1) + START_OFFSET_M >= dist - 1e-6))


def _how_far(dist: float) -> str:
    if dist < 0:
        return f"inside the space, {-dist:.2f} m from its boundary"
    return "on the space's boundary" if dist == 0 else f"{dist:.2f} m from the space"


def _space_windows(scene: Scene, margin_m: float) -> list[WindowSpaces]:
    if scene.space_windows is None:
        scene.space_windows = match_windows(scene, margin_m)
        scene.notes.extend(m.note for m in scene.space_windows if m.note)
    return scene.space_windows  # type: ignore[return-value]


def rooms_from_spaces(scene: Scene, spec: RoomSpec, where: str) -> list[Room]:
    """A room for each space whose Name, LongName or GlobalId the spec's glob matches.

    Floor: the space's footprint at its bottom; ceiling: its top. Windows: those that open into
    it (:func:`match_windows`), narrowed by the spec's ``windows`` globs. A space with no window is
    left out (``validate`` lists it); a space with windows but no usable floor is left out with the
    reason, and the run cannot pass (:attr:`Scene.left_out`); a space without a window that is drawn
    over one with windows says so (:mod:`~en17037cli.scene.space_overlap`).
    """
    key, kind = ("gbxml_spaces", "gbXML Space") if spec.gbxml_spaces is not None else ("ifc_spaces", "IfcSpace")
    glob = getattr(spec, key) or "*"
    spaces = [(i, s) for i, (_, s) in enumerate(scene.spaces) if s.kind == kind]
    if not spaces:
        raise InputError(f"{where}.{key}: the model has no {kind}; make a room of every region its walls enclose with a "
                         "window (rooms: [{auto: true}]), or list the rooms with name and floor_z")
    picked = [(i, s) for i, s in spaces
              if any(fnmatch.fnmatchcase(v, glob) for v in (s.name, s.long_name, s.id, room_name(s)) if v)]
    if not picked:
        known = ", ".join(room_name(s) for _, s in spaces[:8])
        raise InputError(f"{where}.{key}: '{glob}' matches no {kind}; spaces: {known}")
    matches = _space_windows(scene, spec.window_margin_m)
    by_space: dict[int, list[tuple[Window, str]]] = {}
    for w, m in zip(scene.windows, matches):
        for i, normal, why in m.spaces:
            by_space.setdefault(i, []).append((replace(w.facing(normal), open_depth_m=m.open_depth.get(i, 0.0),
                                                       space_distance_m=m.distance.get(i)), why))
    keys = {w.key for w in scene.windows if w.key}
    names = space_names(scene)
    rooms = []
    for i, space in sorted(picked, key=lambda p: (p[1].floor_z, names[p[0]])):  # storey by storey
        name = names[i]
        opening = by_space.get(i, [])
        chosen = opening if spec.windows is None else \
            [(w, why) for w, why in opening if any(fnmatch.fnmatchcase(w.name, g) for g in spec.windows)]
        if space.problem:
            named = [k for k in space.windows if k in keys]
            scene.left_out.append(LeftOut(name, f"the space has no floor ({space.problem})",
                                          tuple(w.name for w in scene.windows if w.key in named)))
            continue
        if not chosen:  # the project's own globs leaving out every window: its choice, not a space left out unasked
            why = (overlap_reason([s for _, s in scene.spaces], names, i, by_space) or "no window opens into it") \
                if not opening else f"none of its {len(opening)} window(s) matches rooms[{spec.index}].windows"
            scene.left_out.append(LeftOut(name, why))
            continue
        room_spec = replace(spec, name=name, floor_z=space.floor_z, floor=space.footprint, ceiling_z=space.top_z,
                            view_points=None, sun_points=None, windows=None)
        try:
            room = make_room(scene, room_spec, f"{where} '{name}'", chosen=chosen)
        except InputError as exc:  # a space the file gives no usable floor: listed, never the whole run stopped
            why = str(exc).split(": ", 2)[-1]
            scene.left_out.append(LeftOut(name, f"its footprint is not usable ({why})", tuple(w.name for w, _ in chosen)))
            continue
        room.zones, room.storey, room.usage, room.space = space.zones, space.storey, space.usage, i
        room.floor_source, room.ceiling_source = f"the {kind}'s footprint", f"the {kind}'s top"
        rooms.append(room)
    return rooms


def windows_in_no_room(scene: Scene) -> list[tuple[str, str]]:
    """(window name, why) of each window of the model that is in no room of the project: it opens
    into no space (the matching's reason), or into spaces the project does not make rooms."""
    in_room = {w.name for r in scene.rooms for w in r.windows}
    display = space_names(scene)
    left = {lo.name: lo.reason for lo in scene.left_out}
    out = []
    for k, w in enumerate(scene.windows):
        if w.name in in_room:
            continue
        m = scene.space_windows[k] if scene.space_windows is not None else None  # type: ignore[index]
        if m is None:
            out.append((w.name, "it bounds no room of the project"))
        elif not m.spaces:
            out.append((w.name, m.why))
        else:
            names = [display[i] for i, _, _ in m.spaces]
            why = "; ".join(f"'{n}' is left out ({left[n]})" if n in left else f"no rooms[] entry picks '{n}'" for n in names)
            out.append((w.name, f"it opens into {', '.join(repr(n) for n in names)}: {why}"))
    return out
