"""CityJSON reader: city context models (3D BAG tiles, municipal LoD2 models) as triangles with parts.

Reads CityJSON 1.0, 1.1 and 2.0 files (``.city.json``, ``.json``) and CityJSON Text Sequences
(CityJSONSeq, spec 2.0 §7.2; ``.city.jsonl``, ``.jsonl``): a first line holding a ``"CityJSON"``
object with ``transform``, ``metadata`` and ``geometry-templates``, then one
``"CityJSONFeature"`` per line whose ``vertices`` are indexed locally. Section numbers are those
of the CityJSON 2.0 specification (https://www.cityjson.org/specs/2.0.1/); 1.0 and 1.1 number
the geometry and transform sections alike, 1.0 has the CRS in §5.1.

The reader, by concept (each module's docstring has the details):

| module | what |
|---|---|
| `documents` | the file as JSON: documents, header and version, CRS, transformed vertices, templates |
| `semantics` | default layer by CityObject type and semantic surface (its table), LoD choice, exclusion |
| `builder` | geometries flattened into rings, parts per object and surface type, near-culling |
| `triangulate` | rings with holes and without, Newell areas, what could not be triangulated |
| `footprint` | :func:`footprint_overlap`, :func:`without_objects`: the checked building out of a tile |

Parts: one :class:`~en17037cli.io.mesh.Part` per (CityObject, semantic surface type), in file
order (objects, then surface types as the object's ``semantics.surfaces`` list them); a
PlantCover given both as surfaces and as solids gets one of each. ``Part.attrs``:

| key | value |
|---|---|
| `class` | the CityObject type: `Building`, `BuildingPart`, `TINRelief`, `+NoiseBarrier`... |
| `id` | the CityObject id (its key in `"CityObjects"`) |
| `parent` | the type of the object's first parent (`"parents"`, §2), when it has one |
| `surface` | the semantic surface type (§3.3): `RoofSurface`, `WallSurface`, `Window`..., if the face has one |
| `attr.<key>` | `str(value)` of each scalar attribute (string, number, bool; not lists, objects, null) |

Parts inherit nothing from their parent objects. ``Part.layer`` is the default layer of
:mod:`~en17037cli.io.cityjson.semantics` (its table); ``Part.obstructs_sun`` is True for every
part, vegetation included.

Options: ``ReadOptions.lod`` (``"highest"`` or a LoD such as ``"2.2"``, with fallback to a lower
one) and ``ReadOptions.exclude`` (ids with their descendants) in
:mod:`~en17037cli.io.cityjson.semantics`; ``ReadOptions.near = ((x, y), r)`` (objects entirely
farther away in plan left out before triangulation) in :mod:`~en17037cli.io.cityjson.builder`.
MultiPoint and MultiLineString geometries carry no surfaces and are left out (counted note).

Not read: appearances (materials, textures), Extensions' schemas, ``geographicalExtent``.
Python's cyclic garbage collector is paused while a file is read (JSON trees hold no cycles;
collecting during the parse would triple the load time of a large tile).
"""
from __future__ import annotations

import gc
from pathlib import Path

from en17037cli.errors import InputError
from en17037cli.io.cityjson.builder import Builder
from en17037cli.io.cityjson.documents import (
    GEOMETRY_TYPES,
    NON_SURFACE_TYPES,
    SOLID_TYPES,
    SURFACE_DEPTH,
    VERSIONS,
    all_vertices,
    check_header,
    header_site,
    header_templates,
    load_documents,
    normalise_crs,
    template_of,
)
from en17037cli.io.cityjson.footprint import footprint_overlap, without_objects
from en17037cli.io.cityjson.semantics import (
    BUILDING_CLASSES,
    choose_lod,
    counted,
    default_layer,
    excluded_ids,
    lod_key,
    lod_label,
    parse_lod_request,
)
from en17037cli.io.mesh import Mesh
from en17037cli.io.registry import ReadOptions, register

__all__ = [
    "BUILDING_CLASSES", "GEOMETRY_TYPES", "NON_SURFACE_TYPES", "SOLID_TYPES", "SURFACE_DEPTH", "VERSIONS",
    "default_layer", "footprint_overlap", "normalise_crs", "read_cityjson", "without_objects",
]


