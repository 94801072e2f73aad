"""Where a model says it stands and which way is north, checked (scene/site.py, io/ifc_site.py):
the null site is no location, a tool's default site is warned, a TrueNorth that is not a
horizontal direction is warned with what was taken, and validate prints each window's bearing.

The sample house (en17037cli.samples.ifc.house) with its IfcSite and TrueNorth rewritten as real
exports write them: Vectorworks' (0, 0, 0) site, ArchiCAD's default 24°28'N 54°25'E, Revit
2013's TrueNorth (2, cos 90 deg, 1). Its windows face, by construction, south (living), west
(living), north (kitchen), south (bedroom west) and east (round window), in the model's frame
(+Y north before TrueNorth).
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.io.ifc_site import true_north
from en17037cli.samples.ifc import house
from en17037cli.scene.site import DEFAULT_SITES, compass_bearing, compass_point, default_site

ifcopenshell = pytest.importorskip("ifcopenshell")


def edited_house(tmp_path: Path, lat=None, lon=None, north_ratios=None) -> Path:
    """The sample house with its IfcSite's RefLatitude / RefLongitude (compound degrees) and its
    model context's TrueNorth ratios replaced where given."""
    path = house(tmp_path / "house.ifc")
    f = ifcopenshell.open(str(path))
    site = f.by_type("IfcSite")[0]
    if lat is not None:
        site.RefLatitude, site.RefLongitude = lat, lon
    if north_ratios is not None:
        ctx = next(c for c in f.by_type("IfcGeometricRepresentationContext") if c.ContextType == "Model")
        ctx.TrueNorth = f.createIfcDirection(north_ratios)
    f.write(str(path))
    return path


def project(tmp_path: Path, model: Path, location: dict | None = None, north: float | None = None) -> Path:
    doc = {"version": 1, "name": "site", "model": {"files": [{"path": model.name}]},  # beside the project file
           "location": {"timezone": "UTC", **(location or {})}, "rooms": [{"ifc_spaces": "*"}],
           "sunlight": {"date": "02-01", "period": {"start": "02-01", "end": "02-01"}}}
    if north is not None:
        doc["model"]["true_north_deg"] = north
    p = tmp_path / "project.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p


def validate(path: Path, *extra) -> tuple[int, str]:
    r = CliRunner().invoke(cli, ["validate", str(path), *extra])
    return r.exit_code, r.output


def test_the_null_site_is_not_a_location(tmp_path):
    """(0, 0, 0) for both, as Vectorworks writes a site nobody set: the project must give one."""
    ifc = edited_house(tmp_path, (0, 0, 0), (0, 0, 0))
    code, out = validate(project(tmp_path, ifc))
    assert code == 2 and len(out.strip().splitlines()) == 1
    assert "location.latitude: not given, and no model file says where it stands" in out
    assert "house.ifc gives latitude 0 and longitude 0, the null site" in out and "give location.latitude and location.longitude" in out
    # the project's location: the run goes on, nothing said of the file's
    code, out = validate(project(tmp_path, ifc, {"latitude": 52.0, "longitude": 4.36}))
    assert code == 0 and "location: 52.0000 N, 4.3600 E, UTC, given by the project" in out and "null site" not in out


@pytest.mark.parametrize("lat, lon, what", [
    ((24, 28, 0), (54, 25, 0), "ArchiCAD's default site (24°28'N 54°25'E, Abu Dhabi)"),
    ((42, 21, 30, 344238), (-71, -3, -35, -194702), "Revit's default site (Boston, MA)"),
])
def test_a_tools_default_site_is_warned_and_the_location_printed(tmp_path, lat, lon, what):
    ifc = edited_house(tmp_path, lat, lon)
    code, out = validate(project(tmp_path, ifc))
    deg = lambda v: math.copysign(abs(v[0]) + abs(v[1]) / 60 + abs(v[2]) / 3600 + abs(v[3] if len(v) > 3 else 0) / 3.6e9, v[0])  # noqa: E731
    la, lo = deg(lat), deg(lon)
    shown = f"{abs(la):.4f} {'N' if la >= 0 else 'S'}, {abs(lo):.4f} {'E' if lo >= 0 else 'W'}"
    assert code == 0
    assert f"location: {shown}, UTC, from house.ifc: latitude and longitude from IfcSite RefLatitude/RefLongitude" in out
    assert "confirm it is the building's site" in out
    assert (f"warning: project.yaml: location {shown} taken from house.ifc is probably the tool's default: {what}, not the "
            "building's site; confirm it, or give location.latitude and location.longitude") in out
    # given by the project, the file's site is not used: nothing to warn
    code, out = validate(project(tmp_path, ifc, {"latitude": la, "longitude": lo}))
    assert code == 0 and "probably the tool's default" not in out


