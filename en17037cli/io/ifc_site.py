"""Where an IFC model stands: IfcSite location, the context's true north, IfcMapConversion.

References: buildingSMART IFC4 ADD2 TC1, IfcMapConversion (8.18.3.6), IfcSite (5.4.3.4),
IfcGeometricRepresentationContext (8.18.3.4).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from en17037cli.io.mesh import Site


def compound_degrees(v) -> float | None:
    """Degrees of an IfcCompoundPlaneAngleMeasure (deg, min, sec[, millionths]), signs alike."""
    if not v:
        return None
    parts = list(v) + [0] * (4 - len(v))
    return float(parts[0] + parts[1] / 60 + parts[2] / 3600 + parts[3] / 3.6e9)


def map_conversion(f):
    """(Eastings, Northings, height, a, b, scale, crs name) of the model context's IfcMapConversion, or None."""
    if f.schema == "IFC2X3":
        return None
    convs = f.by_type("IfcMapConversion")
    if not convs:
        return None
    c = convs[0]
    a, b = (c.XAxisAbscissa if c.XAxisAbscissa is not None else 1.0), (c.XAxisOrdinate or 0.0)
    r = math.hypot(a, b) or 1.0
    crs = getattr(c.TargetCRS, "Name", None)
    if crs and crs.upper().replace("EPSG::", "EPSG:").startswith("EPSG:"):
        crs = "EPSG:" + crs.split(":")[-1].strip()
    return (float(c.Eastings), float(c.Northings), float(c.OrthogonalHeight or 0.0), a / r, b / r,
            float(c.Scale if c.Scale is not None else 1.0), crs)


def apply_map(xyz: np.ndarray, m) -> np.ndarray:
    e, n, h, a, b, s, _ = m
    x, y = xyz[:, 0], xyz[:, 1]
    return np.column_stack([e + s * (x * a - y * b), n + s * (x * b + y * a), h + xyz[:, 2]])


def site_of(f, path: Path, m) -> Site | None:
    lat = lon = elev = None
    src = []
    sites = f.by_type("IfcSite")
    if sites:
        s = sites[0]
        lat, lon = compound_degrees(s.RefLatitude), compound_degrees(s.RefLongitude)
        elev = float(s.RefElevation) if s.RefElevation is not None else None
        if lat is not None:
            src.append("latitude and longitude from IfcSite RefLatitude/RefLongitude")
    north = None
    for ctx in f.by_type("IfcGeometricRepresentationContext"):
        if ctx.is_a() == "IfcGeometricRepresentationContext" and ctx.ContextType == "Model" and ctx.TrueNorth is not None:
            x, y = ctx.TrueNorth.DirectionRatios[:2]
            north = math.degrees(math.atan2(x, y)) % 360.0
            src.append("true north from the model context's TrueNorth")
            break
    crs = None
    if m is not None:
        crs = m[6]
        rot = math.degrees(math.atan2(m[4], m[3]))  # the project's x axis, counterclockwise from the map's
        north = None if north is None else (north - rot) % 360.0
        src.append(f"placed by IfcMapConversion in {crs or 'its map CRS'}")
    if lat is None and north is None and crs is None:
        return None
    return Site(latitude=lat, longitude=lon, elevation_m=elev, true_north_deg=north, crs=crs,
                source=f"{path.name}: " + "; ".join(src))
