"""CityJSON reader: city context models (3D BAG tiles, municipal LoD2 models) as triangles with parts.

Reads CityJSON 1.0, 1.1 and 2.0 files (``.city.json``, ``.json``) and CityJSON Text Sequences
(CityJSONSeq, spec 2.0 §7.2; ``.city.jsonl``, ``.jsonl``): a first line holding a ``"CityJSON"``
object with ``transform``, ``metadata`` and ``geometry-templates``, then one
``"CityJSONFeature"`` per line whose ``vertices`` are indexed locally. Section numbers are those
of the CityJSON 2.0 specification (https://www.cityjson.org/specs/2.0.1/); 1.0 and 1.1 number
the geometry and transform sections alike, 1.0 has the CRS in §5.1.

Coordinates (§3.1 Coordinates of the vertices, §4 Transform Object): ``vertex = integer * scale
+ translate``, in float64, for all vertices of the file in one numpy step (a 1.0 file without
``transform`` holds real coordinates). Template vertices (§3.4) are real coordinates and are not
transformed. CityJSON vertices are in the units of the file's CRS with z up; the reader returns
``Mesh(units="m", up_axis="z")`` because the CRSs of city models are projected ones in metres
(EPSG:7415, 28992, 25832...); a CRS in degrees (EPSG:4326, 4979...) is refused.

Geometry (§3.2 Arrays to represent boundaries): MultiSurface and CompositeSurface (boundaries
nested 3 deep: surface > ring > vertex index), Solid (4: shell > surface > ring > index),
MultiSolid and CompositeSolid (5), and GeometryInstance (§3.4 Geometry templates: a template
placed by its 4x4 row-major ``transformationMatrix`` M at the reference point, the vertex
``boundaries[0]``: ``world = M[:3, :3] @ v + M[:3, 3] + reference_point``). MultiPoint and
MultiLineString carry no surfaces and are left out (counted note). A surface is an outer ring
and optional inner rings (holes). Surfaces without holes are ear-clipped in their best-fit
(Newell) plane, all surfaces of one vertex count together
(:func:`en17037cli.geometry.triangulate_polygons`); surfaces with holes get their planes and
projections all at once too, and mapbox-earcut runs once per surface with the hole indices.
A surface whose triangles cover less than 99.9 % of its area (self-intersecting, degenerate) is
counted in a warning.

Level of detail (``ReadOptions.lod``): ``"highest"`` takes each object's highest LoD; a given
LoD (``"2.2"``, ``"1.2"``, ``"2"``...) takes it, or else the highest LoD below it (one note counts
the fallbacks); ``"2"`` takes the highest of 2, 2.0, 2.1... Objects with surface geometry, but
none at or below the LoD, are left out (counted note). All geometries of the chosen LoD are read.

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

Parts inherit nothing from their parent objects.

Default layer (``Part.layer``): the first matching row wins; the project's layer rules may
override any of it (matching ``class``, ``surface``, ``id``, ``attr.*``).

| CityObject type / semantic surface | layer | why |
|---|---|---|
| `GroundSurface` of a `Building` or `BuildingPart` | ignore | never seen from outside |
| `ClosureSurface`, `WaterClosureSurface` (any object) | ignore | virtual, not matter |
| `InteriorWallSurface`, `CeilingSurface`, `FloorSurface` (any object) | ignore | inside a building |
| `Building`, `BuildingPart`, `BuildingInstallation`, `BuildingConstructiveElement` | landscape | |
| `Bridge`, `BridgePart`, `BridgeInstallation`, `BridgeConstructiveElement` | landscape | |
| `BridgeConstructionElement` (CityJSON 1.0 name) | landscape | |
| `Tunnel`, `TunnelPart`, `TunnelInstallation`, `TunnelConstructiveElement` | landscape | |
| `CityFurniture`, `GenericCityObject`, `OtherConstruction`, `SolitaryVegetationObject` | landscape | |
| `PlantCover` given as Solid, MultiSolid or CompositeSolid | landscape | |
| `PlantCover` given as MultiSurface or CompositeSurface | ground | |
| `TINRelief`, `LandUse`, `Road`, `Railway`, `TransportSquare`, `WaterBody`, `Waterway` | ground | |
| `BuildingRoom`, `BuildingStorey`, `BuildingUnit`, `BuildingFurniture` | ignore | inside a shell (1) |
| `BridgeRoom`, `BridgeFurniture`, `TunnelHollowSpace`, `TunnelFurniture` | ignore | inside a shell (1) |
| `CityObjectGroup` | ignore | groups objects that have their own geometry |
| any other type (an Extension's `+Something`) | landscape | counted in a note |

(1) Never seen from outside; as landscape, the checked building's rooms would fill the checked room.

Other semantic surfaces keep their object's layer: a context building's ``Window`` and ``Door``
surfaces are landscape (the ``window`` layer is the checked room's glazing, from its own model).

``Part.obstructs_sun`` is True for every part, vegetation included (``SolitaryVegetationObject``
and ``PlantCover`` solids): whether foliage lets the sun through is the project's decision (a
layer rule with ``obstructs_sun: false``).

Other options: ``ReadOptions.exclude`` leaves out objects by id together with their
descendants (``"children"``, and objects naming them in ``"parents"``, recursively);
``ReadOptions.near = ((x, y), r)`` leaves out, before triangulation, each object whose vertex
bounding box lies entirely farther than ``r`` from ``(x, y)`` in plan (counted note). The CRS
(§5.5 ``metadata.referenceSystem``, ``https://www.opengis.net/def/crs/EPSG/0/7415``; 1.0 §5.1
``urn:ogc:def:crs:EPSG::7415``) becomes ``Mesh.site.crs = "EPSG:7415"``; for a CityJSONSeq it
comes from the first line.

Not read: appearances (materials, textures), Extensions' schemas, ``geographicalExtent``.
Python's cyclic garbage collector is paused while a file is read (JSON trees hold no cycles;
collecting during the parse would triple the load time of a large tile).
"""
from __future__ import annotations

