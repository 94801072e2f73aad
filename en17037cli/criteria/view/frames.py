"""Windows as the view engine samples them: each in its own 2D frame, with the vertices of its frame
(mullions, transoms, reveals), and the per-room lookups built from them."""
from __future__ import annotations

import functools
import threading
from dataclasses import dataclass

import numpy as np

from en17037cli.geometry import area2, boxes_vs_convex, convex_halfplanes, points_in_convex, window_axes
from en17037cli.scene.model import WINDOW, Room, Scene, room_window_group

#: An outline whose convex hull is larger by at most this fraction of its area is convex (round-off
#: of the collinear vertices of a tessellated arc).
CONVEX_REL = 1e-12
#: Points within this distance of a convex outline's edges lie on it [m] (shapely's exact test
#: counts the edges in; this counts round-off of the edges' lines in too).
ON_OUTLINE_M = 1e-12

#: The window outlines' shapely objects (prepared geometries, STR trees) build their indexes on
#: first use and are not safe to share between threads: their queries take turns (the view's
#: solid angles run on several threads; only windows that are not rectangles ask shapely).
_GEOS = threading.RLock()


def _one_thread_at_a_time(method):
    @functools.wraps(method)
    def locked(*args, **kwargs):
        with _GEOS:
            return method(*args, **kwargs)

    return locked


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
    #: (a, 2) and (b, 2) float [m]: (x, s) of the frame's edges parallel to ``v`` and (y, s) of
    #: those parallel to ``u`` (:func:`axis_breakpoints`): the grid lines the view engine draws
    frame_x: np.ndarray = None
    frame_y: np.ndarray = None
    #: (k, 2, 3) float [m]: edges of the frame's faces that may bound what it hides (:func:`frame_edges`)
    frame_edges: np.ndarray = None
    #: (k, 2, 3) float [m]: the vertices opposite each edge in its two faces, NaN for an edge of one face
    frame_edge_opposite: np.ndarray = None
    _tree: object = None
    _outline: object = None
    #: (e, 3) half-planes of the outline where it is convex (:func:`~en17037cli.geometry.convex_halfplanes`), else empty
    _convex: np.ndarray | None = None

    @_one_thread_at_a_time
    def _outline_index(self):
        import shapely

        if self._outline is None:
            outline = shapely.union_all(shapely.polygons(self.tri2))
            shapely.prepare(outline)
            verts = shapely.get_coordinates(outline)
            self._outline = (outline, shapely.STRtree(shapely.points(verts)))
            self._convex = np.zeros((0, 3))
            if outline.geom_type == "Polygon" and not outline.interiors and \
                    outline.convex_hull.area <= outline.area * (1 + CONVEX_REL):
                ring = np.asarray(shapely.orient_polygons(outline).exterior.coords)[:-1]
                self._convex = convex_halfplanes(ring)
        return self._outline

    def _halfplanes(self) -> np.ndarray:
        """The outline's half-planes where it is convex (a rectangle, a triangle, an arched or
        round pane), else an empty array: then shapely answers."""
        self._outline_index()
        return self._convex

    def on_glazing(self, x, y) -> np.ndarray:
        """Whether points (plane coordinates [m]) lie on the glazing (its outline polygon, edges included)."""
        import shapely

        hp = self._halfplanes()
        if len(hp):
            return points_in_convex(hp, x, y, ON_OUTLINE_M)
        with _GEOS:
            return shapely.intersects_xy(self._outline_index()[0], x, y)

    @_one_thread_at_a_time
    def meets_glazing(self, x0, y0, x1, y1) -> np.ndarray:
        """Whether segments (plane coordinates [m] of their ends) meet the glazing's outline polygon."""
        import shapely

        lines = shapely.linestrings(np.stack([np.column_stack([x0, y0]), np.column_stack([x1, y1])], axis=1))
        return shapely.intersects(self._outline_index()[0], lines)

    def classify_boxes(self, x0, x1, y0, y1) -> tuple[np.ndarray, np.ndarray]:
        """Where axis-aligned boxes (plane coordinates [m]) lie against the glazing's outline.

        Returns
        -------
        inside : (m,) bool, the four corners lie on the outline polygon (edges included) and no
            vertex of the outline lies strictly inside the box (a slit narrower than a box that
            crosses it whole would pass: no real window has one)
        disjoint : (m,) bool, the box does not meet the outline polygon
        """
        hp = self._halfplanes()
        if len(hp):  # vectorised, exact for a convex outline
            return boxes_vs_convex(hp, (self.xmin, self.xmax, self.ymin, self.ymax), x0, x1, y0, y1, ON_OUTLINE_M)
        with _GEOS:
            return self._classify_boxes_shapely(x0, x1, y0, y1)

    def _classify_boxes_shapely(self, x0, x1, y0, y1) -> tuple[np.ndarray, np.ndarray]:
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

    @_one_thread_at_a_time
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


