"""Room kinds (scene/kinds.py, project/kinds.py) and the UK's daylight targets per kind (practice.py,
gb-br209-2022: 100 lx bedrooms, 150 lx living rooms, 200 lx kitchens, the highest for a room of
several uses).

The UK run: a block of six rooms (en17037cli.samples.block, three south, three north) named
'Bedroom 1', 'Living room', 'Kitchen', 'Living/Kitchen', 'Schlafzimmer' (the default name table)
and 'Raum 6' (a room_kinds rule: kitchen), daylight by method 1 on a 1 m grid.
"""
from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.criteria.daylight.assess import climate_shares
from en17037cli.practice import PRACTICES, highest_of_uses
from en17037cli.project.kinds import KindRule
from en17037cli.samples.block import Block, block_project
from en17037cli.scene.kinds import by_name, fold, room_kind
from en17037cli.standard import THRESHOLDS, Thresholds

ROOT = Path(__file__).resolve().parents[1]
NAMES = ["Bedroom 1", "Living room", "Kitchen", "Living/Kitchen", "Schlafzimmer", "Raum 6"]
#: What each of NAMES is, and the target illuminance E_T of the minimum level the UK practice gives it [lx].
UK = {"Bedroom 1": (["bedroom"], 100.0), "Living room": (["living_room"], 150.0), "Kitchen": (["kitchen"], 200.0),
      "Living/Kitchen": (["living_room", "kitchen"], 200.0), "Schlafzimmer": (["bedroom"], 100.0),
      "Raum 6": (["kitchen"], 200.0)}
MEDIAN_LX = 14000.0


def docs_words() -> dict[str, list[str]]:
    """kind -> the example words of docs/project-file.md's default name table."""
    text = (ROOT / "docs" / "project-file.md").read_text(encoding="utf-8")
    table = re.search(r"<!-- kind-words -->(.*?)<!-- /kind-words -->", text, re.S).group(1)
    out = {}
    for row in table.strip().splitlines()[2:]:
        cells = [c.strip() for c in row.strip().strip("|").split("|")]
        out[cells[0]] = [w.strip() for c in cells[1:] for w in c.split(",") if w.strip()]
    return out


def test_every_word_of_the_documented_table_names_its_kind_and_no_other():
    words = docs_words()
    assert set(words) == {"bedroom", "living_room", "kitchen", "office"}
    assert sum(len(v) for v in words.values()) > 60
    for kind, examples in words.items():
        for w in examples:
            assert by_name(w)[0] == (kind,), (w, by_name(w))


@pytest.mark.parametrize("name, kinds", [
    ("Living/Kitchen/Dining", ("living_room", "kitchen")), ("Kitchen-Diner", ("living_room", "kitchen")),
    ("Wohnküche", ("living_room", "kitchen")), ("Wohnen/Kochen", ("living_room", "kitchen")),
    ("Woonkeuken", ("living_room", "kitchen")), ("Séjour/Cuisine", ("living_room", "kitchen")),
    ("Soggiorno / Cottura", ("living_room", "kitchen")),  # Terlago.xml (a real Revit gbXML) names its flats' rooms so
    ("Wohnung 3", ()), ("Wohnungsflur", ()), ("Bathroom", ()), ("WC Herren", ()), ("Flur", ()), ("Stanza", ()),
    ("Studio", ()), ("Fireplace Room", ()), ("Bedienraum", ())])
def test_several_uses_and_none(name, kinds):
    assert by_name(name)[0] == kinds


def test_fold():
    assert fold("Wohn-/Küche") == "wohn kuche"
    assert fold("SALLE À MANGER") == "salle a manger"
    assert fold("Straße_2") == "strasse 2"