def test_the_report_says_where_the_location_came_from(tmp_path):
    """A location from the model: a note to confirm it (report.json notes, report.md), and
    inputs.resolved with its source; a tool's default: the warning instead."""
    out = tmp_path / "o"
    r = CliRunner().invoke(cli, ["check", str(project(tmp_path, house(tmp_path / "house.ifc"))), "--out", str(out), "-q",
                                 "--no-plots"])
    assert r.exit_code in (0, 1), r.output
    report = json.loads((out / "report.json").read_text())
    note = ("location 52.0116 N, 4.3571 E taken from house.ifc: latitude and longitude from IfcSite RefLatitude/RefLongitude: "
            "confirm it is the building's site (or give location.latitude and location.longitude)")
    assert note in report["notes"] and note in (out / "report.md").read_text()
    assert report["inputs"]["resolved"]["location.latitude"]["value"] == pytest.approx(52.0116, abs=1e-9)
    assert not [w for w in report["warnings"] if "location" in w]
    (tmp_path / "d").mkdir()
    ifc = edited_house(tmp_path / "d", (24, 28, 0), (54, 25, 0))
    r = CliRunner().invoke(cli, ["check", str(project(tmp_path / "d", ifc)), "--out", str(tmp_path / "o2"), "-q", "--no-plots"])
    report = json.loads((tmp_path / "o2" / "report.json").read_text())
    assert [w for w in report["warnings"] if "probably the tool's default: ArchiCAD's default site" in w]
    assert not [n for n in report["notes"] if n.startswith("location")]


def test_a_site_near_a_default_is_not_it():
    """Within 0.001 deg (about 100 m) of a listed site is that site; the sample house's Delft, or
    a place 1 km from ArchiCAD's default, is not."""
    assert default_site(52.0116, 4.3571) is None and default_site(24.4667 + 0.01, 54.4167) is None
    assert all(default_site(la + 5e-4, lo - 5e-4) == what for la, lo, what in DEFAULT_SITES)


@pytest.mark.parametrize("ratios, north, warned", [
    ((math.sin(math.radians(20)), math.cos(math.radians(20))), 20.0, None),  # a 2D unit direction
    ((3.0, 3.0), 45.0, None),  # not normalised: still a direction (IfcDirection need not be unit)
    ((0.0, 1.0, 0.0), 0.0, None),  # three ratios, horizontal
    ((2.0, math.cos(math.pi / 2), 1.0), 0.0, "read as the 2D direction (0, 1) after a dimension count 2"),  # Revit 2013
    ((1.0, 0.0, 1.0), 90.0, "read as its horizontal part"),
    ((0.0, 0.0, 1.0), None, "has no horizontal direction: north taken along the model's +Y"),
])
def test_true_north_ratios(ratios, north, warned):
    got, warning = true_north(ratios)
    assert (got is None) == (north is None) and (north is None or abs(got - north) < 1e-9)
    assert (warning is None) == (warned is None) and (warned is None or warned in warning)


def test_revit_2013_true_north_is_warned_and_each_window_shows_its_bearing(tmp_path):
    """TrueNorth (2, 6.1e-17, 1): taken as +Y (0 deg), warned; before, its horizontal part (2, 0) put
    north at 90 deg silently. The windows' bearings follow from their outward normals."""
    ifc = edited_house(tmp_path, north_ratios=(2.0, math.cos(math.pi / 2), 1.0))
    path = project(tmp_path, ifc)
    code, out = validate(path)
    assert code == 0
    assert ("warning: house.ifc: the model context's TrueNorth (2, 0, 1) is not a horizontal direction; read as the 2D "
            "direction (0, 1) after a dimension count 2 (as Revit 2013 wrote it): true north 0.0 deg clockwise from the "
            "model's +Y (its horizontal part would put it at 90.0 deg); confirm it against the drawings") in out
    assert "true north: 0 deg clockwise from the model's +Y, from house.ifc" in out
    for name, bearing in (("W living south", "faces 180 deg (S)"), ("W living west", "faces 270 deg (W)"),
                          ("W kitchen north", "faces 0 deg (N)"), ("W bedroom round", "faces 90 deg (E)")):
        line = next(x for x in out.splitlines() if f"window '{name}'" in x)
        assert bearing in line
    # the project's north: no warning, the bearings turn with it (north 20 deg clockwise of +Y:
    # the +Y window faces 340)
    code, out = validate(project(tmp_path, ifc, north=20.0))
    assert "not a horizontal direction" not in out and "true north: 20 deg clockwise from the model's +Y, given by the project" in out
    assert "faces 340 deg (NNW)" in next(x for x in out.splitlines() if "window 'W kitchen north'" in x)
    doc = json.loads(validate(project(tmp_path, ifc, north=20.0), "--json")[1])
    got = {w["name"]: w["bearing_deg"] for r in doc["rooms"] for w in r.get("windows", [])}
    assert got == {"W living south": 160.0, "W living west": 250.0, "W kitchen north": 340.0, "W bedroom south": 160.0,
                   "W bedroom round": 70.0}


def test_bearings_do_not_depend_on_how_the_model_is_turned():
    """A model turned by A counterclockwise with north turned by -A faces the same way: the bearing
    of the turned normal with the turned north is the bearing before (an invariant, every 7 deg)."""
    for a in range(0, 360, 7):
        for az in range(0, 360, 13):
            n = (math.sin(math.radians(az)), math.cos(math.radians(az)), 0.0)  # azimuth az clockwise from +Y
            t = math.radians(a)  # counterclockwise: azimuth az - a
            turned = (math.cos(t) * n[0] - math.sin(t) * n[1], math.sin(t) * n[0] + math.cos(t) * n[1], 0.0)
            b0, b1 = compass_bearing(n, 10.0), compass_bearing(turned, (10.0 - a) % 360)
            assert abs((b0 - b1 + 180) % 360 - 180) < 1e-9
    assert compass_bearing((0.0, 0.0, 1.0), 0.0) is None  # a roof light has no bearing
    assert [compass_point(b) for b in (0, 11.2, 11.3, 90, 180, 348.7, 348.8)] == ["N", "N", "NNE", "E", "S", "NNW", "N"]