import gc
import json
import re
from itertools import chain, pairwise
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangulate_polygons
from en17037cli.io import ReadOptions, register
from en17037cli.io.mesh import Mesh, Part, Site

#: CityJSON versions read (the file's "version", major.minor)
VERSIONS = ("1.0", "1.1", "2.0")

#: surface geometry type -> how many levels of arrays lie above the surfaces (§3.2)
SURFACE_DEPTH = {"MultiSurface": 0, "CompositeSurface": 0, "Solid": 1, "MultiSolid": 2, "CompositeSolid": 2}
SOLID_TYPES = frozenset(("Solid", "MultiSolid", "CompositeSolid"))
NON_SURFACE_TYPES = frozenset(("MultiPoint", "MultiLineString"))
GEOMETRY_TYPES = ("MultiPoint", "MultiLineString", *SURFACE_DEPTH, "GeometryInstance")

_LANDSCAPE = frozenset((
    "Building", "BuildingPart", "BuildingInstallation", "BuildingConstructiveElement",
    "Bridge", "BridgePart", "BridgeInstallation", "BridgeConstructiveElement", "BridgeConstructionElement",
    "Tunnel", "TunnelPart", "TunnelInstallation", "TunnelConstructiveElement",
    "CityFurniture", "GenericCityObject", "OtherConstruction", "SolitaryVegetationObject",
))
_GROUND = frozenset(("TINRelief", "LandUse", "Road", "Railway", "TransportSquare", "WaterBody", "Waterway"))
_IGNORE = frozenset((
    "BuildingRoom", "BuildingStorey", "BuildingUnit", "BuildingFurniture", "BridgeRoom", "BridgeFurniture",
    "TunnelHollowSpace", "TunnelFurniture", "CityObjectGroup",
))
_IGNORED_SURFACES = frozenset(("ClosureSurface", "WaterClosureSurface", "InteriorWallSurface", "CeilingSurface", "FloorSurface"))
_BUILDING = frozenset(("Building", "BuildingPart"))

#: CityObject types whose parts :func:`footprint_overlap` considers: a building and what belongs to it
BUILDING_CLASSES = ("Building", "BuildingPart", "BuildingInstallation", "BuildingConstructiveElement")

#: EPSG codes of common geographic (degree) CRSs, refused: their coordinates are not metres
_GEOGRAPHIC_EPSG = frozenset((4326, 4979, 4258, 4937, 4269, 4617, 4283, 4490, 4612, 4167))

_LOD_RE = re.compile(r"(\d+)(?:\.(\d+))?")


def default_layer(cls: str, surface: str | None, solid: bool) -> tuple[str, bool]:
    """Default layer of a face from its CityObject type, semantic surface and geometry kind.

    Parameters
    ----------
    cls : CityObject type ("Building", "PlantCover", "+Noise"...)
    surface : semantic surface type ("GroundSurface"...) or None
    solid : the geometry is a Solid, MultiSolid or CompositeSolid

    Returns
    -------
    layer : one of "ground", "landscape", "ignore" (see the module's table)
    known : False when ``cls`` is not a CityJSON type (an Extension's "+Something")
    """
    if surface is not None and (surface in _IGNORED_SURFACES or (surface == "GroundSurface" and cls in _BUILDING)):
        return "ignore", True
    if cls in _LANDSCAPE:
        return "landscape", True
    if cls in _GROUND:
        return "ground", True
    if cls == "PlantCover":
        return ("landscape" if solid else "ground"), True
    if cls in _IGNORE:
        return "ignore", True
    return "landscape", False


