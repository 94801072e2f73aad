"""Where the building stands and which way is north: the project's values, else the model's, checked.

A model file may say where it stands (an IfcSite's RefLatitude / RefLongitude, a gbXML
Campus/Location) and which way is north (an IFC context's TrueNorth, a gbXML CADModelAzimuth);
the project leaves a value out to take it from there. What a file says is often not the
building's site:

- **The null site.** Latitude and longitude both 0 (Vectorworks 2013 writes ``(0, 0, 0)`` when the
  user set none; it is a point in the Gulf of Guinea): not a location. It is taken as not given,
  so the project must give one (the one-line error says the file's is null).
- **A tool's default.** Authoring tools write their own default site when the user set none
  (:data:`DEFAULT_SITES`: ArchiCAD's 24°28'N 54°25'E, Revit's Boston and its templates'
  capitals). A location taken from the model there is warned as probably the tool's default; any
  location taken from the model is printed by ``validate`` and listed in report.json
  ``inputs.resolved`` with its source, to be confirmed.
- **The georeference.** A file in a map CRS (an IFC's IfcMapConversion, a CityGML or CityJSON
  city model, a ``crs`` key) says where it stands too (:mod:`en17037cli.scene.georef`), more surely
  than an IfcSite an exporter fills with its default. A project that leaves its location out takes
  the georeference where the file's site is missing, null, a tool's default, or more than
  :data:`GEOREF_MATCH_KM` from it (a warning names both); the site where they agree (a note). A
  georeference outside its CRS's area of use is no location (warned); if the site is then a tool's
  default, neither can be trusted and the run stops (exit 2) asking for ``location.latitude`` and
  ``location.longitude``; with no georeference at all a default site is only warned, as above.
  A location the project gives is kept, with a warning where a georeferenced file (a city model
  around the building) lies more than :data:`GEOREF_MATCH_KM` from it.
- **North.** A TrueNorth that is not a horizontal direction is read as the reader says and warned
  (:func:`en17037cli.io.ifc_site.true_north`); ``validate`` prints each window's compass bearing
  (:func:`compass_bearing`) so the orientation can be checked against the drawings.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.georef import distance_km, format_latlon
from en17037cli.project.settings import Location, Project
from en17037cli.scene.city_frame import NORTH_MISMATCH_DEG, SITE_MISMATCH_M, CityFrame, angle_between_deg, distance_m
from en17037cli.scene.georef import outside_warnings
from en17037cli.scene.model import Geometry

#: Latitude and longitude within this of a listed site are that site [deg] (about 100 m; the
#: tools write their defaults to the second of arc or better).
SITE_MATCH_DEG = 1e-3

#: Sites authoring tools write when the user set none: (latitude, longitude) [deg, north and east
#: positive], what it is. Sources: ArchiCAD's default 24°28'N 54°25'E (Abu Dhabi) in ArchiCAD 9-13
#: exports (FamilyHouse_AC13.ifc, 'Default Site'); Revit places a model "near Boston or your
#: nearest capital city" when its location is not set (Bentley Communities, "Publishing Revit model
#: files", the iTwin connector's notes on geolocation): Boston as Revit 2013's IFC export writes it
#: (42°21'30.34"N 71°3'35.19"W, Jesse.1.ifc) and as its gbXML export writes the "Boston, MA"
#: location (42.213 N, 71.033 W: Revit 2009 and 2016 gbXML samples); the capitals as Revit writes
#: them: Paris (48°51'24.00"N 2°21'3.55"E, the French Revit 2020/2021 exports ExternalEarth and
#: Aalseth Lane, a house that is not in Paris), London (51°30'0.55"N 0°7'34.45"W, SampleHouse4.ifc);
#: ArchiCAD's French version's Paris (48°51'12.25"N 2°20'55.63"E, the Aalseth Lane and Triangle
#: AC24 files). A project really in one of those places confirms it by giving its location.
DEFAULT_SITES = (
    (24.0 + 28 / 60, 54.0 + 25 / 60, "ArchiCAD's default site (24°28'N 54°25'E, Abu Dhabi)"),
    (42.0 + 21 / 60 + 30.344238 / 3600, -(71.0 + 3 / 60 + 35.194702 / 3600), "Revit's default site (Boston, MA)"),
    (42.213, -71.033, "Revit's default location (Boston, MA) as its gbXML export writes it"),
    (48.0 + 51 / 60 + 23.999633 / 3600, 2.0 + 21 / 60 + 3.553905 / 3600, "Revit's Paris, where its French version places a model by default"),
    (51.0 + 30 / 60 + 0.549316 / 3600, -(7 / 60 + 34.450321 / 3600), "Revit's London, where it places a model near by default"),
    (48.0 + 51 / 60 + 12.2485 / 3600, 2.0 + 20 / 60 + 55.62563 / 3600, "ArchiCAD's default site in its French version (Paris)"),
)

#: A site and a georeference farther apart than this disagree: the georeference is taken [km]
#: (an IfcSite set to the nearest city lies within a few kilometres; a tool's default or a
#: template's, hundreds away).
GEOREF_MATCH_KM = 5.0

#: 16 compass points, clockwise from north.
COMPASS = ("N", "NNE", "NE", "ENE", "E", "ESE", "SE", "SSE", "S", "SSW", "SW", "WSW", "W", "WNW", "NW", "NNW")
#: A window whose outward normal has a horizontal part shorter than this faces up or down (a roof
#: light within about 6 deg of horizontal): it has no compass bearing.
MIN_HORIZONTAL = 0.1


def is_null_site(lat: float | None, lon: float | None) -> bool:
    """Latitude and longitude both 0: what tools write when no site was set."""
    return lat is not None and lon is not None and lat == 0.0 and lon == 0.0


def default_site(lat: float, lon: float) -> str | None:
    """What a site is when it is an authoring tool's default (:data:`DEFAULT_SITES`), else None."""
    for la, lo, what in DEFAULT_SITES:
        if abs(lat - la) <= SITE_MATCH_DEG and abs(lon - lo) <= SITE_MATCH_DEG:
            return what
    return None


