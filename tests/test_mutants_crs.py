"""Mutation tests (issue 39): the CityGML ``srsName`` forms, the heights' unit, the axis order and
the placement of coordinates (``io/citygml/crs.py``), against the EPSG registry's own figures (the
US survey foot is 1200 / 3937 m by its definition) and coordinates worked by hand.
"""
from __future__ import annotations

import pytest

from en17037cli.io.citygml.crs import parse_srs_name, parse_vertical

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
