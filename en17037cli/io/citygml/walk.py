"""One ``cityObjectMember`` of a CityGML document walked into city objects and their polygons.

The walk knows CityGML by local element names, so 1.0, 2.0 and 3.0 read alike (their namespaces
differ, their names mostly do not):

- an element whose name is a city object type of the class table
  (:data:`~en17037cli.io.cityjson.semantics.CITY_OBJECT_TYPES`: ``Building``, ``BuildingPart``,
  ``TINRelief``, ``SolitaryVegetationObject``...) starts an object, a child of the enclosing one;
- an element named as a thematic surface (``WallSurface``, ``RoofSurface``, ``Window``...,
  :data:`~en17037cli.io.cityjson.semantics.SURFACE_TYPES`) labels the faces below it;
- a geometry property ``lod<N>...`` (``lod2Solid``, ``lod2MultiSurface``, ``lod0FootPrint``,
  ``lod3ImplicitRepresentation``...) or ``tin`` (a TINRelief's, LoD from its ``lod``) holds the
  polygons, at LoD N: every ``gml:Polygon``, ``gml:Triangle``, ``gml:Rectangle`` and
  ``gml:PolygonPatch`` below it, outer ring first (``exterior`` / GML 2 ``outerBoundaryIs``),
  then its holes; coordinates from ``posList``, ``pos`` sequences or GML 2 ``coordinates``;
- everything else is walked through (``boundedBy``, ``consistsOfBuildingPart``, ``opening``...).

Polygons given by reference (``xlink:href``, as a ``lod2Solid`` lists the polygons of the
thematic surfaces) are counted once, where they are written out. An implicit geometry (a
template tree) is placed by its ``transformationMatrix`` M (4x4, row major) at its
``referencePoint`` r: ``world = M[:3, :3] @ v + M[:3, 3] + r`` (CityGML 2.0 §8.3.1, 10.3.4); a
template given by reference is the one first written out with that id.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from en17037cli.io.cityjson.semantics import CITY_OBJECT_TYPES, SURFACE_TYPES

XLINK_HREF = "{http://www.w3.org/1999/xlink}href"
GML_ID = ("{http://www.opengis.net/gml}id", "{http://www.opengis.net/gml/3.2}id")
_LOD_PROP = re.compile(r"lod(\d)")
_POLYGONS = frozenset(("Polygon", "Triangle", "Rectangle", "PolygonPatch"))
_SOLIDS = frozenset(("Solid", "MultiSolid", "CompositeSolid"))
_SKIP = frozenset(("appearance", "externalReference", "appearanceMember", "generalizesTo", "address", "Address"))
_OUTER = frozenset(("exterior", "outerBoundaryIs"))
_INNER = frozenset(("interior", "innerBoundaryIs"))


def local(tag) -> str:
    """An element's name without its namespace ('' for comments and processing instructions)."""
    if not isinstance(tag, str):
        return ""
    return tag[tag.index("}") + 1:] if tag[:1] == "{" else tag


def gml_id(el) -> str | None:
    for key in GML_ID:
        v = el.get(key)
        if v:
            return v
    return None


@dataclass
class CityObject:
    """A city object met in the walk: its polygons by LoD, before any is chosen.

    polys : (lod, surface type or None, solid, srsName or None, ring lengths, flat coordinate tokens)
    """

    oid: str
    cls: str
    parent: int | None
    parent_cls: str | None
    attrs: dict = field(default_factory=dict)
    polys: list = field(default_factory=list)
    lod_hint: int | None = None  # a TINRelief's own lod


@dataclass
class Walk:
    """What one walk collected, and the counts for the notes."""

    objects: list[CityObject] = field(default_factory=list)
    curves: int = 0  # geometry properties without surfaces (curves, points, terrain intersections)
    hrefs: int = 0  # polygons given by reference
    no_triangles: int = 0  # gml:Tin without triangles (control points only)
    templates: dict = field(default_factory=dict)  # implicit geometry id -> (rings, tokens)
    excluded: set = field(default_factory=set)  # ids of the objects left out by exclude (with descendants)


