"""The facade screen's bad input, its CityGML write-back and its executors (issue 45).

Bad input is one line naming the file or key and what to do (exit 2); one bad building is left
out with a warning and the others are screened. A Dask LocalCluster of two worker processes
writes the same bytes as this process alone (summary.json's timings apart), as dask.distributed's
own tests compare a function run locally and on a cluster.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner
from district_city import City, screen_project
from test_district import probes, run_screen

from en17037cli.cli import cli

ROOT = Path(__file__).resolve().parents[1]
BERLIN = ROOT.parent / "shared" / "data" / "real-models" / "berlin_3890_5819.gml"


def row(tmp: Path) -> Path:
    """Three detached houses and a low shed, as CityJSON."""
    c = City().box("a", 0, 8, 0, 8, 6.0).box("b", 20, 28, 0, 8, 3.0).box("c", 0, 8, 20, 28, 3.0).box("shed", 20, 24, 20, 24, 2.0)
    return c.write(tmp / "row.city.json")


@pytest.mark.parametrize("what, edit, message", [
    ("no CRS", {"crs": None}, "the city model names no CRS"),
    ("an unknown CRS", {"crs_key": "EPSG:999999"}, "its CRS EPSG:999999 is not a projected CRS that PROJ knows"),
    ("a polygon that selects nothing", {"buildings": {"polygon": [[0, 0], [10, 0], [10, 10]]}}, "screen.buildings.polygon: selects no building"),
    ("ids that are no building", {"buildings": ["nope"]}, "screen.buildings: none of the 1 id(s) is a Building"),
    ("a window over its storey", {"window": {"width_m": 1.2, "height_m": 2.5}}, "screen.window.height_m: the window's head"),
])
def test_bad_input_is_one_line(tmp_path, what, edit, message):
    """Each stops with exit 2 and one line naming the key or file and what to do."""
    city = City().box("a", 0, 8, 0, 8, 3.0).write(tmp_path / "c.city.json", crs=None if edit.get("crs", 1) is None else
                                                   "https://www.opengis.net/def/crs/EPSG/0/7415")
    screen = {k: v for k, v in edit.items() if k in ("window",)}
    p = screen_project(tmp_path, city, buildings=edit.get("buildings", "*"), location={"timezone": "Europe/Amsterdam"}, **screen)
    if "crs_key" in edit:
        doc = yaml.safe_load(p.read_text())
        doc["model"]["files"][0]["crs"] = edit["crs_key"]
        p.write_text(yaml.safe_dump(doc))
    code, out = run_screen(p, tmp_path / "o")
    assert code == 2, out
    lines = [ln for ln in out.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and message in lines[0], out
    assert not (tmp_path / "o").exists()


def test_one_bad_building_is_left_out_with_a_warning(tmp_path):
    """A house without its roof (an open solid) and a Building with no wall (a roof alone) are left
    out, each with one warning naming it and what to do; the others are screened."""
    c = City().box("good", 0, 8, 0, 8, 3.0).box("open", 20, 28, 0, 8, 3.0, roof=False)
    roof = [[(40, 0, 3), (48, 0, 3), (48, 8, 3), (40, 8, 3)]]
    c.solid("flat", [roof], ["RoofSurface"])
    c.objects["flat"]["geometry"][0]["type"] = "MultiSurface"
    c.objects["flat"]["geometry"][0]["boundaries"] = c.objects["flat"]["geometry"][0]["boundaries"][0]
    c.objects["flat"]["geometry"][0]["semantics"]["values"] = [0]
    city = c.write(tmp_path / "c.city.json")
    code, out = run_screen(screen_project(tmp_path, city), tmp_path / "o")
    assert code in (0, 1), out
    assert "building 'open' left out: its solid open is not closed" in out
    assert "building 'flat' left out: it has no wall surface" in out
    assert {r["building_id"] for r in probes(tmp_path / "o")} == {"good"}
    left = {r["building_id"]: r["left_out"] for r in __import__("csv").DictReader((tmp_path / "o" / "buildings.csv").open())}
    assert left["good"] == "" and "not closed" in left["open"] and "no wall surface" in left["flat"]


def test_a_project_without_rooms_says_what_to_do_to_check(tmp_path):
    p = screen_project(tmp_path, row(tmp_path))
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / "c"), "-q"])
    assert r.exit_code == 2 and "rooms: none given" in r.output and "en17037 screen" in r.output, r.output


def test_dask_local_cluster_writes_the_same_bytes(tmp_path):
    """Four buildings in tasks of one on a LocalCluster of two worker processes, and in this process:
    every output byte-identical, summary.json but for its timings."""
    pytest.importorskip("distributed")
    p = screen_project(tmp_path, row(tmp_path), buildings_per_task=1)
    code, out = run_screen(p, tmp_path / "local")
    assert code in (0, 1), out
    r = CliRunner().invoke(cli, ["screen", str(p), "--out", str(tmp_path / "dask"), "-q", "--scheduler", "local", "-j", "2"],
                           catch_exceptions=False)
    assert r.exit_code == code, r.output
    names = sorted(f.name for f in (tmp_path / "local").iterdir() if not f.name.startswith("."))
    assert names == sorted(f.name for f in (tmp_path / "dask").iterdir() if not f.name.startswith("."))
    assert len(probes(tmp_path / "local")) > 20
    for name in names:
        a, b = (tmp_path / "local" / name).read_bytes(), (tmp_path / "dask" / name).read_bytes()
        if name == "summary.json":
            a, b = (json.loads(x) for x in (a, b))
            a.pop("timings_s"), b.pop("timings_s")
        assert a == b, name


GML = """<?xml version="1.0" encoding="UTF-8"?>
<core:CityModel xmlns:core="http://www.opengis.net/citygml/2.0" xmlns:bldg="http://www.opengis.net/citygml/building/2.0"
 xmlns:gml="http://www.opengis.net/gml" xmlns:gen="http://www.opengis.net/citygml/generics/2.0">
