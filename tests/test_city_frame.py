"""One building, two formats, one city, one answer (issue 45).

Set in a georeferenced city model, a building's location and true north come from the city
model's CRS at its windows (en17037cli/scene/georef.py), whatever the building's format says: the
FZK-Haus from its IFC (IfcSite near Karlsruhe, TrueNorth 50 deg off its +Y) and from an OBJ export
of it (no site, no north) get the same sun and the same view. Before, the IFC took its IfcSite and
TrueNorth and the OBJ took whatever the project gave.

The CRS's numbers are checked against the published approximation of RD New to WGS 84
(Schreutelkamp and Strang van Hees, "Benaderingsformules voor de transformatie tussen RD- en
WGS84-kaartcoordinaten", 2001; about 1 m), independent of PROJ.
"""
from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data"
FZK = SHARED / "real-models" / "AC20-FZK-Haus.ifc"
ROTTERDAM = SHARED / "cityjson" / "rotterdam_subset.json"
#: cjio's Delft tile (cityjson/cjio tests/data/delft.json, MIT), kept out of the repository: where set,
#: the same test runs in it too
DELFT = os.environ.get("EN17037_DELFT_TILE")


def rd_to_wgs84(x: float, y: float) -> tuple[float, float]:
    """(latitude, longitude) [deg] of RD New (x, y) [m] by the published polynomial (about 1 m)."""
    dx, dy = (x - 155000.0) * 1e-5, (y - 463000.0) * 1e-5
    n = (3235.65389 * dy - 32.58297 * dx**2 - 0.2475 * dy**2 - 0.84978 * dx**2 * dy - 0.0655 * dy**3
         - 0.01709 * dx**2 * dy**2 - 0.00738 * dx + 0.0053 * dx**4 - 0.00039 * dx**2 * dy**3 + 0.00033 * dx**4 * dy
         - 0.00012 * dx * dy)
    e = (5260.52916 * dx + 105.94684 * dx * dy + 2.45656 * dx * dy**2 - 0.81885 * dx**3 + 0.05594 * dx * dy**3
         - 0.05607 * dx**3 * dy + 0.01199 * dy - 0.00256 * dx**3 * dy**2 + 0.00128 * dx * dy**4 + 0.00022 * dy**2
         - 0.00022 * dx**2 + 0.00026 * dx**5)
    return 52.15517440 + n / 3600.0, 5.38720621 + e / 3600.0


def rd_north(x: float, y: float, h: float = 1.0) -> float:
    """True north [deg clockwise from +Y] on the RD grid at (x, y): the direction along which the
    polynomial's longitude stays constant and its latitude grows (central differences over h [m])."""
    dlon = np.array([rd_to_wgs84(x + h, y)[1] - rd_to_wgs84(x - h, y)[1], rd_to_wgs84(x, y + h)[1] - rd_to_wgs84(x, y - h)[1]])
    dlat = np.array([rd_to_wgs84(x + h, y)[0] - rd_to_wgs84(x - h, y)[0], rd_to_wgs84(x, y + h)[0] - rd_to_wgs84(x, y - h)[0]])
    d = np.array([-dlon[1], dlon[0]])  # perpendicular to the gradient of longitude
    d *= np.sign(d @ dlat)
    return math.degrees(math.atan2(d[0], d[1]))


@pytest.mark.parametrize("x, y", [(155000.0, 463000.0), (84878.0, 447587.0), (90965.0, 435708.0), (233000.0, 581000.0)])
def test_the_frame_of_rd_new_against_the_published_approximation(x, y):
    """Amersfoort (the projection's centre: north is +Y up to the datum shift), Delft, Rotterdam and Groningen: latitude and
    longitude within 2e-5 deg (the polynomial's 1 m is 1e-5 deg), north within 0.01 deg (the
    polynomial's angular error over a few metres of step is far below)."""
    pytest.importorskip("pyproj")
    from en17037cli.scene.city_frame import frame_at

    f = frame_at("EPSG:7415", "tile", x, y)
    lat, lon = rd_to_wgs84(x, y)
    assert (f.latitude, f.longitude) == pytest.approx((lat, lon), abs=2e-5)
    north = (f.north_deg + 180.0) % 360.0 - 180.0
    assert north == pytest.approx(rd_north(x, y), abs=0.01)
    if (x, y) == (155000.0, 463000.0):  # the central meridian (of Bessel's ellipsoid: WGS 84's differs by 1.7 m)
        assert abs(north) < 1e-3


