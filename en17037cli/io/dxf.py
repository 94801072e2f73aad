"""DXF reader: the 3D faces and meshes of a CAD drawing, by layer, through ezdxf.

Read from the model space: ``3DFACE`` (a triangle, or a quad as two triangles), ``POLYLINE``
polyface meshes and polygon meshes (M x N), ``MESH`` (the base cage; subdivision levels are not
applied), and ``INSERT`` block references expanded with their transforms (nested blocks, arrays
of ``MINSERT``) by ezdxf's ``virtual_entities``; an entity on layer ``0`` inside a block takes the
layer of its INSERT, a colour BYBLOCK the INSERT's colour (DXF reference, "Block references").
Faces of more than three vertices are ear-clipped. Everything else (lines, 2D polylines, text,
hatches, ``3DSOLID`` / ``REGION`` / ``SURFACE``, whose ACIS bodies ezdxf cannot tessellate) is
left out and counted by type in a note; a drawing with no 3D face at all is an input error.

Units: ``$INSUNITS`` of the header: inches, feet, mm, cm and m are the file's units (a ``units``
key on the file entry still wins); the others ezdxf knows (km, yards, miles...) are scaled to
metres here; unitless (0) or no header: the project's ``units``.

Parts: one :class:`~en17037cli.io.mesh.Part` per (layer, entity type, colour, block):

| key | value |
|---|---|
| `group` | the DXF layer name (layer rules match it like an OBJ group) |
| `class` | the entity type: `3DFACE`, `POLYFACE`, `POLYMESH`, `MESH` |
| `type` | the name of the block the faces are drawn in, for faces that came from an INSERT |
| `colour` | the ACI colour number (BYLAYER and BYBLOCK resolved) |
| `name` | EnergyPlus DXF only: the surface's name (``ZONE:SURFACE``) from the comment before it |

Default layers: none (the project's rules place each layer), except in EnergyPlus's DXF output
(``Output:Surfaces:Drawing, DXF``; recognised by its ``DXF created from EnergyPlus`` comment with
the default colour scheme), which writes one layer per zone and the surface class in the colour
(EnergyPlus DataSurfaceColors): windows, glass doors and tubular daylight domes and diffusers
(143) -> window; walls (43), doors (45), floors (8), roofs (15), attached shading (13) and
photovoltaics (174) -> interior; detached building shading (195) and detached fixed shading (9)
-> landscape; the north arrow and the text on layer ``1`` -> ignore.

Windows drawn on their walls (EnergyPlus draws each wall whole with its windows coplanar on top):
``Mesh.openings_drawn`` asks the scene to cut every window face lying on a coplanar opaque face
out of that face once the layers are known (:func:`~en17037cli.io.openings.cut_openings`), with a
note; glazing over an uncut wall would otherwise hide the window from every ray.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangulate_polygons
from en17037cli.io.mesh import Mesh, Part
from en17037cli.io.registry import ReadOptions, register

#: EnergyPlus's default DXF colour scheme (DataSurfaceColors defaultcolorno) -> layer
ENERGYPLUS_COLOURS = {143: "window", 43: "interior", 45: "interior", 8: "interior", 15: "interior", 13: "interior",
                      174: "interior", 195: "landscape", 9: "landscape"}
FACE_TYPES = ("3DFACE", "POLYLINE", "MESH")
#: $INSUNITS codes of the units the project knows: the file's units (its ``units`` key still wins)
INSUNITS = {1: "in", 2: "ft", 4: "mm", 5: "cm", 6: "m"}
ACIS_TYPES = ("3DSOLID", "REGION", "SURFACE", "BODY", "EXTRUDEDSURFACE", "LOFTEDSURFACE", "REVOLVEDSURFACE",
              "SWEPTSURFACE", "PLANESURFACE")
MAX_BLOCK_DEPTH = 16


def _ezdxf(path: Path):
    try:
        import ezdxf
        import ezdxf.recover  # noqa: F401
    except ImportError:
        raise InputError(f"{path}: reading DXF needs ezdxf: pip install 'en17037cli[dxf]'") from None
    return ezdxf


def _open(path: Path):
    ezdxf = _ezdxf(path)
    try:
        head = path.read_bytes()[:4096]
    except OSError as exc:
        raise InputError(f"{path}: cannot read model file: {exc.strerror}") from None
    if head.startswith(b"AutoCAD Binary DXF"):
        pass
    elif b"SECTION" not in head.upper():
        raise InputError(f"{path}: not a DXF file (no SECTION in its first lines); export the drawing as DXF")
    try:
        doc, auditor = ezdxf.recover.readfile(str(path))
    except ezdxf.DXFStructureError as exc:
        raise InputError(f"{path}: broken DXF ({exc}); save the drawing as DXF again") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read the DXF file ({exc}); save it as DXF again") from None
    return doc, auditor, head.decode("latin-1")


class _Faces:
    """Faces collected per part, as polygons grouped by vertex count (vectorised triangulation later)."""

    def __init__(self):
        self.parts: list[Part] = []
        self.index: dict = {}
        self.polys: dict[int, list] = {}  # vertex count -> list of (part, (k, 3) polygon)
        self.skipped: dict[str, int] = {}
        self.n_entities = 0

    def part(self, attrs: dict, layer: str | None) -> int:
        key = tuple(sorted(attrs.items()))
        i = self.index.get(key)
        if i is None:
            i = self.index[key] = len(self.parts)
            self.parts.append(Part(attrs, layer=layer))
        return i

    def add(self, part: int, poly) -> None:
        poly = np.asarray(poly, dtype=np.float64).reshape(-1, 3)
        if len(poly) > 3:  # drop repeated consecutive vertices (a 3DFACE triangle repeats its third)
            keep = np.any(poly != np.roll(poly, 1, axis=0), axis=1)
            poly = poly[keep] if keep.sum() >= 3 else poly[:3]
        if len(poly) >= 3:
            self.polys.setdefault(len(poly), []).append((part, poly))

    def skip(self, kind: str) -> None:
        self.skipped[kind] = self.skipped.get(kind, 0) + 1


def energyplus_names(text: str) -> list[str]:
    """The surface name of each face entity (3DFACE, POLYLINE) of an EnergyPlus DXF, in file order: the
    ``999`` comment EnergyPlus writes before each surface ("ZONE:SURFACE NAME", "Building Shading:NAME")."""
    lines = text.splitlines()
    names, last = [], ""
    for k in range(0, len(lines) - 1, 2):
        code, value = lines[k].strip(), lines[k + 1].strip()
        if code == "999":
            last = value
        elif code == "0" and value in ("3DFACE", "POLYLINE"):
            names.append(last)
    return names


def _colour(e, layer_colours: dict, block_colour: int | None) -> int:
    c = e.dxf.get("color", 256)
    if c == 256:  # BYLAYER
        return abs(layer_colours.get(e.dxf.get("layer", "0"), 7))
    if c == 0:  # BYBLOCK
        return block_colour if block_colour is not None else 7
    return abs(c)


def _walk(entities, faces: _Faces, layer_colours: dict, energyplus: bool, inherited=None, depth: int = 0,
          names: list | None = None) -> None:
    """Collect the faces of ``entities``; ``inherited`` = (layer, colour, block name) of the enclosing INSERT;
    ``names``: a name for each face entity of ``entities`` in order (EnergyPlus surface names), or None."""
    from ezdxf.render import MeshBuilder

    k_face = 0
    for e in entities:  # one pass per entity: DXF gives them one by one
        kind = e.dxftype()
        layer = e.dxf.get("layer", "0")
        block = None
        if inherited is not None:
            if layer == "0":
                layer = inherited[0]
            block = inherited[2]
        colour = _colour(e, layer_colours, None if inherited is None else inherited[1])
        if kind == "INSERT":
            if depth >= MAX_BLOCK_DEPTH:
                faces.skip("INSERT nested too deep")
                continue
            try:
                virtual = list(e.virtual_entities())
            except Exception:  # a block reference ezdxf cannot expand (non-uniform scaling of arcs...): counted
                faces.skip("INSERT not expandable")
                continue
            _walk(virtual, faces, layer_colours, energyplus, (layer, colour, e.dxf.get("name")), depth + 1)
            continue
        if kind == "3DFACE":
            cls, polys = kind, [[e.dxf.vtx0, e.dxf.vtx1, e.dxf.vtx2, e.dxf.get("vtx3", e.dxf.vtx2)]]
        elif kind == "POLYLINE" and (e.is_poly_face_mesh or e.is_polygon_mesh):
            cls = "POLYFACE" if e.is_poly_face_mesh else "POLYMESH"
            mb = MeshBuilder.from_polyface(e)
            v = np.asarray(mb.vertices, dtype=np.float64).reshape(-1, 3)
            polys = [v[list(f)] for f in mb.faces if len(f) >= 3]
        elif kind == "MESH":
            cls = kind
            mb = MeshBuilder.from_mesh(e)
            v = np.asarray(mb.vertices, dtype=np.float64).reshape(-1, 3)
            polys = [v[list(f)] for f in mb.faces if len(f) >= 3]
        else:
            faces.skip(kind if kind not in ACIS_TYPES else f"{kind} (ACIS solid)")
            continue
        faces.n_entities += 1
        attrs = {"group": layer, "class": cls, "colour": str(colour)}
        if names is not None and kind in ("3DFACE", "POLYLINE"):
            attrs["name"] = names[k_face]
            k_face += 1
        if block:
            attrs["type"] = block
        default = None
        if energyplus:
            default = "ignore" if layer == "1" else ENERGYPLUS_COLOURS.get(colour)
        p = faces.part(attrs, default)
        for poly in polys:
            faces.add(p, poly)


def _triangles(faces: _Faces):
    """Vertices (n, 3), triangles (m, 3) and part per triangle of the collected polygons, grouped by vertex count."""
    verts, tris, parts = [], [], []
    base = 0
    for k in sorted(faces.polys):
        items = faces.polys[k]
        pts = np.stack([p for _, p in items])  # (n, k, 3)
        pid = np.fromiter((i for i, _ in items), dtype=np.int64, count=len(items))
        if k == 3:
            local = [np.array([[0, 1, 2]])] * len(items)
        else:
            local = triangulate_polygons(pts)
        counts = np.fromiter(map(len, local), dtype=np.int64, count=len(local))
        poly = np.repeat(np.arange(len(items)), counts)
        loc = np.concatenate(local) if len(local) else np.zeros((0, 3), dtype=np.int64)
        verts.append(pts.reshape(-1, 3))
        tris.append(loc + (poly * k)[:, None] + base)
        parts.append(pid[poly])
        base += len(items) * k
    if not verts:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(verts), np.concatenate(tris), np.concatenate(parts)


@register(".dxf")
def read_dxf(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read the 3D faces of a DXF drawing's model space (see the module docstring).

    Returns
    -------
    Mesh
        ``vertices`` (n, 3) float64 in the drawing's units, ``units`` from ``$INSUNITS`` (None when
        unitless: the project's); z up (the DXF world frame); one part per (layer, entity type,
        colour, block); ``openings_drawn=True``.

    Raises
    ------
    InputError
        Not a DXF file, a broken one, or one with no 3D face in its model space.
    """
    path = Path(path)
    doc, auditor, head = _open(path)
    from ezdxf import units as dxf_units

    energyplus = "DXF created from EnergyPlus" in head
    scheme_default = "Color Scheme,Default" in head or "Color Scheme" not in head
    faces = _Faces()
    layer_colours = {layer.dxf.name: layer.dxf.get("color", 7) for layer in doc.layers}
    msp = doc.modelspace()
    names = None
    if energyplus:  # its surface names are in the comments before each face, which ezdxf does not keep
        names = energyplus_names(path.read_text(encoding="latin-1"))
        if len(names) != sum(1 for e in msp if e.dxftype() in ("3DFACE", "POLYLINE")):
            names = None
    _walk(msp, faces, layer_colours, energyplus and scheme_default, names=names)
    v, tris, part = _triangles(faces)
    skipped = ", ".join(f"{k}: {n}" for k, n in sorted(faces.skipped.items()))
    if len(tris) == 0:
        raise InputError(f"{path}: no 3D face in the drawing's model space (3DFACE, polyface or polygon mesh, MESH)"
                         f"{'; it has ' + skipped if skipped else ''}; export the 3D model with its faces (e.g. as "
                         "3D faces or meshes), not lines or ACIS solids")
    notes, warnings = [], []
    insunits = int(doc.header.get("$INSUNITS", 0) or 0)
    units = None
    if insunits in INSUNITS:  # the project's units key for this file still wins (the scene scales)
        units = INSUNITS[insunits]
        notes.append(f"{path.name}: $INSUNITS {insunits} ({dxf_units.unit_name(insunits)}): drawing units {units}")
    elif insunits:
        try:
            factor = dxf_units.conversion_factor(insunits, dxf_units.M)
        except (KeyError, ValueError, ZeroDivisionError):
            factor = None
        if factor:
            v = v * factor
            units = "m"
            notes.append(f"{path.name}: $INSUNITS {insunits} ({dxf_units.unit_name(insunits)}): scaled by {factor:g} to metres")
        else:
            warnings.append(f"{path.name}: $INSUNITS {insunits} is not a length unit ezdxf knows; the project's units apply")
    if skipped:
        notes.append(f"{path.name}: entities without 3D faces left out ({skipped})")
    if auditor.has_errors:  # its fixes (an undefined text style removed...) change no face
        warnings.append(f"{path.name}: the DXF needed repairs to be read ({len(auditor.errors)} errors, "
                        f"{len(auditor.fixes)} fixes by ezdxf's recover mode); check the drawing")
    if energyplus:
        notes.append(f"{path.name}: EnergyPlus DXF output: layers by the default colour scheme (windows 143, walls 43...)"
                     if scheme_default else f"{path.name}: EnergyPlus DXF output with its own colour scheme: no default "
                     "layers, the project's rules place the layers")
    by_layer: dict = {}
    for i, p in enumerate(faces.parts):
        by_layer[p.attrs["group"]] = by_layer.get(p.attrs["group"], 0) + int(np.count_nonzero(part == i))
    listed = ", ".join(f"{k}: {n}" for k, n in list(by_layer.items())[:12]) + (" ..." if len(by_layer) > 12 else "")
    summary = (f"{faces.n_entities} entities with 3D faces, {len(tris)} triangles on {len(by_layer)} layers ({listed})"
               + (f"; left out: {skipped}" if skipped else ""))
    return Mesh(v, tris, part, faces.parts, warnings, notes, units=units, up_axis="z",
                summary=summary, openings_drawn=True)
