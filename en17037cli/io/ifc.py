"""IFC reader (IFC2X3, IFC4, IFC4X3) through ifcopenshell's geometry iterator.

Every product is tessellated in world coordinates, in metres, on all cores; openings are cut
from their walls. Each product becomes one :class:`~en17037cli.io.mesh.Part` per surface style
of its faces, so the glass and the frame of an IfcWindow are separate parts:

| part attribute | value |
|---|---|
| `class` | the IFC entity: `IfcWindow`, `IfcWall`... |
| `name`, `id` | the product's Name and GlobalId |
| `type` | the Name of its type object (IfcWindowType...), where it has one |
| `storey` | the Name of the IfcBuildingStorey that contains it |
| `material` | the name of the surface style or material of those faces, where the file names one |
| `surface` | `glazing` (transparent parts of windows, doors, curtain walls and plates) or `frame` |

A piece is transparent when its surface style has a transparency of 0.5 or more, or, where the
file gives no transparency, when its style or material is named like glass ("glass", "glazing",
"glas", "verre", "vitrage"). Default layers (the project's rules win, matching any attribute):

| IFC class | layer |
|---|---|
| transparent parts of `IfcWindow`, `IfcDoor`, `IfcCurtainWall`, `IfcPlate` | window |
| opaque parts of windows and doors (frames, mullions), `IfcWall`, `IfcWallStandardCase`, `IfcSlab`, `IfcRoof`, `IfcDoor`, `IfcColumn`, `IfcBeam`, `IfcMember`, `IfcPlate`, `IfcRailing`, `IfcStair`, `IfcStairFlight`, `IfcRamp`, `IfcCovering`, `IfcCurtainWall`, `IfcFooting`, `IfcChimney`, `IfcShadingDevice` | interior |
| `IfcSite` | ground |
| `IfcBuildingElementProxy`, `IfcGeographicElement` | landscape |
| `IfcSpace`, `IfcOpeningElement`, `IfcAnnotation`, `IfcGrid`, `IfcVirtualElement`, furniture (`IfcFurnishingElement`, `IfcFurniture`), MEP (`IfcDistributionElement` and its subtypes: ducts, pipes, fittings, terminals...) | ignore (not tessellated) |
| any other class | interior |

All glazing parts of one IfcWindow (or door, curtain wall, plate) share ``Part.window`` = its
GlobalId: its panes together make one window, named after the product. Glass modelled as thin
solids keeps all its faces here; the scene keeps one surface of each pane.

Spaces (IfcSpace) become :class:`~en17037cli.io.mesh.Space`: the footprint is the union of the
downward faces at the bottom of its body, ``floor_z`` and ``top_z`` its lowest and highest
points, ``windows`` the GlobalIds of the windows its IfcRelSpaceBoundary relations name, ``zones``
the names of the IfcZone and IfcSpatialZone groups it belongs to.

The site (:class:`~en17037cli.io.mesh.Site`): latitude and longitude from IfcSite RefLatitude
and RefLongitude (compound degrees, minutes, seconds, millionths), elevation from RefElevation,
true north from the TrueNorth of the model's geometric context (a direction (x, y) in the project
frame: azimuth clockwise from +Y = atan2(x, y)). Where the file has an IfcMapConversion (IFC4 and
later), every vertex and footprint is placed in the map: E = Eastings + Scale (x a - y b),
N = Northings + Scale (x b + y a), H = OrthogonalHeight + z, with (a, b) the normalised
(XAxisAbscissa, XAxisOrdinate); the CRS is the IfcProjectedCRS Name (``EPSG:nnnn``); true north
turns with the map rotation (the map's grid north is then +Y; the meridian convergence between
grid and true north, under 1 deg in most national grids, is not applied).

References: buildingSMART IFC4 ADD2 TC1, IfcMapConversion (8.18.3.6), IfcSite (5.4.3.4),
IfcGeometricRepresentationContext (8.18.3.4), IfcRelSpaceBoundary (6.1.3.20), IfcZone (5.4.3.5).
"""
from __future__ import annotations

import math
import os
import re
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io import ReadOptions, register
from en17037cli.io.mesh import Mesh, Part, Site, Space

