"""What a city object means for the check: its default layer, the level of detail read, and exclusion.

One table for CityJSON and CityGML (the same data model: CityJSON types are CityGML classes);
the rows marked (G) are CityGML names that CityJSON writes otherwise or not at all.

Level of detail (``ReadOptions.lod``): ``"highest"`` takes each object's highest LoD; a given
LoD (``"2.2"``, ``"1.2"``, ``"2"``...) takes it, or else the highest LoD below it (one note counts
the fallbacks); ``"2"`` takes the highest of 2, 2.0, 2.1... Objects with surface geometry, but
none at or below the LoD, are left out (counted note). All geometries of the chosen LoD are read.

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
| (G) `ReliefFeature`, `RasterRelief`, `Track`, `Square`, `Intersection`, `Section` | ground | |
| (G) `GenericOccupiedSpace`, `GenericUnoccupiedSpace` (3.0) | landscape | |
| `BuildingRoom`, `BuildingStorey`, `BuildingUnit`, `BuildingFurniture` | ignore | inside a shell (1) |
| `BridgeRoom`, `BridgeFurniture`, `TunnelHollowSpace`, `TunnelFurniture` | ignore | inside a shell (1) |
| (G) `Room`, `IntBuildingInstallation`, `IntBridgeInstallation`, `IntTunnelInstallation`, `HollowSpace`, `Storey` | ignore | inside a shell (1) |
| `CityObjectGroup`, (G) `GenericLogicalSpace` | ignore | groups objects that have their own geometry |
| any other type (an Extension's `+Something`) | landscape | counted in a note |

(1) Never seen from outside; as landscape, the checked building's rooms would fill the checked room.

The steep faces of a ``ground`` object that rise more than 0.5 m above its base (a LoD1 block of
PlantCover, a wall along a LandUse) go to ``landscape`` with ``slope: steep``
(:mod:`~en17037cli.io.cityjson.relief`).

Other semantic surfaces keep their object's layer: a context building's ``Window`` and ``Door``
surfaces are landscape (the ``window`` layer is the checked room's glazing, from its own model).

``Part.obstructs_sun`` is True for every part, vegetation included (``SolitaryVegetationObject``
and ``PlantCover`` solids): whether foliage lets the sun through is the project's decision (a
layer rule with ``obstructs_sun: false``).

``ReadOptions.exclude`` leaves out objects by id together with their descendants
(``"children"``, and objects naming them in ``"parents"``, recursively).
"""
from __future__ import annotations

import re
from pathlib import Path

from en17037cli.errors import InputError

_LANDSCAPE = frozenset((
    "Building", "BuildingPart", "BuildingInstallation", "BuildingConstructiveElement",
    "Bridge", "BridgePart", "BridgeInstallation", "BridgeConstructiveElement", "BridgeConstructionElement",
    "Tunnel", "TunnelPart", "TunnelInstallation", "TunnelConstructiveElement",
    "CityFurniture", "GenericCityObject", "OtherConstruction", "SolitaryVegetationObject",
    "GenericOccupiedSpace", "GenericUnoccupiedSpace",
))
_GROUND = frozenset(("TINRelief", "LandUse", "Road", "Railway", "TransportSquare", "WaterBody", "Waterway",
                     "ReliefFeature", "RasterRelief", "Track", "Square", "Intersection", "Section"))
_IGNORE = frozenset((
    "BuildingRoom", "BuildingStorey", "BuildingUnit", "BuildingFurniture", "BridgeRoom", "BridgeFurniture",
    "TunnelHollowSpace", "TunnelFurniture", "CityObjectGroup",
    "Room", "IntBuildingInstallation", "IntBridgeInstallation", "IntTunnelInstallation", "HollowSpace", "Storey",
    "GenericLogicalSpace",
))
_IGNORED_SURFACES = frozenset(("ClosureSurface", "WaterClosureSurface", "InteriorWallSurface", "CeilingSurface", "FloorSurface"))
_BUILDING = frozenset(("Building", "BuildingPart"))

#: Every city object type of the table (CityJSON types and CityGML feature classes): what starts a
#: new object when a CityGML document is walked
CITY_OBJECT_TYPES = _LANDSCAPE | _GROUND | _IGNORE | {"PlantCover"}

#: Semantic (thematic) surface types of CityJSON (§3.3) and CityGML 1.0-3.0 boundary surfaces:
#: they label faces of their object, they are not objects of their own
SURFACE_TYPES = frozenset((
    "RoofSurface", "GroundSurface", "WallSurface", "ClosureSurface", "OuterCeilingSurface", "OuterFloorSurface",
    "Window", "Door", "InteriorWallSurface", "CeilingSurface", "FloorSurface", "WaterSurface", "WaterGroundSurface",
    "WaterClosureSurface", "TrafficArea", "AuxiliaryTrafficArea", "TransportationMarking", "TransportationHole",
    "Marking", "HoleSurface", "GenericThematicSurface",
))

#: CityObject types whose parts :func:`~en17037cli.io.cityjson.footprint_overlap` considers: a building and what belongs to it
BUILDING_CLASSES = ("Building", "BuildingPart", "BuildingInstallation", "BuildingConstructiveElement")

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


def counted(n: int, one: str, many: str | None = None) -> str:
    """'1 object', '3 objects': a count in the reader's notes and warnings."""
    return f"{n} {one if n == 1 else (many or one + 's')}"


# ---------------------------------------------------------------------------------------------
# level of detail


def parse_lod_request(path: Path, lod) -> tuple[int, int] | str | tuple[int]:
    """"highest", (major,) for "2", (major, minor) for "2.2"; InputError otherwise."""
    s = str(lod).strip()
    if s.lower() == "highest":
        return "highest"
    m = _LOD_RE.fullmatch(s)
    if not m:
        raise InputError(f"{path}: lod {lod!r} is not a CityJSON level of detail; use 'highest' or one like '2', '1.2', '2.2'")
    return (int(m.group(1)),) if m.group(2) is None else (int(m.group(1)), int(m.group(2)))


def lod_key(lod) -> tuple[int, int]:
    """(major, minor) of a geometry's "lod" (a string since 1.1, a number in 1.0); (-1, 0) when missing or odd."""
    if isinstance(lod, bool) or lod is None:
        return (-1, 0)
    if isinstance(lod, (int, float)):
        lod = str(int(lod)) if float(lod).is_integer() else repr(float(lod))
    m = _LOD_RE.fullmatch(str(lod).strip())
    if not m:
        return (-1, 0)
    return (int(m.group(1)), int(m.group(2) or 0))


def lod_label(key) -> str:
    """A LoD key as the notes write it: "2", "2.2", or "?" when the geometry has none."""
    return "?" if key[0] < 0 else (str(key[0]) if key[1] == 0 else f"{key[0]}.{key[1]}")


def choose_lod(candidates, req):
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


# ---------------------------------------------------------------------------------------------
# exclusion


def excluded_ids(by_id: dict, exclude, notes: list, name: str) -> set:
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
        notes.append(f"{name}: {counted(len(out), 'object')} left out by exclude ({len(listed)} listed, "
                     f"{len(out) - len(listed)} of their descendants)")
    if missing:
        notes.append(f"{name}: {counted(len(missing), 'excluded id')} not in the file: "
                     f"{', '.join(missing[:5])}{' ...' if len(missing) > 5 else ''}")
    return out
