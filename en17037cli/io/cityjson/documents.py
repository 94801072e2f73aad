"""The CityJSON file as JSON: documents, header, version, CRS, vertices and geometry templates.

A ``.city.json`` / ``.json`` file is one CityJSON object; a CityJSONSeq (spec 2.0 §7.2;
``.city.jsonl``, ``.jsonl``, or a ``.json`` file holding a sequence) is a first line holding a
``"CityJSON"`` object with ``transform``, ``metadata`` and ``geometry-templates``, then one
``"CityJSONFeature"`` per line whose ``vertices`` are indexed locally. Each is a *document* here,
with where it is in the file (``""`` or ``":<line>"``) for the messages.

Coordinates (§3.1 Coordinates of the vertices, §4 Transform Object): ``vertex = integer * scale
+ translate``, in float64, for all vertices of the file in one numpy step (a 1.0 file without
``transform`` holds real coordinates). Template vertices (§3.4) are real coordinates and are not
transformed. CityJSON vertices are in the units of the file's CRS with z up; the reader returns
``Mesh(units="m", up_axis="z")`` because the CRSs of city models are projected ones in metres
(EPSG:7415, 28992, 25832...); a CRS in degrees (EPSG:4326, 4979...) is refused.

The CRS (§5.5 ``metadata.referenceSystem``, ``https://www.opengis.net/def/crs/EPSG/0/7415``;
1.0 §5.1 ``urn:ogc:def:crs:EPSG::7415``) becomes ``Mesh.site.crs = "EPSG:7415"``; for a
CityJSONSeq it comes from the first line.
"""
from __future__ import annotations

import json
import re
from itertools import chain
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.mesh import Site

#: CityJSON versions read (the file's "version", major.minor)
VERSIONS = ("1.0", "1.1", "2.0")

#: surface geometry type -> how many levels of arrays lie above the surfaces (§3.2)
SURFACE_DEPTH = {"MultiSurface": 0, "CompositeSurface": 0, "Solid": 1, "MultiSolid": 2, "CompositeSolid": 2}
SOLID_TYPES = frozenset(("Solid", "MultiSolid", "CompositeSolid"))
NON_SURFACE_TYPES = frozenset(("MultiPoint", "MultiLineString"))
GEOMETRY_TYPES = ("MultiPoint", "MultiLineString", *SURFACE_DEPTH, "GeometryInstance")

#: EPSG codes of common geographic (degree) CRSs, refused: their coordinates are not metres
_GEOGRAPHIC_EPSG = frozenset((4326, 4979, 4258, 4937, 4269, 4617, 4283, 4490, 4612, 4167))


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


def load_documents(path: Path) -> list[tuple[str, dict]]:
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


def check_header(path: Path, header: dict) -> str:
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


def header_site(path: Path, header: dict) -> Site | None:
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


def all_vertices(path: Path, docs) -> tuple[np.ndarray, list, list]:
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


def header_templates(path: Path, header: dict) -> tuple[list, np.ndarray]:
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


def template_of(path, where, oid, gi, g, templates) -> dict:
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