#: Classes whose transparent parts are glazing (``window`` layer).
GLAZED = ("IfcWindow", "IfcDoor", "IfcCurtainWall", "IfcPlate")
#: Classes not tessellated at all.
IGNORED = ("IfcSpace", "IfcOpeningElement", "IfcAnnotation", "IfcGrid", "IfcVirtualElement", "IfcFurnishingElement",
           "IfcDistributionElement")
#: Class -> default layer (subclasses match too, checked with is_a); anything else is interior.
DEFAULT_LAYER = {"IfcSite": "ground", "IfcBuildingElementProxy": "landscape", "IfcGeographicElement": "landscape"}
#: A surface style at least this transparent is glass.
GLASS_TRANSPARENCY = 0.5
#: Style or material names that say glass, where the file gives no transparency.
GLASS_WORDS = ("glass", "glazing", "glas", "verre", "vitrage")


def _open(path: Path):
    try:
        import ifcopenshell
    except ImportError:
        raise InputError(f"{path}: reading IFC needs ifcopenshell: pip install 'en17037cli[ifc]'") from None
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read model file: {exc.strerror}") from None
    if not data[:64].lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"ISO-10303-21"):
        raise InputError(f"{path}: not an IFC file (no ISO-10303-21 header); export the model as IFC (STEP)")
    try:
        f = ifcopenshell.open(str(path))
    except Exception as exc:  # ifcopenshell raises its own error types for broken STEP
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise InputError(f"{path}: cannot read the IFC file ({msg}); re-export it") from None
    if f.schema not in ("IFC2X3", "IFC4", "IFC4X3", "IFC4X3_ADD2"):
        raise InputError(f"{path}: IFC schema {f.schema} is not read; export IFC2X3, IFC4 or IFC4X3")
    check_all_read(path, data, f)
    return f


def check_all_read(path: Path, data: bytes, f) -> None:
    """InputError naming the line where ifcopenshell stopped, when it read fewer instances than the
    file defines: on a broken STEP line it may stop without an error, and a model read in part
    would give a wrong answer, not a failed one."""
    read = len(f.entity_names())
    if read >= data.count(b"\n#"):  # cheap: no more instance lines than instances read
        return
    defined = [(int(m.group(1)), m.start()) for m in re.finditer(rb"(?m)^[ \t]*#(\d+)[ \t]*=", data)]
    if read >= len(defined):
        return
    names = set(f.entity_names())
    k = next(i for i, (sid, _) in enumerate(defined) if sid not in names)
    sid, offset = defined[k]  # the first instance missing: reading stopped on its line
    line = data.count(b"\n", 0, offset) + 1
    raise InputError(f"{path}: broken IFC (STEP) data at line {line} (#{sid}): only {read} of {len(defined)} instances "
                     "could be read; re-export the model or repair that line")


def compound_degrees(v) -> float | None:
    """Degrees of an IfcCompoundPlaneAngleMeasure (deg, min, sec[, millionths]), signs alike."""
    if not v:
        return None
    parts = list(v) + [0] * (4 - len(v))
    return float(parts[0] + parts[1] / 60 + parts[2] / 3600 + parts[3] / 3.6e9)


def _map_conversion(f):
    """(Eastings, Northings, height, a, b, scale, crs name) of the model context's IfcMapConversion, or None."""
    if f.schema == "IFC2X3":
        return None
    convs = f.by_type("IfcMapConversion")
    if not convs:
        return None
    c = convs[0]
    a, b = (c.XAxisAbscissa if c.XAxisAbscissa is not None else 1.0), (c.XAxisOrdinate or 0.0)
    r = math.hypot(a, b) or 1.0
    crs = getattr(c.TargetCRS, "Name", None)
    if crs and crs.upper().replace("EPSG::", "EPSG:").startswith("EPSG:"):
        crs = "EPSG:" + crs.split(":")[-1].strip()
    return (float(c.Eastings), float(c.Northings), float(c.OrthogonalHeight or 0.0), a / r, b / r,
            float(c.Scale if c.Scale is not None else 1.0), crs)


def _apply_map(xyz: np.ndarray, m) -> np.ndarray:
    e, n, h, a, b, s, _ = m
    x, y = xyz[:, 0], xyz[:, 1]
    return np.column_stack([e + s * (x * a - y * b), n + s * (x * b + y * a), h + xyz[:, 2]])