def test_the_first_source_that_names_a_kind_decides():
    rule = (KindRule("*schlaf*", ("bedroom",), 0),)
    usage = [("LongName", "Wohnküche"), ("Name", "1.02"), ("ObjectType", "Kitchen"), ("IfcSpaceType", "Bürotyp"),
             ("classification 'Uniclass 2015'", "SL_45_10_09 Bedrooms"), ("gbXML spaceType", "OfficeEnclosed")]
    assert room_kind("Schlafraum", usage, rule) == (("bedroom",), "room_kinds[0] '*schlaf*' on the room name 'Schlafraum'")
    # a rule matches any text of the model too, case-insensitive
    assert room_kind("R", usage, (KindRule("SL_45_10_09*", ("office",), 3),))[1] == \
        "room_kinds[3] 'SL_45_10_09*' on the classification 'Uniclass 2015' 'SL_45_10_09 Bedrooms'"
    assert room_kind("R", usage, ()) == (("bedroom",), "classification 'Uniclass 2015' 'SL_45_10_09 Bedrooms': Uniclass SL_45_10_09")
    assert room_kind("R", usage[:4], ()) == (("kitchen",), "ObjectType 'Kitchen': name table 'kitchen'")
    assert room_kind("R", usage[1:2] + usage[3:4], ())[0] == ("office",)  # the type's name, 'buro' inside Bürotyp
    assert room_kind("R", usage[:2], ()) == (("living_room", "kitchen"), "LongName 'Wohnküche': name table 'wohn', 'kuche'")
    assert room_kind("Kitchen", [], ())[1] == "room name 'Kitchen': name table 'kitchen'"
    assert room_kind("R", usage[5:], ()) == (("office",), "gbXML spaceType 'OfficeEnclosed'")
    assert room_kind("R", [], ())[0] == ("other",)


def test_classifications_of_buildings_and_load_categories_name_no_room():
    # AC11-Institute (ArchiCAD) classes every space, its WCs too, '2 HNF Büroarbeit' (DIN 277): no kind
    assert room_kind("WC Herren", [("LongName", "WC Herren"), ("classification 'DIN 277'", "2 HNF Büroarbeit")], ())[0] == ("other",)
    # a Uniclass code not in the table is read by its name; OmniClass Table 13 by its name
    assert room_kind("R", [("classification 'Uniclass'", "SL_20_15_59 Offices")], ())[0] == ("office",)
    assert room_kind("R", [("classification 'OmniClass'", "13-51 11 11 Bedroom")], ())[0] == ("bedroom",)
    assert room_kind("R", [("classification 'Uniclass 2015'", "SL_45_10_45 Kitchen-dining-living rooms")], ())[0] == \
        ("living_room", "kitchen")
    # Urban_House_MEP.xml (Revit gbXML): the living room is a LivingQuartersHotel as the bedrooms are: its name decides
    assert room_kind("9 1st Floor Living Room", [("Name", "9 1st Floor Living Room"),
                                                 ("gbXML spaceType", "LivingQuartersHotel")], ())[0] == ("living_room",)
    assert room_kind("28 Ground Den", [("Name", "28 Ground Den"), ("gbXML spaceType", "LivingQuartersHotel")], ())[0] == ("other",)
    assert room_kind("Space 1", [("Name", "Space 1"), ("gbXML spaceType", "DormitoryBedroom")], ())[0] == ("bedroom",)


def test_highest_of_uses():
    uses = [{"requirements.daylight": "minimum", "thresholds.daylight_target_lx.minimum": 150.0},
            {"requirements.daylight": "medium", "thresholds.daylight_target_lx.minimum": 200.0},
            {"requirements.daylight": "none", "thresholds.daylight_target_lx.minimum": 200.0, "x": 1.0}]
    assert highest_of_uses(uses) == {"requirements.daylight": ("medium", 1), "thresholds.daylight_target_lx.minimum": (200.0, 1),
                                     "x": (1.0, 2)}
    assert highest_of_uses([]) == {}


def test_the_uk_practice_per_kind_is_the_national_annex():
    p = PRACTICES["gb-br209-2022"]
    assert {k: v["thresholds.daylight_target_lx.minimum"] for k, v in p.kinds.items()} == \
        {"bedroom": 100.0, "living_room": 150.0, "kitchen": 200.0}
    assert all(v["thresholds.daylight_minimum_target_lx.minimum"] == 0.0 for v in p.kinds.values())
    assert "BR 209:2022" in p.kinds_source and "100 lx in bedrooms" in p.kinds_source
    assert PRACTICES["en17037"].kinds == {}


