"""The buildings of a CityGML file and their wall surfaces (see :mod:`~en17037cli.district.walls`).

Streamed like the context reader (:mod:`en17037cli.io.citygml`): lxml's ``iterparse`` hands one
``cityObjectMember`` at a time, whose ``Building`` (with its ``BuildingPart``\\s) is walked and then
dropped. A wall is a ``WallSurface`` element (its handle: the building's id and its number among the building's
``WallSurface`` elements in document order; its ``gml:id``, where it has one, labels it) with its polygons at
the LoD read for its object: the highest ``lod<N>`` property of the object's thematic surfaces
within the project's ``lod`` (CityGML LoDs are whole numbers). An object without thematic surfaces
(LoD1 blocks) gives the upright polygons of its ``lod<N>Solid`` / ``MultiSurface``, as
(object id, polygon number). Coordinates are placed as the context reader places them
(:class:`~en17037cli.io.citygml.crs.CrsResolver`: axis order, heights in metres) in the file's own CRS.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from en17037cli.district.walls import CityBuilding, Wall, is_closed, is_wall_polygon
from en17037cli.errors import InputError
from en17037cli.io.citygml.crs import CrsResolver
from en17037cli.io.citygml.walk import Walk, gml_id, local, polygons_below
from en17037cli.io.cityjson.semantics import parse_lod_request

_LOD = re.compile(r"lod(\d)")
#: Member elements (CityGML 1.0-3.0, GML feature collections)
MEMBERS = ("cityObjectMember", "featureMember", "member")


def read_buildings_gml(path: Path, lod: str, exclude, crs: str | None) -> tuple[list[CityBuilding], str | None]:
    """The ``Building`` features of a CityGML file with their walls, in file order, and its CRS."""
    from en17037cli.io.citygml import _lxml

    etree = _lxml(path)
    req = parse_lod_request(path, lod)
    max_lod = 9 if req == "highest" else req[0]
    resolver = CrsResolver(path, crs, None)
    excluded = set(exclude)
    out: list[CityBuilding] = []
    default = [None]
    try:
        for _, el in etree.iterparse(str(path), events=("end",), tag=[f"{{*}}{t}" for t in (*MEMBERS, "Envelope")],
                                     huge_tree=True, remove_blank_text=True):
            name = local(el.tag)
            if name == "Envelope":
                if default[0] is None:
                    default[0] = el.get("srsName")
                continue
            for feature in el:
                if local(feature.tag) == "Building" and (gml_id(feature) or "") not in excluded:
                    out.append(_building(feature, excluded, max_lod, resolver, default[0], path).finish())
            el.clear()
            parent = el.getparent()
            if parent is not None:
                while el.getprevious() is not None:
                    del parent[0]
    except etree.XMLSyntaxError as exc:
        raise InputError(f"{path}:{exc.lineno or '?'}: not well-formed XML ({exc.msg}); export the file again") from None
    return out, resolver.out_name


def _objects(building, excluded: set) -> list:
    """The building element and its BuildingPart elements (not those excluded), document order."""
    parts = [e for e in building.iter() if local(e.tag) == "BuildingPart" and (gml_id(e) or "") not in excluded]
    return [building, *parts]


def _owner(el):
    """The nearest enclosing Building or BuildingPart element."""
    p = el.getparent()
    while p is not None and local(p.tag) not in ("Building", "BuildingPart"):
        p = p.getparent()
    return p


def _srs(el, default):
    """The srsName on the element, below it, or on an enclosing one; else the file's envelope's."""
    for e in el.iter():
        s = e.get("srsName")
        if s:
            return s
    p = el.getparent()
    while p is not None:
        if p.get("srsName"):
            return p.get("srsName")
        p = p.getparent()
    return default


def _lod_props(el, max_lod: int) -> dict:
    """lod<N> geometry properties directly below ``el`` (N <= max_lod) by N."""
    out: dict = {}
    for child in el:
        m = _LOD.match(local(child.tag))
        if m and int(m.group(1)) <= max_lod and "Implicit" not in local(child.tag):
            out.setdefault(int(m.group(1)), []).append(child)
    return out


def _polygons(prop, resolver: CrsResolver, default, path: Path) -> list:
    """The polygons below a geometry property, each [outer ring (k, 3), holes...] [m]."""
    rings: list = []
    tokens: list = []
    polygons_below(prop, rings, tokens, Walk())
    if not rings:
        return []
    try:
        v = np.array(tokens, dtype=np.float64).reshape(-1, 3)
    except ValueError:
        raise InputError(f"{path}: a posList holds something else than numbers; validate the file") from None
    placement = resolver.placement(_srs(prop, default), v[0, :2] if len(v) else None)
    if placement is not None:
        v = placement.apply(v)
    out, k = [], 0
    for lens in rings:
        poly = []
        for n in lens:
            ring = v[k:k + n]
            k += n
            if len(ring) > 1 and np.array_equal(ring[0], ring[-1]):
                ring = ring[:-1]
            poly.append(ring)
        if len(poly[0]) >= 3:
            out.append(poly)
    return out


def _building(feature, excluded: set, max_lod: int, resolver: CrsResolver, default, path: Path) -> CityBuilding:
    objs = _objects(feature, excluded)
    bid = gml_id(feature) or f"Building#{feature.sourceline}"
    b = CityBuilding(bid, tuple(gml_id(o) or f"{local(o.tag)}#{o.sourceline}" for o in objs))
    thematic = ("WallSurface", "RoofSurface", "GroundSurface", "ClosureSurface", "OuterFloorSurface", "OuterCeilingSurface")
    surfaces = [e for e in feature.iter() if local(e.tag) in thematic]  # kept: one proxy per element
    walls = [e for e in surfaces if local(e.tag) == "WallSurface"]
    owners = [_owner(e) for e in surfaces]
    for obj, oid in zip(objs, b.objects):
        own = [e for e, o in zip(surfaces, owners) if o is obj]
        if own:
            lods = sorted({n for e in own for n in _lod_props(e, max_lod)})
            if not lods:
                continue
            for k, e in enumerate(walls):
                if _owner(e) is not obj:
                    continue
                props = _lod_props(e, max_lod).get(lods[-1], [])
                polys = [p for prop in props for p in _polygons(prop, resolver, default, path)]
                if polys:
                    b.walls.append(Wall(gml_id(e) or f"{oid}/w{k}", oid, polys, ("citygml", bid, k)))
            shell = [p for e in own for prop in _lod_props(e, max_lod).get(lods[-1], [])
                     for p in _polygons(prop, resolver, default, path)]
            if any(local(e.tag) == "GroundSurface" for e in own) and not is_closed(shell):
                b.open_objects.append(oid)
        else:  # a block without thematic surfaces: its upright polygons
            props = _lod_props(obj, max_lod)
            if not props:
                continue
            polys = [p for prop in props[max(props)] for p in _polygons(prop, resolver, default, path)]
            if any("Solid" in local(prop.tag) for prop in props[max(props)]) and not is_closed(polys):
                b.open_objects.append(oid)
            for i, p in enumerate(polys):
                if is_wall_polygon(p[0]):
                    b.walls.append(Wall(f"{oid}/p{i}", oid, [p], ("citygml-polygon", bid, oid, i)))
    return b
