"""IfcSpace -> :class:`~en17037cli.io.mesh.Space`: footprint, heights, body, space boundaries, zones.

The footprint is the union of the downward faces at the bottom of the space's body; ``floor_z`` and
``top_z`` its lowest and highest points; ``body`` its triangles (windows are matched to spaces
against it: a sloped ceiling, a roof light over a stair). ``windows`` are the GlobalIds of the
windows, doors and plates its IfcRelSpaceBoundary relations name (often incomplete: the scene
matches windows to spaces by geometry and uses these to confirm). A space for which ifcopenshell
gives no geometry, or whose body has no floor, is still returned, with ``problem`` saying why.

References: buildingSMART IFC4 ADD2 TC1, IfcSpace (5.4.3.9), IfcRelSpaceBoundary (6.1.3.20),
IfcZone (5.4.3.5).
"""
from __future__ import annotations

import numpy as np

from en17037cli.io.ifc_glazing import GLAZED
from en17037cli.io.mesh import Space


def storey_of(product) -> str:
    """Name of the IfcBuildingStorey that contains ``product`` (or the one it is aggregated into), else ""."""
    import ifcopenshell.util.element as ue

    c = ue.get_container(product)
    if c is None:
        agg = getattr(product, "Decomposes", None)
        c = agg[0].RelatingObject if agg else None
    while c is not None and not c.is_a("IfcBuildingStorey"):
        c = ue.get_aggregate(c) if not c.is_a("IfcBuilding") else None
    return (c.Name or "") if c is not None else ""


def space_footprint(tri: np.ndarray):
    """(outer ring (k, 2), holes) [m] of the downward faces within 1 cm of the body's bottom, or None."""
    import shapely

    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    norm = np.linalg.norm(n, axis=1)
    z0 = float(tri[..., 2].min())
    down = (n[:, 2] < -0.99 * np.maximum(norm, 1e-30)) & np.all(np.abs(tri[..., 2] - z0) < 0.01, axis=1) & (norm > 0)
    plan = shapely.union_all(shapely.make_valid(shapely.polygons(tri[down][..., :2]))) if down.any() else None
    if plan is None or plan.is_empty:
        return None
    polys = [g for g in getattr(plan, "geoms", [plan]) if g.geom_type == "Polygon"]
    if not polys:
        return None
    poly = max(polys, key=lambda g: g.area)
    poly = shapely.orient_polygons(poly) if hasattr(shapely, "orient_polygons") else poly
    return np.asarray(poly.exterior.coords)[:-1], tuple(np.asarray(r.coords)[:-1] for r in poly.interiors)


def boundary_elements(product) -> tuple[str, ...]:
    """GlobalIds of the windows, doors and plates the space's IfcRelSpaceBoundary relations name."""
    return tuple(sorted({r.RelatedBuildingElement.GlobalId for r in (getattr(product, "BoundedBy", None) or ())
                         if r.RelatedBuildingElement is not None and any(r.RelatedBuildingElement.is_a(c) for c in GLAZED)}))


def zones_of(product) -> tuple[str, ...]:
    return tuple(sorted({r.RelatingGroup.Name for r in (getattr(product, "HasAssignments", None) or ())
                         if r.is_a("IfcRelAssignsToGroup") and r.RelatingGroup.is_a() in ("IfcZone", "IfcSpatialZone")
                         and r.RelatingGroup.Name}))


def space_usage(product) -> tuple[tuple[str, str], ...]:
    """What the file says ``product`` (an IfcSpace) is used for (:attr:`Space.usage`): its LongName,
    Name, ObjectType, its IfcSpaceType's Name and the classification references associated with it or
    its type (IfcRelAssociatesClassification: Identification, or ItemReference in IFC2X3, and Name),
    each with its IfcClassification's Name."""
    import ifcopenshell.util.classification as uc
    import ifcopenshell.util.element as ue

    out = [(k, v) for k, v in (("LongName", getattr(product, "LongName", None)), ("Name", product.Name),
                               ("ObjectType", getattr(product, "ObjectType", None))) if v]
    kind = ue.get_type(product)
    if kind is not None and kind.Name:
        out.append(("IfcSpaceType", kind.Name))
    refs = []
    for ref in uc.get_references(product):
        if not ref.is_a("IfcClassificationReference"):
            continue
        system = uc.get_classification(ref)
        code = getattr(ref, "Identification", None) or getattr(ref, "ItemReference", None) or ""
        text = " ".join(x for x in (code, ref.Name or "") if x)
        if text:
            refs.append((f"classification '{(system.Name if system is not None else '') or '?'}'", text))
    return tuple(out + sorted(refs))  # references come as a set: sorted, for a stable report


def read_spaces(f, shapes, place) -> list[Space]:
    """Every IfcSpace of ``f`` as a Space.

    Parameters
    ----------
    shapes : iterable of (product, vertices (n, 3) [m], faces (m, 3)) from the geometry iterator
    place : vertices -> vertices, the map placement (identity without an IfcMapConversion)
    """
    spaces = f.by_type("IfcSpace")
    if not spaces:
        return []
    geometry = {}
    for product, v, faces in shapes:  # one shape per space that has one
        if len(faces):
            geometry[product.id()] = place(v)[faces]
    out = []
    for product in spaces:
        common = dict(id=product.GlobalId, name=product.Name or "", long_name=getattr(product, "LongName", None) or "",
                      storey=storey_of(product), windows=boundary_elements(product), zones=zones_of(product),
                      usage=space_usage(product))
        tri = geometry.get(product.id())
        fp = None if tri is None else space_footprint(tri)
        if fp is None:
            why = ("ifcopenshell gives it no geometry" if tri is None else "its body has no downward face at its bottom (no floor)")
            z = (0.0, 0.0) if tri is None else (float(tri[..., 2].min()), float(tri[..., 2].max()))
            out.append(Space(**common, footprint=np.zeros((0, 2)), floor_z=z[0], top_z=z[1], body=tri, problem=why))
            continue
        out.append(Space(**common, footprint=fp[0], holes=fp[1], floor_z=float(tri[..., 2].min()),
                         top_z=float(tri[..., 2].max()), body=tri))
    # the geometry iterator hands shapes over in no fixed order: floors up, then by name, for a stable report
    return sorted(out, key=lambda s: (round(s.floor_z, 3), s.name, s.long_name, s.id))
