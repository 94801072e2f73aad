"""Where a georeferenced city model puts the building: the latitude, longitude and true north of
its coordinate reference system at the windows.

A city tile (CityJSON's ``metadata.referenceSystem``, CityGML's ``srsName``) fixes the frame the
building is placed in: once a model file is set down in it (``model.files[i].transform``, or a
model already in that CRS), its neighbours stand where the tile says and the sun must come from
where the tile's CRS says too. Before, the location came from the first model file that names
one and north from the first that has a TrueNorth: an IFC brings its IfcSite (the FZK-Haus's is
near Karlsruhe, its TrueNorth 50 deg off its +Y) while an OBJ export of the same building brings
nothing, so one building set in one tile got two suns (issue 45). Now, where the project leaves
them out, both come from the city model's CRS (:func:`city_frame`), for every format alike; a model
file's own site or north that disagrees is warned (:mod:`~en17037cli.scene.site`).

North in a projected CRS: grid north (+Y) differs from true north by the meridian convergence,
found here by projecting a point 1e-4 deg north of the windows' centre (its grid direction from
the centre is true north; RD New: about 0.8 deg clockwise from +Y at Delft, 0 on its central
meridian at Amersfoort). pyproj (PROJ) does the projection; without it (CityJSON needs no extra) the frame is
not known and the run keeps the old rule.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: A model file's own site farther than this from where the city model's CRS puts the building is
#: warned [m] (a site given to the nearest town is a few km off; a tool's default, another country)
SITE_MISMATCH_M = 5000.0
#: A model file's own north (turned with its transform) more than this from the CRS's true north is
#: warned [deg]: a drawing's north arrow is set to the degree, the convergence itself reaches 2 deg
NORTH_MISMATCH_DEG = 1.0
#: Step north used to find the direction of true north on the grid [deg of latitude] (about 11 m)
NORTH_STEP_DEG = 1e-4
#: Mean radius of the Earth [m], for the distance between two sites (IUGG mean radius R1)
EARTH_RADIUS_M = 6_371_008.8


@dataclass(frozen=True)
class CityFrame:
    """The frame a georeferenced city model sets, at the building.

    crs : the city model's CRS (``EPSG:7415``); display : the file, for messages
    latitude, longitude : [deg] of the windows' centre; north_deg : true north [deg clockwise from
    the scene's +Y, grid north]
    """

    crs: str
    display: str
    latitude: float
    longitude: float
    north_deg: float

    @property
    def source(self) -> str:
        return f"{self.display}: the city model's CRS ({self.crs}) at the windows"


def horizontal_crs(pyproj, code: str):
    """The horizontal part of a CRS (the first of a compound's), a pyproj CRS."""
    crs = pyproj.CRS.from_user_input(code)
    if crs.is_compound:
        crs = crs.sub_crs_list[0]
    return crs


def frame_at(code: str, display: str, x: float, y: float) -> CityFrame | None:
    """The :class:`CityFrame` of CRS ``code`` at grid point (x, y) [CRS units, metres]; None where
    pyproj is missing, the CRS unknown, not projected, or the point outside what it can invert.

    Latitude and longitude by PROJ's inverse projection (WGS 84, EPSG:4326); north by projecting a
    point :data:`NORTH_STEP_DEG` north of it: atan2(dx, dy) of the step on the grid.
    """
    try:
        import pyproj
    except ImportError:
        return None
    try:
        crs = horizontal_crs(pyproj, code)
        if not crs.is_projected:
            return None
        to_geo = pyproj.Transformer.from_crs(crs, "EPSG:4326", always_xy=True)
        to_grid = pyproj.Transformer.from_crs("EPSG:4326", crs, always_xy=True)
        lon, lat = to_geo.transform(x, y)
        x1, y1 = to_grid.transform(lon, lat + NORTH_STEP_DEG)
    except (pyproj.exceptions.CRSError, pyproj.exceptions.ProjError, ValueError):
        return None
    if not all(math.isfinite(v) for v in (lon, lat, x1, y1)):
        return None
    north = math.degrees(math.atan2(x1 - x, y1 - y))
    return CityFrame(code, display, float(lat), float(lon), round(north, 9) % 360.0)


def city_frame(g, centre_xy, files=()) -> CityFrame | None:
    """The frame of the first city model (a context file: CityJSON, CityGML) of geometry ``g`` that
    has a projected CRS (the file's ``crs`` key in ``files``, the project's ``model.files``, else its
    own) and gives faces to the scene (something of it within ``context_radius_m`` of the windows:
    the building is set down in it), at ``centre_xy`` [m, world]; None where there is none, or
    pyproj cannot say (:func:`frame_at`)."""
    for index, display, lo, hi in g.context:
        if hi <= lo or not np.any((g.part >= lo) & (g.part < hi)):
            continue
        key = getattr(files[index], "crs", None) if index < len(files) else None
        site = next((s for d, s, _ in g.sites if d == display and s.crs), None)
        code = key or (site.crs if site is not None else None)
        if code:
            return frame_at(code, display, float(centre_xy[0]), float(centre_xy[1]))
    return None


def distance_m(lat1: float, lon1: float, lat2: float, lon2: float) -> float:
    """Great-circle distance [m] between two sites [deg], haversine on a sphere of
    :data:`EARTH_RADIUS_M` (for warnings: 0.5 % is nothing here)."""
    p1, p2 = math.radians(lat1), math.radians(lat2)
    dp, dl = p2 - p1, math.radians(lon2 - lon1)
    h = math.sin(dp / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * EARTH_RADIUS_M * math.asin(min(1.0, math.sqrt(h)))


def angle_between_deg(a: float, b: float) -> float:
    """Smallest angle between two azimuths [deg], 0-180."""
    d = (a - b) % 360.0
    return min(d, 360.0 - d)
