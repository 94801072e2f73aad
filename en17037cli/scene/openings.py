"""One definition of a window for every format: the opening in the wall, with all its panes.

Readers give glazing in pieces that depend on the format and the drawing, not the building: an
IfcWindow is one product with its panes and mullions, an OBJ/glTF/DXF export gives each pane as
its own group of faces, a curtain wall gives one plate per panel, and a window drawn as two panes
and the same window drawn as one pane behind a mullion differ only in where the glass stops. Here
a window is the opening: the panes of a room that lie in one plane and are no farther apart than
a frame member is wide (:data:`MAX_MEMBER_WIDTH_M`: a mullion, a transom, a curtain wall's
member) are one window, whatever the format said. Panes farther apart have wall between them
(a pier) and stay separate windows. Only panes of one room are joined, so no window spans a
partition.

Point P (EN 17037 Annex A.3) then has one rule on every window, and where a member of its frame
lies in front of it (:mod:`en17037cli.criteria.sunlight.point_p`) one rule for that too.
"""
from __future__ import annotations

import numpy as np

from en17037cli.geometry import window_axes
from en17037cli.scene.model import Scene, Window
from en17037cli.scene.windows import covered_faces

#: Panes of one room in one plane whose outlines are at most this far apart are one window: the
#: widest frame member (mullion, transom) this tool expects between two panes of one opening [m].
#: The narrowest wall between two openings of the real exports read so far is 0.215 m (Revit's
#: Duplex); their mullions are 0.05-0.12 m (ArchiCAD's FZK-Haus: 0.12 m).
MAX_MEMBER_WIDTH_M = 0.15
#: ... whose normals differ by less than this [deg] ...
PLANE_ANGLE_DEG = 1.0
#: ... and whose planes are within this of each other [m] (the glass of two sashes of one window
#: is not always in one plane: a casement and a fixed light).
PLANE_OFFSET_M = 0.05


def pane_gap(a: Window, b: Window) -> float:
    """Distance between the outlines of two windows' glazing in ``a``'s plane [m] (0 where they
    touch or overlap)."""
    import shapely

    u, v = window_axes(a.normal)
    pa = shapely.union_all(shapely.make_valid(shapely.polygons(np.stack([a.triangles @ u, a.triangles @ v], axis=-1))))
    pb = shapely.union_all(shapely.make_valid(shapely.polygons(np.stack([b.triangles @ u, b.triangles @ v], axis=-1))))
    return float(pa.distance(pb))


def same_opening(a: Window, b: Window) -> bool:
    """Whether two windows of one room are panes of one opening (see the module docstring)."""
    if abs(float(a.normal @ b.normal)) < np.cos(np.radians(PLANE_ANGLE_DEG)):
        return False
    if abs(float((b.centroid - a.centroid) @ a.normal)) > PLANE_OFFSET_M:
        return False
    lo_a, hi_a = a.triangles.reshape(-1, 3).min(axis=0), a.triangles.reshape(-1, 3).max(axis=0)
    lo_b, hi_b = b.triangles.reshape(-1, 3).min(axis=0), b.triangles.reshape(-1, 3).max(axis=0)
    if np.any(lo_a > hi_b + MAX_MEMBER_WIDTH_M) or np.any(lo_b > hi_a + MAX_MEMBER_WIDTH_M):
        return False  # boxes apart: no polygon test
    return pane_gap(a, b) <= MAX_MEMBER_WIDTH_M


def joined(members: list[Window]) -> Window:
    """One window of the panes ``members`` (in the scene's order): the first one's name, key,
    normal and index, every pane's faces but those hidden behind others of it (double glazing
    drawn as two panes: :func:`~en17037cli.scene.windows.covered_faces`), the hosts and the parts
    (elements) of all, hidden ones included; its area counts each part of the opening once."""
    if len(members) == 1:
        return members[0]
    first = members[0]
    tris = np.concatenate([m.triangles for m in members])
    ids = np.concatenate([m.face_ids for m in members])
    hidden, seen_area = covered_faces(tris, first.normal)
    area = float(sum(m.area_m2 for m in members)) if seen_area is None else seen_area
    more = len(members) - 1
    name = first.name if len({m.key for m in members}) == 1 and first.key else f"{first.name} (+{more} pane{'s' * (more > 1)})"
    host = tuple(sorted({h for m in members for h in m.host}))
    return Window(name=name, index=first.index, face_ids=ids[~hidden], triangles=tris[~hidden], normal=first.normal,
                  area_m2=area, key=first.key, host=host, parts=tuple(sorted({x for m in members for x in m.parts})),
                  open_depth_m=max(m.open_depth_m for m in members),
                  space_distance_m=None if all(m.space_distance_m is None for m in members)
                  else min(m.space_distance_m for m in members if m.space_distance_m is not None))


def join_openings(scene: Scene) -> list[str]:
    """Join the panes of each room's openings into windows (see the module docstring), in the
    rooms and in ``scene.windows``; returns notes naming what was joined. Panes are joined
    transitively (a curtain wall of many panels is one window)."""
    notes = []
    replaced: dict[str, Window] = {}
    for room in scene.rooms:  # a room has a handful of windows: pairwise tests
        ws = room.windows
        label = list(range(len(ws)))
        for i in range(len(ws)):
            for j in range(i + 1, len(ws)):
                if label[i] != label[j] and same_opening(ws[i], ws[j]):
                    old, new = label[j], label[i]
                    label = [new if x == old else x for x in label]
        if len(set(label)) == len(ws):
            continue
        out, reasons = [], dict(room.window_reasons)
        for root in dict.fromkeys(label):  # in the room's order
            members = [w for w, x in zip(ws, label) if x == root]
            w = joined(members)
            out.append(w)
            if len(members) > 1:
                for m in members:
                    replaced[m.name] = w
                    reasons.pop(m.name, None)
                reasons[w.name] = room.window_reasons.get(members[0].name, "")
                notes.append(f"room '{room.name}': {len(members)} panes in one opening (at most {MAX_MEMBER_WIDTH_M:g} m apart: "
                             f"a frame member between them) are one window '{w.name}'")
        room.windows, room.window_reasons = out, reasons
    if replaced:
        seen: set[str] = set()
        windows = []
        for w in scene.windows:  # the scene's order, each joined window once, where its first pane was
            w2 = replaced.get(w.name, w)
            if w2.name not in seen:
                seen.add(w2.name)
                windows.append(w2)
        scene.windows = windows
        scene._boxes = (None,)
    return notes
