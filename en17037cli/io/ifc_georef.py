"""An IFC model's IfcMapConversion read by the schema's rules for units, and checked.

The schema (IFC4 ADD2 TC1 8.18.3.6, IFC4.3 IfcMapConversion and IfcProjectedCRS): a point
(x, y, z) of the model, in the project's length unit, is in the map CRS at

    E = Eastings + Scale (x a - y b),  N = Northings + Scale (x b + y a),  H = OrthogonalHeight + Scale z

with (a, b) the unit direction of (XAxisAbscissa, XAxisOrdinate). Eastings, Northings and
OrthogonalHeight are in the map's unit: IfcProjectedCRS.MapUnit, else the project's length unit;
Scale (default 1) converts the project's unit to the map's, so that Scale x (project unit) =
(map unit). IFC4.3's IfcMapConversionScaled multiplies x, y and z further by FactorX, FactorY,
FactorZ (a grid's scale factor, not a unit); a draft of IFC4.3 wrote ScaleY and ScaleZ beside
Scale, read where a file has them.

What exports write (:func:`map_conversion` reads every case to metres):

| file | read |
|---|---|
| the units agree: Scale x MapUnit = the project's unit (within 1 %) | as the schema says |
| Revit 2020: a millimetre project, no MapUnit, no Scale, Eastings in millimetres | as the schema says: in millimetres |
| a millimetre project, MapUnit metre, no Scale (Scale should be 0.001) | offsets in metres; the model keeps its own size |
| Bonsai: a millimetre project, no MapUnit, Scale 0.001 (MapUnit metre meant) | offsets in the unit the Scale implies, metres |
| Revit 2021: MapUnit 'METER' defined as 0.3048 m, Eastings in millimetres | offsets in the project's unit, millimetres |

Where the units disagree the model keeps its own size (the Scale of a unit conversion gone wrong
would make it 1000 times larger or smaller), and the offsets are read in the first unit, of the
schema's, the one the Scale implies, the project's, the metre, that puts the model's origin inside
the CRS's area of use (:func:`en17037cli.io.georef.locate`); a reading other than the schema's is
warned, naming both. Where none does, or nothing can tell (no pyproj, a CRS PROJ does not know),
the schema's reading stands (the scene then warns that the model lies outside its CRS's area of use).
A Scale that disagrees with the units is a note (buildingSMART's own example file, a millimetre
project with MapUnit metre, has none); offsets read otherwise than the schema says are a warning.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from en17037cli.io.georef import format_latlon, locate, unit_words

#: A Scale x MapUnit within this of the project's unit converts it (grid scale factors differ
#: from 1 by less than 0.1 %; a unit gone wrong by a factor of 0.3048 or 1000).
SCALE_TOLERANCE = 0.01


@dataclass(frozen=True)
class MapPlacement:
    """How an IFC model's vertices [m] become map coordinates [m].

    eastings_m, northings_m, height_m : the offsets [m]; a, b : the unit direction of the
    project's x axis in the map; scale : (3,) [m of map per m of model] for x, y, z; crs : the
    target CRS's name (``EPSG:28992``) or None; notes, warnings : what the reader says of how it
    read them
    """

    eastings_m: float
    northings_m: float
    height_m: float
    a: float
    b: float
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    crs: str | None = None
    notes: tuple[str, ...] = field(default=())
    warnings: tuple[str, ...] = field(default=())

    def apply(self, xyz: np.ndarray) -> np.ndarray:
        """(n, 3) model vertices [m] -> (n, 3) map coordinates [m] (the formula of the module docstring)."""
        sx, sy, sz = self.scale
        x, y = sx * xyz[:, 0], sy * xyz[:, 1]
        return np.column_stack([self.eastings_m + x * self.a - y * self.b, self.northings_m + x * self.b + y * self.a,
                                self.height_m + sz * xyz[:, 2]])

    @property
    def rotation_deg(self) -> float:
        """The project's x axis, counterclockwise from the map's [deg]."""
        return math.degrees(math.atan2(self.b, self.a))


def crs_name(target) -> str | None:
    """The target CRS's name as a code PROJ reads: 'EPSG:28992' for 'EPSG:28992', 'EPSG::28992' or
    'epsg: 28992'; other names as written."""
    name = getattr(target, "Name", None)
    if not name:
        return None
    if name.upper().replace("EPSG::", "EPSG:").startswith("EPSG:"):
        return "EPSG:" + name.split(":")[-1].strip()
    return name


def _conversion(f):
    """The IfcMapConversion of the model's 3D context (else the file's first), or None."""
    convs = f.by_type("IfcMapConversion")
    if not convs:
        return None
    model = [c for c in convs if getattr(c.SourceCRS, "ContextType", None) == "Model"]
    return (model or convs)[0]


def map_conversion(f, name: str = "") -> MapPlacement | None:
    """The model's IfcMapConversion read to metres (see the module docstring), or None (none, IFC2X3).

    Parameters
    ----------
    f : the ifcopenshell file; name : the file's name, for the notes
    """
    if f.schema == "IFC2X3":
        return None
    c = _conversion(f)
    if c is None:
        return None
    import ifcopenshell.util.unit as ifc_unit

    project_m = float(ifc_unit.calculate_unit_scale(f))
    target = c.TargetCRS
    map_unit = getattr(target, "MapUnit", None)
    try:
        map_m = float(ifc_unit.get_unit_scale(map_unit)) if map_unit is not None else project_m
    except Exception:  # a unit ifcopenshell cannot scale: the project's
        map_m = project_m
    scale = float(c.Scale) if c.Scale else 1.0
    sy, sz = (float(getattr(c, k, None) or scale) for k in ("ScaleY", "ScaleZ"))
    factors = [float(getattr(c, k, None) or 1.0) if c.is_a("IfcMapConversionScaled") else 1.0
               for k in ("FactorX", "FactorY", "FactorZ")]
    k = [s * map_m / project_m for s in (scale, sy, sz)]  # [m of map per m of model] as the schema reads it
    agree = all(abs(x - 1.0) <= SCALE_TOLERANCE for x in k)
    a, b = (c.XAxisAbscissa if c.XAxisAbscissa is not None else 1.0), (c.XAxisOrdinate or 0.0)
    r = math.hypot(a, b)
    a, b = (a / r, b / r) if r > 0 else (1.0, 0.0)
    crs = crs_name(target)
    said = (f"MapUnit {_unit_label(map_unit)}" if map_unit is not None else "no MapUnit: the project's length unit")
    schema = (map_m, f"{unit_words(map_m)} ({said})")
    implied = (project_m / scale, f"{unit_words(project_m / scale)} (the unit its Scale {scale:g} converts "
                                  f"{unit_words(project_m)} to)") if c.Scale and not agree else None
    readings = [schema, implied] if map_unit is not None else [implied, schema]
    readings += [(project_m, f"{unit_words(project_m)} (the project's length unit)"), (1.0, "metres")]
    seen: list[float] = []
    cands = []
    for rd in readings:
        if rd is not None and not any(math.isclose(rd[0], s, rel_tol=1e-9) for s in seen):
            seen.append(rd[0])
            cands.append(rd)
    e, n, h = float(c.Eastings), float(c.Northings), float(c.OrthogonalHeight or 0.0)
    where = [(u, why, locate(crs, e * u, n * u) if crs else None) for u, why in cands]
    inside = [w for w in where if w[2] is not None and w[2].inside]
    unit, why, _ = inside[0] if inside else where[0]
    notes, warnings = [], []
    head = f"{name}: placed by its IfcMapConversion to {crs or 'its map CRS'}"
    notes.append(f"{head}: Eastings {_num(e)}, Northings {_num(n)} and OrthogonalHeight {_num(h)} read in {why}")
    if not agree:  # a note: the model's own size is never in doubt, only how the file says it
        notes.append(f"{name}: its IfcMapConversion's Scale ({'none: 1' if not c.Scale else f'{scale:g}'}) does not "
                        f"convert the project's {unit_words(project_m)} to the map's {unit_words(map_m)} ({said}): as written "
                        f"it would make the model {k[0]:.4g} times its size in the map; the model is kept at its own size")
    if inside and unit != schema[0]:
        loc = inside[0][2]
        first = next((w[2] for w in where if w[0] == schema[0]), None)
        out = f" at {format_latlon(first.latitude, first.longitude)}" if first is not None and math.isfinite(first.latitude) else ""
        warnings.append(f"{name}: its IfcMapConversion's Eastings and Northings read in {schema[1]} put the model{out}, "
                        f"outside {loc.area}; read in {why} they put it inside, at {format_latlon(loc.latitude, loc.longitude)}: "
                        "read so")
    elif not inside and any(w[2] is not None for w in where):
        notes.append(f"{name}: no reading of its IfcMapConversion's Eastings and Northings ("
                     + ", ".join(unit_words(u) for u, _, _ in where) + f") puts the model inside {where[0][2].area}")
    e_m, n_m, h_m = e * unit, n * unit, h * unit
    geom = tuple(kk * fac if agree else fac for kk, fac in zip(k, factors))
    return MapPlacement(e_m, n_m, h_m, a, b, geom, crs, tuple(notes), tuple(warnings))  # type: ignore[arg-type]


def _unit_label(unit) -> str:
    """An IfcNamedUnit as written: 'MILLI METRE', "'METER' (a conversion-based unit)"."""
    import ifcopenshell.util.unit as ifc_unit

    if unit.is_a("IfcSIUnit"):
        return " ".join(x for x in (unit.Prefix, unit.Name) if x)
    try:
        size = f" of {float(ifc_unit.get_unit_scale(unit)):g} m"
    except Exception:  # a unit ifcopenshell cannot scale
        size = ""
    return f"'{getattr(unit, 'Name', '?')}', an {unit.is_a()}{size}"


def _num(x: float) -> str:
    """A coordinate as written, to the millimetre at most: '93,869,354.318'."""
    return f"{x:,.3f}".rstrip("0").rstrip(".")
