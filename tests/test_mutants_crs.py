"""Mutation tests (issue 39): the CityGML ``srsName`` forms, the heights' unit, the axis order and
the placement of coordinates (``io/citygml/crs.py``), against the EPSG registry's own figures (the
US survey foot is 1200 / 3937 m by its definition) and coordinates worked by hand.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from en17037cli.errors import InputError
from en17037cli.io.citygml.crs import CrsResolver, Placement, height_unit, parse_srs_name, parse_vertical

pytest.importorskip("pyproj")


@pytest.mark.parametrize("srs, expected", [
    ("", None),
    ("   ", None),
    ("  EPSG:25833  ", "EPSG:25833"),
    ("epsg:25833", "EPSG:25833"),
    ("EPSG:2263+6360", "EPSG:2263"),
    (" epsg:2263 + 6360 ", "EPSG:2263"),
    ("urn:adv:crs:etrs89_utm32", "EPSG:25832"),
    ("URN:ADV:CRS:DE_DHDN_3GK4*DE_DHHN92_NH", "EPSG:31468"),
    ("urn:x-ogc:def:crs,crs:EPSG::2263,crs:EPSG::6360", "EPSG:2263"),
    ("URN:OGC:DEF:CRS,crs:EPSG::25832,crs:EPSG::7837", "EPSG:25832"),
    ("CRS:84", "OGC:CRS84"),
    ("CRS84", "OGC:CRS84"),
    ("http://www.opengis.net/def/crs/OGC/1.3/CRS84", "OGC:CRS84"),
    ("EPSG:25833 (ETRS89)", None),
    ("urn:ogc:def:crs:EPSG::", None),
])
def test_srs_name_forms_by_hand(srs, expected):
    assert parse_srs_name(srs) == expected


@pytest.mark.parametrize("srs, expected", [
    ("EPSG:2263+6360", "EPSG:6360"),
    (" EPSG:2263 + 5703 ", "EPSG:5703"),
    ("urn:adv:crs:ETRS89_UTM32*DE_DHHN2016_NH", "EPSG:7837"),
    ("urn:adv:crs:ETRS89_UTM32* de_dhhn92_nh ", "EPSG:5783"),
    ("urn:adv:crs:ETRS89_UTM32", None),
    ("urn:adv:crs:ETRS89_UTM32*NOT_A_HEIGHT", None),
    ("urn:ogc:def:crs,crs:EPSG::25832,crs:EPSG::7837", "EPSG:7837"),
    ("urn:x-ogc:def:crs,crs:EPSG::2263,crs:EPSG::6360", "EPSG:6360"),
    ("urn:ogc:def:crs,crs:EPSG::25832", None),
    ("urn:ogc:def:crs,crs:EPSG::25832,crs:local", None),
    ("EPSG:25832", None),
    ("urn:ogc:def:crs:EPSG::25832", None),
])
def test_vertical_crs_forms_by_hand(srs, expected):
    assert parse_vertical(srs) == expected


# --- heights, placement and the resolver ----------------------------------------------------------

US_FT = 1200 / 3937  # the US survey foot [m], by its definition


def crs(name):
    import pyproj

    return pyproj.CRS.from_user_input(name)


def test_height_unit_by_the_registry():
    assert height_unit(crs("EPSG:25833"), crs("EPSG:6360")) == (pytest.approx(US_FT, rel=1e-12), "US survey foot", "")
    assert height_unit(crs("EPSG:2263+6360"), None) == (pytest.approx(US_FT, rel=1e-12), "US survey foot", "")
    assert height_unit(crs("EPSG:25832+7837"), None) == (1.0, "metre", "")
    assert height_unit(crs("EPSG:4979"), None) == (1.0, "metre", "")
    assert height_unit(crs("EPSG:4326"), None) == (1.0, "metre", "")
    assert height_unit(crs("EPSG:2263"), None) == (pytest.approx(US_FT, rel=1e-12), "US survey foot",
                                                   "the plan's (the CRS names no vertical unit)")
    assert height_unit(crs("EPSG:25833"), None) == (1.0, "metre", "")


class _Shift:
    def transform(self, x, y):
        return np.asarray(x) + 1000.0, np.asarray(y) * 2.0


def test_placement_by_hand():
    xyz = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
    p = Placement("EPSG:1", True, _Shift(), False, 0.5, 2.0)
    assert p.apply(xyz).tolist() == [[501.0, 1.0, 6.0], [502.5, 4.0, 12.0]]
    assert Placement("EPSG:1", False, None, False).apply(xyz).tolist() == xyz.tolist()
    assert Placement("EPSG:1", False, None, False, 1.0, 0.5).apply(xyz).tolist() == [[1, 2, 1.5], [4, 5, 3]]
    assert Placement("EPSG:1", False, None, False, 3.0).apply(xyz)[:, :2].tolist() == [[3, 6], [12, 15]]
    assert Placement("EPSG:1", False, _Shift(), False).apply(np.zeros((0, 3))).shape == (0, 3)


BERLIN = np.array([390000.0, 5820000.0])  # UTM 33N, easting first


def test_resolver_without_a_crs_and_in_metres():
    r = CrsResolver(Path("m.gml"), None, None)
    assert r.placement(None, None) is None and r.notes == []
    r = CrsResolver(Path("d/m.gml"), None, "EPSG:25832")
    assert r.placement(None, BERLIN) is None
    assert r.notes == ["m.gml: no srsName and no 'crs' key: coordinates taken as EPSG:25832"]
    r = CrsResolver(Path("m.gml"), None, None)
    p = r.placement("urn:ogc:def:crs:EPSG::25833", BERLIN)
    assert (p.name, p.swap, p.transformer, p.geographic, p.xy_scale, p.z_scale) == ("EPSG:25833", False, None, False, 1.0, 1.0)
    assert r.out_name == "EPSG:25833" and r.notes == [] and r.placement("urn:ogc:def:crs:EPSG::25833", None) is p
    # the project's key wins over the file, by name or as PROJ reads it
    r = CrsResolver(Path("m.gml"), "EPSG:25832", None)
    assert r.placement("EPSG:4326", None).name == "EPSG:25832"
    r = CrsResolver(Path("m.gml"), "ESRI:102100", None)
    assert r.placement("whatever", None).name == "ESRI:102100"


def test_resolver_errors_name_the_file_and_say_what_to_do():
    with pytest.raises(InputError, match=r"^m.gml: unknown CRS srsName 'local'; set the file's 'crs' key in the project"):
        CrsResolver(Path("m.gml"), None, None).placement("local", None)
    with pytest.raises(InputError, match=r"srsName 'EPSG:999999' names a CRS that PROJ does not know; set the file's"):
        CrsResolver(Path("m.gml"), None, None).placement("EPSG:999999", None)
    with pytest.raises(InputError, match=r"is in degrees \(latitude, longitude\) and no other model file says its CRS; give the "
                                         r"CRS of the model files in metres with their 'crs' key \(e.g. crs: EPSG:32633, "
                                         r"WGS 84 / UTM zone 33N, if they are in it\) so the city model"):
        CrsResolver(Path("m.gml"), None, None).placement("EPSG:4326", np.array([13.4, 52.5]))
    with pytest.raises(InputError, match=r"\(e.g. crs: EPSG:25832\) so"):
        CrsResolver(Path("m.gml"), None, None).placement("EPSG:4326", None)
    with pytest.raises(InputError, match=r"^m.gml: the project's CRS EPSG:4326 is in degrees; the model files must be in a "
                                         r"projected CRS in metres$"):
        CrsResolver(Path("m.gml"), None, "EPSG:4326").placement("EPSG:25833", BERLIN)


def test_resolver_reprojects_degrees_and_scales_feet():
    import pyproj

    r = CrsResolver(Path("d/m.gml"), None, "EPSG:25833")
    p = r.placement("urn:ogc:def:crs:EPSG::4326", np.array([52.5, 13.4]))  # the URN's own order: latitude first
    assert p.swap and p.geographic and r.reprojected == {"EPSG:4326"}
    assert r.notes == ["m.gml: coordinates in EPSG:4326 (WGS 84) projected to EPSG:25833 (ETRS89 / UTM zone 33N) with PROJ; "
                       "heights in metres, as the file gives them"]
    x, y = pyproj.Transformer.from_crs("EPSG:4326", "EPSG:25833", always_xy=True).transform(13.4, 52.5)
    assert p.apply(np.array([[52.5, 13.4, 30.0]]))[0].tolist() == pytest.approx([x, y, 30.0], abs=1e-6)
    r = CrsResolver(Path("m.gml"), None, "EPSG:25833")
    assert r.placement("EPSG:25833", BERLIN).transformer is None and r.reprojected == set() and r.notes == []
    r = CrsResolver(Path("m.gml"), None, None)
    p = r.placement("EPSG:2263", np.array([987000.0, 195000.0]))
    assert p.xy_scale == pytest.approx(US_FT, rel=1e-12) and p.z_scale == pytest.approx(US_FT, rel=1e-12)
    assert r.notes == ["m.gml: plan coordinates in US survey foot (EPSG:2263) scaled to metres",
                       "m.gml: heights taken in US survey foot, the plan's (the CRS names no vertical unit), and converted to "
                       "metres; if they are in another unit, give the file's crs key with its vertical CRS (e.g. crs: "
                       "EPSG:2263+5703 for NAVD88 heights in metres)"]
    r = CrsResolver(Path("m.gml"), None, None)
    r.placement("EPSG:2263+6360", np.array([987000.0, 195000.0]))
    assert r.notes[1] == "m.gml: heights in US survey foot (the CRS's vertical unit) converted to metres"
    r = CrsResolver(Path("m.gml"), None, "EPSG:2263")  # a target in feet: the plan scaled after the transformation
    p = r.placement("EPSG:32618", np.array([585000.0, 4510000.0]))
    assert p.xy_scale == pytest.approx(US_FT, rel=1e-12) and p.z_scale == 1.0
    assert r.notes[-1] == "m.gml: plan coordinates in US survey foot (EPSG:2263) scaled to metres"


@pytest.mark.parametrize("srs, first, swap, note", [
    ("EPSG:31468", (4468000.0, 5330000.0), False, "(east, north) / (lon, lat), not in the CRS's own axis order; read so"),
    ("EPSG:31468", (5330000.0, 4468000.0), True, None),
    ("EPSG:25833", (5820000.0, 390000.0), True, "are written (north, east) / (lat, lon); read so"),
    ("EPSG:25833", (390000.0, 5820000.0), False, None),
    ("EPSG:25833", (0.0, 0.0), False, None),
    ("urn:ogc:def:crs:EPSG::31468", (0.0, 0.0), False, None),
    ("urn:ogc:def:crs:EPSG::6697", (35.6, 139.7), True, None),
    ("urn:ogc:def:crs:EPSG::6697", (139.7, 35.6), False, "(east, north) / (lon, lat), not in the CRS's own axis order"),
    ("urn:ogc:def:crs:EPSG::4326", (13.4, 100.0), True, None),
    ("CRS:84", (139.7, 35.6), False, None),
    ("urn:ogc:def:crs:EPSG::25833", None, False, None),
])
def test_axis_order_by_the_area_of_use(srs, first, swap, note):
    r = CrsResolver(Path("m.gml"), None, "EPSG:25833")
    p = r.placement(srs, None if first is None else np.array(first))
    assert p.swap is swap
    said = [n for n in r.notes if "written" in n]
    assert (said == []) if note is None else (len(said) == 1 and note in said[0])


def test_messages_in_full():
    import sys

    r = CrsResolver(Path("m.gml"), None, None)
    with pytest.raises(InputError) as e:
        r.placement("local", None)
    assert str(e.value) == ("m.gml: unknown CRS srsName 'local'; set the file's 'crs' key in the project (e.g. crs: EPSG:25832) "
                            "to say which CRS its coordinates are in")
    with pytest.raises(InputError) as e:
        CrsResolver(Path("m.gml"), None, "EPSG:999999").placement("EPSG:25833", BERLIN)
    assert str(e.value) == ("m.gml: srsName 'EPSG:999999' names a CRS that PROJ does not know; set the file's 'crs' key in "
                            "the project (e.g. crs: EPSG:25832) to say which it is")
    with pytest.raises(InputError) as e:  # a vertical CRS PROJ does not know: the srsName as written
        r.placement("urn:ogc:def:crs,crs:EPSG::25832,crs:EPSG::999999", None)
    assert "srsName 'urn:ogc:def:crs,crs:EPSG::25832,crs:EPSG::999999' names a CRS" in str(e.value)
    # degrees with no target: the UTM zone of the file's first vertex, in the order the file writes it
    with pytest.raises(InputError, match=r"\(e.g. crs: EPSG:32734, WGS 84 / UTM zone 34S, if they are in it\)"):
        CrsResolver(Path("m.gml"), None, None).placement("urn:ogc:def:crs:EPSG::4326", np.array([-33.9, 18.4]))
    with pytest.raises(InputError, match=r"\(e.g. crs: EPSG:25832\) so the city model"):  # no UTM zone at 89.5 deg N
        CrsResolver(Path("m.gml"), None, None).placement("EPSG:4326", np.array([10.0, 89.5]))
    # without pyproj: one line naming the file and what to install
    saved = {k: sys.modules.pop(k) for k in [k for k in sys.modules if k == "pyproj" or k.startswith("pyproj.")]}
    sys.modules["pyproj"] = None  # type: ignore[assignment]
    try:
        with pytest.raises(InputError) as e:
            CrsResolver(Path("d/m.gml"), None, None).placement("EPSG:25833", None)
        assert str(e.value) == "d/m.gml: reading CityGML needs pyproj (coordinate reference systems): pip install 'en17037cli[citygml]'"
    finally:
        del sys.modules["pyproj"]
        sys.modules.update(saved)


def test_resolver_caches_none_and_keeps_heights_in_the_reprojection_note():
    r = CrsResolver(Path("m.gml"), None, "EPSG:25832")
    assert r.placement(None, None) is None and r.placement(None, None) is None and len(r.notes) == 1
    r = CrsResolver(Path("m.gml"), None, "EPSG:32618")
    r.placement("EPSG:2263+6360", np.array([987000.0, 195000.0]))
    assert r.notes == ["m.gml: coordinates in EPSG:2263 (NAD83 / New York Long Island (ftUS)) projected to EPSG:32618 "
                       "(WGS 84 / UTM zone 18N) with PROJ; heights in US survey foot (the CRS's vertical unit) converted to metres"]
    # a compound CRS whose horizontal part is the target: nothing to project
    r = CrsResolver(Path("m.gml"), None, "EPSG:2263")
    p = r.placement("EPSG:2263+6360", np.array([987000.0, 195000.0]))
    assert p.transformer is None and r.reprojected == set()


@pytest.mark.parametrize("lat, lon, swap", [
    (35.0, 121.9, True), (35.0, 121.0, False), (35.0, 158.2, True), (35.0, 159.0, False), (16.5, 140.0, True),
    (15.5, 140.0, False), (46.5, 140.0, True), (47.5, 140.0, False), (80.0, 140.0, False)])
def test_degrees_inside_the_area_of_use_within_a_degree(lat, lon, swap):
    # JGD2011, EPSG:6668 (latitude first), area 122.38-157.65 E, 17.09-46.05 N: a first vertex (lat, lon) within a
    # degree of it is read latitude first; outside, the short form's fallback is (longitude, latitude)
    r = CrsResolver(Path("m.gml"), None, "EPSG:6677")
    assert r.placement("EPSG:6668", np.array([lat, lon])).swap is swap


def test_projected_area_padded_by_a_tenth():
    import pyproj

    c = pyproj.CRS.from_user_input("EPSG:25833")
    w, s, e, n = c.area_of_use.bounds
    x0, y0, x1, y1 = pyproj.Transformer.from_crs(c.geodetic_crs, c, always_xy=True).transform_bounds(w, s, e, n)
    pad = 0.1 * max(x1 - x0, y1 - y0)
    x = x1 + 0.5 * pad  # beyond the area's easting, within its pad: written northing first, read so
    r = CrsResolver(Path("m.gml"), None, None)
    assert r.placement("EPSG:25833", np.array([0.5 * (y0 + y1), x])).swap is True
    assert r.notes == ["m.gml: coordinates in EPSG:25833 are written (north, east) / (lat, lon); read so"]
    r = CrsResolver(Path("m.gml"), None, None)
    assert r.placement("epsg:31468", np.array([4468000.0, 5330000.0])).swap is False
    assert r.notes == ["m.gml: coordinates in EPSG:31468 are written (east, north) / (lon, lat), not in the CRS's own axis "
                       "order; read so"]
    r = CrsResolver(Path("m.gml"), None, "EPSG:25833")
    assert r.placement("epsg:4326", np.array([13.4, 52.5])).swap is False  # the short form, any case: longitude first
