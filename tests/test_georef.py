"""The site from the georeference (issue 43): an IfcMapConversion read by the schema's rules for
units, checked against its CRS's area of use, and weighed against the IfcSite.

Built like real exports (never one file): the one-room IFC house of tests/ifc_box.py with a 1.2 m
south window, its IfcSite and an IfcMapConversion to the Dutch grid (EPSG:28992) placing the
centre of its plan (3.3, 2.8) m on the grid's origin, Amersfoort (155000, 463000) m, whose
latitude and longitude the grid's definition gives: 52°09'22.178"N 5°23'15.500"E (Bessel
ellipsoid, the Amersfoort datum the RD projection is defined on: Schreutelkamp and Strang van
Hees, "Benaderingsformules voor de transformatie tussen RD- en WGS84-kaartcoördinaten", 2001).

* ``revit_mm``: Revit 2020: millimetres, no MapUnit, no Scale, Eastings and Northings in
  millimetres (the schema: the project's unit); its IfcSite Revit's default Boston.
* ``mapunit_m``: millimetres, MapUnit metre, Scale 0.001 (the schema's own way of saying metres).
* ``mapunit_m_no_scale``: millimetres, MapUnit metre, no Scale: the Scale as written would make
  the model 1000 times larger: kept at its size, offsets in metres, a note.
* ``scale_implied``: millimetres, no MapUnit, Scale 0.001, offsets in metres (Bonsai writes this):
  read in the unit the Scale converts to, warned.
* ``grid_scale``: metres, MapUnit metre, Scale 0.9996 (a grid's scale factor): the model scaled by it.
* ``outside``: a metre project whose Eastings and Northings are written in millimetres (no
  MapUnit): outside the grid's area of use in every unit it can be read in (metres): no location;
  with Boston as its site neither holds: exit 2 naming the keys.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.errors import InputError
from en17037cli.io import read_model
from en17037cli.project import load_project
from en17037cli.scene import build_scene
from en17037cli.scene.site import DEFAULT_SITES
from tests.ifc_box import box_shell

pytest.importorskip("ifcopenshell")
pytest.importorskip("pyproj")

#: Amersfoort, the origin of the Dutch grid: (155000, 463000) m, 52°09'22.178"N 5°23'15.500"E.
RD_ORIGIN = (155000.0, 463000.0)
AMERSFOORT = (52 + 9 / 60 + 22.178 / 3600, 5 + 23 / 60 + 15.500 / 3600)
CENTRE = (3.3, 2.8)  # the centre of the house's plan [m]
BOSTON = DEFAULT_SITES[1][:2]  # Revit's default site, as its IFC export writes it

#: case -> (project unit, MapUnit, Scale, offset unit [m per unit written], geometry scale)
CASES = {
    "revit_mm": ("MILLIMETER", None, None, 0.001, 1.0),
    "mapunit_m": ("MILLIMETER", "METRE", 0.001, 1.0, 1.0),
    "mapunit_m_no_scale": ("MILLIMETER", "METRE", None, 1.0, 1.0),
    "scale_implied": ("MILLIMETER", None, 0.001, 1.0, 1.0),
    "grid_scale": ("METER", "METRE", 0.9996, 1.0, 0.9996),
    "outside": ("METER", None, None, 0.001, 1.0),  # a metre project, its offsets written in millimetres
}


def house(path: Path, case: str, site=BOSTON) -> Path:
    """The one-room house written as ``case`` says (see the module docstring)."""
    import ifcopenshell.util.unit as ifc_unit

    unit, map_unit, scale, per, _ = CASES[case]
    b, st, walls = box_shell()
    room = b.space("R1", "Room", st, [(0.3, 0.3), (6.3, 0.3), (6.3, 5.3), (0.3, 5.3)], 0.0, 2.7)
    b.window("W", st, walls[0], (3.3, 0.0, 1.5), (0, -1, 0), (1, 0, 0), 1.2, 1.2, spaces=[room])
    b.locate(*site, 0.0)
    f = b.f if unit == "METER" else ifc_unit.convert_file_length_units(b.f, unit)
    (ctx,) = [c for c in f.by_type("IfcGeometricRepresentationContext", include_subtypes=False) if c.ContextType == "Model"]
    mu = f.createIfcSIUnit(None, "LENGTHUNIT", None, map_unit) if map_unit else None
    crs = f.createIfcProjectedCRS(Name="EPSG:28992", Description="Amersfoort / RD New", MapUnit=mu)
    # the centre of the plan on the grid's origin: E = origin - s centre [m], written in units of ``per`` m
    e, n = ((o - CASES[case][4] * c) / per for o, c in zip(RD_ORIGIN, CENTRE))
    f.createIfcMapConversion(SourceCRS=ctx, TargetCRS=crs, Eastings=e, Northings=n, OrthogonalHeight=0.0,
                             XAxisAbscissa=1.0, XAxisOrdinate=0.0, Scale=scale)
    f.write(str(path))
    return path


def project(tmp: Path, case: str, site=BOSTON, location: dict | None = None) -> Path:
    ifc = house(tmp / f"{case}.ifc", case, site)
    doc = {"version": 1, "name": case, "model": {"files": [{"path": str(ifc)}]},
           "location": {"timezone": "Europe/Amsterdam", **(location or {})},
           "rooms": [{"ifc_spaces": "*"}], "sunlight": {"date": "03-21"}, "requirements": {"view": "none", "sunlight": "minimum"}}
    p = tmp / f"{case}.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p


@pytest.mark.parametrize("case", ["revit_mm", "mapunit_m", "mapunit_m_no_scale", "scale_implied", "grid_scale"])
def test_the_map_conversion_is_read_in_its_units(tmp_path, case):
    """The house's south-east corner (6.6, 0, 0) lands at origin + s (6.6 - 3.3, 0 - 2.8) [m], s the
    grid's scale (1 but for grid_scale), whatever unit the offsets are written in."""
    m = read_model(house(tmp_path / "h.ifc", case))
    s = CASES[case][4]
    corner = np.array([RD_ORIGIN[0] + s * (6.6 - CENTRE[0]), RD_ORIGIN[1] + s * (0.0 - CENTRE[1]), 0.0])
    assert np.min(np.linalg.norm(m.vertices - corner, axis=1)) < 2e-6
    assert np.ptp(m.vertices[:, 0]) == pytest.approx(6.6 * s, abs=1e-6)  # the model at its own size (times the grid's)
    (note,) = [x for x in m.notes if "placed by its IfcMapConversion" in x]
    unit_warnings = [w for w in m.warnings if "IfcMapConversion" in w]
    if case in ("revit_mm", "mapunit_m", "grid_scale"):  # as the schema says
        assert unit_warnings == []
        assert ("millimetres" if case == "revit_mm" else "metres") in note
    elif case == "mapunit_m_no_scale":  # a note (buildingSMART's own example writes this): the offsets as the schema says
        assert unit_warnings == []
        (n,) = [x for x in m.notes if "would make the model 1000 times its size" in x]
        assert "kept at its own size" in n
    else:  # scale_implied: the schema's millimetres put it near the grid's origin far south of the Netherlands
        assert any("read in millimetres" in w and "outside EPSG:28992's area of use" in w and "read in metres" in w
                   for w in unit_warnings)