def _srs(prop) -> str | None:
    """The srsName of a geometry property: on its geometry or any element below."""
    for el in prop.iter():
        s = el.get("srsName")
        if s:
            return s
    return None


def _dim(el, default: int = 3) -> int:
    d = el.get("srsDimension")
    try:
        return int(d) if d else default
    except ValueError:
        return default


def _ring_tokens(ring, out: list) -> int:
    """Append a LinearRing's coordinates (as text tokens, 3 per vertex) to ``out``; its vertex count."""
    n0 = len(out)
    for el in ring.iter():
        name = local(el.tag)
        if name == "posList":
            vals = (el.text or "").split()
            dim = _dim(el, _dim(ring))
            if dim == 3:
                out.extend(vals)
            elif dim == 2:
                for i in range(0, len(vals) - 1, 2):
                    out.extend((vals[i], vals[i + 1], "0"))
        elif name == "pos":
            vals = (el.text or "").split()
            out.extend((vals + ["0", "0", "0"])[:3] if len(vals) < 3 else vals[:3])
        elif name == "coordinates":  # GML 2: "x,y,z x,y,z"
            cs, ts = el.get("cs", ","), el.get("ts", " ")
            for tup in (el.text or "").strip().split(ts if ts.strip() else None):
                vals = tup.split(cs)
                out.extend((vals + ["0", "0", "0"])[:3])
    n = len(out) - n0
    if n % 3:
        del out[n0 + n - n % 3:]
    return n // 3


def polygons_below(prop, rings_out: list, tokens: list, walk: Walk) -> tuple[int, int]:
    """Rings of every polygon below ``prop``: appends (ring lengths of one polygon) to ``rings_out``
    and the coordinate tokens to ``tokens``; (polygons, references) counted."""
    n_poly = n_ref = 0
    for el in prop.iter():
        name = local(el.tag)
        if name in _POLYGONS:
            lens = []
            for child in el:
                cname = local(child.tag)
                if cname in _OUTER or cname in _INNER:
                    for ring in child:
                        if local(ring.tag) in ("LinearRing", "Ring"):
                            k = _ring_tokens(ring, tokens)
                            if cname in _OUTER:
                                lens.insert(0, k)
                            else:
                                lens.append(k)
                elif cname == "LinearRing":  # a gml:Triangle's or Rectangle's ring given directly
                    lens.append(_ring_tokens(child, tokens))
            if lens:
                rings_out.append(lens)
                n_poly += 1
        elif el.get(XLINK_HREF) is not None and (name.endswith("Member") or name in ("surfaceMember", "exterior")):
            n_ref += 1
    return n_poly, n_ref


def _implicit(prop, walk: Walk):
    """(rings, tokens) of an ImplicitGeometry placed in the world, or None."""
    geo = next((el for el in prop.iter() if local(el.tag) == "ImplicitGeometry"), None)
    if geo is None:
        return None
    matrix = ref = rel = None
    for child in geo:
        name = local(child.tag)
        if name == "transformationMatrix":
            matrix = child.text
        elif name == "referencePoint":
            pts: list = []
            _ring_tokens(child, pts)
            ref = pts[:3]
        elif name == "relativeGMLGeometry":
            rel = child
    if rel is None or ref is None or len(ref) < 3:
        return None
    href = rel.get(XLINK_HREF)
    if href:
        tpl = walk.templates.get(href.lstrip("#"))
    else:
        rings: list = []
        toks: list = []
        polygons_below(rel, rings, toks, walk)
        tpl = (rings, np.array(toks, dtype=np.float64).reshape(-1, 3))
        first = next((c for c in rel if isinstance(c.tag, str)), None)
        if first is not None and gml_id(first):
            walk.templates[gml_id(first)] = tpl
    if tpl is None or not tpl[0]:
        return None
    rings, v = tpl
    try:
        m = np.array((matrix or "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1").split(), dtype=np.float64).reshape(4, 4)
        r = np.array(ref, dtype=np.float64)
    except ValueError:
        return None
    return rings, v @ m[:3, :3].T + m[:3, 3] + r


