"""Which faces of an IFC element are its glass, and which element holds its opening.

The glazing of a window, door, curtain-wall plate is told apart from its frame by the file's own
semantics, in this order:

1. a surface style with a transparency of :data:`GLASS_TRANSPARENCY` or more (IfcSurfaceStyleRendering);
2. where no style says (none, or ifcopenshell's default material), a style or material named like
   glass (:data:`GLASS_WORDS`);
3. an IfcWindow with neither: its pane from its geometry (:func:`pane_faces`): the thin plates
   in the window's own plane (:func:`~en17037cli.io.ifc_windows.window_plane`; its host only
   confirms), never faces whose style says they are nearly opaque
   (a transparency below :data:`OPAQUE_TRANSPARENCY`: an opal or spandrel panel that the file
   calls a window is a panel, not glass);
4. an IfcPlate of an IfcCurtainWall with no style of its own: glass (curtain-wall infill).

An IfcDoor with no transparent part is an opaque door. IfcWindowType / IfcDoorType panel
properties describe how panels open and how deep frames are, not which faces are glass: not used.

The host of a filling comes from IfcRelFillsElement -> IfcOpeningElement -> IfcRelVoidsElement
(the wall, slab or roof the opening is cut in); a curtain wall's plates and members belong to it by
IfcRelAggregates (or IfcRelNests). References: buildingSMART IFC4 ADD2 TC1, IfcRelFillsElement
(4.5.3.10), IfcRelVoidsElement (4.5.3.22), IfcRelAggregates (4.1.3.1), IfcSurfaceStyleShading
Transparency (8.9.3.13: 0 opaque, 1 fully transparent).
"""
from __future__ import annotations

import re

import numpy as np

from en17037cli.geometry import triangle_normals
from en17037cli.geometry.topology import pieces

#: Classes whose transparent parts are glazing (``window`` layer).
GLAZED = ("IfcWindow", "IfcDoor", "IfcCurtainWall", "IfcPlate")
#: A surface style at least this transparent is glass.
GLASS_TRANSPARENCY = 0.5
#: A surface style this transparent or less (but set: above 0) says its faces are opaque, so no
#: pane is looked for in them: an opal polycarbonate panel (0.01), a spandrel. Between this and
#: :data:`GLASS_TRANSPARENCY` (tinted glass written at 0.3, say) the geometry still decides.
OPAQUE_TRANSPARENCY = 0.1
#: Style or material names that say glass, where the file gives no transparency.
GLASS_WORDS = ("glass", "glazing", "glas", "verre", "vitrage", "vetro", "vidrio", "glazed")
#: A pane from geometry: a piece whose faces within this angle of the wall's plane ... [deg]
PANE_PARALLEL_DEG = 10.0
#: ... make at least this share of its area (a plate, not a frame bar) ...
PANE_PARALLEL_SHARE = 0.75
#: ... no thicker than this across the wall [m] ...
PANE_MAX_THICKNESS_M = 0.1
#: ... and filling at least this share of its outline's convex hull (a pane, not a frame ring).
PANE_MIN_FILL = 0.8
#: A level of faces parallel to the wall inside a frame solid is glass when it covers at least
#: this share of the window's outline ...
PANE_MIN_SHARE = 0.25
#: ... its faces within this distance of one another across the wall [m].
PANE_LEVEL_M = 0.002


def is_default_material(material, product) -> bool:
    """Whether ifcopenshell made this material up (``apply-default-materials``): named after the
    product's class (``IfcWindow``, transparency 0.3) or ``DefaultMaterial``: the file says nothing."""
    name = getattr(material, "name", "") or ""
    if name.startswith("DefaultMaterial"):
        return True
    return bool(re.fullmatch(r"Ifc[A-Za-z]+", name)) and product.is_a(name)


def glass_by_style(material) -> bool | None:
    """True/False where the style says (transparency, else a glass name), None where it says neither."""
    t = getattr(material, "transparency", float("nan"))
    if t == t and t > 0:  # a number the file set: the style says
        return t >= GLASS_TRANSPARENCY
    name = (getattr(material, "name", "") or "").lower()
    if any(w in name for w in GLASS_WORDS):
        return True
    return False if t == t else None


def opaque_by_style(material) -> bool:
    """Whether a style says plainly that its faces let no light through: a transparency set above
    0 and below :data:`OPAQUE_TRANSPARENCY` (0 itself is what many exporters write for 'not
    given'), and no glass name."""
    t = getattr(material, "transparency", float("nan"))
    name = (getattr(material, "name", "") or "").lower()
    return t == t and 0 < t < OPAQUE_TRANSPARENCY and not any(w in name for w in GLASS_WORDS)