def resolve_north(project: Project, g: Geometry, city: CityFrame | None = None) -> tuple[float, dict | None, list[str]]:
    """True north [deg clockwise from +Y]: the project's, else the city model's CRS where the
    building is set in one (``city``, :mod:`~en17037cli.scene.georef`; a model file's own TrueNorth
    that disagrees is warned), else the first model file's own (its TrueNorth turned with the file's
    rotation), else 0; with where it came from and warnings (a TrueNorth that is not a horizontal
    direction, as its reader took it)."""
    if project.model.true_north_deg is not None:
        return project.model.true_north_deg, None, []
    if city is not None:
        return city.north_deg, {"value": round(city.north_deg, 6), "source": city.source}, _north_against_city(g, city)
    warnings = []
    for display, site, rotate_deg in g.sites:
        if site.north_warning:
            warnings.append(f"{display}: {site.north_warning}")
        if site.true_north_deg is not None:
            north = (site.true_north_deg - rotate_deg) % 360.0
            return north, {"value": round(north, 6), "source": site.source + (f", turned by the file's transform ({rotate_deg:g} deg)"
                                                                             if rotate_deg else "")}, warnings
    return 0.0, None, warnings


def resolve_location(project: Project, g: Geometry, where: str,
                     city: CityFrame | None = None) -> tuple[Location | None, dict, list[str], list[str]]:
    """The project's location with a latitude or longitude it leaves out taken from the city model's
    CRS where the building is set in one (``city``: one building, one city, one sun, whatever format
    the building comes in; a model file's own site far from it is warned), else from the model files
    (see the module docstring: the georeference, else the IfcSite or gbXML location), what came from
    where, and what to say of it (warnings, notes)."""
    loc = project.location
    out: dict = {}
    if loc is None:
        return loc, out, [], []
    warnings = outside_warnings(g.located)
    if city is not None and (loc.latitude is None or loc.longitude is None):
        lat = loc.latitude if loc.latitude is not None else round(city.latitude, 6)
        lon = loc.longitude if loc.longitude is not None else round(city.longitude, 6)
        for key, value, given in (("latitude", lat, loc.latitude), ("longitude", lon, loc.longitude)):
            if given is None:
                out[f"location.{key}"] = {"value": value, "source": city.source}
        note = f"location {format_location(lat, lon)} taken from {city.source}"
        return replace(loc, latitude=lat, longitude=lon), out, warnings + _site_against_city(g, city, where), [note]
    geo, geo_file = next(((w, d) for d, w in g.located if w.inside), (None, None))
    if loc.latitude is not None and loc.longitude is not None:
        apart = None if geo is None else distance_km(loc.latitude, loc.longitude, geo.latitude, geo.longitude)
        if geo is not None and apart is not None and apart > GEOREF_MATCH_KM:
            warnings.append(f"{where}: location {format_location(loc.latitude, loc.longitude)} given, but {geo_file}'s "
                            f"georeference ({geo.crs}) puts the model at {format_location(geo.latitude, geo.longitude)}, "
                            f"{apart:,.0f} km away: the sun is taken at the location given; check location.latitude and "
                            "location.longitude, or the file's georeference (its crs key)")
        return loc, out, warnings, []
    null = [display for display, s, _ in g.sites if is_null_site(s.latitude, s.longitude)]
    site, display = next(((s, d) for d, s, _ in g.sites if s.latitude is not None and s.longitude is not None
                          and not is_null_site(s.latitude, s.longitude)), (None, None))
    what = default_site(site.latitude, site.longitude) if site is not None else None
    notes: list[str] = []
    if geo is not None:  # the georeference, unless the site agrees with it
        km = None if site is None else distance_km(site.latitude, site.longitude, geo.latitude, geo.longitude)
        if site is not None and what is None and km is not None and km <= GEOREF_MATCH_KM:
            lat, lon, source = site.latitude, site.longitude, site.source
            notes.append(f"location {format_location(lat, lon)} taken from {location_source(source)}; its georeference "
                         f"({geo.crs}) agrees within {km:.1f} km")
        else:
            lat, lon = geo.latitude, geo.longitude
            source = f"{geo_file}: latitude and longitude from its georeference ({geo.crs}), at the centre of its plan"
            said = _site_said(site, display, what, km, null)
            (warnings if said else notes).append(
                f"{where}: location {format_location(lat, lon)} taken from {geo_file}'s georeference ({geo.crs})"
                + (f"; {said}" if said else ": confirm it is the building's site (or give location.latitude and "
                   "location.longitude)"))
    elif site is None:
        said = (f"; {null[0]} gives latitude 0 and longitude 0, the null site (what a tool writes when none was set), "
                "not a location") if null else ""
        said += f"; {g.located[0][0]}'s georeference lies outside {g.located[0][1].area}" if g.located else ""
        raise InputError(f"{where}: location.latitude: not given, and no model file says where it stands (an IfcSite's "
                         f"RefLatitude, a gbXML Campus/Location, a georeference inside its CRS's area of use){said}; give "
                         "location.latitude and location.longitude")
    elif what is not None and g.located:  # a tool's default site, and a georeference outside its CRS: neither holds
        raise InputError(f"{where}: location.latitude: not given, and neither place the model files give can be trusted: "
                         f"{display}'s site {format_location(site.latitude, site.longitude)} is {what}, and "
                         f"{g.located[0][0]}'s georeference lies outside {g.located[0][1].area}; give "
                         "location.latitude and location.longitude")
    else:
        lat, lon, source = site.latitude, site.longitude, site.source
        if what is not None:
            warnings.append(f"{where}: location {format_location(lat, lon)} taken from {display} is probably the tool's "
                            f"default: {what}, not the building's site; confirm it, or give location.latitude and "
                            "location.longitude")
        else:
            notes.append(f"location {format_location(lat, lon)} taken from {location_source(source)}: confirm it is the "
                         "building's site (or give location.latitude and location.longitude)")
    lat = loc.latitude if loc.latitude is not None else lat
    lon = loc.longitude if loc.longitude is not None else lon
    for key, value, given in (("latitude", lat, loc.latitude), ("longitude", lon, loc.longitude)):
        if given is None:
            out[f"location.{key}"] = {"value": value, "source": source}
    return replace(loc, latitude=lat, longitude=lon), out, warnings, notes