<gml:boundedBy><gml:Envelope srsName="EPSG:28992" srsDimension="3"><gml:lowerCorner>{x0} {y0} 0</gml:lowerCorner>
<gml:upperCorner>{x1} {y1} 10</gml:upperCorner></gml:Envelope></gml:boundedBy>
{members}
</core:CityModel>
"""


def gml_box(bid: str, x0, x1, y0, y1, h) -> str:
    """A bldg:Building with its four WallSurfaces (one with a gml:id), roof and ground, LoD2."""
    def poly(pts):
        ring = " ".join(f"{x:g} {y:g} {z:g}" for x, y, z in [*pts, pts[0]])
        return (f"<gml:surfaceMember><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList>{ring}</gml:posList>"
                "</gml:LinearRing></gml:exterior></gml:Polygon></gml:surfaceMember>")

    c = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    lo, hi = [(x, y, 0) for x, y in c], [(x, y, h) for x, y in c]
    out = [f"<core:cityObjectMember><bldg:Building gml:id='{bid}'><bldg:measuredHeight uom='m'>{h}</bldg:measuredHeight>"]
    for k in range(4):
        a, b = k, (k + 1) % 4
        sid = f" gml:id='{bid}-wall{k}'" if k == 0 else ""
        out.append(f"<bldg:boundedBy><bldg:WallSurface{sid}><bldg:lod2MultiSurface><gml:MultiSurface>"
                   f"{poly([lo[a], lo[b], hi[b], hi[a]])}</gml:MultiSurface></bldg:lod2MultiSurface></bldg:WallSurface></bldg:boundedBy>")
    for kind, pts in (("RoofSurface", hi), ("GroundSurface", [lo[0], lo[3], lo[2], lo[1]])):
        out.append(f"<bldg:boundedBy><bldg:{kind}><bldg:lod2MultiSurface><gml:MultiSurface>{poly(pts)}</gml:MultiSurface>"
                   f"</bldg:lod2MultiSurface></bldg:{kind}></bldg:boundedBy>")
    out.append("</bldg:Building></core:cityObjectMember>")
    return "".join(out)


def test_citygml_written_back_and_reread(tmp_path):
    """Two CityGML 2.0 houses: the written-back file holds every member, a gen:intAttribute
    en17037_probes on each probed WallSurface (the one with a gml:id and the others) equal to its
    probes, and the buildings' summaries, which the CityGML reader reads back as attributes; its
    geometry reads as the original's."""
    lxml = pytest.importorskip("lxml.etree")
    x, y = 85000, 446000
    gml = tmp_path / "two.gml"
    gml.write_text(GML.format(x0=x, y0=y, x1=x + 40, y1=y + 8, members=gml_box("h1", x, x + 8, y, y + 8, 3.0)
                              + gml_box("h2", x + 30, x + 38, y, y + 8, 6.0)))
    code, out = run_screen(screen_project(tmp_path, gml), tmp_path / "o")
    assert code in (0, 1), out
    written = tmp_path / "o" / "two.screened.gml"
    rows = probes(tmp_path / "o")
    ns = {"bldg": "http://www.opengis.net/citygml/building/2.0", "gen": "http://www.opengis.net/citygml/generics/2.0",
          "gml": "http://www.opengis.net/gml"}
    root = lxml.parse(str(written)).getroot()
    assert len(root.findall(".//bldg:Building", ns)) == 2
    counts = [int(w.find("gen:intAttribute[@name='en17037_probes']/gen:value", ns).text)
              for w in root.iterfind(".//bldg:WallSurface", ns) if w.find("gen:intAttribute", ns) is not None]
    assert sum(counts) == len(rows) and len(counts) == 8
    first = root.find(".//bldg:WallSurface[@gml:id='h1-wall0']", ns)
    assert int(first.find("gen:intAttribute/gen:value", ns).text) == sum(1 for r in rows if r["surface"] == "h1-wall0")
    from en17037cli.io import read_model

    a, b = read_model(gml), read_model(written)
    assert len(a.triangles) == len(b.triangles)
    attrs = {p.attrs["id"]: p.attrs for p in b.parts}
    assert int(attrs["h2"]["attr.en17037_probes"]) == sum(1 for r in rows if r["building_id"] == "h2")