def hosts(f) -> dict[str, tuple[str, ...]]:
    """Filling GlobalId -> GlobalIds of the elements its opening is cut in."""
    out: dict[str, tuple[str, ...]] = {}
    for rel in f.by_type("IfcRelFillsElement"):
        op, el = rel.RelatingOpeningElement, rel.RelatedBuildingElement
        if op is None or el is None:
            continue
        walls = tuple(v.RelatingBuildingElement.GlobalId for v in (getattr(op, "VoidsElements", None) or ())
                      if v.RelatingBuildingElement is not None)
        if walls:
            out[el.GlobalId] = tuple(sorted(set(out.get(el.GlobalId, ()) + walls)))
    return out


def assemblies(f) -> dict[str, tuple[str, str]]:
    """Element GlobalId -> (GlobalId, class) of the element it is a piece of (IfcRelAggregates,
    IfcRelNests between elements: a curtain wall's plates, a roof's slabs, a stair's flights)."""
    out: dict[str, tuple[str, str]] = {}
    for kind in ("IfcRelAggregates", "IfcRelNests"):
        try:
            rels = f.by_type(kind)
        except RuntimeError:  # not in this schema
            continue
        for rel in rels:
            whole = rel.RelatingObject
            if whole is None or not whole.is_a("IfcElement"):
                continue
            for part in rel.RelatedObjects or ():
                if part.is_a("IfcElement"):
                    out.setdefault(part.GlobalId, (whole.GlobalId, whole.is_a()))
    return out


def principal_normal(tri: np.ndarray) -> np.ndarray:
    """(3,) unit normal (either sign) of the plane that most of the triangles' area lies in: faces
    are binned by direction (sign folded, 0.02 steps per component) and the bin of most area wins
    (a wall's faces, not its chamfered ends; an eigenvector of the normal tensor would tilt)."""
    n, a = triangle_normals(tri)
    lead = np.argmax(np.abs(n), axis=1)
    n = n * np.where(n[np.arange(len(n)), lead] < 0, -1.0, 1.0)[:, None]
    keys, inverse = np.unique(np.round(n / 0.02).astype(np.int64), axis=0, return_inverse=True)
    best = int(np.argmax(np.bincount(inverse.reshape(-1), a, len(keys))))
    m = (n[inverse.reshape(-1) == best] * a[inverse.reshape(-1) == best, None]).sum(axis=0)
    return m / np.linalg.norm(m)


def _fill(tri: np.ndarray, u: np.ndarray, w: np.ndarray) -> tuple[float, float, int]:
    """(area of the union of the triangles projected on (u, w), area of its convex hull, holes) [m2]."""
    import shapely

    proj = np.stack([tri @ u, tri @ w], axis=-1)
    union = shapely.union_all(shapely.make_valid(shapely.polygons(proj))).buffer(1e-6).buffer(-1e-6)
    polys = [g for g in getattr(union, "geoms", [union]) if g.geom_type == "Polygon"]
    return float(union.area), float(union.convex_hull.area), sum(len(g.interiors) for g in polys)


