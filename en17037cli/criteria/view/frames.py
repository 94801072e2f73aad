"""Windows as the view engine samples them: each in its own 2D frame, with the vertices of its frame
(mullions, transoms, reveals), and the per-room lookups built from them."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli.geometry import area2, window_axes
from en17037cli.scene.model import WINDOW, Room, Scene, room_window_group


@dataclass
class WindowFrame:
    """A planar window in its own 2D frame, for sampling it from viewpoints.

    ``u`` and ``v`` span the glazing plane: ``u`` runs along a side of the window's minimum-area
    bounding rectangle (the side nearest the horizontal), so the frame moves with the model and a
    rectangular window is ``[xmin, xmax] x [ymin, ymax]`` exactly. ``n`` is the outward normal.

    tri2 : (k, 3, 2) float [m], the window's triangles in (u, v) coordinates about ``origin``
    """

    index: int
    name: str
    origin: np.ndarray
    u: np.ndarray
    v: np.ndarray
    n: np.ndarray
    tri2: np.ndarray
    xmin: float
    xmax: float
    ymin: float
    ymax: float
    is_rectangle: bool
    face_ids: np.ndarray
    #: (e, 3) float [m]: vertices (x, y, s) of the window's frame, s along the outward normal
    frame_xys: np.ndarray = None
    _tree: object = None
    _outline: object = None

    def _outline_index(self):
        import shapely

        if self._outline is None:
            outline = shapely.union_all(shapely.polygons(self.tri2))
            shapely.prepare(outline)
            verts = shapely.get_coordinates(outline)
            self._outline = (outline, shapely.STRtree(shapely.points(verts)))
        return self._outline

    def on_glazing(self, x, y) -> np.ndarray:
        """Whether points (plane coordinates [m]) lie on the glazing (its outline polygon, edges included)."""
        import shapely

        return shapely.intersects_xy(self._outline_index()[0], x, y)

    def classify_boxes(self, x0, x1, y0, y1) -> tuple[np.ndarray, np.ndarray]:
        """Where axis-aligned boxes (plane coordinates [m]) lie against the glazing's outline.

        Returns
        -------
        inside : (m,) bool, the four corners lie on the outline polygon (edges included) and no
            vertex of the outline lies strictly inside the box (a slit narrower than a box that
            crosses it whole would pass: no real window has one)
        disjoint : (m,) bool, the box does not meet the outline polygon
        """
        import shapely

        outline, vertex_tree = self._outline_index()
        inside = np.ones(len(x0), dtype=bool)
        for x, y in ((x0, y0), (x1, y0), (x0, y1), (x1, y1)):  # the four corners
            inside &= shapely.intersects_xy(outline, x, y)
        cand = np.flatnonzero(inside)
        if len(cand):
            q, _ = vertex_tree.query(shapely.box(x0[cand], y0[cand], x1[cand], y1[cand]), predicate="contains_properly")
            inside[cand[np.unique(q)]] = False
        disjoint = np.zeros(len(x0), dtype=bool)
        other = np.flatnonzero(~inside)
        if len(other):
            disjoint[other] = ~shapely.intersects(outline, shapely.box(x0[other], y0[other], x1[other], y1[other]))
        return inside, disjoint

    def triangle_pairs(self, xmin, xmax, ymin, ymax) -> tuple[np.ndarray, np.ndarray]:
        """(query index, triangle index) of every axis-aligned box (plane coordinates [m]) whose
        bounding box meets a triangle's bounding box (touching included), from an STR tree of the
        window's triangles: the candidates of exact tests, without a (boxes x triangles) array."""
        import shapely

        if self._tree is None:
            self._tree = shapely.STRtree(shapely.polygons(self.tri2))
        q, t = self._tree.query(shapely.box(xmin, ymin, xmax, ymax))
        order = np.lexsort((t, q))
        return q[order], t[order]