#: A window of more triangles than this whose outline is convex is sampled on a strip triangulation.
STRIP_MIN_TRIANGLES = 8


def convex_strip(poly) -> np.ndarray | None:
    """(k, 3, 2) [m]: a convex polygon's triangles as a strip across its height (each between two
    neighbouring vertex heights, zigzag between its left and right chains), or None where the
    polygon is not convex or has holes. A tessellated round pane comes as a fan from its centre
    whose long triangles each overlap many sampling cells; a strip's overlap few."""
    import shapely

    if poly.geom_type != "Polygon" or poly.interiors or poly.area <= 0 or poly.convex_hull.area > poly.area * (1 + 1e-9):
        return None
    ring = np.asarray(shapely.orient_polygons(poly).exterior.coords)[:-1]
    lo, hi = int(np.argmin(ring[:, 1])), int(np.argmax(ring[:, 1]))
    n = len(ring)
    right = ring[[(lo + k) % n for k in range((hi - lo) % n + 1)]]  # counterclockwise: up the right side
    left = ring[[(lo - k) % n for k in range((lo - hi) % n + 1)]]  # clockwise: up the left side
    out, i, j = [], 0, 0
    while i < len(left) - 1 or j < len(right) - 1:  # one triangle per vertex passed
        if j < len(right) - 1 and (i == len(left) - 1 or right[j + 1, 1] <= left[i + 1, 1]):
            out.append((left[i], right[j], right[j + 1]))
            j += 1
        else:
            out.append((left[i], right[j], left[i + 1]))
            i += 1
    tri = np.array(out)
    keep = np.abs(_area2(tri)) > 0
    return tri[keep] if keep.any() else None