def test_no_frame_without_a_projected_crs():
    """A geographic CRS (degrees) and an unknown code set no frame: the old rule stays."""
    pytest.importorskip("pyproj")
    from en17037cli.scene.city_frame import frame_at

    assert frame_at("EPSG:4326", "tile", 4.3, 52.0) is None
    assert frame_at("EPSG:999999", "tile", 0.0, 0.0) is None


def _project(tmp: Path, name: str, file: dict, city: dict, rooms: list) -> Path:
    doc = {"version": 1, "name": name, "model": {"files": [file, city]}, "location": {"timezone": "Europe/Amsterdam"},
           "rooms": rooms, "view": {"grid_spacing_m": 1.0, "angular_resolution_deg": 3.0}, "sunlight": {"date": "worst"},
           "requirements": {"view": "none", "sunlight": "minimum"}}
    p = tmp / f"{name}.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True))
    return p


TILES = [pytest.param(ROTTERDAM, {"crs": "EPSG:7415"}, (90960.0, 435712.0, 0.0, 30.0), id="rotterdam")]
if DELFT:
    TILES.append(pytest.param(Path(DELFT), {}, (84859.0, 447590.0, 0.0, 0.0), id="delft"))


@pytest.mark.real_models
@pytest.mark.skipif(not FZK.is_file() or not ROTTERDAM.is_file(), reason="../shared/data is absent")
@pytest.mark.parametrize("tile, keys, place", TILES)
def test_the_fzk_haus_in_a_city_tile_from_its_ifc_and_its_obj_gives_one_answer(tmp_path, tile, keys, place):
    """The FZK-Haus set down in a city tile (turned and moved by the same transform), the project
    giving only the time zone: the IFC and the OBJ export get the location and north of the tile's
    CRS at the windows (the IFC's IfcSite and TrueNorth warned, not taken), every room the same hours
    within 0.05 h, the same sunlight level and the same view level."""
    pytest.importorskip("ifcopenshell")
    pytest.importorskip("pyproj")
    from test_one_window import fzk_as_obj, report

    from en17037cli.project import load_project
    from en17037cli.scene import build_scene
    from en17037cli.scene.city_frame import frame_at

    x, y, z, turn = place
    transform = {"rotate_deg": turn, "translate_m": [x, y, z]}
    city = {"path": str(tile), **keys}
    ifc_p = _project(tmp_path, "ifc", {"path": str(FZK), "transform": transform}, city, [{"ifc_spaces": "*"}])
    scene = build_scene(load_project(ifc_p, []))
    frame = frame_at("EPSG:7415", "tile", *scene.origin[:2])
    assert (scene.location.latitude, scene.location.longitude) == pytest.approx((frame.latitude, frame.longitude), abs=1e-6)
    assert scene.true_north_deg == pytest.approx(frame.north_deg, abs=1e-9)
    said = " ".join(scene.warnings)
    assert "says it stands at 49.1004 N, 8.4365 E" in said and "its TrueNorth" in said, said
    rooms = [{"name": r.name, "floor_z": float(r.floor_z + scene.origin[2]),
              "floor": [[float(u), float(v)] for u, v in np.asarray(r.floor.exterior.coords)[:-1] + scene.origin[:2]]}
             for r in scene.rooms if r.windows]
    layers = [{"match": "glass*", "layer": "window"}, {"match": "ground*", "layer": "ground"}, {"match": "*", "layer": "interior"}]
    obj_p = _project(tmp_path, "obj", {"path": str(fzk_as_obj(tmp_path)), "layers": layers, "transform": transform}, city, rooms)
    a = {r["name"]: r for r in report(ifc_p, tmp_path / "a")["rooms"]}
    b = {r["name"]: r for r in report(obj_p, tmp_path / "b")["rooms"]}
    assert set(a) == set(b) and len(a) == 6
    for name in a:
        sa, sb = a[name]["sunlight"], b[name]["sunlight"]
        assert sb["hours_h"] == pytest.approx(sa["hours_h"], abs=0.05), name
        assert sb["level"] == sa["level"], name
        assert b[name]["view"]["level"] == a[name]["view"]["level"], name