def test_a_revit_model_with_a_default_site_is_located_by_its_georeference(tmp_path):
    """Revit 2020: the IfcSite is Revit's Boston, the map conversion (in millimetres) puts the house
    on Amersfoort: the location is Amersfoort, from the georeference, and a warning names both."""
    p = project(tmp_path, "revit_mm")
    s = build_scene(load_project(p, []))
    assert s.location.latitude == pytest.approx(AMERSFOORT[0], abs=1e-6)
    assert s.location.longitude == pytest.approx(AMERSFOORT[1], abs=1e-6)
    assert "georeference (EPSG:28992)" in s.resolved["location.latitude"]["source"]
    (w,) = [x for x in s.warnings if "taken from" in x and "georeference" in x]
    assert "52.1562 N, 5.3876 E" in w and "42.3584 N, 71.0598 W" in w and "Revit's default site (Boston, MA)" in w
    r = CliRunner().invoke(cli, ["validate", str(p)], catch_exceptions=False)
    assert r.exit_code == 0
    (line,) = [x for x in r.output.splitlines() if x.startswith("location: ")]
    assert line.startswith("location: 52.1562 N, 5.3876 E, Europe/Amsterdam, from ")
    assert "revit_mm.ifc: latitude and longitude from its georeference (EPSG:28992)" in line


def test_a_site_that_agrees_with_the_georeference_is_kept(tmp_path):
    """An IfcSite 2 km from where the georeference puts the house: the site, with a note."""
    site = (AMERSFOORT[0] + 2.0 / 111.2, AMERSFOORT[1])  # 2 km north (111.2 km per degree of latitude)
    s = build_scene(load_project(project(tmp_path, "revit_mm", site=site), []))
    assert (s.location.latitude, s.location.longitude) == pytest.approx(site, abs=1e-9)
    assert any("agrees within 2.0 km" in n for n in s.notes) and not any("georeference" in w for w in s.warnings)


