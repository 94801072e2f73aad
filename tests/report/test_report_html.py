"""The client report end to end: fisheyes traced from the scene where the closed form puts the
window, no sun inside a north window, report.html opened in a real headless browser, and the
limiting criterion named with its margin.

The box room (en17037cli.samples.box): the opening x in [-1, 1] m, z in [0.8, 2.2] m in the plane
y = 0, facing south; ground z = 0 south of it; a 10 m building whose face is 25 m south of the
facade.
"""
from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.samples import BoxRoom, box_room_project

ROOT = Path(__file__).resolve().parents[2]
FAST_VIEW = {"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 3.0, "refine_levels": 1}
SUN = {"date": "02-01", "period": {"start": "02-01", "end": "02-03"}}
#: One fisheye pixel of an n-pixel raster spans 180 / n deg; a boundary is placed within one pixel.
N = 361


def scene_and_engine(tmp_path, **project):
    from en17037cli.project import load_project
    from en17037cli.raytrace import RayEngine
    from en17037cli.scene import build_scene

    p = box_room_project(tmp_path / "box", BoxRoom(), sunlight=SUN, view=FAST_VIEW, **project)
    scene = build_scene(load_project(p, []))
    return scene, RayEngine(scene.vertices, scene.triangles, scene.ray_groups())


def test_traced_fisheye_puts_the_window_where_the_closed_form_does(tmp_path):
    """From (0, 2, 1.5) m looking south: the opening's top and bottom edges at +-atan(0.7 / 2) =
    19.29 deg, its sides at +-atan(1 / 2) = 26.57 deg; through it the building's top at atan(8.5 /
    27) = 17.48 deg and its foot at -atan(1.5 / 27) = -3.18 deg; ground below, sky above."""
    from en17037cli.criteria.sunlight.pictures import fisheye_classes
    from en17037cli.geometry.fisheye import fisheye_pixel_xy

    scene, engine = scene_and_engine(tmp_path)
    with engine:
        img = fisheye_classes(engine, scene, scene.rooms[0], scene.to_local([0.0, 2.0, 1.5]), 180.0, n=N)
    x, y = fisheye_pixel_xy(N)
    c = N // 2  # the centre column: x = 0, altitude = 90 y
    alt = 90.0 * y[:, c]
    px = 180.0 / N

    def edges(cls_set):  # altitudes of the column's pixels in the classes, as (lowest, highest)
        a = alt[np.isin(img[:, c], cls_set)]
        return a.min(), a.max()

    lo, hi = edges([1, 2, 3])  # anything seen through the opening
    assert abs(hi - math.degrees(math.atan(0.7 / 2))) <= px and abs(lo + math.degrees(math.atan(0.7 / 2))) <= px
    lo, hi = edges([2])  # the building
    assert abs(hi - math.degrees(math.atan(8.5 / 27))) <= px and abs(lo + math.degrees(math.atan(1.5 / 27))) <= px
    row = int(np.argmin(np.abs(y[:, 0])))  # the horizon row: azimuth off the axis = 90 x
    side = 90.0 * x[row][img[row] >= 1]
    assert abs(side.max() - math.degrees(math.atan(0.5))) <= px and abs(side.min() + math.degrees(math.atan(0.5))) <= px


def test_no_sun_inside_a_north_window(tmp_path):
    """True north turned 180 deg: the window faces north; at 52 N from 1 to 3 February the sun never
    enters the opening: no path sample is seen, and none lies on a pixel seen through the opening."""
    from en17037cli import load_project, run
    from en17037cli.geometry.fisheye import fisheye_xy

    p = box_room_project(tmp_path / "north", BoxRoom(), sunlight=SUN, view=FAST_VIEW, true_north_deg=180.0)
    result = run(load_project(p), pictures=True)
    (fe,) = result.rooms[0].illustrations["sunlight"]
    assert abs(fe.view_azimuth_deg - 0.0) < 1e-9
    n = fe.image.shape[0]
    for path in fe.paths:
        assert not path.visible.any()
        xs, ys = fisheye_xy(path.azimuth_deg, path.altitude_deg, fe.view_azimuth_deg)
        inside = (np.hypot(xs, ys) <= 1.0) & (path.altitude_deg >= 0)
        cols = np.clip(((xs[inside] + 1) * n / 2).astype(int), 0, n - 1)
        rows = np.clip(((1 - ys[inside]) * n / 2).astype(int), 0, n - 1)
        assert not np.isin(fe.image[rows, cols], [1, 2, 3]).any()
    # the same room facing south sees the sun on its assessed day (1 February)
    p = box_room_project(tmp_path / "south", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    result = run(load_project(p), pictures=True)
    (fe,) = result.rooms[0].illustrations["sunlight"]
    assert fe.view_azimuth_deg == 180.0 and fe.paths[0].visible.any()


def test_limiting_criterion_and_margin_on_the_seed_office():
    """The seed office's pinned report: 67 % of the points reach a 28 deg sight angle where 75 % are
    needed (58 of 87); 5 h 52 min of sun on 1 February, 4 h 22 min above the 1.5 h of minimum."""
    from tests.golden.scenes import pinned

    md = pinned("seed-office")["report.md"]
    assert ("| office | view out (5.2) | minimum | medium | **FAIL** | sight angle: 67 % of points reach medium at 1.2 m eye "
            "height, 75 % needed |") in md
    assert ("| office | exposure to sunlight (5.3) | high | minimum | **PASS** | sunlight: 5 h 52 min on 1 February, "
            "4 h 22 min above minimum |") in md
    doc = json.loads(pinned("seed-office")["report.json"])
    view = doc["rooms"][0]["view"]
    assert view["limiting"] == {"level": "medium", "criterion": "horizontal_sight_angle", "value": 0.6667, "needed": 0.75,
                                "margin": -0.0833, "eye_height_m": 1.2}
    assert view["eye_heights"][0]["share_by_level"]["horizontal_sight_angle"]["medium"] == round(58 / 87, 4)


def test_limiting_sunlight_short_of_a_level(tmp_path):
    """A south box room, 2 m wide window, required high (4 h) on 1 February; its hours fall short:
    the margin is the hours less 4 h, and the sentence says how much is missing."""
    p = box_room_project(tmp_path / "b", BoxRoom(), sunlight=SUN, view=None)
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / "o"), "-q", "--no-plots",
                                 "--set", "requirements.sunlight=high"])
    doc = json.loads((tmp_path / "o" / "report.json").read_text())
    s = doc["rooms"][0]["sunlight"]
    lim = s["limiting"]
    assert lim["level"] == "high" and lim["needed"] == 4.0 and abs(lim["margin"] - (s["hours_h"] - 4.0)) < 1e-4
    assert (r.exit_code == 1) == (s["hours_h"] < 4.0)
    from en17037cli.report.numbers import fmt_duration

    word = f"{fmt_duration(4.0 - s['hours_h'])} short of high" if s["hours_h"] < 4 else f"{fmt_duration(s['hours_h'] - 4.0)} above high"
    assert f"sunlight: {fmt_duration(s['hours_h'])} on 1 February, {word}" in (tmp_path / "o" / "report.md").read_text()
    assert not (tmp_path / "o" / "figures").exists()  # --no-plots