@register(".city.json", ".json", ".city.jsonl", ".jsonl", context=True)
def read_cityjson(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read a CityJSON file or CityJSON Text Sequence into triangles with one part per object and surface type.

    Parameters
    ----------
    path : a ``.city.json`` / ``.json`` CityJSON 1.0, 1.1 or 2.0 file, or a ``.city.jsonl`` /
        ``.jsonl`` CityJSONSeq (a ``.json`` file holding a sequence is read as one too)
    options : ``lod``, ``exclude`` and ``near`` (see :class:`~en17037cli.io.ReadOptions` and the
        module docstring); None for the defaults

    Returns
    -------
    Mesh
        ``vertices`` (n, 3) float64 [m] in the file's CRS, z up (only the vertices the triangles
        use, in file order); ``triangles`` (m, 3) int64 in file order of the surfaces;
        ``part`` (m,) int64; ``parts`` in file order (objects, then surface types as first met);
        ``units="m"``, ``up_axis="z"``; ``site`` with the CRS when the file names one.

    Raises
    ------
    InputError
        One line naming the file (and object) and the fix: not JSON, not CityJSON, an
        unsupported version, no vertices, a vertex index out of range, an unknown geometry type,
        boundaries not nested as their type says, a CRS in degrees.
    """
    path = Path(path)
    options = options or ReadOptions()
    gc_enabled = gc.isenabled()
    gc.disable()  # JSON trees hold no reference cycles; collecting during the parse triples its time
    try:
        return _read(path, options)
    finally:
        if gc_enabled:
            gc.enable()


def _read(path: Path, options: ReadOptions) -> Mesh:
    """The work of :func:`read_cityjson`."""
    name = path.name
    lod_req = parse_lod_request(path, options.lod)
    docs = load_documents(path)
    header = docs[0][1]
    check_header(path, header)
    site = header_site(path, header)
    vertices, doc_base, doc_count = all_vertices(path, docs)
    templates, tverts = header_templates(path, header)

    objects = []  # (doc index, id, CityObject) in file order
    by_id: dict = {}
    for di, (where, doc) in enumerate(docs):
        cos = doc.get("CityObjects")
        if cos is None and di == 0 and len(docs) > 1:
            continue
        if not isinstance(cos, dict):
            raise InputError(f"{path}{where}: 'CityObjects' must be an object of id: CityObject; validate the file with cjval")
        for oid, obj in cos.items():
            if not isinstance(obj, dict):
                raise InputError(f"{path}{where}: CityObject '{oid}' is not a JSON object; validate the file with cjval")
            objects.append((di, oid, obj))
            by_id.setdefault(oid, obj)

    notes: list[str] = []
    warnings: list[str] = []
    excluded = excluded_ids(by_id, options.exclude, notes, name)

    b = Builder(path, vertices, by_id)
    n_points = 0
    n_fallback: dict = {}
    n_skipped = 0
    unknown: dict = {}
    by_lod: dict = {}  # (type, LoD read) -> objects, for validate's summary
    for di, oid, obj in objects:
        if oid in excluded:
            continue
        geoms = obj.get("geometry")
        if geoms is None:
            continue
        if not isinstance(geoms, list):
            raise InputError(f"{path}{docs[di][0]}: object '{oid}': 'geometry' must be a list of Geometry Objects; "
                             "validate the file with cjval")
        candidates = []
        for gi, g in enumerate(geoms):
            gtype = g.get("type") if isinstance(g, dict) else None
            if gtype in SURFACE_DEPTH:
                candidates.append((lod_key(g.get("lod")), gi, g, None))
            elif gtype == "GeometryInstance":
                tpl = template_of(path, docs[di][0], oid, gi, g, templates)
                if tpl.get("type") in NON_SURFACE_TYPES:
                    n_points += 1
                    continue
                candidates.append((lod_key(tpl.get("lod")), gi, tpl, g))
            elif gtype in NON_SURFACE_TYPES:
                n_points += 1
            else:
                raise InputError(f"{path}{docs[di][0]}: object '{oid}' geometry[{gi}] has unknown type {gtype!r}; "
                                 f"CityJSON geometry types are {', '.join(GEOMETRY_TYPES)}")
        if not candidates:
            continue
        chosen, fallback = choose_lod(candidates, lod_req)
        if chosen is None:
            n_skipped += 1
            continue
        if fallback:
            label = lod_label(chosen)
            n_fallback[label] = n_fallback.get(label, 0) + 1
        cls = obj.get("type")
        cls = cls if isinstance(cls, str) else "?"
        by_lod[(cls, lod_label(chosen))] = by_lod.get((cls, lod_label(chosen)), 0) + 1
        if default_layer(cls, None, False)[1] is False:
            unknown[cls] = unknown.get(cls, 0) + 1
        b.start_object(oid, obj, cls, docs[di][0])
        for key, gi, g, inst in candidates:
            if key != chosen:
                continue
            if inst is None:
                b.add_geometry(g, gi, doc_base[di], doc_count[di])
            else:
                b.add_instance(g, inst, gi, tverts, doc_base[di], doc_count[di])

    if n_points:
        notes.append(f"{name}: {counted(n_points, 'point/line geometry', 'point/line geometries')} (MultiPoint, "
                     "MultiLineString) left out: no surfaces")
    if n_fallback:
        total = sum(n_fallback.values())
        detail = ", ".join(f"LoD {k}: {v}" for k, v in sorted(n_fallback.items(), reverse=True))
        notes.append(f"{name}: LoD {options.lod} requested; {counted(total, 'object')} fell back to a lower LoD ({detail})")
    if n_skipped:
        notes.append(f"{name}: {counted(n_skipped, 'object')} without surface geometry at or below LoD {options.lod} left out")
    if unknown:
        detail = ", ".join(f"{k}: {v}" for k, v in unknown.items())
        notes.append(f"{name}: {counted(sum(unknown.values()), 'object')} of types that are not CityJSON core types "
                     f"given layer landscape ({detail})")

    mesh_v, tris, part, parts = b.finish(options.near, notes, warnings)
    lods = ", ".join(f"{cls} LoD {lod}: {n}" for (cls, lod), n in sorted(by_lod.items()))
    summary = (f"CityJSON, {counted(len(objects), 'object')}; with surfaces, by type and LoD read: {lods or 'none'}; "
               f"{counted(len(tris), 'triangle')} kept")
    return Mesh(mesh_v, tris, part, parts, warnings, notes, units="m", up_axis="z", site=site, summary=summary)