def _area2(tri: np.ndarray) -> np.ndarray:
    """Twice the signed areas of triangles (k, 3, 2)."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


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
    if len(tri2) > STRIP_MIN_TRIANGLES:  # a finely tessellated round or arched pane: thin triangles, few overlaps per cell
        import shapely.affinity

        strip = convex_strip(shapely.affinity.rotate(poly, -phi, origin=(0, 0), use_radians=True))
        tri2 = tri2 if strip is None else strip
    xmin, xmax = float(tri2[..., 0].min()), float(tri2[..., 0].max())
    ymin, ymax = float(tri2[..., 1].min()), float(tri2[..., 1].max())
    box = (xmax - xmin) * (ymax - ymin)
    return WindowFrame(index, window.name, origin, u, v, n, tri2, xmin, xmax, ymin, ymax,
                       bool(abs(poly.area - box) <= 1e-9 * box), np.asarray(window.face_ids))


def frame_faces(frame: WindowFrame, vertices: np.ndarray, triangles: np.ndarray, depth_m: float) -> np.ndarray:
    """The opaque faces that frame a window: mullions, transoms, frames, reveals.

    A face is part of the frame when all its vertices lie within ``depth_m`` of the glazing
    plane and its extent over the plane overlaps the window's.

    Parameters
    ----------
    frame : WindowFrame
    vertices : (n, 3) float [m], local frame
    triangles : (m, 3) int, the opaque faces
    depth_m : float [m]

    Returns
    -------
    (f, 3, 3) float [m], the faces' corners (x, y, s) in the window's (u, v, n) frame
    """
    s_v = (vertices - frame.origin) @ frame.n  # per vertex first: no (m, 3, 3) copy of a large scene
    tri = triangles[np.all(np.abs(s_v[triangles]) <= depth_m, axis=1)]
    rel = vertices[tri] - frame.origin
    s, x, y = rel @ frame.n, rel @ frame.u, rel @ frame.v
    over = (x.min(axis=1) < frame.xmax) & (x.max(axis=1) > frame.xmin) & (y.min(axis=1) < frame.ymax) & (y.max(axis=1) > frame.ymin)
    return np.stack([x[over], y[over], s[over]], axis=-1)


def frame_vertices(faces: np.ndarray) -> np.ndarray:
    """Unique corners (x, y, s) [m] of the frame's faces (:func:`frame_faces`, (f, 3, 3) [m]), rounded
    to 1 nm. Returns (e, 3) float [m]."""
    return np.unique(np.round(faces.reshape(-1, 3), 9), axis=0)


#: An edge whose ends differ by at most the larger of these in a coordinate (in metres, and as a
#: fraction of its length) is constant in it: real models are planar to a few microns (the seed
#: office's transom runs 5e-6 m off its frame's plane over 1 m).
AXIS_M = 1e-6
AXIS_REL = 1e-4


def axis_breakpoints(edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where the frame's axis-parallel edges put grid lines of the view's sampling grid.

    Seen from a point at distance d in front of the glazing plane, a frame point (x, y, s) has the
    gnomonic image X = (x - x0) / (d + s), Y = (y - y0) / (d + s): an edge of constant x and s
    (a jamb, the side of a mullion) images on the line alpha = atan(X), an edge of constant y and s
    (a sill, a head, a transom) on a line beta = atan(Y). The view engine draws those lines, so a
    mullion or a transom fills whole cells. Any other edge (an arc's segments, a diagonal member,
    a reveal's edges running into the wall) images on no grid line: the cells its image crosses
    count as mixed and are refined (:func:`~en17037cli.criteria.view.solid_angle.edge_pieces`),
    so a finely tessellated arch costs cells along its length, not a line per vertex.

    Parameters
    ----------
    edges : (k, 2, 3) float [m], (x, y, s) of the edges' ends (:func:`frame_edges`)

    Returns
    -------
    xs : (a, 2) float [m], unique (x, s) of the edges parallel to v; ys : (b, 2), (y, s) of those parallel to u
    """
    if len(edges) == 0:
        return np.zeros((0, 2)), np.zeros((0, 2))
    d = np.abs(edges[:, 1] - edges[:, 0])
    tol = np.maximum(AXIS_M, AXIS_REL * np.linalg.norm(d, axis=1))
    flat_s = d[:, 2] <= tol
    out = []
    for c, other in ((0, 1), (1, 0)):  # x lines: x and s constant, y varies
        sel = flat_s & (d[:, c] <= tol) & (d[:, other] > tol)
        pts = edges[sel].reshape(-1, 3)[:, [c, 2]]  # both ends: an edge a hair off the axis images between their lines
        out.append(np.unique(np.round(pts, 9), axis=0) if len(pts) else np.zeros((0, 2)))
    return out[0], out[1]


#: Two faces sharing an edge whose far corners lie closer than this to each other's plane, on
#: both sides of the edge, are one flat surface: the edge between them hides nothing [m].
COPLANAR_M = 1e-6


