"""The gbXML document as plain records: location, storeys, zones, spaces, surfaces and their openings.

gbXML (https://www.gbxml.org, schema 0.37 to 7.03; element and attribute names are the same in
all of them) is read with lxml's ``iterparse``: each ``Space``, ``Surface``, ``BuildingStorey``,
``Zone`` and ``Location`` is turned into a record as it ends and cleared, so the file's
schedules, constructions and results never sit in memory. Names are matched without their
namespace (files without one read the same). Coordinates are ``PlanarGeometry/PolyLoop/
CartesianPoint/Coordinate`` triples in the file's ``lengthUnit``, scaled to metres here.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError

#: gbXML lengthUnitEnum -> metres
LENGTH_UNITS = {"Kilometers": 1000.0, "Meters": 1.0, "Centimeters": 0.01, "Millimeters": 0.001, "Miles": 1609.344,
                "Yards": 0.9144, "Feet": 0.3048, "Inches": 0.0254}
#: gbXML areaUnitEnum -> square metres
AREA_UNITS = {"SquareKilometers": 1e6, "SquareMeters": 1.0, "SquareCentimeters": 1e-4, "SquareMillimeters": 1e-6,
              "SquareMiles": 1609.344 ** 2, "SquareYards": 0.9144 ** 2, "SquareFeet": 0.3048 ** 2, "SquareInches": 0.0254 ** 2}


def local(tag) -> str:
    if not isinstance(tag, str):
        return ""
    return tag[tag.index("}") + 1:] if tag[:1] == "{" else tag


def _child(el, name: str):
    for c in el:
        if local(c.tag) == name:
            return c
    return None


def _text(el, name: str) -> str:
    c = _child(el, name)
    return (c.text or "").strip() if c is not None else ""


def _loops(geom, scale: float) -> list[np.ndarray]:
    """Every PolyLoop below ``geom`` as (k, 3) float64 [m] (a repeated closing point dropped)."""
    out = []
    for loop in geom.iter("{*}PolyLoop", "PolyLoop"):
        pts = []
        for cp in loop:
            if local(cp.tag) != "CartesianPoint":
                continue
            xyz = [c.text for c in cp if local(c.tag) == "Coordinate"]
            pts.append((xyz + ["0", "0", "0"])[:3])
        try:
            v = np.array(pts, dtype=np.float64).reshape(-1, 3) * scale
        except ValueError:
            raise InputError("a CartesianPoint Coordinate is not a number") from None
        if len(v) > 3 and np.array_equal(v[0], v[-1]):
            v = v[:-1]
        out.append(v)
    return out


@dataclass
class Opening:
    id: str
    kind: str  # openingType
    name: str
    loop: np.ndarray | None  # (k, 3) [m]


@dataclass
class Surface:
    id: str
    kind: str  # surfaceType
    name: str
    cad: str
    spaces: tuple[str, ...]  # AdjacentSpaceId spaceIdRef, in file order
    loop: np.ndarray | None
    openings: list[Opening] = field(default_factory=list)


@dataclass
class SpaceRecord:
    id: str
    name: str
    storey: str  # buildingStoreyIdRef
    zone: str  # zoneIdRef
    shell: list[np.ndarray]  # ShellGeometry ClosedShell loops [m]
    planar: list[np.ndarray]  # the Space's own PlanarGeometry loops [m]
    area_m2: float | None = None  # the Space's Area as the file gives it, in m² (None: not given or no areaUnit)
    space_type: str = ""  # the Space's spaceType attribute (spaceTypeEnum, a load category: OfficeEnclosed...)


@dataclass
class Document:
    version: str
    unit: str
    scale: float
    area_scale: float | None = None  # areaUnit -> m², None where the file gives none (or an unknown one)
    latitude: float | None = None
    longitude: float | None = None
    elevation: float | None = None
    azimuth: float | None = None  # CADModelAzimuth [deg]
    spaces: list[SpaceRecord] = field(default_factory=list)
    surfaces: list[Surface] = field(default_factory=list)
    storeys: dict = field(default_factory=dict)
    zones: dict = field(default_factory=dict)


def _float(s: str) -> float | None:
    try:
        return float(s) if s else None
    except ValueError:
        return None


def read_document(path: Path, etree, unit: str | None = None) -> Document:
    """Parse ``path`` into a :class:`Document` (InputError for malformed XML, not gbXML, no or an unknown
    lengthUnit); ``unit`` (a gbXML length unit) overrides the file's lengthUnit, and its square the
    areaUnit where that is the square of the file's (see :func:`likely_unit`)."""
    doc = None
    tags = ["{*}Space", "{*}Surface", "{*}Location", "{*}BuildingStorey", "{*}Zone",
            "Space", "Surface", "Location", "BuildingStorey", "Zone"]
    try:
        for _, el in etree.iterparse(str(path), events=("end",), tag=tags, huge_tree=True):
            if doc is None:
                doc = _root(path, el.getroottree().getroot(), unit)
            name = local(el.tag)
            try:
                if name == "Space" and el.getparent() is not None and local(el.getparent().tag) == "Building":
                    doc.spaces.append(_space(el, doc.scale, doc.area_scale))
                elif name == "Surface" and el.getparent() is not None and local(el.getparent().tag) == "Campus":
                    doc.surfaces.append(_surface(el, doc.scale))
                elif name == "Location":
                    doc.latitude, doc.longitude = _float(_text(el, "Latitude")), _float(_text(el, "Longitude"))
                    doc.elevation, doc.azimuth = _float(_text(el, "Elevation")), _float(_text(el, "CADModelAzimuth"))
                elif name == "BuildingStorey":
                    doc.storeys[el.get("id", "")] = _text(el, "Name") or el.get("id", "")
                elif name == "Zone":
                    doc.zones[el.get("id", "")] = _text(el, "Name") or el.get("id", "")
                else:
                    continue
            except InputError as exc:
                raise InputError(f"{path}:{el.sourceline}: {name} '{el.get('id', '?')}': {exc}; export the file again") from None
            el.clear()
    except etree.XMLSyntaxError as exc:
        raise InputError(f"{path}:{exc.lineno or '?'}: not well-formed XML ({exc.msg}); the file is cut short or corrupt, "
                         "export it again") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read model file: {exc.strerror or exc}") from None
    if doc is None:
        try:
            root = etree.parse(str(path)).getroot()
        except etree.XMLSyntaxError as exc:
            raise InputError(f"{path}:{exc.lineno or '?'}: not well-formed XML ({exc.msg}); export it again") from None
        doc = _root(path, root, unit)
    return doc