def normalise_crs(reference_system) -> str | None:
    """``"EPSG:<code>"`` from a CityJSON ``referenceSystem`` (§5.5; 1.0 §5.1), else the string as given.

    Accepts ``https://www.opengis.net/def/crs/EPSG/0/7415`` (1.1, 2.0), ``urn:ogc:def:crs:EPSG::7415``
    and ``urn:ogc:def:crs:EPSG:6.3:7415`` (1.0), ``EPSG:7415``. None for a missing or empty value.
    """
    if not isinstance(reference_system, str) or not reference_system.strip():
        return None
    s = reference_system.strip()
    m = re.search(r"EPSG(?:/[^/]*/|:[\d.]*:|:)(\d+)$", s, re.IGNORECASE)
    return f"EPSG:{m.group(1)}" if m else s


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
    lod_req = _parse_lod_request(path, options.lod)
    docs = _load_documents(path)
    header = docs[0][1]
    _check_header(path, header)
    site = _site(path, header)
    vertices, doc_base, doc_count = _vertices(path, docs)
    templates, tverts = _templates(path, header)

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
    excluded = _excluded(by_id, options.exclude, notes, name)

    b = _Builder(path, vertices, by_id)
    n_points = 0
    n_fallback: dict = {}
    n_skipped = 0
    unknown: dict = {}
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
                candidates.append((_lod_key(g.get("lod")), gi, g, None))
            elif gtype == "GeometryInstance":
                tpl = _template_of(path, docs[di][0], oid, gi, g, templates)
                if tpl.get("type") in NON_SURFACE_TYPES:
                    n_points += 1
                    continue
                candidates.append((_lod_key(tpl.get("lod")), gi, tpl, g))
            elif gtype in NON_SURFACE_TYPES:
                n_points += 1
            else:
                raise InputError(f"{path}{docs[di][0]}: object '{oid}' geometry[{gi}] has unknown type {gtype!r}; "
                                 f"CityJSON geometry types are {', '.join(GEOMETRY_TYPES)}")
        if not candidates:
            continue
        chosen, fallback = _choose_lod(candidates, lod_req)
        if chosen is None:
            n_skipped += 1
            continue
        if fallback:
            label = _lod_label(chosen)
            n_fallback[label] = n_fallback.get(label, 0) + 1
        cls = obj.get("type")
        cls = cls if isinstance(cls, str) else "?"
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
        notes.append(f"{name}: {_count(n_points, 'point/line geometry', 'point/line geometries')} (MultiPoint, "
                     "MultiLineString) left out: no surfaces")
    if n_fallback:
        total = sum(n_fallback.values())
        detail = ", ".join(f"LoD {k}: {v}" for k, v in sorted(n_fallback.items(), reverse=True))
        notes.append(f"{name}: LoD {options.lod} requested; {_count(total, 'object')} fell back to a lower LoD ({detail})")
    if n_skipped:
        notes.append(f"{name}: {_count(n_skipped, 'object')} without surface geometry at or below LoD {options.lod} left out")
    if unknown:
        detail = ", ".join(f"{k}: {v}" for k, v in unknown.items())
        notes.append(f"{name}: {_count(sum(unknown.values()), 'object')} of types that are not CityJSON core types "
                     f"given layer landscape ({detail})")

    mesh_v, tris, part, parts = b.finish(options.near, notes, warnings)
    return Mesh(mesh_v, tris, part, parts, warnings, notes, units="m", up_axis="z", site=site)


# ---------------------------------------------------------------------------------------------
# reading the JSON