def _site(f, path: Path, m) -> Site | None:
    lat = lon = elev = None
    src = []
    sites = f.by_type("IfcSite")
    if sites:
        s = sites[0]
        lat, lon = compound_degrees(s.RefLatitude), compound_degrees(s.RefLongitude)
        elev = float(s.RefElevation) if s.RefElevation is not None else None
        if lat is not None:
            src.append("latitude and longitude from IfcSite RefLatitude/RefLongitude")
    north = None
    for ctx in f.by_type("IfcGeometricRepresentationContext"):
        if ctx.is_a() == "IfcGeometricRepresentationContext" and ctx.ContextType == "Model" and ctx.TrueNorth is not None:
            x, y = ctx.TrueNorth.DirectionRatios[:2]
            north = math.degrees(math.atan2(x, y)) % 360.0
            src.append("true north from the model context's TrueNorth")
            break
    crs = None
    if m is not None:
        crs = m[6]
        rot = math.degrees(math.atan2(m[4], m[3]))  # the project's x axis, counterclockwise from the map's
        north = None if north is None else (north - rot) % 360.0
        src.append(f"placed by IfcMapConversion in {crs or 'its map CRS'}")
    if lat is None and north is None and crs is None:
        return None
    return Site(latitude=lat, longitude=lon, elevation_m=elev, true_north_deg=north, crs=crs,
                source=f"{path.name}: " + "; ".join(src))


def _glassy(material) -> bool:
    t = getattr(material, "transparency", float("nan"))
    if t == t:  # a number: the style says
        return t >= GLASS_TRANSPARENCY
    name = (getattr(material, "name", "") or "").lower()
    return any(w in name for w in GLASS_WORDS)


def default_layer(product, glazing: bool) -> str:
    """The layer of a product's faces by the table in the module docstring."""
    if glazing and any(product.is_a(c) for c in GLAZED):
        return "window"
    for cls, layer in DEFAULT_LAYER.items():
        if product.is_a(cls):
            return layer
    return "interior"


def _attrs(product, cache: dict) -> dict:
    import ifcopenshell.util.element as ue

    out = {"class": product.is_a(), "name": getattr(product, "Name", None), "id": product.GlobalId}
    t = ue.get_type(product)
    if t is not None and t.Name:
        out["type"] = t.Name
    c = ue.get_container(product)
    while c is not None and not c.is_a("IfcBuildingStorey"):
        c = ue.get_aggregate(c) if not c.is_a("IfcBuilding") else None
    if c is not None and c.Name:
        out["storey"] = c.Name
    return out


def _settings():
    import ifcopenshell.geom

    s = ifcopenshell.geom.settings()
    s.set("use-world-coords", True)
    s.set("apply-default-materials", True)
    return s


def _iterate(f, include=None, exclude=None):
    """(product, vertices (n, 3) [m], faces (m, 3), material ids (m,), materials) of each shape."""
    import ifcopenshell.geom

    it = ifcopenshell.geom.iterator(_settings(), f, max(1, os.cpu_count() or 1), include=include, exclude=exclude)
    if not it.initialize():
        return
    while True:
        shape = it.get()
        g = shape.geometry
        yield (f.by_id(shape.id), np.asarray(g.verts, dtype=np.float64).reshape(-1, 3),
               np.asarray(g.faces, dtype=np.int64).reshape(-1, 3), np.asarray(g.material_ids, dtype=np.int64), g.materials)
        if not it.next():
            break