def test_method_2_counts_a_target_of_no_lux_as_reached_everywhere():
    # four points, four hours: the UK bedroom's 100 lx minimum with no minimum target (0 lx)
    e = np.array([[0.0, 0.0, 150, 150], [120, 90, 80, 110], [300, 300, 0, 0], [10, 20, 30, 40]], float)
    t = {**THRESHOLDS, "daylight_target_lx": {"minimum": 100.0, "medium": 500.0, "high": 750.0},
         "daylight_minimum_target_lx": {"minimum": 0.0, "medium": 300.0, "high": 500.0}}
    target, minimum, per_point = climate_shares(e, Thresholds.from_dict(t), "hours_first")
    # 100 lx on at least 2 of 4 hours: points 0 (2), 1 (2), 2 (2) and not 3: 3 of 4
    assert target["minimum"] == 0.75 and minimum["minimum"] == 1.0
    assert per_point[0.0].tolist() == [1.0, 1.0, 1.0, 1.0]


def uk_project(tmp: Path, practice: str = "gb-br209-2022", **extra) -> Path:
    path = block_project(tmp, Block(rooms_per_side=3), view=None, sunlight=None, requirements={"view": "none", "sunlight": "none"})
    doc = yaml.safe_load(path.read_text())
    for room, name in zip(doc["rooms"], NAMES):
        room["name"] = name
    doc |= {"practice": practice, "room_kinds": [{"match": "raum 6", "kind": "kitchen"}],
            "daylight": {"median_diffuse_lx": MEDIAN_LX, "grid_spacing_m": 1.0, "radiance": {"rays": 64, "max_rays": 256}},
            **extra}
    path.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def uk_reports(tmp_path_factory):
    pytest.importorskip("pyradiance")
    out = {}
    for practice in ("gb-br209-2022", "en17037"):
        d = tmp_path_factory.mktemp(practice)
        path = uk_project(d, practice)
        r = CliRunner().invoke(cli, ["check", str(path), "--out", str(d / "out"), "--no-plots", "--quiet"], catch_exceptions=False)
        assert r.exit_code in (0, 1), r.output
        out[practice] = json.loads((d / "out" / "report.json").read_text(encoding="utf-8")), path
    return out


def test_uk_rooms_get_the_national_annex_target_of_their_kind(uk_reports):
    import jsonschema

    from en17037cli.schemas import load_schema

    report, _ = uk_reports["gb-br209-2022"]
    jsonschema.validate(report, load_schema("report"))
    assert [r["name"] for r in report["rooms"]] == NAMES
    for room in report["rooms"]:
        uses, lx = UK[room["name"]]
        assert room["kind"]["uses"] == uses
        assert room["kind"]["set"]["thresholds.daylight_target_lx.minimum"]["value"] == lx
        d = room["daylight"]
        assert d["levels"]["minimum"]["target_lx"] == lx and d["levels"]["minimum"]["minimum_target_lx"] == 0.0
        assert (d["levels"]["medium"]["target_lx"], d["levels"]["high"]["minimum_target_lx"]) == (500.0, 500.0)  # Table A.1
        # the target flows into the computation: the share of the plane whose D reaches D_T = E_T / E_v,d,med
        df = np.array([p["daylight_factor_pct"] for p in d["points"]])
        assert d["levels"]["minimum"]["target_share"] == pytest.approx(np.mean(df >= 100.0 * lx / MEDIAN_LX), abs=1e-4)
        assert d["levels"]["minimum"]["minimum_target_share"] == 1.0 and d["levels"]["minimum"]["minimum_target_share_error"] == 0
        reached = d["levels"]["minimum"]["target_share"] >= 0.5
        assert (d["level"] != "none") == reached
        if d["level"] == "minimum":
            assert d["limiting"]["criterion"] == "daylight_target"  # no minimum target never limits
    combined = next(r for r in report["rooms"] if r["name"] == "Living/Kitchen")["kind"]
    assert combined["set"]["thresholds.daylight_target_lx.minimum"]["from"] == "practice gb-br209-2022, kitchen"
    assert next(r for r in report["rooms"] if r["name"] == "Raum 6")["kind"]["source"] == \
        "room_kinds[0] 'raum 6' on the room name 'Raum 6'"
    assert report["practice"]["kinds"]["living_room"] == {"thresholds.daylight_target_lx.minimum": 150.0,
                                                          "thresholds.daylight_minimum_target_lx.minimum": 0.0}


