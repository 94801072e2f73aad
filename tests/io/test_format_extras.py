"""A reader whose library is missing stops with one line naming the extra to install."""
from __future__ import annotations

import sys

import pytest
from citygml_files import box_polys, building, city_model
from citygml_files import write as write_gml
from gbxml_files import box_room_gbxml
from gbxml_files import write as write_xml

from en17037cli.errors import InputError
from en17037cli.io import read_model


@pytest.mark.parametrize("missing, name, extra", [
    ("lxml", "city.gml", "citygml"), ("pyproj", "city.gml", "citygml"), ("lxml", "model.xml", "gbxml"),
    ("ezdxf", "model.dxf", "dxf")])
def test_missing_library_names_the_extra(tmp_path, monkeypatch, missing, name, extra):
    if name.endswith(".gml"):
        p = write_gml(tmp_path, city_model([building("b", box_polys(0.0, 1.0, 0.0, 1.0, 0.0, 1.0), srs="EPSG:25832")]), name)
    elif name.endswith(".xml"):
        p = write_xml(tmp_path, box_room_gbxml(), name)
    else:
        p = tmp_path / name
        p.write_text("  0\nSECTION\n  2\nENTITIES\n  0\nENDSEC\n  0\nEOF\n")
    for mod in [m for m in sys.modules if m == missing or m.startswith(missing + ".")]:
        monkeypatch.delitem(sys.modules, mod)
    monkeypatch.setitem(sys.modules, missing, None)  # import of it fails as if not installed
    with pytest.raises(InputError) as e:
        read_model(p)
    assert f"pip install 'en17037cli[{extra}]'" in str(e.value) and str(p) in str(e.value) and "\n" not in str(e.value)