def test_a_site_far_from_the_georeference_gives_way_to_it(tmp_path):
    """An IfcSite in Delft (52.0116 N, 4.3571 E, 73 km away) that is no tool's default: the
    georeference wins, and the warning says how far apart they are."""
    s = build_scene(load_project(project(tmp_path, "revit_mm", site=(52.0116, 4.3571)), []))
    assert s.location.latitude == pytest.approx(AMERSFOORT[0], abs=1e-6)
    (w,) = [x for x in s.warnings if "taken from" in x and "georeference" in x]
    # haversine, R = 6371.0088 km: 52.0116 N 4.3571 E to 52.15616 N 5.38764 E
    p1, p2, dl = math.radians(52.0116), math.radians(AMERSFOORT[0]), math.radians(AMERSFOORT[1] - 4.3571)
    km = 2 * 6371.0088 * math.asin(math.sqrt(math.sin((p2 - p1) / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2))
    assert f"lies {km:,.0f} km from it" in w and "52.0116 N, 4.3571 E" in w


def test_a_given_location_far_from_a_georeferenced_file_is_warned(tmp_path):
    """The project gives Delft; the house's georeference says Amersfoort: the location given is
    kept (the project's word), with a warning naming both."""
    s = build_scene(load_project(project(tmp_path, "revit_mm", location={"latitude": 52.0116, "longitude": 4.3571}), []))
    assert (s.location.latitude, s.location.longitude) == (52.0116, 4.3571)
    (w,) = [x for x in s.warnings if "location 52.0116 N, 4.3571 E given" in x]
    assert "52.1562 N, 5.3876 E" in w and "the sun is taken at the location given" in w


def test_a_georeference_outside_its_crs_is_no_location(tmp_path):
    """Offsets 1000 times too large lie outside the grid's area of use in every unit: with a
    plausible site the site is taken and the georeference warned; with Revit's Boston neither
    holds: exit 2 naming the keys to set."""
    s = build_scene(load_project(project(tmp_path, "outside", site=(52.0116, 4.3571)), []))
    assert (s.location.latitude, s.location.longitude) == pytest.approx((52.0116, 4.3571), abs=1e-6)
    (w,) = [x for x in s.warnings if "outside EPSG:28992's area of use" in x]
    assert "outside.ifc: its georeference puts the model" in w and "not taken as the building's location" in w
    (tmp_path / "b").mkdir()
    p = project(tmp_path / "b", "outside")
    with pytest.raises(InputError) as e:
        build_scene(load_project(p, []))
    assert "neither place the model files give can be trusted" in str(e.value)
    assert "Revit's default site (Boston, MA)" in str(e.value) and "give location.latitude and location.longitude" in str(e.value)
    r = CliRunner().invoke(cli, ["validate", str(p)], catch_exceptions=False)
    assert r.exit_code == 2 and "location.latitude" in r.output


ROTTERDAM = Path(__file__).resolve().parents[1] / "sample_projects" / "cityjson-rotterdam" / "project.yaml"


def test_a_city_model_says_where_the_building_stands(tmp_path):
    """The Rotterdam sample: a box room placed among 15 CityJSON buildings (EPSG:7415). The
    location the project gives (51.922 N, 4.481 E) agrees with the city model: nothing said. Given
    as Paris, the city model's CRS puts the model 350 km away: warned, the given location kept.
    Left out, it is taken from the city model's CRS where the building is set in it (issue 45: one
    building, one city, one sun), read at the windows (the OBJ placed by its transform) in WGS 84,
    which is within metres of the box room's centre read in the CRS's own datum (Amersfoort)."""
    s = build_scene(load_project(ROTTERDAM))
    assert not any("georeference" in w for w in s.warnings)
    s = build_scene(load_project(ROTTERDAM, ["location.latitude=48.8566", "location.longitude=2.3522"]))
    (w,) = [x for x in s.warnings if "georeference" in x]
    assert "location 48.8566 N, 2.3522 E given" in w and "rotterdam_subset.json's georeference (EPSG:7415)" in w
    assert (s.location.latitude, s.location.longitude) == (48.8566, 2.3522)
    doc = yaml.safe_load(ROTTERDAM.read_text())
    for f in doc["model"]["files"]:
        f["path"] = str(ROTTERDAM.parent / f["path"])
    del doc["location"]["latitude"], doc["location"]["longitude"]
    (tmp_path / "p.yaml").write_text(yaml.safe_dump(doc))
    s = build_scene(load_project(tmp_path / "p.yaml"))
    import pyproj

    obj = np.array([[float(x) for x in line.split()[1:4]] for line in (ROTTERDAM.parent / "box.obj").read_text().splitlines()
                    if line.startswith("v ")])
    x, y = 0.5 * (obj[:, :2].min(axis=0) + obj[:, :2].max(axis=0)) + (90965.0, 435708.0)  # the box room's centre, placed
    lon, lat = pyproj.Transformer.from_crs("EPSG:28992", "EPSG:4289", always_xy=True).transform(x, y)  # RD -> Amersfoort
    # the datums differ by about 100 m here (Bessel against WGS 84), the windows lie within the room: 0.002 deg
    assert (s.location.latitude, s.location.longitude) == pytest.approx((lat, lon), abs=2e-3)
    assert "rotterdam_subset.json: the city model's CRS (EPSG:7415) at the windows" in s.resolved["location.latitude"]["source"]