def test_the_default_practice_keeps_table_a1_for_every_kind(uk_reports):
    uk, _ = uk_reports["gb-br209-2022"]
    report, _ = uk_reports["en17037"]
    assert "kinds" not in report["practice"]
    for room, room_uk in zip(report["rooms"], uk["rooms"]):
        assert room["kind"]["uses"] == UK[room["name"]][0] and room["kind"]["set"] == {}
        lv = room["daylight"]["levels"]["minimum"]
        assert (lv["target_lx"], lv["minimum_target_lx"]) == (300.0, 100.0)
        df = np.array([p["daylight_factor_pct"] for p in room["daylight"]["points"]])
        assert lv["target_share"] == pytest.approx(np.mean(df >= 100.0 * 300.0 / MEDIAN_LX), abs=1e-4)
        # the same light on the same plane: the practice changes the targets, not the daylight factors (each
        # within its error: a point's paths stop once its D is clear of the room's thresholds)
        err = np.array([p["daylight_factor_error_pct"] for p in room["daylight"]["points"]])
        df_uk = np.array([p["daylight_factor_pct"] for p in room_uk["daylight"]["points"]])
        err_uk = np.array([p["daylight_factor_error_pct"] for p in room_uk["daylight"]["points"]])
        assert np.all(np.abs(df_uk - df) <= err + err_uk + 1e-4)


def test_validate_says_each_rooms_kind_and_target(uk_reports, tmp_path):
    _, path = uk_reports["gb-br209-2022"]
    r = CliRunner().invoke(cli, ["validate", str(path)], catch_exceptions=False)
    assert r.exit_code == 0, r.output
    lines = r.output.splitlines()
    for name, (uses, lx) in UK.items():
        i = lines.index(next(x for x in lines if x.startswith(f"room '{name}'")))
        assert lines[i + 1].startswith(f"  kind: {' + '.join(u.replace('_', ' ') for u in uses)} (")
        assert f"daylight target {lx:g} lx at minimum" in lines[i + 1], lines[i + 1]
    r = CliRunner().invoke(cli, ["validate", str(path), "--json"], catch_exceptions=False)
    doc = json.loads(r.output)
    got = {x["name"]: (x["kind"]["uses"], x["kind"]["set"]["thresholds.daylight_target_lx.minimum"]["value"]) for x in doc["rooms"]}
    assert got == {k: (u, lx) for k, (u, lx) in UK.items()}


def test_by_kind_wins_over_the_practice_and_a_rooms_own_requirement_over_both(tmp_path):
    path = uk_project(tmp_path, by_kind={"bedroom": {"thresholds": {"daylight_target_lx": {"minimum": 120}},
                                                      "requirements": {"daylight": "medium"}}})
    doc = yaml.safe_load(path.read_text())
    doc["rooms"][4]["requirements"] = {"daylight": "none"}  # Schlafzimmer
    path.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True), encoding="utf-8")
    r = CliRunner().invoke(cli, ["validate", str(path), "--json"], catch_exceptions=False)
    assert r.exit_code == 0, r.output
    rooms = {x["name"]: x["kind"]["set"] for x in json.loads(r.output)["rooms"]}
    assert rooms["Bedroom 1"]["thresholds.daylight_target_lx.minimum"] == {"value": 120, "from": "by_kind.bedroom"}
    assert rooms["Bedroom 1"]["requirements.daylight"] == {"value": "medium", "from": "by_kind.bedroom"}
    assert rooms["Schlafzimmer"]["requirements.daylight"] == {"value": "none", "from": "rooms[4].requirements"}
    assert rooms["Kitchen"]["thresholds.daylight_target_lx.minimum"]["value"] == 200.0  # the practice's, untouched
    # a room of several uses takes the highest: a living room/kitchen whose living room asks 250 lx gets 250
    path = uk_project(tmp_path / "b", by_kind={"living_room": {"thresholds": {"daylight_target_lx": {"minimum": 250}}}})
    rooms = {x["name"]: x["kind"]["set"] for x in json.loads(CliRunner().invoke(cli, ["validate", str(path), "--json"]).output)["rooms"]}
    assert rooms["Living/Kitchen"]["thresholds.daylight_target_lx.minimum"] == {"value": 250, "from": "by_kind.living_room"}


