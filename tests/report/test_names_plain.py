"""Names from a model are data: every picture, the HTML, the Markdown, the CSVs, JUnit XML and
report.json carry them as plain text, whatever they hold (issue 43).

AC11-Institute's windows are told apart by their GlobalIds, whose alphabet includes ``$``; a label
with ``$...$`` in it was parsed as mathematics by matplotlib and stopped the run with exit 3. Here a
room and its window carry every character that means something to one of the writers: ``$`` (TeX
mathematics), ``\\``, ``_``, ``^``, ``{``, ``%``, ``#``, ``<`` and ``&`` (HTML, XML), ``|`` and
``*`` (Markdown tables), quotes and commas (CSV), a right-to-left script, an emoji, and 200
characters in all.
"""
from __future__ import annotations

import csv
import html
import json
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli

pytest.importorskip("matplotlib")

ROOT = Path(__file__).resolve().parents[2]
STREET = ROOT / "sample_projects" / "synthetic-street"

#: A room name with every character that means something to a writer, padded to 200 characters.
ROOM = ("Bürø \u0007 $\\alpha$ $x^2_{i}$ \\n 100% #3 _a ^b {c} <b>&amp; \"q\", 'p'; |t| *e* `c` "
        "مرحبا עברית 😀 IBf$$ZaZkjsa)")
ROOM = (ROOM + " " + "x" * 200)[:200]
#: Two window (OBJ object) names with a GlobalId's ``$$`` and the rest (the layer rule matches
#: ``glazing*``): a room of two windows names them in its sunlight chart's legend.
WINDOW = "glazing $$ZaZkjsa) $\\frac{1}{0}$ _^{%#} <i> 😀 שלום"
WINDOW_2 = "glazing_2 $x$ \\ {1} ^ % # & 0"
#: The sample's 2 x 1.4 m window as two panes 0.4 m apart, the wall between them (two windows).
PANES = f"""o {WINDOW}
v -1.0 0.0 0.8
v -0.2 0.0 0.8
v -0.2 0.0 2.2
v -1.0 0.0 2.2
f 37 38 39 40
o {WINDOW_2}
v 0.2 0.0 0.8
v 1.0 0.0 0.8
v 1.0 0.0 2.2
v 0.2 0.0 2.2
f 41 42 43 44
o room
v -0.2 0.0 0.8
v 0.2 0.0 0.8
v 0.2 0.0 2.2
v -0.2 0.0 2.2
f 45 46 47 48
"""


def nasty_project(tmp_path: Path) -> Path:
    lines = (STREET / "model.obj").read_text(encoding="utf-8").splitlines(keepends=True)
    at = lines.index("o glazing\n")
    rest = "".join(lines[at + 6:])
    offset = 12  # the later objects' vertex indices move by the 12 - 4 new vertices
    rest = "\n".join(" ".join([w[0]] + [str(int(v) + offset - 4) for v in w[1:]]) if w and w[0] == "f" else " ".join(w)
                     for w in (line.split() for line in rest.splitlines())) + "\n"
    model = "".join(lines[:at]) + PANES + rest
    (tmp_path / "model.obj").write_text(model, encoding="utf-8")
    doc = yaml.safe_load((STREET / "project.yaml").read_text(encoding="utf-8"))
    doc["rooms"][0]["name"] = ROOM
    doc["model"]["files"][0]["layers"][1]["match"] = "glazing*"
    doc["view"] |= {"grid_spacing_m": 1.0, "angular_resolution_deg": 3, "refine_levels": 1}
    doc["sunlight"] |= {"period": {"start": "02-01", "end": "02-03"}}
    path = tmp_path / "project.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True), encoding="utf-8")
    return path


def test_names_with_every_special_character_are_drawn_and_written_as_plain_text(tmp_path):
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["check", str(nasty_project(tmp_path)), "--out", str(out), "--quiet",
                                 "--junit", str(tmp_path / "junit.xml")], catch_exceptions=False)
    assert r.exit_code in (0, 1), r.output
    report = json.loads((out / "report.json").read_text(encoding="utf-8"))
    (room,) = report["rooms"]
    assert room["name"] == ROOM
    assert sorted(w["name"] for w in room["windows"]) == sorted([WINDOW, WINDOW_2])
    # every picture of the room was drawn (view, sunlight, plans), none left out for its name
    figures = sorted(p.name for p in (out / "figures").rglob("*.png"))
    assert len(figures) >= 4, figures
    # the HTML's vector pictures are well-formed XML with the names as text, drawn as written
    page = (out / "report.html").read_text(encoding="utf-8")
    svgs = re.findall(r"<svg.*?</svg>", page, flags=re.S)
    assert len(svgs) >= 4
    for svg in svgs:
        ET.fromstring(svg)
    assert any("window glazing $$Za" in svg for svg in svgs)  # the hours chart's legend, cut in the middle
    # HTML: the names are escaped text, never markup
    assert "<b>&amp;" not in page and "<i> 😀" not in page
    assert html.escape(ROOM, quote=False)[:60] in page
    # Markdown (rendered by a CommonMark parser, tables on): the names read back as written, as text
    from markdown_it import MarkdownIt

    rendered = MarkdownIt("commonmark").enable("table").render((out / "report.md").read_text(encoding="utf-8"))
    assert "<b>" not in rendered and "<em>e</em>" not in rendered and "<code>c</code>" not in rendered
    plain = html.unescape(re.sub(r"<[^>]+>", "", rendered))
    assert ROOM in plain
    assert WINDOW in plain and WINDOW_2 in plain
    verdicts = [r for r in re.findall(r"<tr>.*?</tr>", rendered, flags=re.S) if "IBf$$ZaZkjsa)" in r]
    assert verdicts and all(r.count("<td") == 7 for r in verdicts)  # the name's | did not split the row
    # CSV: the name is one field, read back whole
    with open(out / "rooms.csv", newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert any(ROOM in row.values() for row in rows)
    # JUnit XML parses, with the name in it
    tree = ET.parse(tmp_path / "junit.xml")
    named = [tc.get("name") or "" for tc in tree.iter("testcase")]
    assert any("IBf$$ZaZkjsa)" in n and "<b>&amp;" in n and "مرحبا עברית 😀" in n for n in named)


def test_validate_draws_the_plan_of_rooms_with_such_names(tmp_path):
    plans = tmp_path / "plans"
    r = CliRunner().invoke(cli, ["validate", str(nasty_project(tmp_path)), "--plan", str(plans)], catch_exceptions=False)
    assert r.exit_code == 0, r.output
    assert ROOM in r.output
    assert list(plans.glob("*.png"))