def pane_faces(vertices: np.ndarray, faces: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """(m,) bool: the faces of a window's geometry that are its panes, where nothing else says.

    Looked for in the window's plane (``normal``: the wall's), piece by piece (edge-connected
    faces):

    * a piece that is a thin plate: at least :data:`PANE_PARALLEL_SHARE` of its area in faces within
      :data:`PANE_PARALLEL_DEG` of the plane, at most :data:`PANE_MAX_THICKNESS_M` across, its
      outline filled (:data:`PANE_MIN_FILL` of its convex hull, no hole): a glass solid or surface
      (a frame is a ring, a bar mostly sides);
    * else, in a piece that is frame and glass in one solid, each level of faces parallel to the
      plane whose outline is filled and at least :data:`PANE_MIN_SHARE` of the window's own
      outline: the glass's face inside the frame (a skylight modelled as one solid).

    All False where neither is found.

    Parameters
    ----------
    vertices : (n, 3) float [m]; faces : (m, 3) int
    normal : (3,) unit normal of the wall the window sits in
    """
    tri = vertices[faces]
    n, a = triangle_normals(tri)
    label = pieces(vertices, faces)
    d = np.asarray(normal, float) / np.linalg.norm(normal)
    parallel = np.abs(n @ d) >= np.cos(np.radians(PANE_PARALLEL_DEG))
    u = np.cross(d, [0.0, 0.0, 1.0] if abs(d[2]) < 0.9 else [1.0, 0.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(d, u)
    _, whole, _ = _fill(tri, u, w)
    offset = tri.mean(axis=1) @ d
    out = np.zeros(len(faces), bool)
    for k in np.unique(label):  # a window has a handful of pieces
        s = label == k
        area = a[s].sum()
        if area <= 0 or not (s & parallel).any():
            continue
        pts = tri[s].reshape(-1, 3)
        covered, hull, holes = _fill(tri[s & parallel], u, w)
        if (a[s & parallel].sum() >= PANE_PARALLEL_SHARE * area and np.ptp(pts @ d) <= PANE_MAX_THICKNESS_M
                and not holes and covered >= PANE_MIN_FILL * hull):
            out |= s
            continue
        idx = np.flatnonzero(s & parallel)
        order = idx[np.argsort(offset[idx])]
        cuts = np.flatnonzero(np.diff(offset[order]) > PANE_LEVEL_M) + 1
        for level in np.split(order, cuts):  # levels of faces parallel to the wall in one solid
            covered, hull, holes = _fill(tri[level], u, w)
            if not holes and covered >= PANE_MIN_FILL * hull and covered >= PANE_MIN_SHARE * whole:
                out[level] = True
    return out


#: The holes in a window's frames are its panes (where the file models no glass) when together they
#: make at least this share of the window's outline (a sash's opening, not gaps between members) ...
OPENING_MIN_SHARE = 0.2
#: ... each at least this share (the quarters of a round window's glazing bars count, slits do not).
OPENING_MIN_PIECE = 0.02


def frame_opening_panes(vertices: np.ndarray, faces: np.ndarray, normal: np.ndarray) -> np.ndarray | None:
    """(k, 3, 3) [m]: panes for a window modelled as frames only (no glass at all: Autodesk
    Architectural Desktop's IFC2x exports draw a frame and a sash, each a ring): the holes of the
    window's outline projected on the wall's plane (each at least :data:`OPENING_MIN_PIECE` of the
    outline, together at least :data:`OPENING_MIN_SHARE`), triangulated (mapbox-earcut) in the plane through the middle of the window's depth.
    None where the outline has no such hole.

    Parameters
    ----------
    vertices : (n, 3) float [m]; faces : (m, 3) int; normal : (3,) unit normal of the wall
    """
    import mapbox_earcut
    import shapely

    tri = vertices[faces]
    d = np.asarray(normal, float) / np.linalg.norm(normal)
    u = np.cross(d, [0.0, 0.0, 1.0] if abs(d[2]) < 0.9 else [1.0, 0.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(d, u)
    proj = np.stack([tri @ u, tri @ w], axis=-1)
    # pieces that touch within a micron made one; mitred, so the holes keep their corners
    union = shapely.union_all(shapely.make_valid(shapely.polygons(proj))).buffer(1e-6, join_style="mitre").buffer(
        -1e-6, join_style="mitre")
    polys = [g for g in getattr(union, "geoms", [union]) if g.geom_type == "Polygon"]
    whole = sum(shapely.Polygon(g.exterior).area for g in polys)
    rings = [r for g in polys for r in g.interiors if shapely.Polygon(r).area >= OPENING_MIN_PIECE * whole]
    if sum(shapely.Polygon(r).area for r in rings) < OPENING_MIN_SHARE * whole:
        return None
    holes = [np.asarray(shapely.Polygon(r).simplify(1e-6).exterior.coords)[:-1] for r in rings]  # no collinear points
    depth = tri.reshape(-1, 3) @ d
    mid = 0.5 * (depth.min() + depth.max())
    out = []
    for ring in holes:  # a window has one or a few openings
        idx = mapbox_earcut.triangulate_float64(ring, np.array([len(ring)], np.uint32)).reshape(-1, 3)
        xy = ring[idx]
        a2 = (xy[:, 1, 0] - xy[:, 0, 0]) * (xy[:, 2, 1] - xy[:, 0, 1]) - (xy[:, 1, 1] - xy[:, 0, 1]) * (xy[:, 2, 0] - xy[:, 0, 0])
        xy = xy[np.abs(a2) > 1e-12]  # slivers of nearly collinear points add nothing
        out.append(xy[..., :1] * u + xy[..., 1:] * w + mid * d)
    return np.concatenate(out)