@pytest.mark.parametrize("extra, message", [
    ({"by_kind": {"office": {"requirements": {"glare": "minimum"}}}},
     "by_kind.office.requirements.glare: the project has no 'glare' section"),
    ({"by_kind": {"kitchen": {"thresholds": {"daylight_target_lx": {"minimum": 600}}}}},
     "by_kind.kitchen: thresholds.daylight_target_lx of a kitchen: expected minimum <= medium <= high, got [600, 500.0, 750.0]"),
    ({"by_kind": {"bathroom": {}}}, "by_kind: unknown key 'bathroom'"),
    ({"room_kinds": [{"match": "*", "kind": "lounge"}]}, "room_kinds[0].kind"),
    ({"room_kinds": [{"kind": "bedroom"}]}, "room_kinds[0]: missing required key 'match'")])
def test_kind_errors_are_one_line_naming_the_key(tmp_path, extra, message):
    path = uk_project(tmp_path, **extra)
    r = CliRunner().invoke(cli, ["validate", str(path)])
    assert r.exit_code == 2 and message in r.output, r.output


def test_method_2_takes_the_kinds_target_too(tmp_path):
    # the box room named 'Kitchen' under the UK practice, climate-based on the synthetic Delft year: its
    # minimum level is 200 lx on half the plane for half of the daylight hours, from each point's share of hours
    pytest.importorskip("pyradiance")
    from en17037cli.samples import BoxRoom, box_room_project
    from en17037cli.samples.weather import synthetic_epw

    path = box_room_project(tmp_path, BoxRoom(building_height=0.0), view=None, sunlight=None)
    synthetic_epw(tmp_path / "site.epw")
    doc = yaml.safe_load(path.read_text())
    doc["rooms"][0]["name"] = "Kitchen"
    doc |= {"practice": "gb-br209-2022", "requirements": {"view": "none", "sunlight": "none"},
            "daylight": {"method": "climate_based", "weather": "site.epw", "grid_spacing_m": 1.0,
                         "radiance": {"ab": 1, "ad": 128, "replicates": 2, "climate_rays": 256}}}
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    r = CliRunner().invoke(cli, ["check", str(path), "--out", str(tmp_path / "out"), "--no-plots", "--quiet"], catch_exceptions=False)
    assert r.exit_code in (0, 1), r.output
    d = json.loads((tmp_path / "out" / "report.json").read_text())["rooms"][0]["daylight"]
    assert d["method"] == "climate_based" and d["levels"]["minimum"]["target_lx"] == 200.0
    # hours_first: the share of points reaching 200 lx on half the hours, per replicate, then the mean; a point
    # counts alike in every replicate unless its replicates straddle half the hours, when its mean lies within
    # its error of 0.5 (two replicates: t(0.975, 1) s / sqrt(2) >= their half-difference)
    hours = np.array([p["share_of_hours"]["200"] for p in d["points"]])
    err = np.array([p["share_of_hours_error"]["200"] for p in d["points"]])
    unsure = float(np.mean(np.abs(hours - 0.5) <= err))
    assert abs(d["levels"]["minimum"]["target_share"] - np.mean(hours >= 0.5)) <= unsure + 1e-4
    assert d["levels"]["minimum"]["minimum_target_share"] == 1.0