def window_frame(window, index: int) -> WindowFrame:
    """The :class:`WindowFrame` of a :class:`~en17037cli.scene.model.Window` (triangles projected on its mean plane)."""
    import shapely

    n = np.asarray(window.normal, float)
    origin = window.centroid
    a, up = window_axes(n)
    rel = window.triangles - origin
    flat = np.stack([rel @ a, rel @ up], axis=-1)
    poly = shapely.union_all([shapely.Polygon(t) for t in flat if area2(t) > 0])
    rect = np.asarray(shapely.minimum_rotated_rectangle(poly).exterior.coords)[:4]
    sides = [rect[1] - rect[0], rect[2] - rect[1]]
    phis = [np.arctan2(s[1], s[0]) for s in sides]
    phis = [(ph + np.pi / 2) % np.pi - np.pi / 2 for ph in phis]  # a side direction, folded to [-90, 90) deg
    phi = min(phis, key=abs)
    if abs(phi) < 1e-12:
        phi = 0.0
    u = np.cos(phi) * a + np.sin(phi) * up
    v = -np.sin(phi) * a + np.cos(phi) * up
    tri2 = np.stack([rel @ u, rel @ v], axis=-1)
    xmin, xmax = float(tri2[..., 0].min()), float(tri2[..., 0].max())
    ymin, ymax = float(tri2[..., 1].min()), float(tri2[..., 1].max())
    box = (xmax - xmin) * (ymax - ymin)
    return WindowFrame(index, window.name, origin, u, v, n, tri2, xmin, xmax, ymin, ymax,
                       bool(abs(poly.area - box) <= 1e-9 * box), np.asarray(window.face_ids))


def frame_vertices(frame: WindowFrame, vertices: np.ndarray, triangles: np.ndarray, depth_m: float) -> np.ndarray:
    """Vertices of the opaque faces that frame a window: mullions, transoms, frames, reveals.

    A face is part of the frame when all its vertices lie within ``depth_m`` of the glazing
    plane and its extent over the plane overlaps the window's. The view engine draws a grid
    line through the image of each of these vertices.

    Parameters
    ----------
    frame : WindowFrame
    vertices : (n, 3) float [m], local frame
    triangles : (m, 3) int, the opaque faces
    depth_m : float [m]

    Returns
    -------
    (e, 3) float [m], unique (x, y, s) in the window's (u, v, n) frame
    """
    s_v = (vertices - frame.origin) @ frame.n  # per vertex first: no (m, 3, 3) copy of a large scene
    tri = triangles[np.all(np.abs(s_v[triangles]) <= depth_m, axis=1)]
    rel = vertices[tri] - frame.origin
    s, x, y = rel @ frame.n, rel @ frame.u, rel @ frame.v
    over = (x.min(axis=1) < frame.xmax) & (x.max(axis=1) > frame.xmin) & (y.min(axis=1) < frame.ymax) & (y.max(axis=1) > frame.ymin)
    xys = np.stack([x[over], y[over], s[over]], axis=-1).reshape(-1, 3)
    return np.unique(np.round(xys, 9), axis=0)


@dataclass
class RoomGeometry:
    """Per-room lookups: the room's windows as :class:`~en17037cli.view_math.WindowFrame` and their faces."""

    frames: list
    window_of_face: np.ndarray  # (n_faces,) int, index into frames, -1 for faces that are no window of the room
    triangles: np.ndarray  # (k, 3, 3) all window triangles of the room [m]
    triangle_window: np.ndarray  # (k,) int, index into frames
    group: str  # ray-engine group of the room's windows

    def frame_array(self, attr: str) -> np.ndarray:
        return np.array([getattr(f, attr) for f in self.frames])


def room_geometry(scene: Scene, room: Room, frame_depth_m: float = 0.5) -> RoomGeometry:
    """Lookups of ``room``'s windows; opaque faces within ``frame_depth_m`` [m] of a window's plane
    and over it are its frame (:func:`frame_vertices`)."""
    opaque = scene.triangles[scene.layer != WINDOW]
    frames = [window_frame(w, i) for i, w in enumerate(room.windows)]
    for f in frames:
        f.frame_xys = frame_vertices(f, scene.vertices, opaque, frame_depth_m)
    wof = np.full(len(scene.triangles), -1, dtype=np.int64)
    for f in frames:
        wof[f.face_ids] = f.index
    tris = np.concatenate([w.triangles for w in room.windows])
    tw = np.concatenate([np.full(len(w.triangles), i) for i, w in enumerate(room.windows)])
    return RoomGeometry(frames, wof, tris, tw, room_window_group(room))