def _site_said(site, display, what: str | None, km: float | None, null: list[str]) -> str:
    """Why the file's site is not taken where its georeference is: a tool's default, or far from it
    ("" where the file gives no site)."""
    if site is None:
        return f"{null[0]}'s site is the null site (latitude 0, longitude 0)" if null else ""
    at = f"{display}'s site {format_location(site.latitude, site.longitude)}"
    if what is not None:
        return f"{at} is {what}, not the building's site"
    return f"{at} lies {km:,.0f} km from it (more than {GEOREF_MATCH_KM:g} km): the georeference is taken"


def location_source(source: str) -> str:
    """A site's source (``'house.ifc: latitude and longitude from IfcSite ...; true north from ...'``)
    without what it says of north."""
    head, _, rest = source.partition(": ")
    kept = [c for c in rest.split("; ") if "latitude" in c]
    return f"{head}: {'; '.join(kept)}" if kept else source


def format_location(lat: float, lon: float) -> str:
    """'52.0116 N, 4.3571 E' [deg]."""
    return format_latlon(lat, lon)


def compass_bearing(normal, true_north_deg: float) -> float | None:
    """The compass bearing a window faces [deg, clockwise from true north, 0-360): the direction of
    the horizontal part of its outward ``normal`` (3,), with true north at ``true_north_deg``
    [deg clockwise from the model's +Y]; None for a window facing up or down (:data:`MIN_HORIZONTAL`).

    The azimuth of a horizontal vector (x, y) clockwise from +Y is atan2(x, y); less north's.
    """
    n = np.asarray(normal, dtype=float)
    if math.hypot(n[0], n[1]) < MIN_HORIZONTAL:
        return None
    return (math.degrees(math.atan2(n[0], n[1])) - true_north_deg) % 360.0