@pytest.mark.real_models
@pytest.mark.skipif(not BERLIN.is_file(), reason="../shared/data/real-models is absent")
def test_the_berlin_tile_screened_by_polygon(tmp_path):
    """A real CityGML 1.0 tile (Berlin, EPSG:25833): the three buildings whose centres lie in a
    40 x 60 m rectangle in its west are screened (the tile's 37 others are context), every figure in its
    range, the site from the tile's CRS (52.5 N, 13.37 E)."""
    x, y = 389042.0, 5819528.0
    p = screen_project(tmp_path, BERLIN, buildings={"polygon": [[x - 20, y - 30], [x + 20, y - 30], [x + 20, y + 30],
                                                               [x - 20, y + 30]]},
                       location={"timezone": "Europe/Berlin"})
    code, out = run_screen(p, tmp_path / "o")
    assert code in (0, 1), out
    info = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert info["site"]["latitude"] == pytest.approx(52.515, abs=0.01) and info["site"]["longitude"] == pytest.approx(13.37, abs=0.02)
    rows = probes(tmp_path / "o")
    screened = {r["building_id"] for r in rows}
    assert {"BLDG_0003000b0071da49", "BLDG_0003000b0071da4d"} <= screened and len(screened) == info["counts"]["buildings"] == 3
    for r in rows:
        assert 0.0 <= float(r["sunlight_hours_h"]) <= 12.5
        assert 0.0 <= float(r["sky_component_pct"]) <= 39.62 + float(r["sky_component_pct_error"])
        assert r["sunlight_level"] in ("none", "minimum", "medium", "high")


def test_the_report_draws_every_probe_and_names_are_text(tmp_path):
    """report.html: one dot per probe on the map, its class the probe's levels; a building id with
    markup, quotes, a right-to-left script and an emoji is text everywhere (escaped in the page,
    whole in the CSV and GeoJSON)."""
    lxml_html = pytest.importorskip("lxml.html")
    name = "<b onclick='x'>&\"שלום\" 🏠"
    city = City().box(name, 0, 8, 0, 8, 3.0).box("b", 20, 28, 0, 8, 6.0).write(tmp_path / "c.city.json")
    code, out = run_screen(screen_project(tmp_path, city), tmp_path / "o")
    assert code in (0, 1), out
    page = (tmp_path / "o" / "report.html").read_text()
    assert "<b onclick" not in page
    doc = lxml_html.fromstring(page)
    rows = probes(tmp_path / "o")
    dots = doc.findall(".//circle")
    assert len(dots) == len(rows) > 0
    levels = ("none", "minimum", "medium", "high")
    assert sorted(d.get("class").split()[0] for d in dots) == sorted(f"s{levels.index(r['sunlight_level'])}" for r in rows)
    assert name in doc.text_content()
    assert {r["building_id"] for r in rows} == {name, "b"}
    feats = json.loads((tmp_path / "o" / "probes.geojson").read_text())["features"]
    assert {f["properties"]["building_id"] for f in feats} == {name, "b"}