def _root(path: Path, root, override: str | None = None) -> Document:
    if local(root.tag) != "gbXML":
        hint = " (a CityGML file: give it the ending .gml)" if local(root.tag) == "CityModel" else ""
        raise InputError(f"{path}: XML but not gbXML (root element '{local(root.tag)}', expected gbXML){hint}; "
                         "export the building model as gbXML")
    unit = root.get("lengthUnit")
    if not unit:
        raise InputError(f"{path}: the gbXML root has no lengthUnit (it is required); export the file again, or add "
                         "lengthUnit=\"Meters\" (or Feet, Inches, Millimeters...) to its <gbXML> element")
    if unit not in LENGTH_UNITS:
        raise InputError(f"{path}: lengthUnit '{unit}' is not a gbXML length unit ({', '.join(LENGTH_UNITS)}); "
                         "export the file again")
    area = root.get("areaUnit", "")
    if override is not None:
        area = f"Square{override}" if area == f"Square{unit}" else area
        unit = override
    return Document(version=root.get("version", "?"), unit=unit, scale=LENGTH_UNITS[unit], area_scale=AREA_UNITS.get(area))


#: The median height of a gbXML file's spaces [m] that rooms can have, read in its lengthUnit ...
SPACE_PLAUSIBLE_M = (1.8, 30.0)
#: ... and the range another unit must bring it into (the likeliest nearest the typical storey).
SPACE_LIKELY_M, SPACE_TYPICAL_M = (2.0, 8.0), 3.0


