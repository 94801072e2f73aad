"""A CityGML ``srsName`` as a CRS, the axis order its coordinates are written in, and reprojection.

Forms of ``srsName`` read (the horizontal part of a compound CRS places the vertices in plan, its
vertical part gives the heights' unit):

| form | example |
|---|---|
| EPSG code | `EPSG:25833` |
| OGC URN (also `urn:x-ogc:`, with or without a version) | `urn:ogc:def:crs:EPSG::25833`, `urn:ogc:def:crs:EPSG:6.12:25832` |
| OGC compound URN | `urn:ogc:def:crs,crs:EPSG::25832,crs:EPSG::7837` |
| EPSG compound code (PROJ's form) | `EPSG:2263+6360` |
| OGC URL (http or https) | `http://www.opengis.net/def/crs/EPSG/0/6697` |
| GML 2 URL | `http://www.opengis.net/gml/srs/epsg.xml#25833` |
| AdV URN (German states' files) | `urn:adv:crs:ETRS89_UTM32*DE_DHHN2016_NH` -> EPSG:25832 (+ height) |
| OGC CRS84 | `urn:ogc:def:crs:OGC:1.3:CRS84`, `CRS:84` (longitude, latitude) |

Axis order: GML writes coordinates in the CRS's own axis order (latitude first for EPSG:4326 and
Japan's EPSG:6697), but many projected files write easting first whatever the CRS defines
(Gauss-Krüger EPSG:31468, Helsinki's EPSG:3879), and files naming a CRS in degrees as plain
``EPSG:4979`` write longitude first. The order is decided by the data: the one that puts the
file's first vertex inside the CRS's area of use (pyproj); where both or neither do, easting
first for a projected CRS, and for one in degrees (longitude, latitude) for the plain
``EPSG:nnnn`` form, the CRS's own order for URNs and URLs. A order other than the CRS's own is
said in a note.

Reprojection (pyproj, PROJ): a file whose horizontal CRS differs from the target (the CRS of the
project's other files) is transformed to it, x and y; a CRS in degrees with no target is an input
error (the vertices must be metres). A CRS whose unit is not the metre (New York City's EPSG:2263
in US survey feet) is scaled to metres after any transformation.

Heights (:func:`height_unit`): in the unit of the vertical CRS where the ``srsName`` (or the file's
``crs`` key) names one (a compound CRS, ``EPSG:2263+6360``: NAVD88 heights in US survey feet) or
the CRS is 3D (EPSG:4979: metres); a 2D CRS names none, and then a file whose plan is in feet gives
its heights in feet too (New York's CityGML: EPSG:2263, NAVD88 heights in US feet): taken in the
plan's unit, with a note saying so and how to say otherwise (``crs: EPSG:2263+5703``, heights in
metres). Heights in metres are kept as the file gives them.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError

#: AdV CRS names (German surveying authorities' URNs, urn:adv:crs:<horizontal>*<height>) -> EPSG code
ADV_CRS = {
    "ETRS89_UTM31": 25831, "ETRS89_UTM32": 25832, "ETRS89_UTM33": 25833,
    "DE_DHDN_3GK2": 31466, "DE_DHDN_3GK3": 31467, "DE_DHDN_3GK4": 31468, "DE_DHDN_3GK5": 31469,
    "ETRS89_LAT-LON": 4258, "ETRS89_LAT-LON_H": 4937,
    "DE_DHHN92_NH": 5783, "DE_DHHN2016_NH": 7837,
}

_EPSG_RE = re.compile(r"(?:EPSG(?:/[^/]*/|:[\d.]*:|:)|epsg\.xml#)(\d+)\s*$", re.IGNORECASE)
_EPSG_PLUS_RE = re.compile(r"^\s*EPSG:(\d+)\s*\+\s*(\d+)\s*$", re.IGNORECASE)
_CRS84_RE = re.compile(r"(?:CRS:?84|OGC(?:/[^/]*/|:[\d.]*:)CRS84)\s*$", re.IGNORECASE)


def parse_srs_name(srs: str) -> str | None:
    """The horizontal CRS of a ``srsName`` as ``"EPSG:<code>"`` (``"OGC:CRS84"`` for CRS84), or None when not recognised.

    Parameters
    ----------
    srs : the attribute as the file writes it (see the module's table)
    """
    s = srs.strip()
    if not s:
        return None
    plus = _EPSG_PLUS_RE.match(s)
    if plus:
        return f"EPSG:{plus.group(1)}"
    if s.lower().startswith("urn:adv:crs:"):
        first = s[len("urn:adv:crs:"):].split("*")[0].strip().upper()
        code = ADV_CRS.get(first)
        return None if code is None else f"EPSG:{code}"
    if s.lower().startswith("urn:ogc:def:crs,") or s.lower().startswith("urn:x-ogc:def:crs,"):
        s = s.split(",")[1]  # the first component of a compound URN: the horizontal CRS
    if _CRS84_RE.search(s):
        return "OGC:CRS84"
    m = _EPSG_RE.search(s)
    return f"EPSG:{m.group(1)}" if m else None


def parse_vertical(srs: str) -> str | None:
    """The vertical CRS a ``srsName`` names beside its horizontal one, as ``"EPSG:<code>"``, or None:
    the second component of an OGC compound URN, the height of an AdV URN, the ``+v`` of PROJ's
    ``EPSG:h+v``."""
    s = srs.strip()
    plus = _EPSG_PLUS_RE.match(s)
    if plus:
        return f"EPSG:{plus.group(2)}"
    if s.lower().startswith("urn:adv:crs:") and "*" in s:
        code = ADV_CRS.get(s.split("*", 1)[1].strip().upper())
        return None if code is None else f"EPSG:{code}"
    if s.lower().startswith("urn:ogc:def:crs,") or s.lower().startswith("urn:x-ogc:def:crs,"):
        parts = s.split(",")
        m = _EPSG_RE.search(parts[2]) if len(parts) > 2 else None
        return f"EPSG:{m.group(1)}" if m else None
    return None


def _unit(axis) -> tuple[float, str]:
    """(metres per unit, unit name) of a pyproj axis."""
    return float(axis.unit_conversion_factor), str(axis.unit_name)


def height_unit(full, vertical) -> tuple[float, str, str]:
    """The heights' unit: (metres per unit, unit name, where it comes from: "" when the CRS says).

    Parameters
    ----------
    full : the pyproj CRS as named (compound, 3D or 2D); vertical : the vertical CRS named beside it, or None
    """
    if vertical is not None:
        return (*_unit(vertical.axis_info[0]), "")
    if full.is_compound and len(full.sub_crs_list) > 1:
        return (*_unit(full.sub_crs_list[1].axis_info[0]), "")
    if len(full.axis_info) >= 3:
        return (*_unit(full.axis_info[2]), "")
    h = _horizontal(full)
    if h.is_geographic or not h.axis_info:
        return 1.0, "metre", ""
    factor, name = _unit(h.axis_info[0])
    return factor, name, "" if factor == 1.0 else "the plan's (the CRS names no vertical unit)"


def _pyproj(path: Path):
    try:
        import pyproj
    except ImportError:
        raise InputError(f"{path}: reading CityGML needs pyproj (coordinate reference systems): "
                         "pip install 'en17037cli[citygml]'") from None
    return pyproj


def _horizontal(crs):
    """The horizontal part of a (compound) pyproj CRS."""
    return crs.sub_crs_list[0] if crs.is_compound and crs.sub_crs_list else crs


def _utm_hint(crs, first_xy, swap: bool) -> str:
    """'e.g. crs: EPSG:32654, the UTM zone of the file's first vertex' (any CRS in metres of the model files will do)."""
    import pyproj.database

    if first_xy is None:
        return "e.g. crs: EPSG:25832"
    lon, lat = (first_xy[1], first_xy[0]) if swap else (first_xy[0], first_xy[1])
    try:
        info = pyproj.database.query_utm_crs_info(datum_name="WGS 84", area_of_interest=pyproj.aoi.AreaOfInterest(
            lon, lat, lon, lat))
    except Exception:  # PROJ cannot say: a plain example
        info = []
    return f"e.g. crs: EPSG:{info[0].code}, {info[0].name}, if they are in it" if info else "e.g. crs: EPSG:25832"


@dataclass
class Placement:
    """How one ``srsName``'s coordinates become the mesh's: axis swap, reprojection, then metres.

    name : the horizontal CRS (``EPSG:25833``); swap : (y, x) -> (x, y) first; transformer :
    pyproj Transformer to the target CRS (x, y in, x, y out), or None; geographic : in degrees;
    xy_scale : metres per unit of the plan's CRS after any transformation; z_scale : metres per
    unit of the heights (:func:`height_unit`)
    """

    name: str
    swap: bool
    transformer: object | None
    geographic: bool
    xy_scale: float = 1.0
    z_scale: float = 1.0

    def apply(self, xyz: np.ndarray) -> np.ndarray:
        """(n, 3) float64 coordinates as written -> (n, 3) float64 [m] in the target CRS, x east, y north."""
        if self.swap:
            xyz = xyz[:, [1, 0, 2]]
        if self.transformer is not None and len(xyz):
            x, y = self.transformer.transform(xyz[:, 0], xyz[:, 1])
            xyz = np.column_stack([x, y, xyz[:, 2]])
        if self.xy_scale != 1.0 or self.z_scale != 1.0:
            xyz = xyz * np.array([self.xy_scale, self.xy_scale, self.z_scale])
        return xyz


class CrsResolver:
    """``srsName`` -> :class:`Placement`, once per distinct name, all to one target CRS.

    path : the file (for messages); given : the project's ``crs`` key for the file (wins over what
    the file says); target : the CRS of the project's other files, or None (the file's first CRS
    is then the mesh's)
    """

    def __init__(self, path: Path, given: str | None, target: str | None):
        self.path = path
        self.given = given
        self.target = target
        self.cache: dict = {}
        self.notes: list[str] = []
        self.out_name: str | None = None  # the mesh's CRS
        self.reprojected: set[str] = set()

    def _full(self, name: str, said: str):
        """The pyproj CRS ``name`` as named (compound, 3D or 2D)."""
        pyproj = _pyproj(self.path)
        try:
            return pyproj.CRS.from_user_input(name)
        except pyproj.exceptions.CRSError:
            raise InputError(f"{self.path}: srsName '{said}' names a CRS that PROJ does not know; set the file's "
                             "'crs' key in the project (e.g. crs: EPSG:25832) to say which it is") from None

    def _crs(self, name: str, said: str):
        return _horizontal(self._full(name, said))

    def placement(self, srs: str | None, first_xy: np.ndarray | None) -> Placement | None:
        """How to place coordinates written in ``srs`` (None: the file names no CRS); ``first_xy`` a
        vertex (2,) as written, to decide the axis order. None when there is no CRS at all."""
        key = srs if self.given is None else self.given
        if key in self.cache:
            return self.cache[key]
        if key is None:
            if self.target is not None:
                self.notes.append(f"{self.path.name}: no srsName and no 'crs' key: coordinates taken as {self.target}")
            self.cache[key] = None
            return None
        name = parse_srs_name(key) if self.given is None else (parse_srs_name(self.given) or self.given)
        if name is None:
            raise InputError(f"{self.path}: unknown CRS srsName '{key}'; set the file's 'crs' key in the project "
                             "(e.g. crs: EPSG:25832) to say which CRS its coordinates are in")
        full = self._full(name, key)
        crs = _horizontal(full)
        vname = parse_vertical(key)
        z_scale, z_unit, z_source = height_unit(full, None if vname is None else self._full(vname, key))
        swap = self._swap(crs, name, first_xy, short=bool(re.fullmatch(r"\s*EPSG:\d+\s*", key, re.IGNORECASE)))
        target = self.target or self.out_name
        if target is None and crs.is_geographic:
            raise InputError(f"{self.path}: srsName '{key}' is in degrees (latitude, longitude) and no other model file "
                             "says its CRS; give the CRS of the model files in metres with their 'crs' key "
                             f"({_utm_hint(crs, first_xy, swap)}) so the city model can be projected to it")
        transformer, out_crs = None, crs
        heights = self._heights_note(name, z_scale, z_unit, z_source)
        if target is not None:
            tcrs = self._crs(target, target)
            if tcrs.is_geographic:
                raise InputError(f"{self.path}: the project's CRS {target} is in degrees; the model files must be in a "
                                 "projected CRS in metres")
            out_crs = tcrs
            if not tcrs.equals(crs, ignore_axis_order=True):
                pyproj = _pyproj(self.path)
                transformer = pyproj.Transformer.from_crs(crs, tcrs, always_xy=True)
                self.reprojected.add(name)
                self.notes.append(f"{self.path.name}: coordinates in {name} ({crs.name}) projected to {target} "
                                  f"({tcrs.name}) with PROJ; {heights}")
                heights = ""
        xy_scale, xy_unit = _unit(out_crs.axis_info[0]) if out_crs.axis_info and not out_crs.is_geographic else (1.0, "metre")
        if xy_scale != 1.0:
            self.notes.append(f"{self.path.name}: plan coordinates in {xy_unit} ({target or name}) scaled to metres")
        if heights and z_scale != 1.0:
            self.notes.append(f"{self.path.name}: {heights}")
        self.out_name = target or name
        p = Placement(name, swap, transformer, bool(crs.is_geographic), xy_scale, z_scale)
        self.cache[key] = p
        return p

    def _heights_note(self, name: str, z_scale: float, z_unit: str, z_source: str) -> str:
        """What was done with the heights of coordinates in ``name``, for the notes."""
        if z_scale == 1.0:
            return "heights in metres, as the file gives them"
        if z_source:
            return (f"heights taken in {z_unit}, {z_source}, and converted to metres; if they are in another unit, "
                    f"give the file's crs key with its vertical CRS (e.g. crs: {name}+5703 for NAVD88 heights in metres)")
        return f"heights in {z_unit} (the CRS's vertical unit) converted to metres"

    def _swap(self, crs, name: str, first_xy, short: bool) -> bool:
        """Whether the file writes (north, east) / (lat, lon) where x east is wanted: the order that puts
        ``first_xy`` inside the CRS's area of use; where that does not decide, easting first for a
        projected CRS, and for a geographic one the CRS's own order for URN and URL forms but
        (longitude, latitude) for the short ``EPSG:nnnn`` (GeoServer's convention, what such files do)."""
        axes = [a.direction.lower() for a in crs.axis_info[:2]]
        own = axes[:1] == ["north"]  # the CRS's own order puts north (or latitude) first
        if first_xy is None or crs.area_of_use is None:
            return own
        w, s, e, n = crs.area_of_use.bounds
        x, y = float(first_xy[0]), float(first_xy[1])
        if crs.is_geographic:
            inside = lambda lon, lat: w - 1 <= lon <= e + 1 and s - 1 <= lat <= n + 1  # noqa: E731
            xy_ok, yx_ok = inside(x, y), inside(y, x)
        else:
            pyproj = _pyproj(self.path)
            try:
                t = pyproj.Transformer.from_crs(crs.geodetic_crs, crs, always_xy=True)
                x0, y0, x1, y1 = t.transform_bounds(w, s, e, n)
            except Exception:  # PROJ cannot bound this CRS's area: its own order
                return own
            pad = 0.1 * max(x1 - x0, y1 - y0)
            inside = lambda a, b: x0 - pad <= a <= x1 + pad and y0 - pad <= b <= y1 + pad  # noqa: E731
            xy_ok, yx_ok = inside(x, y), inside(y, x)
        if xy_ok == yx_ok:
            return own and not crs.is_projected and not short  # projected files write easting first in practice
        if yx_ok and not own:
            self.notes.append(f"{self.path.name}: coordinates in {name} are written (north, east) / (lat, lon); read so")
        elif xy_ok and own:
            self.notes.append(f"{self.path.name}: coordinates in {name} are written (east, north) / (lon, lat), not in "
                              "the CRS's own axis order; read so")
        return yx_ok
