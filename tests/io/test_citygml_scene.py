"""CityGML context in a project: the CityJSON sample written as CityGML gives the same report, the real
Berlin tile around a box room, and bad files end with one line and exit 2."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
import yaml
from citygml_files import box_polys, building, city_model, from_cityjson, write
from click.testing import CliRunner

from en17037cli.cli import cli

pytest.importorskip("lxml")
pytest.importorskip("pyproj")

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "sample_projects" / "cityjson-rotterdam"
BERLIN = ROOT.parent / "shared" / "data" / "real-models" / "berlin_3890_5819.gml"
SUN = {"date": "02-01", "period": {"start": "02-01", "end": "02-01"}}


def run(args) -> tuple[int, str]:
    r = CliRunner().invoke(cli, args, catch_exceptions=False)
    return r.exit_code, r.output


def test_the_cityjson_sample_as_citygml_gives_the_same_report(tmp_path):
    shutil.copytree(SAMPLE, tmp_path / "p")
    p = tmp_path / "p"
    doc = json.loads((p / "rotterdam_subset.json").read_text())
    write(p, from_cityjson(doc, "urn:ogc:def:crs,crs:EPSG::28992,crs:EPSG::5709"), "rotterdam_subset.gml")
    proj = yaml.safe_load((p / "project.yaml").read_text())
    proj["model"]["files"][1]["path"] = "rotterdam_subset.gml"
    (p / "gml.yaml").write_text(yaml.safe_dump(proj, sort_keys=False))
    reports = []
    for name in ("project.yaml", "gml.yaml"):
        code, out = run(["check", str(p / name), "--out", str(tmp_path / name), "--no-plots", "-q"])
        assert code in (0, 1), out
        reports.append(json.loads((tmp_path / name / "report.json").read_text()))
    j, g = reports
    # every figure: view, sunlight hours per window and day, levels; the room's source names its project file
    assert [r["source"]["file"] for r in (j["rooms"][0], g["rooms"][0])] == ["project.yaml", "gml.yaml"]
    for r in (*j["rooms"], *g["rooms"]):
        r["source"].pop("file")
    assert g["rooms"] == j["rooms"]
    assert g["rooms"][0]["sunlight"]["status"] == j["rooms"][0]["sunlight"]["status"]
    code, out = run(["validate", str(p / "gml.yaml")])
    assert code == 0
    assert "read rotterdam_subset.gml: 16 city object members, 16 objects; with surfaces, by class and LoD read: Building LoD 2: 16" in out


def _box_among(tmp_path: Path, city_name: str, place, crs: str | None = "EPSG:25833", **file_keys) -> Path:
    """The cityjson-rotterdam box room placed at ``place`` (world x, y) with a city model beside it."""
    shutil.copy(SAMPLE / "box.obj", tmp_path / "box.obj")
    doc = yaml.safe_load((SAMPLE / "project.yaml").read_text())
    doc["model"]["files"][0]["transform"]["translate_m"] = [place[0], place[1], place[2]]
    if crs:
        doc["model"]["files"][0]["crs"] = crs
    doc["model"]["files"][1] = {"path": city_name, **file_keys}
    doc["rooms"][0]["floor_z"] = place[2]
    doc["location"] = {"latitude": 52.515, "longitude": 13.37, "timezone": "Europe/Berlin"}
    doc["sunlight"] = SUN
    p = tmp_path / "project.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p


def test_a_city_model_in_degrees_is_projected_to_the_models_crs(tmp_path):
    # a 30 m tall block south of the box room's window, written in WGS 84 (lat, lon) and in UTM 33N: same report
    import pyproj

    to_deg = pyproj.Transformer.from_crs("EPSG:25833", "EPSG:4326")  # (E, N) -> (lat, lon), the authority order
    e0, n0 = 389500.0, 5819600.0
    polys = box_polys(e0 - 30, e0 + 30, n0 - 40, n0 - 20, 34.0, 30.0)
    deg = {k: [[[(*to_deg.transform(x, y), z) for x, y, z in ring] for ring in poly] for poly in v] for k, v in polys.items()}
    reports = []
    for name, text in (("deg", city_model([building("block", deg, srs="urn:ogc:def:crs:EPSG::4326")])),
                       ("utm", city_model([building("block", polys, srs="EPSG:25833")]))):
        d = tmp_path / name
        d.mkdir()
        write(d, text, "city.gml")
        p = _box_among(d, "city.gml", (e0, n0, 34.0))
        code, out = run(["validate", str(p)])
        assert code == 0, out
        assert ("projected to EPSG:25833" in out) == (name == "deg")
        code, out = run(["check", str(p), "--out", str(d / "r"), "--only", "sunlight", "--no-plots", "-q"])
        assert code in (0, 1), out
        reports.append(json.loads((d / "r" / "report.json").read_text())["rooms"])
    assert reports[0] == reports[1]
    assert reports[0][0]["sunlight"]["hours_h"] < 1.0  # the block stands in the low February sun


@pytest.mark.skipif(not BERLIN.is_file(), reason="../shared/data/real-models absent")
def test_real_berlin_tile_around_a_box_room(tmp_path):
    shutil.copy(BERLIN, tmp_path / BERLIN.name)
    place = (389192.9, 5819898.2, 34.0)  # 12 m north of a 44 m tall building (its ground at 34.0 m), facing it
    p = _box_among(tmp_path, BERLIN.name, place, context_radius_m=300)
    code, out = run(["validate", str(p)])
    assert code == 0, out
    assert "read berlin_3890_5819.gml: 40 city object members, 40 objects" in out
    assert "lying entirely farther than 300 m" in out
    code, out = run(["check", str(p), "--out", str(tmp_path / "r"), "--only", "sunlight", "--no-plots", "-q"])
    assert code in (0, 1), out
    with_city = json.loads((tmp_path / "r" / "report.json").read_text())
    doc = yaml.safe_load(p.read_text())
    doc["model"]["files"][1]["layer"] = "ignore"
    q = tmp_path / "open.yaml"
    q.write_text(yaml.safe_dump(doc, sort_keys=False))
    run(["check", str(q), "--out", str(tmp_path / "o"), "--only", "sunlight", "--no-plots", "-q"])
    open_ = json.loads((tmp_path / "o" / "report.json").read_text())
    h_city = with_city["rooms"][0]["sunlight"]["hours_h"]
    h_open = open_["rooms"][0]["sunlight"]["hours_h"]
    assert h_city < h_open  # the building to the south takes sun away; obstructions cannot add any


@pytest.mark.parametrize("bad, expect", [
    ("cut", "not well-formed XML"),
    ("crs", "unknown CRS srsName 'urn:adv:crs:NO_SUCH'"),
])
def test_bad_city_models_exit_2_with_one_line(tmp_path, bad, expect):
    text = city_model([building("b", box_polys(389400.0, 389410.0, 5819500.0, 5819510.0, 34.0, 10.0),
                                srs="urn:adv:crs:NO_SUCH" if bad == "crs" else "EPSG:25833")])
    write(tmp_path, text[: len(text) // 2] if bad == "cut" else text, "city.gml")
    p = _box_among(tmp_path, "city.gml", (389480.0, 5819520.0, 34.0))
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / "r"), "-q"])
    assert r.exit_code == 2
    lines = [x for x in r.output.strip().splitlines() if x.strip()]
    assert len(lines) == 1 and expect in lines[0] and "city.gml" in lines[0]
    assert not (tmp_path / "r" / "report.json").exists()


def test_a_window_on_a_city_objects_wall_names_the_object_and_the_exclude_key(tmp_path):
    """The checked building drawn in the city model too, placed so that the city's wall lies on
    the box room's glazing (y = 0, the room to the north): one line naming the city object and
    the file key that leaves it out, not 'cut the opening' (a city model is not the user's to cut)."""
    e0, n0 = 389500.0, 5819600.0
    write(tmp_path, city_model([building("the-checked-building", box_polys(e0 - 5, e0 + 5, n0 - 10, n0, 34.0, 10.0),
                                         srs="EPSG:25833")]), "city.gml")
    p = _box_among(tmp_path, "city.gml", (e0, n0, 34.0))
    code, out = run(["validate", str(p)])
    assert code == 2
    line = out.strip().splitlines()[-1]
    assert "lies on 'city: the-checked-building'" in line and "exclude: ['the-checked-building']" in line, line
    assert "cut the opening" not in line
    doc = yaml.safe_load(p.read_text())
    doc["model"]["files"][1]["exclude"] = ["the-checked-building"]
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    code, out = run(["validate", str(p)])
    assert code == 0, out