def _load_documents(path: Path) -> list[tuple[str, dict]]:
    """The file's JSON objects with where they are: [("", CityJSON)] or [(":1", header), (":2", feature)...]."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read model file: {exc.strerror}") from None
    if path.name.lower().endswith(".jsonl"):
        return _load_sequence(path, data)
    try:
        doc = json.loads(data)
    except json.JSONDecodeError as exc:
        if exc.msg == "Extra data":  # a CityJSONSeq saved as .json: JSON objects one per line
            first = data.split(b"\n", 1)[0]
            try:
                head = json.loads(first.strip(b"\x1e \t\r"))
            except (json.JSONDecodeError, UnicodeDecodeError):
                head = None
            if isinstance(head, dict) and head.get("type") == "CityJSON":
                return _load_sequence(path, data)
        raise InputError(f"{path}:{exc.lineno}:{exc.colno}: not valid JSON ({exc.msg}); "
                         "fix the file or export it again") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not valid JSON (not UTF-8 text); is this a CityJSON file?") from None
    if not isinstance(doc, dict):
        raise InputError(f"{path}: JSON but not CityJSON (a {type(doc).__name__}, not an object with \"type\": "
                         "\"CityJSON\"); export the model as CityJSON")
    return [("", doc)]


def _load_sequence(path: Path, data: bytes) -> list[tuple[str, dict]]:
    """CityJSONSeq (§7.2): a CityJSON object, then one CityJSONFeature per line (RFC 7464 separators allowed)."""
    docs = []
    for lineno, line in enumerate(data.split(b"\n"), 1):
        rs = len(line) - len(line.lstrip(b"\x1e"))  # RFC 7464 record separators
        line = line[rs:]
        if not line.strip():
            continue
        try:
            doc = json.loads(line)
        except json.JSONDecodeError as exc:
            raise InputError(f"{path}:{lineno}:{exc.colno + rs}: not valid JSON ({exc.msg}); each line of a "
                             "CityJSONSeq must be one JSON object") from None
        except UnicodeDecodeError:
            raise InputError(f"{path}:{lineno}: not valid JSON (not UTF-8 text); is this a CityJSONSeq file?") from None
        kind = doc.get("type") if isinstance(doc, dict) else None
        if not docs:
            if kind != "CityJSON":
                raise InputError(f"{path}:{lineno}: JSON but not CityJSON: the first line of a CityJSONSeq must be an "
                                 f"object with \"type\": \"CityJSON\" (transform, metadata), found type {kind!r}")
        elif kind != "CityJSONFeature":
            raise InputError(f"{path}:{lineno}: expected a CityJSONFeature line, found type {kind!r}; each line after "
                             "the first must be a CityJSONFeature")
        docs.append((f":{lineno}", doc))
    if not docs:
        raise InputError(f"{path}: empty file; expected a CityJSON object")
    return docs


def _check_header(path: Path, header: dict) -> str:
    """The CityJSON version ("1.0", "1.1", "2.0"); InputError if the object is not CityJSON or the version is not read."""
    kind = header.get("type")
    if kind != "CityJSON":
        raise InputError(f"{path}: JSON but not CityJSON (\"type\" is {kind!r}, expected \"CityJSON\"); export the "
                         "model as CityJSON")
    version = header.get("version")
    short = ".".join(str(version).split(".")[:2]) if isinstance(version, (str, int, float)) else None
    if short not in VERSIONS:
        raise InputError(f"{path}: CityJSON version {version!r} is not supported (read: {', '.join(VERSIONS)}); "
                         f"upgrade it with 'cjio {path.name} upgrade save out.city.json'")
    return short


def _site(path: Path, header: dict) -> Site | None:
    """Site with the CRS of ``metadata.referenceSystem``, or None when the file names none."""
    meta = header.get("metadata")
    crs = normalise_crs(meta.get("referenceSystem")) if isinstance(meta, dict) else None
    if crs is None:
        return None
    m = re.fullmatch(r"EPSG:(\d+)", crs)
    if m and int(m.group(1)) in _GEOGRAPHIC_EPSG:
        raise InputError(f"{path}: metadata.referenceSystem is {crs}, in degrees; reproject it to a CRS in metres, "
                         f"e.g. 'cjio {path.name} crs_reproject 7415 save out.city.json'")
    return Site(crs=crs, source=f"{path.name}: metadata.referenceSystem")


def _vertices(path: Path, docs) -> tuple[np.ndarray, list, list]:
    """All documents' vertices as (n, 3) float64 [m], transformed (§4) in one step; each document's offset and count."""
    header = docs[0][1]
    lists, base, count = [], [], []
    n = 0
    for where, doc in docs:
        v = doc.get("vertices")
        if v is None and doc is header and len(docs) > 1:
            v = []
        if not isinstance(v, list):
            raise InputError(f"{path}{where}: no 'vertices' list; a CityJSON object must have \"vertices\": [[x, y, z], ...]")
        lists.append(v)
        base.append(n)
        count.append(len(v))
        n += len(v)
    if n == 0:
        raise InputError(f"{path}: no vertices: the file holds no geometry; export the model with its geometry")
    flat = lists[0] if len(lists) == 1 else list(chain.from_iterable(lists))
    try:
        raw = np.array(flat, dtype=np.float64)
    except (ValueError, TypeError):
        raw = None
    if raw is None or raw.ndim != 2 or raw.shape[1] != 3:
        raise InputError(f"{path}: 'vertices' must be a list of [x, y, z] numbers; validate the file with cjval")
    tr = header.get("transform")
    if tr is None:
        return raw, base, count
    try:
        scale = np.array(tr["scale"], dtype=np.float64).reshape(3)
        translate = np.array(tr["translate"], dtype=np.float64).reshape(3)
    except (KeyError, TypeError, ValueError):
        raise InputError(f"{path}: 'transform' must have \"scale\" and \"translate\", 3 numbers each; validate the "
                         "file with cjval") from None
    return raw * scale + translate, base, count


def _templates(path: Path, header: dict) -> tuple[list, np.ndarray]:
    """Geometry templates (§3.4) and their vertices, (k, 3) float64 [m], not transformed."""
    gt = header.get("geometry-templates")
    if not gt:
        return [], np.zeros((0, 3))
    try:
        templates = list(gt["templates"])
        tv = np.array(gt.get("vertices-templates") or np.zeros((0, 3)), dtype=np.float64).reshape(-1, 3)
    except (KeyError, TypeError, ValueError):
        raise InputError(f"{path}: 'geometry-templates' must have \"templates\" and \"vertices-templates\" [[x, y, z], ...]; "
                         "validate the file with cjval") from None
    return templates, tv


def _template_of(path, where, oid, gi, g, templates) -> dict:
    """The template a GeometryInstance refers to, or InputError naming the object."""
    t = g.get("template")
    if not isinstance(t, int) or isinstance(t, bool) or not 0 <= t < len(templates) or not isinstance(templates[t], dict):
        raise InputError(f"{path}{where}: object '{oid}' geometry[{gi}] (GeometryInstance) refers to template {t!r} "
                         f"but the file has {len(templates)} geometry-templates; validate the file with cjval")
    tpl = templates[t]
    if tpl.get("type") not in SURFACE_DEPTH and tpl.get("type") not in NON_SURFACE_TYPES:
        raise InputError(f"{path}: geometry-templates[{t}] has unknown type {tpl.get('type')!r} (used by object '{oid}'); "
                         f"template types are {', '.join([*SURFACE_DEPTH, *NON_SURFACE_TYPES])}")
    return tpl


# ---------------------------------------------------------------------------------------------
# objects: LoD, exclusion


def _parse_lod_request(path: Path, lod) -> tuple[int, int] | str | tuple[int]:
    """"highest", (major,) for "2", (major, minor) for "2.2"; InputError otherwise."""
    s = str(lod).strip()
    if s.lower() == "highest":
        return "highest"
    m = _LOD_RE.fullmatch(s)
    if not m:
        raise InputError(f"{path}: lod {lod!r} is not a CityJSON level of detail; use 'highest' or one like '2', '1.2', '2.2'")
    return (int(m.group(1)),) if m.group(2) is None else (int(m.group(1)), int(m.group(2)))


def _lod_key(lod) -> tuple[int, int]:
    """(major, minor) of a geometry's "lod" (a string since 1.1, a number in 1.0); (-1, 0) when missing or odd."""
    if isinstance(lod, bool) or lod is None:
        return (-1, 0)
    if isinstance(lod, (int, float)):
        lod = str(int(lod)) if float(lod).is_integer() else repr(float(lod))
    m = _LOD_RE.fullmatch(str(lod).strip())
    if not m:
        return (-1, 0)
    return (int(m.group(1)), int(m.group(2) or 0))


def _count(n: int, one: str, many: str | None = None) -> str:
    """'1 object', '3 objects'."""
    return f"{n} {one if n == 1 else (many or one + 's')}"


def _lod_label(key) -> str:
    return "?" if key[0] < 0 else (str(key[0]) if key[1] == 0 else f"{key[0]}.{key[1]}")


