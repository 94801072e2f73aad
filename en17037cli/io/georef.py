"""Where a georeference puts a model on the earth, and whether that lies inside its CRS's area of use.

A model file in a map CRS (an IFC placed by its IfcMapConversion, a CityGML or CityJSON city
model, a file given a ``crs`` key) says where it stands twice over: its coordinates, read in the
CRS, are a latitude and longitude. :func:`locate` turns a point of such a file into one with PROJ
(pyproj), in the CRS's own geodetic datum (the datum shift to WGS 84, at most a few hundred
metres, does not matter to the sun), and checks it against the CRS's area of use (the EPSG
bounding box, ``pyproj.CRS.area_of_use``): a point outside it (an easting read in the wrong unit,
a CRS named wrongly) is no location. Without pyproj, or with a CRS PROJ does not know, nothing is
located and nothing is checked.

References: PROJ coordinate operations (https://proj.org), EPSG Geodetic Parameter Dataset
(area of use of each CRS); haversine distance: R. W. Sinnott, "Virtues of the Haversine", Sky and
Telescope 68 (2), 1984, p. 159.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import lru_cache

#: Mean radius of the earth [m] (IUGG), for distances between two locations.
EARTH_RADIUS_M = 6_371_008.8


@dataclass(frozen=True)
class Located:
    """Where a point in a map CRS lies.

    crs : the CRS's code as given (``EPSG:28992``); latitude, longitude : [deg] in the CRS's
    geodetic datum, north and east positive (NaN where PROJ gives no finite value); inside : the
    point lies in the CRS's area of use; area : the area of use in words, for messages
    """

    crs: str
    latitude: float
    longitude: float
    inside: bool
    area: str


@lru_cache(maxsize=32)
def map_crs(name: str):
    """The horizontal pyproj CRS named ``name`` (a compound CRS's first part), or None where pyproj
    is not installed, PROJ does not know the name, or the CRS is not projected."""
    try:
        import pyproj
    except ImportError:
        return None
    try:
        crs = pyproj.CRS.from_user_input(name)
    except pyproj.exceptions.CRSError:
        return None
    if crs.is_compound and crs.sub_crs_list:
        crs = crs.sub_crs_list[0]
    return crs if crs.is_projected else None


def crs_unit_m(crs) -> float:
    """Metres per unit of a projected CRS's first axis (1 for metres, 0.3048006 for US survey feet)."""
    return float(crs.axis_info[0].unit_conversion_factor) if crs.axis_info else 1.0


def area_text(name: str, crs) -> str:
    """``"EPSG:28992's area of use (Netherlands - onshore ..., 3.2 to 7.22 E, 50.75 to 53.7 N)"``."""
    a = crs.area_of_use
    if a is None:
        return f"{name} (no area of use known)"
    w, s, e, n = a.bounds
    where = re.split(r"[,:;]| - ", a.name)[0].strip() if a.name else ""
    return f"{name}'s area of use ({where + ', ' if where else ''}{w:g} to {e:g} E, {s:g} to {n:g} N)"


def locate(name: str, x_m: float, y_m: float) -> Located | None:
    """Latitude and longitude [deg] of the point (``x_m``, ``y_m``) [m] of a model in the map CRS
    ``name`` (easting, northing in metres: the CRS's own units times :func:`crs_unit_m`), and
    whether it lies in the CRS's area of use (its bounding box); None where nothing can say
    (:func:`map_crs`)."""
    import pyproj

    crs = map_crs(name)
    if crs is None:
        return None
    unit = crs_unit_m(crs)
    to_geo = pyproj.Transformer.from_crs(crs, crs.geodetic_crs, always_xy=True)
    lon, lat = to_geo.transform(x_m / unit, y_m / unit)
    lat, lon = float(lat), float(lon)
    finite = math.isfinite(lat) and math.isfinite(lon)
    inside = finite and crs.area_of_use is not None and _in_bounds(crs.area_of_use.bounds, lon, lat)
    return Located(name, lat if finite else math.nan, lon if finite else math.nan, inside, area_text(name, crs))


def _in_bounds(bounds, lon: float, lat: float) -> bool:
    """Whether (lon, lat) [deg] lies in an EPSG bounding box (west, south, east, north), which may
    cross the antimeridian (west > east)."""
    w, s, e, n = bounds
    if not s <= lat <= n:
        return False
    return w <= lon <= e if w <= e else (lon >= w or lon <= e)


def distance_km(lat1: float, lon1: float, lat2: float, lon2: float) -> float:
    """Great-circle distance [km] between two locations [deg] on a sphere of radius
    :data:`EARTH_RADIUS_M` (haversine formula, Sinnott 1984)."""
    p1, p2 = math.radians(lat1), math.radians(lat2)
    dp, dl = p2 - p1, math.radians(lon2 - lon1)
    h = math.sin(dp / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * EARTH_RADIUS_M * math.asin(min(1.0, math.sqrt(h))) / 1000.0


def unit_words(metres: float) -> str:
    """A length unit in words from its size [m]: 'metres', 'millimetres', 'units of 0.3048 m'."""
    known = {1.0: "metres", 0.001: "millimetres", 0.01: "centimetres", 0.1: "decimetres", 1000.0: "kilometres",
             0.3048: "feet", 1200 / 3937: "US survey feet", 0.0254: "inches"}
    for size, words in known.items():
        if math.isclose(metres, size, rel_tol=1e-9):
            return words
    return f"units of {metres:g} m"


def format_latlon(lat: float, lon: float) -> str:
    """'52.0116 N, 4.3571 E' [deg]."""
    return f"{abs(lat):.4f} {'N' if lat >= 0 else 'S'}, {abs(lon):.4f} {'E' if lon >= 0 else 'W'}"