def compass_point(bearing: float) -> str:
    """The nearest of the 16 compass points of a bearing [deg]."""
    return COMPASS[int(math.floor((bearing % 360.0) / 22.5 + 0.5)) % 16]


def bearing_label(normal, true_north_deg: float) -> str:
    """'faces 340 deg (NNW)', or 'faces up' / 'faces down' for a roof light."""
    b = compass_bearing(normal, true_north_deg)
    if b is None:
        return "faces up" if float(np.asarray(normal)[2]) > 0 else "faces down"
    b = round(b) % 360
    return f"faces {b:d} deg ({compass_point(b)})"


def location_lines(project: Project, scene) -> list[str]:
    """What ``validate`` says of the site: the location and north the run takes, and where from."""
    loc = scene.location
    out = []
    if loc is not None and loc.latitude is not None and loc.longitude is not None:
        src = [location_source(v["source"]) for k, v in scene.resolved.items() if k.startswith("location.")]
        from_ = (f"from {src[0]}: confirm it is the building's site" if src else "given by the project")
        out.append(f"location: {format_location(loc.latitude, loc.longitude)}, {loc.timezone}, {from_}")
    north = scene.resolved.get("model.true_north_deg")
    how = (f"from {north['source']}" if north else "given by the project" if project.model.true_north_deg is not None
           else "the model's +Y (no file says)")
    out.append(f"true north: {round(scene.true_north_deg, 6) + 0.0:g} deg clockwise from the model's +Y, {how}")
    return out


def _north_against_city(g: Geometry, city: CityFrame) -> list[str]:
    """A warning per model file whose own north (its TrueNorth turned with its transform) is more
    than :data:`~en17037cli.scene.georef.NORTH_MISMATCH_DEG` from the city model's true north."""
    out = []
    for display, site, rotate_deg in g.sites:
        if site.true_north_deg is None or display == city.display:
            continue
        own = (site.true_north_deg - rotate_deg) % 360.0
        if angle_between_deg(own, city.north_deg) > NORTH_MISMATCH_DEG:
            turn = (site.true_north_deg - city.north_deg) % 360.0
            out.append(f"{display}: its TrueNorth, turned with its transform, puts true north at {own:.1f} deg clockwise "
                       f"from +Y, where {city.source} has it at {city.north_deg:.1f} deg: north taken from the city model "
                       f"(the frame its neighbours stand in); to set the file down as its TrueNorth says, give its "
                       f"transform rotate_deg: {turn:.2f}, or give model.true_north_deg")
    return out


def _site_against_city(g: Geometry, city: CityFrame, where: str) -> list[str]:
    """A warning per model file whose own site (not the null site) lies more than
    :data:`~en17037cli.scene.georef.SITE_MISMATCH_M` from where the city model puts the building."""
    out = []
    for display, site, _ in g.sites:
        if site.latitude is None or site.longitude is None or is_null_site(site.latitude, site.longitude):
            continue
        d = distance_m(site.latitude, site.longitude, city.latitude, city.longitude)
        if d > SITE_MISMATCH_M:
            out.append(f"{where}: {display} says it stands at {format_location(site.latitude, site.longitude)}, "
                       f"{d / 1000:.0f} km from where {city.source} puts it ({format_location(city.latitude, city.longitude)}): "
                       "the location is taken from the city model (a site in the file is often the authoring tool's or "
                       "the office's); give location.latitude and location.longitude to choose another")
    return out
