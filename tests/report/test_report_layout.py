"""The client report on a phone, on a desktop and on paper (issue 29): report.html of the seed office
in headless Chromium (driven over the DevTools protocol, tests/report/cdp.py) at 390 and 1280 CSS px
and printed to A4 PDF.

Asserted: no sideways scrolling of the page at 390 px (tables scroll inside their own box), every
picture inside the viewport at both widths, at most 3 PDF pages, and on paper no text of any
picture under 8 pt: each SVG's text size in its own units times the SVG's printed scale
(rendered width over viewBox width), in points (0.75 pt per CSS px).
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest
from cdp import Browser, chromium, pdf_pages
from click.testing import CliRunner

from en17037cli.cli import cli

ROOT = Path(__file__).resolve().parents[2]
#: A4 less 15 mm margins each side, in CSS px (96 per inch): the width the page is laid out at on paper.
A4_CONTENT_PX = round((210 - 30) / 25.4 * 96)
#: The smallest text on paper [pt], with the browser's rounding of a font size to 1/64 px.
MIN_TEXT_PT = 8.0 - 0.02

FIGURES_JS = """Array.from(document.querySelectorAll('figure')).filter(f => getComputedStyle(f).display != 'none').map(f => {
  const r = f.getBoundingClientRect(); const s = f.querySelector('svg');
  const k = s.getBoundingClientRect().width / s.viewBox.baseVal.width;
  const pts = Array.from(s.querySelectorAll('text')).map(t => parseFloat(getComputedStyle(t).fontSize) * k * 0.75);
  return {left: r.left, right: r.right, min_pt: Math.min(...pts), texts: pts.length}; })"""


@pytest.fixture(scope="module")
def browser():
    if chromium() is None:
        if os.environ.get("EN17037_REQUIRE_BROWSER"):
            pytest.fail("EN17037_REQUIRE_BROWSER is set but no chromium is installed (apt-get install chromium)")
        pytest.skip("chromium is not installed (CI installs it: apt-get install chromium)")
    with Browser() as b:
        yield b


@pytest.fixture(scope="module")
def seed_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("seed") / "report"
    r = CliRunner().invoke(cli, ["check", str(ROOT / "sample_projects/seed-office/project.yaml"), "--out", str(out), "-q"])
    assert r.exit_code in (0, 1), r.output
    return out / "report.html"


@pytest.mark.parametrize("width", [390, 1280])
def test_the_page_fits_the_screen(browser, seed_report, width):
    browser.call("Emulation.setEmulatedMedia", session=True, media="screen")
    browser.open(seed_report, width)
    assert browser.eval("document.documentElement.scrollWidth") <= width  # no sideways scrolling of the page
    figs = browser.eval(FIGURES_JS)
    assert len(figs) == 11  # every picture on screen: 4 maps per eye height, sunlight chart and fisheye, daylight map
    assert all(f["left"] >= 0 and f["right"] <= width for f in figs), figs


def test_on_paper(browser, seed_report, tmp_path):
    browser.call("Emulation.setEmulatedMedia", session=True, media="print")
    browser.open(seed_report, A4_CONTENT_PX)
    figs = browser.eval(FIGURES_JS)
    # printed: each eye height's level map and what limits it, the daylight map, the sun chart and fisheye
    assert len(figs) == 7
    assert all(f["texts"] > 0 for f in figs)  # text stays text in the SVG (and so is measured)
    assert min(f["min_pt"] for f in figs) >= MIN_TEXT_PT, figs
    assert all(f["left"] >= 0 and f["right"] <= A4_CONTENT_PX + 1 for f in figs), figs
    assert pdf_pages(browser.pdf(tmp_path / "report.pdf")) <= 3
