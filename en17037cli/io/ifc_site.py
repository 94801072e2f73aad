"""Where an IFC model stands: IfcSite location, the context's true north, IfcMapConversion
(read by :mod:`~en17037cli.io.ifc_georef`).

References: buildingSMART IFC4 ADD2 TC1, IfcMapConversion (8.18.3.6), IfcSite (5.4.3.4),
IfcGeometricRepresentationContext (8.18.3.4).
"""
from __future__ import annotations

import math
from pathlib import Path

from en17037cli.io.ifc_georef import MapPlacement
from en17037cli.io.mesh import Site


def compound_degrees(v) -> float | None:
    """Degrees of an IfcCompoundPlaneAngleMeasure (deg, min, sec[, millionths]), signs alike."""
    if not v:
        return None
    parts = list(v) + [0] * (4 - len(v))
    return float(parts[0] + parts[1] / 60 + parts[2] / 3600 + parts[3] / 3.6e9)


def site_of(f, path: Path, m: MapPlacement | None) -> Site | None:
    lat = lon = elev = None
    src = []
    sites = f.by_type("IfcSite")
    if sites:
        s = sites[0]
        lat, lon = compound_degrees(s.RefLatitude), compound_degrees(s.RefLongitude)
        elev = float(s.RefElevation) if s.RefElevation is not None else None
        if lat is not None:
            src.append("latitude and longitude from IfcSite RefLatitude/RefLongitude")
    north = north_warning = None
    for ctx in f.by_type("IfcGeometricRepresentationContext"):
        if ctx.is_a() == "IfcGeometricRepresentationContext" and ctx.ContextType == "Model" and ctx.TrueNorth is not None:
            north, north_warning = true_north(ctx.TrueNorth.DirectionRatios)
            if north is not None:
                src.append("true north from the model context's TrueNorth")
            break
    crs = None
    if m is not None:
        crs = m.crs
        north = None if north is None else round((north - m.rotation_deg) % 360.0, 9) % 360.0  # x turned in the map; 360 is 0
        src.append(f"placed by IfcMapConversion in {crs or 'its map CRS'}")
    if lat is None and north is None and crs is None and north_warning is None:
        return None
    return Site(latitude=lat, longitude=lon, elevation_m=elev, true_north_deg=north, crs=crs,
                source=f"{path.name}: " + "; ".join(src), north_warning=north_warning)


def true_north(ratios) -> tuple[float | None, str | None]:
    """Azimuth of true north [deg, clockwise from the model's +Y] from a context's TrueNorth
    DirectionRatios, and a warning when they are not a horizontal direction.

    IFC's TrueNorth is a direction in the model's XY plane (IFC4 8.18.3.4); its ratios need not
    be normalised (IfcDirection, 8.9.3.26), so (x, y) of any length is the direction atan2(x, y)
    clockwise from +Y. Three ratios with a zero z are the same. Three with a non-zero z are not a
    horizontal direction: Revit 2013 wrote (2, 0, 1) (exactly (2, 6.1e-17, 1), i.e. a dimension
    count 2 before the 2D direction (cos 90 deg, sin 90 deg) = +Y: its curtain wall named
    'noordzijde', north side, then faces north, where the horizontal part (2, 0) would turn it
    west); ratios (2, b, c) with b² + c² = 1 are read that way, others by their horizontal part
    (x, y). None where no horizontal direction is left (north then stays the model's +Y).
    """
    r = [float(x) for x in ratios]
    shown = "(" + ", ".join(f"{round(x, 6) + 0.0:g}" for x in r) + ")"
    tail = ("; confirm it against the drawings (validate prints each window's compass bearing) or give "
            "model.true_north_deg")
    if len(r) < 2:
        return None, f"the model context's TrueNorth {shown} is not a direction: north taken along the model's +Y{tail}"
    horizontal = len(r) == 2 or abs(r[2]) <= 1e-9 * max(math.hypot(*r), 1e-300)
    how, other = "its horizontal part", None
    x, y = r[0], r[1]
    if not horizontal and len(r) == 3 and r[0] == 2.0 and abs(math.hypot(r[1], r[2]) - 1.0) < 1e-6:
        x, y = r[1], r[2]
        how = f"the 2D direction ({round(x, 6) + 0.0:g}, {round(y, 6) + 0.0:g}) after a dimension count 2 (as Revit 2013 wrote it)"
        other = math.degrees(math.atan2(r[0], r[1])) % 360.0
    if math.hypot(x, y) <= 1e-12:
        return None, (f"the model context's TrueNorth {shown} has no horizontal direction: north taken along the model's "
                      f"+Y{tail}")
    north = round(math.degrees(math.atan2(x, y)), 9) % 360.0  # (cos 90 deg, 1) is 0 deg, not 3.5e-15
    if horizontal:
        return north, None
    alt = "" if other is None else f" (its horizontal part would put it at {other:.1f} deg)"
    return north, (f"the model context's TrueNorth {shown} is not a horizontal direction; read as {how}: true north "
                   f"{north:.1f} deg clockwise from the model's +Y{alt}{tail}")
