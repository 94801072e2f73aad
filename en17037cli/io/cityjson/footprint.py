"""Using a read city model around the checked building: which objects stand on its footprint, and dropping them.

A context tile usually holds the checked building too; :func:`footprint_overlap` finds its
objects from the building's footprint, :func:`without_objects` removes their faces.
"""
from __future__ import annotations

from itertools import pairwise

import numpy as np

from en17037cli.io.cityjson.semantics import BUILDING_CLASSES
from en17037cli.io.mesh import Mesh


def footprint_overlap(mesh: Mesh, footprint, min_share: float = 0.5, classes=BUILDING_CLASSES) -> list[str]:
    """Ids of the building objects standing on ``footprint``: to drop the checked building from a context tile.

    An object is one CityJSON id among the parts whose ``class`` is in ``classes`` (Building,
    BuildingPart and what belongs to a building by default). Its plan (xy projection of all its
    triangles, unioned) overlaps ``footprint`` by more than ``min_share`` of its own plan area.

    Parameters
    ----------
    mesh : a Mesh from :func:`~en17037cli.io.cityjson.read_cityjson` (parts with ``class`` and ``id``)
    footprint : shapely Polygon or MultiPolygon [m], in the mesh's x, y
    min_share : fraction of the object's own plan area, 0..1
    classes : CityObject types considered

    Returns
    -------
    list of str
        Object ids in the order of ``mesh.parts``.
    """
    import shapely

    ids: dict = {}
    part_obj = np.full(len(mesh.parts), -1, dtype=np.int64)
    for i, p in enumerate(mesh.parts):
        if p.attrs.get("class") in classes and "id" in p.attrs:
            part_obj[i] = ids.setdefault(p.attrs["id"], len(ids))
    if not ids or footprint is None or footprint.is_empty or len(mesh.triangles) == 0:
        return []
    tri_obj = part_obj[mesh.part]
    origin = np.array(shapely.centroid(footprint).coords[0])
    fp = shapely.transform(footprint, lambda xy: xy - origin)
    xmin, ymin, xmax, ymax = shapely.bounds(fp)
    xy = mesh.vertices[mesh.triangles][:, :, :2] - origin  # (m, 3, 2)
    lo, hi = xy.min(axis=1), xy.max(axis=1)
    e1, e2 = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
    plan_area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    near = (tri_obj >= 0) & (lo[:, 0] <= xmax) & (hi[:, 0] >= xmin) & (lo[:, 1] <= ymax) & (hi[:, 1] >= ymin)
    candidates = np.unique(tri_obj[near])
    if len(candidates) == 0:
        return []
    sel = np.isin(tri_obj, candidates) & (plan_area > 1e-9)
    rows = np.flatnonzero(sel)
    if len(rows) == 0:  # the candidates' triangles are all flat in plan (walls only, or degenerate)
        return []
    rows = rows[np.argsort(tri_obj[rows], kind="stable")]
    polys = shapely.polygons(np.concatenate([xy[rows], xy[rows, :1]], axis=1))
    objs = tri_obj[rows]
    cut = np.flatnonzero(np.r_[True, objs[1:] != objs[:-1], True])
    plans = [shapely.union_all(polys[a:b]) for a, b in pairwise(cut)]
    plans = np.array(plans, dtype=object)
    own = shapely.area(plans)
    inter = shapely.area(shapely.intersection(plans, fp))
    hit = set(objs[cut[:-1]][(own > 0) & (inter > min_share * own)].tolist())
    return [oid for oid, k in ids.items() if k in hit]


def without_objects(mesh: Mesh, ids) -> Mesh:
    """The mesh without the faces of the objects (parts) whose ``id`` is in ``ids``; vertices stay as they are.

    Parameters
    ----------
    mesh : Mesh with parts carrying ``id``
    ids : iterable of CityJSON object ids

    Returns
    -------
    Mesh
        Same vertices, units, site, notes and warnings; the remaining triangles in their order,
        the remaining parts in their order (part indices renumbered).
    """
    drop = set(ids)
    gone = np.array([p.attrs.get("id") in drop for p in mesh.parts], dtype=bool)
    keep_tri = ~gone[mesh.part] if len(mesh.parts) else np.ones(len(mesh.triangles), dtype=bool)
    pmap = np.cumsum(~gone) - 1
    parts = [p for p, g in zip(mesh.parts, gone) if not g]
    return Mesh(mesh.vertices, mesh.triangles[keep_tri], pmap[mesh.part[keep_tri]], parts, list(mesh.warnings), list(mesh.notes),
                units=mesh.units, up_axis=mesh.up_axis, site=mesh.site, spaces=list(mesh.spaces))