def frame_edges(frame: WindowFrame, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edges of the frame's faces that may bound what the frame hides, for the view engine to
    count the cells their images cross as mixed.

    Left out: edges shared by two coplanar faces of one flat surface (a quad's diagonal, the
    seams of a triangulated ring or wall), and edges in the glazing plane that do not enter the
    glazing's outline (the wall around the opening, the opaque part of an opening beside a pane
    that is not a rectangle: a view through the glazing meets its plane inside the outline, and
    the cells' weights are clipped to the outline exactly). Corners are matched to 1 nm.

    Parameters
    ----------
    faces : (f, 3, 3) float [m], (x, y, s) in the window's frame (:func:`frame_faces`)

    Returns
    -------
    edges : (k, 2, 3) float [m], endpoints (x, y, s)
    opposite : (k, 2, 3) float [m], the corner opposite the edge in each of its two faces (an
        edge seen with both faces on one side of it is a silhouette); NaN for an edge of one face
        or of more than two
    """
    empty = np.zeros((0, 2, 3))
    if len(faces) == 0:
        return empty, empty
    pts, vid = np.unique(np.round(faces.reshape(-1, 3), 9), axis=0, return_inverse=True)
    vid = vid.reshape(-1, 3)
    vid = vid[(vid[:, 0] != vid[:, 1]) & (vid[:, 1] != vid[:, 2]) & (vid[:, 2] != vid[:, 0])]
    vid = vid[np.unique(np.sort(vid, axis=1), axis=0, return_index=True)[1]]  # a face given twice (both sides) once
    # every face's three edges (lower vertex id first) and the corner opposite each
    a = np.concatenate([vid[:, 0], vid[:, 1], vid[:, 2]])
    b = np.concatenate([vid[:, 1], vid[:, 2], vid[:, 0]])
    o = np.concatenate([vid[:, 2], vid[:, 0], vid[:, 1]])
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    order = np.lexsort((hi, lo))
    lo, hi, o = lo[order], hi[order], o[order]
    start = np.flatnonzero(np.r_[True, (lo[1:] != lo[:-1]) | (hi[1:] != hi[:-1])])
    count = np.diff(np.r_[start, len(lo)])
    e0, e1 = pts[lo[start]], pts[hi[start]]
    two = count == 2
    opp = np.full((len(start), 2, 3), np.nan)
    opp[two, 0] = pts[o[start[two]]]
    opp[two, 1] = pts[o[start[two] + 1]]
    # coplanar pairs on both sides of their edge: one flat surface
    d = e1 - e0
    n1 = np.cross(d, opp[:, 0] - e0)
    n2 = np.cross(d, opp[:, 1] - e0)
    with np.errstate(invalid="ignore"):
        off = np.abs(np.einsum("ij,ij->i", opp[:, 1] - e0, n1)) / np.maximum(np.linalg.norm(n1, axis=1), 1e-300)
        flat = two & (off <= COPLANAR_M) & (np.einsum("ij,ij->i", n1, n2) < 0)
    keep = ~flat
    # edges in the glazing plane that stay out of the glazing's outline (on it included)
    in_plane = keep & (np.abs(e0[:, 2]) <= COPLANAR_M) & (np.abs(e1[:, 2]) <= COPLANAR_M)
    if in_plane.any():
        import shapely

        cand = np.flatnonzero(in_plane)
        inner = shapely.buffer(frame._outline_index()[0], -COPLANAR_M)
        lines = shapely.linestrings(np.stack([e0[cand, :2], e1[cand, :2]], axis=1))
        keep[cand[~shapely.intersects(lines, inner)]] = False
    return np.stack([e0[keep], e1[keep]], axis=1), opp[keep]


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
    and over it are its frame (:func:`frame_faces`), with their corners and edges. Where the model
    says which element a window is and which it is set in (``Window.key``, ``Window.host``: IFC),
    only their faces can be its frame (its own frame, the wall's reveal, a curtain wall's
    mullions): a roof edge or a railing over the glazing is an obstruction the rays find, not a
    frame whose every edge splits the sampling cells."""
    from en17037cli.scene.hosts import host_faces

    opaque_mask = scene.layer != WINDOW
    opaque = scene.triangles[opaque_mask]
    frames = [window_frame(w, i) for i, w in enumerate(room.windows)]
    for f, w in zip(frames, room.windows):
        own = host_faces(scene, w) if w.key is not None else None
        faces = frame_faces(f, scene.vertices, opaque if own is None else scene.triangles[own[opaque_mask[own]]], frame_depth_m)
        f.frame_xys = frame_vertices(faces)
        f.frame_edges, f.frame_edge_opposite = frame_edges(f, faces)
        f.frame_x, f.frame_y = axis_breakpoints(f.frame_edges)
    wof = np.full(len(scene.triangles), -1, dtype=np.int64)
    for f in frames:
        wof[f.face_ids] = f.index
    tris = np.concatenate([w.triangles for w in room.windows])
    tw = np.concatenate([np.full(len(w.triangles), i) for i, w in enumerate(room.windows)])
    return RoomGeometry(frames, wof, tris, tw, room_window_group(room))