def _chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")


@pytest.fixture(scope="module")
def report_folder(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("html")
    p = box_room_project(tmp / "box", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp / "out"), "-q"])
    assert r.exit_code in (0, 1), r.output
    return tmp / "out"


def test_html_is_self_contained(report_folder):
    html = (report_folder / "report.html").read_text("utf-8")
    # the clauses this report checks (view and sunlight), not daylight provision it did not
    assert "EN 17037:2018+A1:2021 clauses 5.2 (view out) and 5.3 (exposure to sunlight)." in html and "5.1 (" not in html
    assert "<script" not in html.lower()
    refs = re.findall(r'(?:src|href)\s*=\s*"([^"]*)"', html)
    # inline SVG pictures: their rasters as data URIs, their clip paths by fragment; nothing else
    assert all(r.startswith(("data:image/png;base64,", "#")) for r in refs)
    assert not re.search(r"url\((?!#)", html)  # no CSS url() outside the page
    assert "default-src 'none'" in html
    figures = sorted((report_folder / "figures").iterdir())
    assert len(figures) == 6 and html.count("<svg ") == 6
    md = (report_folder / "report.md").read_text("utf-8")
    assert all(f"](figures/{f.name})" in md for f in figures)


def _browser(tmp_path: Path) -> list[str]:
    exe = _chromium()
    if exe is None:
        if os.environ.get("EN17037_REQUIRE_BROWSER"):
            pytest.fail("EN17037_REQUIRE_BROWSER is set but no chromium is installed (apt-get install chromium)")
        pytest.skip("chromium is not installed (CI installs it: apt-get install chromium)")
    return [exe, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", f"--user-data-dir={tmp_path / 'profile'}",
            "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def page_requests(browser: list[str], page: Path, netlog: Path, *extra: str) -> set[str]:
    """URLs the page itself asked for while Chromium loaded it: requests in the network log whose
    initiator is an origin (the browser's own background requests have none: 'not an origin')."""
    subprocess.run([*browser, f"--log-net-log={netlog}", *extra, page.as_uri()], capture_output=True, timeout=120, check=True)
    out = set()
    for line in netlog.read_text(errors="replace").splitlines():  # one event per line
        i, u = re.search(r'"initiator":"([^"]*)"', line), re.search(r'"url":"([^"]+)"', line)
        if i and u and i[1] != "not an origin":
            out.add(u[1])
    return out


def test_html_in_a_headless_browser(report_folder, tmp_path):
    """Chromium opens the file and renders it (a screenshot that is not blank, with a PASS or FAIL
    badge; the verdict table and the six pictures in the DOM), and the page asks for nothing: the
    same check catches a control page that loads an image from the network."""
    browser = _browser(tmp_path)
    page = report_folder / "report.html"
    shot = tmp_path / "shot.png"
    assert page_requests(browser, page, tmp_path / "net.json", "--window-size=1000,1400", f"--screenshot={shot}") == set()
    control = tmp_path / "control.html"
    control.write_text('<!DOCTYPE html><html><body><img src="http://192.0.2.1/x.png"></body></html>')
    assert page_requests(browser, control, tmp_path / "net-control.json", "--dump-dom") == {"http://192.0.2.1/x.png"}
    dom = subprocess.run([*browser, "--dump-dom", page.as_uri()], capture_output=True, timeout=120, check=True, text=True).stdout
    assert "Verdict" in dom and "view out (5.2)" in dom and dom.count("<svg ") == 6
    import matplotlib.image

    px = matplotlib.image.imread(shot)[..., :3]
    assert px.shape[:2] == (1400, 1000) and px.std() > 0.1  # not blank
    badge = [np.array(c) / 255 for c in ((0xB4, 0x23, 0x18), (0x1A, 0x7F, 0x37))]  # FAIL red, PASS green
    assert any(np.count_nonzero(np.all(np.abs(px - c) < 0.02, axis=-1)) > 100 for c in badge)


def test_without_matplotlib_the_check_writes_its_reports_without_pictures(tmp_path, monkeypatch):
    """A plain install (no 'plot' extra): the reports come without pictures and say why."""
    from en17037cli.report import figures

    monkeypatch.setattr(figures, "pictures_available", lambda: False)
    p = box_room_project(tmp_path / "box", BoxRoom(), sunlight=SUN, view=FAST_VIEW)
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / "out"), "-q"])
    assert r.exit_code in (0, 1), r.output
    assert not (tmp_path / "out" / "figures").exists() and "<img" not in (tmp_path / "out" / "report.html").read_text()
    doc = json.loads((tmp_path / "out" / "report.json").read_text())
    assert any(w.startswith("no pictures: they need matplotlib") for w in doc["warnings"])