def _spaces(f, m) -> list[Space]:
    import shapely

    spaces = f.by_type("IfcSpace")
    if not spaces:
        return []
    out = []
    for product, v, faces, _, _ in _iterate(f, include=spaces):  # one shape per space
        if m is not None:
            v = _apply_map(v, m)
        tri = v[faces]
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        norm = np.linalg.norm(n, axis=1)
        z0 = float(v[:, 2].min())
        down = (n[:, 2] < -0.99 * np.maximum(norm, 1e-30)) & np.all(np.abs(tri[..., 2] - z0) < 0.01, axis=1) & (norm > 0)
        plan = shapely.union_all(shapely.make_valid(shapely.polygons(tri[down][..., :2]))) if down.any() else None
        if plan is None or plan.is_empty:
            continue
        poly = max(getattr(plan, "geoms", [plan]), key=lambda g: g.area) if plan.geom_type != "Polygon" else plan
        poly = shapely.orient_polygons(poly) if hasattr(shapely, "orient_polygons") else poly
        windows = tuple(sorted(r.RelatedBuildingElement.GlobalId for r in (getattr(product, "BoundedBy", None) or ())
                               if r.RelatedBuildingElement is not None and any(r.RelatedBuildingElement.is_a(c) for c in GLAZED)))
        zones = tuple(sorted({r.RelatingGroup.Name for r in (getattr(product, "HasAssignments", None) or ())
                              if r.is_a("IfcRelAssignsToGroup") and r.RelatingGroup.is_a() in ("IfcZone", "IfcSpatialZone")
                              and r.RelatingGroup.Name}))
        storey = _attrs(product, {}).get("storey", "")
        agg = getattr(product, "Decomposes", None)
        if not storey and agg:
            parent = agg[0].RelatingObject
            storey = parent.Name if parent.is_a("IfcBuildingStorey") else ""
        out.append(Space(id=product.GlobalId, name=product.Name or "", long_name=getattr(product, "LongName", None) or "",
                         storey=storey, footprint=np.asarray(poly.exterior.coords)[:-1], floor_z=z0,
                         top_z=float(v[:, 2].max()), windows=windows, zones=zones,
                         holes=tuple(np.asarray(r.coords)[:-1] for r in poly.interiors)))
    # the geometry iterator hands shapes over in no fixed order: floors up, then by name, for a stable report
    return sorted(out, key=lambda s: (round(s.floor_z, 3), s.name, s.long_name, s.id))


@register(".ifc")
def read_ifc(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read an IFC file: products as parts by class and style, spaces, site (see the module docstring)."""
    options = options or ReadOptions()
    f = _open(path)
    m = _map_conversion(f)
    excluded = set(options.exclude)
    verts, tris, pidx, parts = [], [], [], []
    offset = 0
    cache: dict = {}
    untransparent = []
    for product, v, faces, mids, materials in _iterate(f, exclude=list(IGNORED)):  # one pass per product
        if product is None or product.GlobalId in excluded or len(faces) == 0:
            continue
        if m is not None:
            v = _apply_map(v, m)
        base = _attrs(product, cache)
        glazed_class = any(product.is_a(c) for c in GLAZED)
        keys = np.unique(mids)
        seen_glass = False
        for k in keys:  # one part per surface style of the product
            mat = materials[int(k)] if 0 <= int(k) < len(materials) else None
            glass = glazed_class and mat is not None and _glassy(mat)
            seen_glass |= glass
            attrs = dict(base)
            if glazed_class:
                attrs["surface"] = "glazing" if glass else "frame"
            mname = getattr(mat, "name", None) if mat is not None else None
            if mname and not mname.startswith(("IfcSurfaceStyle", "DefaultMaterial")) and mname != base["class"]:
                attrs["material"] = mname
            parts.append(Part(attrs, layer=default_layer(product, glass), window=product.GlobalId if glass else None))
            sel = mids == k
            tris.append(faces[sel] + offset)
            pidx.append(np.full(int(sel.sum()), len(parts) - 1))
        if product.is_a("IfcWindow") and not seen_glass:
            untransparent.append(product.Name or product.GlobalId)
        verts.append(v)
        offset += len(v)
    if not tris:
        raise InputError(f"{path}: no product with geometry in the IFC file; export the model with its 3D geometry")
    warnings = []
    if untransparent:
        warnings.append(f"{path.name}: {len(untransparent)} IfcWindow(s) with no transparent part (no surface style with "
                        f"transparency >= {GLASS_TRANSPARENCY}, no material named like glass), taken as opaque: "
                        f"{', '.join(untransparent[:5])}")
    notes = [f"{path.name}: placed by its IfcMapConversion ({m[6] or 'map CRS'})"] if m is not None else []
    return Mesh(np.concatenate(verts), np.concatenate(tris), np.concatenate(pidx), parts, warnings, notes,
                units="m", up_axis="z", site=_site(f, path, m), spaces=_spaces(f, m))