def _choose_lod(candidates, req):
    """The LoD key to read among an object's candidate geometries, and whether it is a fallback; (None, False) if none fits."""
    keys = [c[0] for c in candidates]
    if req == "highest":
        return max(keys), False
    if len(req) == 1:
        ok = [k for k in keys if k[0] <= req[0]]
        if not ok:
            return None, False
        best = max(ok)
        return best, best[0] != req[0]
    ok = [k for k in keys if k <= req]
    if not ok:
        return None, False
    best = max(ok)
    return best, best != req


def _excluded(by_id: dict, exclude, notes: list, name: str) -> set:
    """Ids to leave out: ``exclude`` and their descendants ("children", and objects naming them in "parents")."""
    if not exclude:
        return set()
    kids: dict = {}
    for oid, obj in by_id.items():
        for c in obj.get("children") or ():
            kids.setdefault(oid, set()).add(c)
        for p in obj.get("parents") or ():
            kids.setdefault(p, set()).add(oid)
    listed = [i for i in dict.fromkeys(exclude) if i in by_id]
    missing = [i for i in dict.fromkeys(exclude) if i not in by_id]
    out = set(listed)
    todo = list(listed)
    while todo:
        for c in kids.get(todo.pop(), ()):
            if c not in out and c in by_id:
                out.add(c)
                todo.append(c)
    if out:
        notes.append(f"{name}: {_count(len(out), 'object')} left out by exclude ({len(listed)} listed, "
                     f"{len(out) - len(listed)} of their descendants)")
    if missing:
        notes.append(f"{name}: {_count(len(missing), 'excluded id')} not in the file: "
                     f"{', '.join(missing[:5])}{' ...' if len(missing) > 5 else ''}")
    return out


# ---------------------------------------------------------------------------------------------
# flattening and triangulation


def _flatten(nested, depth: int) -> list:
    """The surfaces (or semantic values) of a boundary array with ``depth`` levels above them (§3.2)."""
    if depth == 0:
        return nested
    if depth == 1:
        return [s for shell in nested for s in shell]
    return [s for solid in nested for shell in solid for s in shell]