def _attributes(el, attrs: dict) -> None:
    """Simple attributes of an object: its text-only children (``bldg:function``, ``bldg:roofType``...)
    and generic attributes (2.0 ``gen:stringAttribute name=``, 3.0 ``gen:genericAttribute``)."""
    for child in el:
        name = local(child.tag)
        if not name or name in CITY_OBJECT_TYPES:
            continue
        if name.endswith("Attribute") and child.get("name"):
            val = next((c.text for c in child if local(c.tag) == "value"), None)
            if val and val.strip():
                attrs[f"attr.{child.get('name')}"] = val.strip()
        elif name == "genericAttribute":
            for g in child:
                kv = {local(c.tag): (c.text or "").strip() for c in g}
                if kv.get("name") and kv.get("value"):
                    attrs[f"attr.{kv['name']}"] = kv["value"]
        elif len(child) == 0 and child.text and child.text.strip() and name not in ("name", "description", "lod"):
            attrs.setdefault(f"attr.{name}", child.text.strip())


def walk_member(member, walk: Walk, exclude: set) -> None:
    """Walk one ``cityObjectMember`` (or ``featureMember``), adding its objects to ``walk``."""
    stack = [(child, None, None) for child in reversed(member)]
    # iterative depth-first walk: (element, enclosing object index, surface type); the member's own
    # child is an object whatever its name (an ADE's class is landscape, counted in a note)
    while stack:
        el, obj, surface = stack.pop()
        name = local(el.tag)
        if not name or name in _SKIP:
            continue
        if name in CITY_OBJECT_TYPES or (obj is None and el.getparent() is member):
            oid = gml_id(el) or f"{name}#{len(walk.objects) + 1}"
            parent = walk.objects[obj] if obj is not None else None
            if oid in exclude:  # left out with the objects inside it
                walk.excluded.add(oid)
                walk.excluded.update(gml_id(d) or f"{local(d.tag)}@{id(d)}" for d in el.iterdescendants()
                                     if local(d.tag) in CITY_OBJECT_TYPES)
                continue
            o = CityObject(oid, name, obj, parent.cls if parent is not None else None)
            _attributes(el, o.attrs)
            lod = next((c.text for c in el if local(c.tag) == "lod"), None)
            if lod and lod.strip().isdigit():
                o.lod_hint = int(lod.strip())
            walk.objects.append(o)
            obj, surface = len(walk.objects) - 1, None
            stack.extend((c, obj, surface) for c in reversed(el))
            continue
        if name in SURFACE_TYPES:
            stack.extend((c, obj, name) for c in reversed(el))
            continue
        m = _LOD_PROP.match(name)
        if (m or name == "tin") and obj is not None:
            o = walk.objects[obj]
            lod = int(m.group(1)) if m else (o.lod_hint if o.lod_hint is not None else -1)
            if "Implicit" in name:
                placed = _implicit(el, walk)
                if placed is None:
                    walk.curves += 1
                    continue
                rings, v = placed
                o.polys.append((lod, surface, False, _srs(el), rings, v))
                continue
            rings: list = []
            tokens: list = []
            n_poly, n_ref = polygons_below(el, rings, tokens, walk)
            walk.hrefs += n_ref
            if n_poly:
                solid = any(local(c.tag) in _SOLIDS for c in el)
                o.polys.append((lod, surface, solid, _srs(el), rings, tokens))
            elif not n_ref:
                if any(local(c.tag) == "Tin" for c in el.iter()):
                    walk.no_triangles += 1
                else:
                    walk.curves += 1
            continue
        stack.extend((c, obj, surface) for c in reversed(el))
