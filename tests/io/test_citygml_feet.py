"""CityGML in a CRS whose unit is the foot (issue 35): New York City's city model is in EPSG:2263
(NAD83 / New York Long Island, US survey feet) with NAVD88 heights in US feet. Projected to a
project's CRS in metres, its plan became metres and its heights stayed in feet: every building
3.28 times too tall, with a note saying the heights were kept as the file gives them. A file whose
plan is in feet gives its heights in feet too: they are converted, the note says from what, and a
compound CRS (EPSG:2263+5703) says otherwise where the heights are in metres."""
from __future__ import annotations

import numpy as np
import pytest
from citygml_files import box_polys, building, city_model, write

from en17037cli.geometry import triangle_normals
from en17037cli.io import ReadOptions
from en17037cli.io.citygml import read_citygml
from en17037cli.io.citygml.crs import parse_srs_name, parse_vertical

pytest.importorskip("lxml")
pytest.importorskip("pyproj")

#: The US survey foot [m] (exactly 1200/3937), the unit of EPSG:2263 and of NAVD88 height (ftUS), EPSG:6360.
US_FT = 1200.0 / 3937.0
#: A 40 x 60 ft building, 30 ft tall, on a ground 10 ft above the datum, in Manhattan [ftUS].
X0, Y0, W, D, Z0, H = 987000.0, 212000.0, 40.0, 60.0, 10.0, 30.0


def tile(tmp_path, srs: str, name: str = "nyc.gml"):
    return write(tmp_path, city_model([building("b", box_polys(X0, X0 + W, Y0, Y0 + D, Z0, H), srs=srs)]), name)


def heights(mesh) -> tuple[float, float]:
    z = mesh.vertices[:, 2]
    return float(z.min()), float(z.max())


@pytest.mark.parametrize("srs", ["EPSG:2263", "EPSG:2263+6360", "urn:ogc:def:crs,crs:EPSG::2263,crs:EPSG::6360"])
def test_heights_in_feet_are_metres_once_the_plan_is(tmp_path, srs):
    """Projected to UTM 18N (metres): the ground at 10 ftUS = 3.048006 m and the roof 30 ftUS higher
    (exact conversions; 1e-9 m: float64). The roof's 40 x 60 ft is 222.97 m² within the ratio of the
    two projections' scale factors squared (UTM's k about 0.99970 at 85 km from its central meridian,
    the state plane's within 1e-4 of 1: 0.1 %)."""
    m = read_citygml(tile(tmp_path, srs), ReadOptions(target_crs="EPSG:32618"))
    lo, hi = heights(m)
    assert abs(lo - Z0 * US_FT) < 1e-9 and abs(hi - lo - H * US_FT) < 1e-9
    roof = m.vertices[m.triangles][np.all(m.vertices[m.triangles][..., 2] == hi, axis=1)]
    roof_m2 = float(triangle_normals(roof)[1].sum())
    assert abs(roof_m2 / (W * D * US_FT ** 2) - 1.0) < 1e-3
    said = " ".join(m.notes)
    assert "projected to EPSG:32618" in said and "heights kept as the file gives them" not in said
    if srs == "EPSG:2263":  # a 2D CRS names no vertical unit: the plan's, said, with the key that says otherwise
        assert "heights taken in US survey foot, the plan's (the CRS names no vertical unit)" in said
        assert "crs: EPSG:2263+5703" in said
    else:
        assert "heights in US survey foot (the CRS's vertical unit) converted to metres" in said


def test_a_compound_crs_with_heights_in_metres_keeps_them(tmp_path):
    m = read_citygml(tile(tmp_path, "EPSG:2263+5703"), ReadOptions(target_crs="EPSG:32618"))
    lo, hi = heights(m)
    assert lo == Z0 and hi == Z0 + H and "heights in metres, as the file gives them" in " ".join(m.notes)


def test_the_files_crs_key_says_the_heights_unit(tmp_path):
    m = read_citygml(tile(tmp_path, "EPSG:2263"), ReadOptions(crs="EPSG:2263+5703", target_crs="EPSG:32618"))
    assert heights(m) == (Z0, Z0 + H)


def test_a_tile_in_feet_read_on_its_own_is_in_metres(tmp_path):
    """No other file to project to: the tile stays in EPSG:2263, scaled to metres, plan and heights alike."""
    m = read_citygml(tile(tmp_path, "EPSG:2263"))
    assert np.allclose(m.vertices[:, :2].min(axis=0), [X0 * US_FT, Y0 * US_FT], rtol=0, atol=1e-6)
    lo, hi = heights(m)
    assert abs(hi - lo - H * US_FT) < 1e-9
    assert m.site.crs == "EPSG:2263"
    assert any("plan coordinates in US survey foot (EPSG:2263) scaled to metres" in n for n in m.notes)


@pytest.mark.parametrize("srs, plan, height", [
    ("EPSG:2263+6360", "EPSG:2263", "EPSG:6360"), ("urn:ogc:def:crs,crs:EPSG::25832,crs:EPSG::7837", "EPSG:25832", "EPSG:7837"),
    ("urn:adv:crs:ETRS89_UTM32*DE_DHHN2016_NH", "EPSG:25832", "EPSG:7837"), ("EPSG:2263", "EPSG:2263", None)])
def test_compound_forms(srs, plan, height):
    assert parse_srs_name(srs) == plan and parse_vertical(srs) == height