class _Builder:
    """Collects surfaces of all objects as flat lists, then triangulates them with numpy.

    Per geometry: its object, vertex base (offset of its vertex block) and limit (the block's
    length, for the range check); per surface: ring count and part; per ring: the local vertex
    indices as the file gives them. Nothing is looked at per vertex in Python.
    """

    def __init__(self, path: Path, vertices: np.ndarray, by_id: dict):
        self.path = path
        self.blocks = [vertices]
        self.nverts = len(vertices)
        self.by_id = by_id
        self.parts: list[Part] = []
        self.part_index: dict = {}
        self.obj_ids: list[str] = []  # kept objects, in order
        self.obj_where: list[str] = []
        self.g_obj: list[int] = []
        self.g_base: list[int] = []
        self.g_limit: list[int] = []
        self.g_nsurf: list[int] = []
        self.g_label: list[str] = []
        self.s_nrings: list[int] = []
        self.s_part: list[int] = []
        self.rings: list = []
        self.ring_len: list[int] = []
        self.bad_semantics = 0
        self.tpl_range: dict = {}

    # -- objects and parts

    def start_object(self, oid: str, obj: dict, cls: str, where: str) -> None:
        self.obj = len(self.obj_ids)
        self.obj_ids.append(oid)
        self.obj_where.append(where)
        attrs = {"class": cls, "id": oid}
        parents = obj.get("parents")
        if isinstance(parents, list) and parents:
            ptype = self.by_id.get(parents[0], {}).get("type") if isinstance(parents[0], str) else None
            if isinstance(ptype, str):
                attrs["parent"] = ptype
        self.attrs = attrs
        a = obj.get("attributes")
        scalar = (str, int, float, bool)
        self.free = {f"attr.{k}": v for k, v in a.items() if isinstance(v, scalar)} if isinstance(a, dict) else {}
        self.cls = cls

    def part_for(self, surface, solid: bool) -> int:
        surface = surface if isinstance(surface, str) else None
        layer, _ = default_layer(self.cls, surface, solid)
        key = (self.obj, surface, layer)
        i = self.part_index.get(key)
        if i is None:
            attrs = dict(self.attrs)
            if surface is not None:
                attrs["surface"] = surface
            attrs.update(self.free)
            i = self.part_index[key] = len(self.parts)
            self.parts.append(Part(attrs, layer=layer, obstructs_sun=True))
        return i

    # -- geometries

    def add_geometry(self, g: dict, gi: int, base: int, limit: int, label: str | None = None) -> None:
        gtype = g["type"]
        depth = SURFACE_DEPTH[gtype]
        solid = gtype in SOLID_TYPES
        oid = self.obj_ids[-1]
        label = label or f"object '{oid}' geometry[{gi}] ({gtype})"
        try:
            surfaces = _flatten(g["boundaries"], depth)
            nrings = list(map(len, surfaces))
            rings = list(chain.from_iterable(surfaces))
            ring_len = list(map(len, rings))
        except (KeyError, TypeError):
            raise InputError(f"{self.path}{self.obj_where[-1]}: {label}: 'boundaries' are not nested as a {gtype} "
                             f"({depth + 3} levels of arrays, §3.2); validate the file with cjval") from None
        n = len(surfaces)
        self.s_part.extend(self._semantic_parts(g, depth, n, solid))
        self.g_obj.append(self.obj)
        self.g_base.append(base)
        self.g_limit.append(limit)
        self.g_nsurf.append(n)
        self.g_label.append(label)
        self.s_nrings.extend(nrings)
        self.rings.extend(rings)
        self.ring_len.extend(ring_len)

    def _semantic_parts(self, g: dict, depth: int, n: int, solid: bool) -> list[int]:
        """Part index of each of the geometry's ``n`` surfaces from its semantics (§3.3)."""
        sem = g.get("semantics")
        if not isinstance(sem, dict):
            return [self.part_for(None, solid)] * n
        surfs = sem.get("surfaces") or []
        values = sem.get("values")
        if values is None:
            return [self.part_for(None, solid)] * n
        try:
            flat = _flatten(values, depth)
            ok = len(flat) == n and all(v is None or (type(v) is int and 0 <= v < len(surfs)) for v in flat)
        except TypeError:
            ok = False
        if not ok:
            self.bad_semantics += 1
            return [self.part_for(None, solid)] * n
        pm = [self.part_for(s.get("type") if isinstance(s, dict) else None, solid) for s in surfs]
        none = None
        out = []
        for v in flat:
            if v is None:
                if none is None:
                    none = self.part_for(None, solid)
                out.append(none)
            else:
                out.append(pm[v])
        return out

    def add_instance(self, tpl: dict, inst: dict, gi: int, tverts: np.ndarray, base: int, limit: int) -> None:
        """A GeometryInstance (§3.4): the template's vertices placed by its matrix at the reference point."""
        oid = self.obj_ids[-1]
        where = f"{self.path}{self.obj_where[-1]}: object '{oid}' geometry[{gi}] (GeometryInstance)"
        try:
            ref = inst["boundaries"][0]
            m = np.array(inst["transformationMatrix"], dtype=np.float64).reshape(4, 4)
        except (KeyError, IndexError, TypeError, ValueError):
            raise InputError(f"{where}: needs \"boundaries\": [reference vertex] and a 16-number \"transformationMatrix\"; "
                             "validate the file with cjval") from None
        if not isinstance(ref, int) or isinstance(ref, bool) or not 0 <= ref < limit:
            raise InputError(f"{where}: reference point {ref!r} is not a vertex of the file ({limit} vertices); "
                             "validate the file with cjval")
        t = inst["template"]
        lo, hi = self._template_range(t, tpl, tverts, oid)
        placed = tverts[lo:hi] @ m[:3, :3].T + m[:3, 3] + self.blocks[0][base + ref]
        self.blocks.append(placed)
        label = f"object '{oid}' geometry[{gi}] (GeometryInstance of template {t})"
        self.add_geometry(tpl, gi, self.nverts - lo, hi, label=label)
        self.nverts += len(placed)

    def _template_range(self, t: int, tpl: dict, tverts: np.ndarray, oid: str) -> tuple[int, int]:
        """[lo, hi) of the template vertices template ``t`` uses (checked once per template)."""
        r = self.tpl_range.get(t)
        if r is None:
            try:
                surfaces = _flatten(tpl["boundaries"], SURFACE_DEPTH[tpl["type"]])
                idx = np.fromiter(chain.from_iterable(chain.from_iterable(surfaces)), dtype=np.int64)
            except (KeyError, TypeError, ValueError):
                raise InputError(f"{self.path}: geometry-templates[{t}] ({tpl.get('type')}): 'boundaries' are not "
                                 "nested as its type says (§3.2); validate the file with cjval") from None
            if len(idx) == 0:
                r = (0, 0)
            elif idx.min() < 0 or idx.max() >= len(tverts):
                raise InputError(f"{self.path}: geometry-templates[{t}] (used by object '{oid}') refers to template "
                                 f"vertex {int(idx.max())} but there are {len(tverts)} vertices-templates; "
                                 "validate the file with cjval")
            else:
                r = (int(idx.min()), int(idx.max()) + 1)
            self.tpl_range[t] = r
        return r

    # -- numpy stage

    def finish(self, near, notes: list, warnings: list):
        """Vertices, triangles, part per triangle and parts, after range checks and near-culling."""
        name = self.path.name
        if self.bad_semantics:
            warnings.append(f"{name}: {_count(self.bad_semantics, 'geometry', 'geometries')} with semantics.values "
                            "that do not match their surfaces: their semantics ignored")
        vertices = np.concatenate(self.blocks) if len(self.blocks) > 1 else self.blocks[0]
        ring_len = np.array(self.ring_len, dtype=np.int64)
        s_nrings = np.array(self.s_nrings, dtype=np.int64)
        g_nsurf = np.array(self.g_nsurf, dtype=np.int64)
        try:
            local = np.fromiter(chain.from_iterable(self.rings), dtype=np.int64, count=int(ring_len.sum()))
        except (TypeError, ValueError):
            self._raise_bad_nesting()
        ring_surf = np.repeat(np.arange(len(s_nrings)), s_nrings)
        surf_geom = np.repeat(np.arange(len(g_nsurf)), g_nsurf)
        ring_geom = surf_geom[ring_surf]
        vert_geom = np.repeat(ring_geom, ring_len)
        limit = np.array(self.g_limit, dtype=np.int64)[vert_geom]
        bad = (local < 0) | (local >= limit)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            gi = int(vert_geom[i])
            raise InputError(f"{self.path}{self.obj_where[self.g_obj[gi]]}: {self.g_label[gi]} refers to vertex "
                             f"{int(local[i])} but there are {int(limit[i])} vertices; the file is corrupt, "
                             "validate it with cjval")
        gidx = local + np.array(self.g_base, dtype=np.int64)[vert_geom]
        del local, limit, bad

        surf_keep = np.ones(len(s_nrings), dtype=bool)
        g_obj = np.array(self.g_obj, dtype=np.int64)
        if near is not None and len(gidx):
            keep_obj = self._near(vertices, gidx, g_obj[vert_geom], near, notes)
            surf_keep &= keep_obj[g_obj[surf_geom]]
        tris, tri_surf = self._triangulate(vertices, gidx, ring_len, s_nrings, surf_keep, warnings)
        s_part = np.array(self.s_part, dtype=np.int64)
        order = np.argsort(tri_surf, kind="stable")
        tris, part = tris[order], s_part[tri_surf[order]]
        # keep only what the triangles use: vertices in file order, parts in file order
        used = np.zeros(len(vertices), dtype=bool)
        used[tris.ravel()] = True
        vmap = np.cumsum(used) - 1
        used_parts = np.zeros(len(self.parts), dtype=bool)
        used_parts[part] = True
        pmap = np.cumsum(used_parts) - 1
        parts = [p for p, u in zip(self.parts, used_parts) if u]
        return vertices[used], vmap[tris], pmap[part], parts

    def _raise_bad_nesting(self):
        """Find the first geometry whose rings hold something else than vertex indices and name it."""
        g = 0
        s_start = 0
        r_start = 0
        for gi, ns in enumerate(self.g_nsurf):
            nr = sum(self.s_nrings[s_start:s_start + ns])
            for ring in self.rings[r_start:r_start + nr]:
                if not all(type(v) is int for v in ring):
                    raise InputError(f"{self.path}{self.obj_where[self.g_obj[gi]]}: {self.g_label[gi]}: 'boundaries' "
                                     "are not nested as its type says (rings must be lists of vertex indices, §3.2); "
                                     "validate the file with cjval")
            s_start += ns
            r_start += nr
            g = gi
        raise InputError(f"{self.path}: {self.g_label[g]}: 'boundaries' hold something else than vertex indices; "
                         "validate the file with cjval")

    def _near(self, vertices, gidx, vert_obj, near, notes) -> np.ndarray:
        """Per kept object: does its vertex bounding box come within the radius of the point (in plan)?"""
        try:
            (px, py), radius = near
            px, py, radius = float(px), float(py), float(radius)
        except (TypeError, ValueError):
            raise InputError(f"{self.path}: near must be ((x, y), radius_m), got {near!r}") from None
        n_obj = len(self.obj_ids)
        starts = np.flatnonzero(np.r_[True, vert_obj[1:] != vert_obj[:-1]])
        objs = vert_obj[starts]
        xy = vertices[gidx, :2]
        lo = np.minimum.reduceat(xy, starts, axis=0)
        hi = np.maximum.reduceat(xy, starts, axis=0)
        dx = np.maximum(np.maximum(lo[:, 0] - px, px - hi[:, 0]), 0.0)
        dy = np.maximum(np.maximum(lo[:, 1] - py, py - hi[:, 1]), 0.0)
        keep = np.ones(n_obj, dtype=bool)
        keep[objs] = np.hypot(dx, dy) <= radius
        dropped = int(n_obj - keep.sum())
        if dropped:
            notes.append(f"{self.path.name}: {_count(dropped, 'object')} lying entirely farther than {radius:g} m "
                         f"from ({px:g}, {py:g}) left out")
        return keep

    def _triangulate(self, vertices, gidx, ring_len, s_nrings, surf_keep, warnings):
        """Triangles (t, 3) of global vertex indices and the surface of each (t,)."""
        ring_start = np.cumsum(ring_len) - ring_len
        first_ring = np.cumsum(s_nrings) - s_nrings
        has_ring = s_nrings > 0
        outer_len = np.zeros(len(s_nrings), dtype=np.int64)
        outer_len[has_ring] = ring_len[first_ring[has_ring]]
        valid = surf_keep & has_ring & (outer_len >= 3)
        n_degenerate = int((surf_keep & ~(has_ring & (outer_len >= 3))).sum())
        holes = valid & (s_nrings > 1)
        simple = valid & ~holes
        out_t, out_s = [], []
        n_failed = 0
        for k in np.unique(outer_len[simple]):
            rows = np.flatnonzero(simple & (outer_len == k))
            idx = gidx[ring_start[first_ring[rows]][:, None] + np.arange(k)]
            if k == 3:
                out_t.append(idx)
                out_s.append(rows)
                continue
            pts = vertices[idx]
            local = triangulate_polygons(pts)
            counts = np.fromiter(map(len, local), dtype=np.int64, count=len(local))
            poly = np.repeat(np.arange(len(rows)), counts)
            loc = np.concatenate(local) if len(local) else np.zeros((0, 3), dtype=np.int64)
            t = idx[poly[:, None], loc]
            n_failed += _count_lost_area(pts, vertices[t], poly, len(rows))
            out_t.append(t)
            out_s.append(rows[poly])
        if holes.any():
            rows = np.flatnonzero(holes)
            t, surf, lost = _triangulate_with_holes(vertices, gidx, ring_start, ring_len, first_ring, s_nrings, rows)
            n_failed += lost
            out_t.append(t)
            out_s.append(surf)
        name = self.path.name
        if n_degenerate:
            warnings.append(f"{name}: {_count(n_degenerate, 'surface')} with fewer than 3 vertices dropped")
        if n_failed:
            warnings.append(f"{name}: {_count(n_failed, 'polygon')} could not be fully triangulated "
                            "(self-intersecting or degenerate); their remaining area was dropped")
        if not out_t:
            return np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
        return np.concatenate(out_t).astype(np.int64), np.concatenate(out_s).astype(np.int64)