def likely_unit(doc: Document) -> tuple[str, float, float] | None:
    """(unit, median height read [m], median height in that unit [m]) where the spaces of ``doc``
    are implausible as rooms in its lengthUnit and one other gbXML unit makes them likely; else None.

    A space's height is the vertical extent of its ShellGeometry, else of the surfaces adjacent to
    it. A file that says Feet and writes metres (Ladybug Spider's SPEED generator: 4.0 "ft"
    storeys, 1.22 m) gives rooms nobody stands in: P above every window's head, no utilised area.
    """
    by_space: dict[str, list[np.ndarray]] = {}
    for srf in doc.surfaces:
        if srf.loop is not None:
            for sid in srf.spaces:
                by_space.setdefault(sid, []).append(srf.loop[:, 2])
    heights = []
    for sp in doc.spaces:
        z = [lp[:, 2] for lp in sp.shell] or by_space.get(sp.id, [])
        if z:
            zz = np.concatenate(z)
            heights.append(float(zz.max() - zz.min()))
    heights = [h for h in heights if h > 0]
    if not heights:
        return None
    med = float(np.median(heights))
    if SPACE_PLAUSIBLE_M[0] <= med <= SPACE_PLAUSIBLE_M[1]:
        return None
    best = None
    for name in ("Meters", "Centimeters", "Millimeters", "Feet", "Inches"):  # the units exports are written in
        h = med / doc.scale * LENGTH_UNITS[name]
        if name != doc.unit and SPACE_LIKELY_M[0] <= h <= SPACE_LIKELY_M[1]:
            score = abs(np.log(h / SPACE_TYPICAL_M))
            if best is None or score < best[0]:
                best = (score, name, h)
    return None if best is None else (best[1], med, best[2])


def _space(el, scale: float, area_scale: float | None = None) -> SpaceRecord:
    """A Space's record. Its shell is the ``ClosedShell`` of its ``ShellGeometry`` only: older Revit
    exports (2008-2010) also write an ``AnalyticalShell`` there, the space's surfaces on the walls'
    centre lines and the next level, with their openings; its loops are not the room's volume. A
    ``unit`` on the ShellGeometry (those exports write it) scales its coordinates."""
    shell = []
    sg = _child(el, "ShellGeometry")
    if sg is not None:
        closed = _child(sg, "ClosedShell")
        unit = LENGTH_UNITS.get(sg.get("unit", ""), scale)
        shell = _loops(closed, unit) if closed is not None else [lp for c in sg if local(c.tag) == "PolyLoop"
                                                                  for lp in _loops(c, unit)]
    pg = _child(el, "PlanarGeometry")
    area = _float(_text(el, "Area"))
    return SpaceRecord(id=el.get("id", ""), name=_text(el, "Name") or el.get("id", ""),
                       storey=el.get("buildingStoreyIdRef", ""), zone=el.get("zoneIdRef", ""), shell=shell,
                       planar=_loops(pg, scale) if pg is not None else [],
                       area_m2=None if area is None or area_scale is None or area <= 0 else area * area_scale,
                       space_type=el.get("spaceType", ""))


def _surface(el, scale: float) -> Surface:
    pg = _child(el, "PlanarGeometry")
    loops = _loops(pg, scale) if pg is not None else []
    openings = []
    for o in el:
        if local(o.tag) != "Opening":
            continue
        og = _child(o, "PlanarGeometry")
        ol = _loops(og, scale) if og is not None else []
        openings.append(Opening(id=o.get("id", ""), kind=o.get("openingType", ""), name=_text(o, "Name") or o.get("id", ""),
                                loop=ol[0] if ol else None))
    spaces = tuple(a.get("spaceIdRef", "") for a in el if local(a.tag) == "AdjacentSpaceId")
    return Surface(id=el.get("id", ""), kind=el.get("surfaceType", ""), name=_text(el, "Name") or el.get("id", ""),
                   cad=_text(el, "CADObjectId"), spaces=spaces, loop=loops[0] if loops else None, openings=openings)
