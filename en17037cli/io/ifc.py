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

Which faces are glass is decided by the file's own semantics (:mod:`~en17037cli.io.ifc_glazing`:
transparent styles, glass names, else the thin panes of an IfcWindow's geometry, the plates of a
curtain wall). Each part also carries ``Part.host`` (the element its opening is cut in:
IfcRelFillsElement -> IfcOpeningElement -> IfcRelVoidsElement; a plate's curtain wall) and
``Part.assembly`` (IfcRelAggregates). Default layers (the project's rules win, matching any
attribute):

| IFC class | layer |
|---|---|
| transparent parts of `IfcWindow`, `IfcDoor`, `IfcCurtainWall`, `IfcPlate` | window |
| opaque parts of windows and doors (frames, mullions), `IfcWall`, `IfcWallStandardCase`, `IfcSlab`, `IfcRoof`, `IfcDoor`, `IfcColumn`, `IfcBeam`, `IfcMember`, `IfcPlate`, `IfcRailing`, `IfcStair`, `IfcStairFlight`, `IfcRamp`, `IfcCovering`, `IfcCurtainWall`, `IfcFooting`, `IfcChimney`, `IfcShadingDevice` | interior |
| `IfcSite` | ground |
| `IfcBuildingElementProxy`, `IfcGeographicElement` | landscape |
| `IfcSpace`, `IfcOpeningElement`, `IfcSpatialZone`, `IfcAnnotation`, `IfcGrid`, `IfcVirtualElement`, furniture (`IfcFurnishingElement`, `IfcFurniture`), MEP (`IfcDistributionElement` and its subtypes: ducts, pipes, fittings, terminals...) | ignore (not tessellated) |
| any other class | interior |

All glazing parts of one IfcWindow (or door, curtain wall, plate) share ``Part.window`` = its
GlobalId: its panes together make one window, named after the product. Glass modelled as thin
solids keeps all its faces here; the scene keeps one surface of each pane.

Spaces: :mod:`~en17037cli.io.ifc_spaces`; site, north and map placement:
:mod:`~en17037cli.io.ifc_site`; the STEP text's quirks: :mod:`~en17037cli.io.ifc_step`. Elements
the geometry iterator cannot tessellate are named in a warning (class, Name, GlobalId and
ifcopenshell's error). See docs/bim.md.

References: buildingSMART IFC4 ADD2 TC1, IfcMapConversion (8.18.3.6), IfcSite (5.4.3.4),
IfcGeometricRepresentationContext (8.18.3.4), IfcRelSpaceBoundary (6.1.3.20), IfcZone (5.4.3.5).
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.ifc_georef import map_conversion
from en17037cli.io.ifc_glazing import (
    GLASS_TRANSPARENCY,
    GLAZED,
    OPAQUE_TRANSPARENCY,
    assemblies,
    glass_by_style,
    hosts,
    is_default_material,
    opaque_by_style,
)
from en17037cli.io.ifc_site import site_of
from en17037cli.io.ifc_spaces import read_spaces, storey_of
from en17037cli.io.ifc_step import open_ifc
from en17037cli.io.ifc_windows import (
    PANE_MIN_OUTLINE_SHARE,
    host_normal,
    openings_of,
    overall_size,
    panes_from_geometry,
    panes_of_bare_windows,
    placement_axes,
    window_plane,
)
from en17037cli.io.mesh import Mesh, Part
from en17037cli.io.registry import ReadOptions, register

#: Classes not tessellated at all.
#: ifcopenshell's geometry kernel: CGAL for what it can do (planar extrusions and their openings,
#: most of a building), Open CASCADE where it cannot (curved or failing shapes). On the 14 MB Revit
#: 2019 office of ../shared (FM_ARC_DigitalHub.ifc) it meshes every shape in 10.7 s of CPU against
#: 61.6 s for Open CASCADE alone, with 139,150 triangles instead of 332,446 (the planar faces
#: triangulated without the extra vertices of Open CASCADE's mesher); the real-model tests hold
#: the windows, rooms and sunlight hours to what they were. Spaces stay with Open CASCADE alone: CGAL
#: meshed the Duplex's two hallways (an IfcSpace with a clipping) without the downward face at their
#: bottom, so they had no floor.
GEOMETRY_LIBRARY = "hybrid-cgal-simple-opencascade"
IGNORED = ("IfcSpace", "IfcOpeningElement", "IfcAnnotation", "IfcGrid", "IfcVirtualElement", "IfcFurnishingElement",
           "IfcDistributionElement")
#: Class -> default layer (subclasses match too, checked with is_a); anything else is interior.
DEFAULT_LAYER = {"IfcSite": "ground", "IfcBuildingElementProxy": "landscape", "IfcGeographicElement": "landscape"}
#: Elements without geometry whose ifcopenshell error is looked up (one shape each) and named.
MAX_GEOMETRY_ERRORS = 20


def default_layer(product, glazing: bool) -> str:
    """The layer of a product's faces by the table in the module docstring."""
    if glazing and any(product.is_a(c) for c in GLAZED):
        return "window"
    for cls, layer in DEFAULT_LAYER.items():
        if product.is_a(cls):
            return layer
    return "interior"


def label(product) -> str:
    """How messages name an element: ``IfcWindow 'Name' (GlobalId)``."""
    name = getattr(product, "Name", None)
    return f"{product.is_a()} '{name}' ({product.GlobalId})" if name else f"{product.is_a()} ({product.GlobalId})"


def _attrs(product) -> dict:
    import ifcopenshell.util.element as ue

    out = {"class": product.is_a(), "name": getattr(product, "Name", None), "id": product.GlobalId}
    t = ue.get_type(product)
    if t is not None and t.Name:
        out["type"] = t.Name
    storey = storey_of(product)
    if storey:
        out["storey"] = storey
    return out


def _settings():
    import ifcopenshell.geom

    s = ifcopenshell.geom.settings()
    s.set("use-world-coords", True)
    s.set("apply-default-materials", True)
    return s


def _iterate(f, include=None, exclude=None, library: str = "opencascade"):
    """(product, vertices (n, 3) [m], faces (m, 3), material ids (m,), materials) of each shape."""
    import ifcopenshell.geom

    it = ifcopenshell.geom.iterator(_settings(), f, max(1, os.cpu_count() or 1), include=include, exclude=exclude,
                                    geometry_library=library)
    if not it.initialize():
        return
    while True:
        shape = it.get()
        g = shape.geometry
        yield (f.by_id(shape.id), np.asarray(g.verts, dtype=np.float64).reshape(-1, 3),
               np.asarray(g.faces, dtype=np.int64).reshape(-1, 3), np.asarray(g.material_ids, dtype=np.int64), g.materials)
        if not it.next():
            break


def without_geometry(f, read: set[int], excluded: set[str]) -> list[tuple[object, str]]:
    """(product, why) of the products that have a representation but no shape from the geometry
    iterator (which leaves them out silently): ifcopenshell's own error for each, where it gives one."""
    import ifcopenshell.geom

    out = []
    for p in f.by_type("IfcProduct"):
        if p.id() in read or p.GlobalId in excluded or not getattr(p, "Representation", None):
            continue
        if any(p.is_a(c) for c in IGNORED) or (p.is_a("IfcSpatialStructureElement") and not p.is_a("IfcSite")) \
                or (f.schema != "IFC2X3" and p.is_a("IfcSpatialZone")):
            continue
        why = "no body geometry"
        if len(out) < MAX_GEOMETRY_ERRORS:
            try:
                shape = ifcopenshell.geom.create_shape(_settings(), p)
                if len(shape.geometry.faces) == 0:
                    why = "its body geometry has no faces"
            except Exception as exc:  # ifcopenshell's error text, for the message
                why = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        out.append((p, why))
    return out


def _in_schema(f, cls: str) -> bool:
    import ifcopenshell.ifcopenshell_wrapper as wrapper

    try:
        wrapper.schema_by_name(f.schema).declaration_by_name(cls)
    except Exception:  # not an entity of this schema
        return False
    return True


class _Builder:
    """The parts of a model, product by product, and what the reader says about them."""

    def __init__(self, f, path: Path, place=None):
        import ifcopenshell.util.unit as ifc_unit

        self.path, self.place = path, place or (lambda v: v)
        self.unit_m = float(ifc_unit.calculate_unit_scale(f))
        self.host_of, self.assembly_of = hosts(f), assemblies(f)
        self.members: dict[str, list[str]] = {}  # an assembly's pieces: a roof's slabs hold its skylights
        for part, (whole, _) in self.assembly_of.items():
            self.members.setdefault(whole, []).append(part)
        self.verts: list = []
        self.tris: list = []
        self.pidx: list = []
        self.parts: list[Part] = []
        self.offset = 0
        self.panes_from_geometry: list[str] = []
        self.panes_in_openings: list[str] = []
        self.plates_as_glass: list[str] = []
        self.left_out: list[tuple[str, str]] = []
        self.planes_not_hosts: list[str] = []  # windows whose host's faces lie in another plane than their own
        self.panes_of_openings: list[str] = []  # windows with no geometry: a pane from their opening
        self.bare: list[tuple[object, str]] = []  # windows with no geometry and no opening to stand for them

    def add(self, product, v, faces, mids, materials, by_id) -> None:
        """One product's faces as parts: one per surface style, or glazing and frame where the
        glass comes from its geometry (see :mod:`~en17037cli.io.ifc_glazing`)."""
        base = _attrs(product)
        gid = product.GlobalId
        glazed_class = any(product.is_a(c) for c in GLAZED)
        asm = self.assembly_of.get(gid)
        host = self.host_of.get(gid, ())
        key = gid
        if asm is not None and asm[1] in ("IfcWindow", "IfcDoor"):  # a pane or member of a window assembly
            key, host = asm[0], host or self.host_of.get(asm[0], ())
        if not host and asm is not None and asm[1] == "IfcCurtainWall":
            host = (asm[0],)  # a curtain wall's plate: the curtain wall holds it
        keys = [int(k) for k in np.unique(mids)]
        mats = {k: materials[k] if 0 <= k < len(materials) else None for k in keys}
        says = {k: None if m is None or is_default_material(m, product) else glass_by_style(m) for k, m in mats.items()}
        glass = np.zeros(len(faces), bool)
        by_face = True
        if glazed_class and any(says.values()):
            glass = np.isin(mids, [k for k, s in says.items() if s])
            by_face = False
        elif product.is_a("IfcWindow") and mats and all(m is not None and opaque_by_style(m) for m in mats.values()):
            t = max(getattr(m, "transparency", 0.0) for m in mats.values())
            names = sorted({getattr(m, "name", "") or "unnamed" for m in mats.values()})
            self.left_out.append((label(product), f"its surface style ({', '.join(names)}) has transparency {t:g}: a panel, "
                                  "not glass; taken as opaque"))
        elif product.is_a("IfcWindow"):
            hn = None
            hv = [by_id[x] for h in host for x in (h, *self.members.get(h, ())) if x in by_id]
            if hv:
                hn = host_normal(np.concatenate([hv_v[hv_f] for hv_v, hv_f in hv]), np.array([v.min(axis=0), v.max(axis=0)]))
            plane = window_plane(v, faces, placement_axes(product, self.place), overall_size(product, self.unit_m), hn)
            if plane.host_disagrees:
                self.planes_not_hosts.append(f"{label(product)} ({plane.how})")
            glass, opening, share = panes_from_geometry(v, faces, plane.normal)
            if opening is not None:  # frames only: the pane fills what they leave open
                n0 = len(v)
                v = np.concatenate([v, opening.reshape(-1, 3)])
                faces = np.concatenate([faces, n0 + np.arange(3 * len(opening)).reshape(-1, 3)])
                mids = np.concatenate([mids, np.full(len(opening), -1, dtype=np.asarray(mids).dtype)])
                glass = np.r_[glass, np.ones(len(opening), bool)]
                self.panes_in_openings.append(label(product))
            elif glass.any():
                self.panes_from_geometry.append(label(product))
            elif share > 0:
                self.left_out.append((label(product), f"no transparent style, no material named like glass, and its only thin "
                                      f"plates in its plane cover {share:.0%} of its outline (frame members, not glass; "
                                      f"a pane covers at least {PANE_MIN_OUTLINE_SHARE:.0%}): taken as opaque"))
            else:
                self.left_out.append((label(product), "no transparent style, no material named like glass, and no thin "
                                      "pane in its geometry: taken as opaque"))
        elif product.is_a("IfcPlate") and asm is not None and asm[1] == "IfcCurtainWall" and all(s is None for s in says.values()):
            glass[:] = True
            self.plates_as_glass.append(label(product))
        groups = [(glass, True), (~glass, False)] if by_face else [(mids == k, bool(says[k]) and glazed_class) for k in keys]
        for sel, is_glass in groups:  # one part per surface style (or glass and the rest) of the product
            if not sel.any():
                continue
            attrs = dict(base)
            if glazed_class:
                attrs["surface"] = "glazing" if is_glass else "frame"
            if not by_face:
                mat = mats[int(mids[sel][0])]
                mname = getattr(mat, "name", None) if mat is not None else None
                if mname and not mname.startswith(("IfcSurfaceStyle", "DefaultMaterial")) and not is_default_material(mat, product):
                    attrs["material"] = mname
            self.parts.append(Part(attrs, layer=default_layer(product, is_glass), window=key if is_glass else None,
                                   host=host, assembly=None if asm is None else asm[0]))
            self.tris.append(faces[sel] + self.offset)
            self.pidx.append(np.full(int(sel.sum()), len(self.parts) - 1))
        self.verts.append(v)
        self.offset += len(v)

    def add_pane(self, product, tri: np.ndarray, host: tuple[str, ...]) -> None:
        """An unglazed pane ``tri`` (k, 3, 3) [m] for an IfcWindow the file gives no geometry (its opening's outline)."""
        self.parts.append(Part({**_attrs(product), "surface": "glazing"}, layer="window", window=product.GlobalId, host=host))
        self.tris.append(np.arange(3 * len(tri)).reshape(-1, 3) + self.offset)
        self.pidx.append(np.full(len(tri), len(self.parts) - 1))
        self.verts.append(tri.reshape(-1, 3))
        self.offset += 3 * len(tri)
        self.panes_of_openings.append(label(product))

    def messages(self, missing) -> tuple[list[str], list[str]]:
        name = self.path.name
        warnings, notes = [], []
        if self.panes_of_openings:
            notes.append(f"{name}: {len(self.panes_of_openings)} IfcWindow(s) with no geometry whose IfcOpeningElement is "
                         "cut in a wall: each taken as an unglazed pane filling its opening, at the wall's mid-plane (no "
                         "frame: the glazed area is the opening's, larger than the glass would be): "
                         f"{_listed(self.panes_of_openings)}")
        if self.bare:
            warnings.append(f"{name}: {len(self.bare)} IfcWindow(s) with no geometry and no opening to stand for them, left "
                            f"out: {_listed([label(w) for w, _ in self.bare])}; their rooms are assessed without them")
        if self.panes_from_geometry:
            notes.append(f"{name}: {len(self.panes_from_geometry)} IfcWindow(s) with no transparent style or glass name: "
                         "their panes taken from their geometry (the thin plates in the wall's plane): "
                         f"{_listed(self.panes_from_geometry)}")
        if self.panes_in_openings:
            notes.append(f"{name}: {len(self.panes_in_openings)} IfcWindow(s) modelled as frames only (no glass, no "
                         "transparent style): a pane put in each opening their frames leave, in the middle of their "
                         f"depth: {_listed(self.panes_in_openings)}")
        if self.planes_not_hosts:
            notes.append(f"{name}: {len(self.planes_not_hosts)} IfcWindow(s) whose host's faces around them lie in another "
                         "plane (a lintel, a slab): each pane's plane taken from the window itself: "
                         f"{_listed(self.planes_not_hosts)}")
        if self.plates_as_glass:
            notes.append(f"{name}: {len(self.plates_as_glass)} IfcPlate(s) of curtain walls with no surface style of their "
                         f"own taken as glass: {_listed(self.plates_as_glass)}")
        panels = [w for w, why in self.left_out if "a panel, not glass" in why]
        blind = [w for w, why in self.left_out if "a panel, not glass" not in why]
        if panels:
            warnings.append(f"{name}: {len(panels)} IfcWindow(s) whose every surface style is nearly opaque (transparency "
                            f"below {OPAQUE_TRANSPARENCY}: an opal or spandrel panel), taken as opaque: {_listed(panels)}; "
                            "a layer rule {id: '<GlobalId>', layer: window} makes one glass")
        if blind:
            warnings.append(f"{name}: {len(blind)} IfcWindow(s) with no transparent part (no surface style with "
                            f"transparency >= {GLASS_TRANSPARENCY}, no material named like glass, no thin pane in the "
                            f"geometry), taken as opaque: {_listed(blind)}; a layer rule "
                            "{id: '<GlobalId>', layer: window} makes one glass")
        if missing:
            warnings.append(f"{name}: {len(missing)} element(s) with no geometry from ifcopenshell, left out: "
                            + "; ".join(f"{label(p)}: {why}" for p, why in missing[:MAX_GEOMETRY_ERRORS])
                            + (" ..." if len(missing) > MAX_GEOMETRY_ERRORS else ""))
        return warnings, notes


def _listed(names: list[str], n: int = 5) -> str:
    return ", ".join(names[:n]) + (f" and {len(names) - n} more" if len(names) > n else "")


@register(".ifc")
def read_ifc(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read an IFC file: products as parts by class and style, spaces, site (see the module docstring)."""
    options = options or ReadOptions()
    f, notes = open_ifc(path)
    m = map_conversion(f, path.name)

    def place(v: np.ndarray) -> np.ndarray:
        return v if m is None else m.apply(v)

    excluded = set(options.exclude)
    shapes = []
    ignored = [c for c in IGNORED + ("IfcSpatialZone",) if _in_schema(f, c)]
    for product, v, faces, mids, materials in _iterate(f, exclude=ignored, library=GEOMETRY_LIBRARY):  # one shape per product
        if product is None or product.GlobalId in excluded or len(faces) == 0:
            continue
        shapes.append((product, place(v), faces, mids, materials))
    if not shapes:
        raise InputError(f"{path}: no product with geometry in the IFC file; export the model with its 3D geometry")
    missing = without_geometry(f, {s[0].id() for s in shapes}, excluded)
    by_id = {p.GlobalId: (v, faces) for p, v, faces, _, _ in shapes}
    b = _Builder(f, path, place)
    for shape in sorted(shapes, key=lambda s: s[0].id()):  # file order: the iterator's order depends on its threads
        b.add(*shape, by_id)
    read = {s[0].id() for s in shapes}
    bare = [w for w in f.by_type("IfcWindow") if w.id() not in read and w.GlobalId not in excluded]
    if bare:  # an IfcWindow with no geometry: its opening stands for it
        ops = [op for w in bare for op in openings_of(w)]
        panes, left = panes_of_bare_windows(bare, ((p, v, fc) for p, v, fc, _, _ in _iterate(f, include=ops)) if ops else (),
                                              by_id, b.host_of, place, b.unit_m)
        for w, tri, host in sorted(panes, key=lambda p: p[0].id()):
            b.add_pane(w, tri, host)
        placed = {w.id() for w, _, _ in panes}
        b.bare = [(w, why) for w, why in left if w.Representation is None]  # the others: in ``missing`` already
        missing = [(p, why) for p, why in missing if p.id() not in placed]
    warnings, more = b.messages(missing)
    if m is not None:  # how its offsets and scale were read
        notes.extend(m.notes)
        warnings.extend(m.warnings)
    spaces = f.by_type("IfcSpace")
    space_shapes = ((p, v, fc) for p, v, fc, _, _ in _iterate(f, include=spaces)) if spaces else ()
    unread = [(label(p), f"no geometry from ifcopenshell ({why})") for p, why in missing if any(p.is_a(c) for c in GLAZED)]
    return Mesh(np.concatenate(b.verts), np.concatenate(b.tris), np.concatenate(b.pidx), b.parts, warnings, notes + more,
                units="m", up_axis="z", site=site_of(f, path, m), spaces=read_spaces(f, space_shapes, place),
                windows_left_out=b.left_out + unread + [(label(w), why) for w, why in b.bare])