def _newell_area(polys: np.ndarray) -> np.ndarray:
    """Area [m^2] of (n, k, 3) planar polygons from the Newell normal, computed about each centroid."""
    c = polys - polys.mean(axis=1, keepdims=True)
    return 0.5 * np.linalg.norm(np.cross(c, np.roll(c, -1, axis=1)).sum(axis=1), axis=1)


def _count_lost_area(polys: np.ndarray, tri_pts: np.ndarray, poly: np.ndarray, n: int) -> int:
    """How many polygons' triangles cover less than 99.9 % of the polygon's area (ear clipping gave up)."""
    area = _newell_area(polys)
    tri_area = 0.5 * np.linalg.norm(np.cross(tri_pts[:, 1] - tri_pts[:, 0], tri_pts[:, 2] - tri_pts[:, 0]), axis=1)
    covered = np.bincount(poly, weights=tri_area, minlength=n)
    return int((covered < area * (1 - 1e-3) - 1e-9).sum())


def _triangulate_with_holes(vertices, gidx, ring_start, ring_len, first_ring, s_nrings, rows):
    """Ear-clip surfaces with holes, each in the best-fit (Newell) plane of its outer ring.

    The planes, the 2D projections and the areas are computed for all the surfaces at once;
    mapbox-earcut then runs once per surface with the ring ends (its hole indices).

    Parameters
    ----------
    vertices : (n, 3) float [m]
    gidx : (v,) int, global vertex index of every ring vertex, rings one after the other
    ring_start, ring_len : (r,) int, each ring's offset into ``gidx`` and vertex count
    first_ring, s_nrings : (s,) int, each surface's first ring and ring count
    rows : (h,) int, the surfaces to triangulate (two or more rings each)

    Returns
    -------
    triangles : (t, 3) int, global vertex indices
    surface : (t,) int, the surface (a value of ``rows``) of each triangle
    lost : how many surfaces' triangles cover less than 99.9 % of their area
    """
    import mapbox_earcut

    nr = s_nrings[rows]
    ring = np.repeat(first_ring[rows] - np.cumsum(nr) + nr, nr) + np.arange(nr.sum())  # ring ids, surface by surface
    ring_surf = np.repeat(np.arange(len(rows)), nr)
    is_outer = np.r_[True, ring_surf[1:] != ring_surf[:-1]]
    ok = is_outer | (ring_len[ring] >= 3)  # inner rings with fewer than 3 vertices are no holes
    ring, ring_surf, is_outer = ring[ok], ring_surf[ok], is_outer[ok]
    lens = ring_len[ring]
    off = np.cumsum(lens) - lens
    ids = gidx[np.repeat(ring_start[ring] - off, lens) + np.arange(lens.sum())]
    pts = vertices[ids]
    vert_ring = np.repeat(np.arange(len(ring)), lens)
    centre = np.add.reduceat(pts, off, axis=0) / lens[:, None]
    nxt = np.arange(len(pts)) + 1
    nxt[off + lens - 1] = off
    c = pts - centre[vert_ring]
    newell = np.add.reduceat(np.cross(c, c[nxt]), off, axis=0)  # (rings, 3): twice the area vector
    ring_area = 0.5 * np.linalg.norm(newell, axis=1)
    outer = np.flatnonzero(is_outer)
    n = newell[outer]
    norm = np.linalg.norm(n, axis=1)
    good = np.isfinite(norm) & (norm > 0)
    n = np.where(good[:, None], n / np.where(good, norm, 1.0)[:, None], [0.0, 0.0, 1.0])
    helper = np.where((np.abs(n[:, 2]) < 0.9)[:, None], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    u = np.cross(helper, n)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    v = np.cross(n, u)
    vert_surf = ring_surf[vert_ring]
    d = pts - centre[outer][vert_surf]
    flat = np.stack([np.einsum("ij,ij->i", d, u[vert_surf]), np.einsum("ij,ij->i", d, v[vert_surf])], axis=1)
    s_off = off[outer]
    s_end = np.r_[s_off[1:], len(pts)]
    r_end = off + lens  # ring ends, global; minus the surface's offset gives earcut's ring_end_indices
    r_bounds = np.r_[outer, len(ring)]
    out = []
    for i in np.flatnonzero(good):
        a = s_off[i]
        loc = mapbox_earcut.triangulate_float64(flat[a:s_end[i]], (r_end[r_bounds[i]:r_bounds[i + 1]] - a).astype(np.uint32))
        out.append(loc.astype(np.int64) + a)
    loc = np.concatenate(out).reshape(-1, 3) if out else np.zeros((0, 3), dtype=np.int64)
    tri_surf = vert_surf[loc[:, 0]]
    tp = pts[loc]
    tri_area = 0.5 * np.linalg.norm(np.cross(tp[:, 1] - tp[:, 0], tp[:, 2] - tp[:, 0]), axis=1)
    covered = np.bincount(tri_surf, weights=tri_area, minlength=len(rows))
    want = np.bincount(ring_surf, weights=np.where(is_outer, ring_area, -ring_area), minlength=len(rows))
    lost = int((good & (covered < want * (1 - 1e-3) - 1e-9)).sum())
    return ids[loc], rows[tri_surf], lost


# ---------------------------------------------------------------------------------------------
# helpers for the scene


def footprint_overlap(mesh: Mesh, footprint, min_share: float = 0.5, classes=BUILDING_CLASSES) -> list[str]:
    """Ids of the building objects standing on ``footprint``: to drop the checked building from a context tile.

    An object is one CityJSON id among the parts whose ``class`` is in ``classes`` (Building,
    BuildingPart and what belongs to a building by default). Its plan (xy projection of all its
    triangles, unioned) overlaps ``footprint`` by more than ``min_share`` of its own plan area.

    Parameters
    ----------
    mesh : a Mesh from :func:`read_cityjson` (parts with ``class`` and ``id``)
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
