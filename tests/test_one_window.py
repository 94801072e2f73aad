"""One building, one answer: a window is the opening, whatever the format or the drawing (issue 35).

* one window drawn three ways — two panes with a mullion between them (an OBJ, two groups of glass),
  one pane across the frame with the mullion over it (an OBJ), and an IfcWindow of two panes and a
  mullion (ifcopenshell.api) — gives one window, the same point P and the same hours;
* where P lies behind the mullion, ``sunlight.point_p_behind_member`` decides: by default the sun
  through the clear glass either side; the report gives the hours at P as drawn and at the glass
  beside the member, worked out here from the sun's direction against the opening, the frame and
  the mullion;
* the FZK-Haus (ArchiCAD 20) from its IFC and from an OBJ export of the same geometry (written
  here: the glass on the window layer, everything else interior, the same site, north and rooms)
  gives every room the same hours within 0.05 h.

The room: 5 x 4 m inside 0.3 m walls, 2.7 m high, at 52 N; its south window 2.0 x 1.4 m (sill
0.8 m), drawn as en17037cli.samples.ifc.Builder draws windows: an 8 cm deep frame 6 cm wide set
2 cm into the wall, a 6 cm mullion of the same depth between two panes, the glass (6 mm) in the
middle of the frame's depth, its outer face 5.7 cm inside the wall's outer face; P on the wall's
room-side face, 0.243 m behind the glass.
"""
from __future__ import annotations

import datetime as dt
import json
import zoneinfo
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from tests.oracles import sun_position, sun_vectors

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT.parent / "shared" / "data" / "real-models"
DAY = "03-01"
SUN = {"date": DAY, "period": {"start": DAY, "end": DAY}}
LAT, LON, TZ = 52.0, 4.36, "Europe/Amsterdam"
W, H, SILL, WALL = 2.0, 1.4, 0.8, 0.3  # the opening and the wall [m]
FRAME, DEPTH, GLASS = 0.06, 0.08, 0.006  # frame (and mullion) width and depth, glass thickness [m]
X0, X1 = 1.5, 3.5  # the opening's jambs [m]; the wall's outer face at y = -0.3, room side y = 0
Y_FRAME = (-WALL + 0.02, -WALL + 0.02 + DEPTH)  # the frame's outer and room-side faces [m]
Y_GLASS = -WALL + 0.02 + DEPTH / 2 - GLASS / 2  # the glass's outer face [m]
OBJ_LAYERS = [{"match": "glass*", "layer": "window"}, {"match": "*", "layer": "interior"}]
ROOM = [{"name": "room", "floor_z": 0.0, "inside": [2.5, 2.0]}]


def box(x0, x1, y0, y1, z0, z1) -> list:
    """The 12 triangles of an axis-aligned box [m]."""
    v = np.array([[x, y, z] for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)], float)
    q = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return [v[[a, b, c]] for a, b, c, d in q] + [v[[a, c, d]] for a, b, c, d in q]


def rect_y(x0, x1, z0, z1, y) -> list:
    """The two triangles of a rectangle in the plane y [m]."""
    a, b, c, d = (np.array(p, float) for p in ((x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)))
    return [np.array([a, b, c]), np.array([a, c, d])]


def shell() -> list:
    """Walls, floor and roof as boxes; the south wall has the opening."""
    t = box(-WALL, 5 + WALL, 4, 4 + WALL, 0, 2.7) + box(-WALL, 0, -WALL, 4, 0, 2.7) + box(5, 5 + WALL, -WALL, 4, 0, 2.7)
    t += box(-WALL, X0, -WALL, 0, 0, 2.7) + box(X1, 5 + WALL, -WALL, 0, 0, 2.7)
    t += box(X0, X1, -WALL, 0, 0, SILL) + box(X0, X1, -WALL, 0, SILL + H, 2.7)
    return t + box(-WALL, 5 + WALL, -WALL, 4 + WALL, -0.2, 0) + box(-WALL, 5 + WALL, -WALL, 4 + WALL, 2.7, 2.9)


def frame() -> list:
    """The frame round the opening and the mullion at its middle."""
    z0, z1, (y0, y1), xm = SILL, SILL + H, Y_FRAME, 0.5 * (X0 + X1)
    t = box(X0, X0 + FRAME, y0, y1, z0, z1) + box(X1 - FRAME, X1, y0, y1, z0, z1)
    t += box(X0 + FRAME, X1 - FRAME, y0, y1, z0, z0 + FRAME) + box(X0 + FRAME, X1 - FRAME, y0, y1, z1 - FRAME, z1)
    return t + box(xm - FRAME / 2, xm + FRAME / 2, y0, y1, z0 + FRAME, z1 - FRAME)


def write_obj(path: Path, objects: dict[str, list]) -> Path:
    lines, n = [], 0
    for name, tris in objects.items():
        lines.append(f"o {name}")
        for t in tris:
            lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in t]
            lines.append(f"f {n + 1} {n + 2} {n + 3}")
            n += 3
    path.write_text("\n".join(lines) + "\n")
    return path


def obj_window(tmp: Path, how: str) -> Path:
    """The room as an OBJ: ``two_panes`` (two glass groups, the mullion between them) or ``one_pane``
    (one pane across the whole frame, the mullion over it)."""
    x0, x1, z0, z1, xm = X0 + FRAME, X1 - FRAME, SILL + FRAME, SILL + H - FRAME, 0.5 * (X0 + X1)
    if how == "two_panes":
        glass = {"glass left": rect_y(x0, xm - FRAME / 2, z0, z1, Y_GLASS),
                 "glass right": rect_y(xm + FRAME / 2, x1, z0, z1, Y_GLASS)}
    else:
        glass = {"glass": rect_y(x0, x1, z0, z1, Y_GLASS)}
    return write_obj(tmp / f"{how}.obj", {**glass, "walls": shell(), "frame": frame()})


def ifc_window(path: Path) -> Path:
    """The room as an IFC: walls, the opening cut, one IfcWindow of two panes and a mullion."""
    from en17037cli.samples import ifc as sample

    assert (sample.FRAME_M, sample.FRAME_DEPTH_M, sample.GLASS_M, sample.WALL_M) == (FRAME, DEPTH, GLASS, WALL)
    b = sample.Builder("IFC4")
    st = b.storey("Ground", 0.0)
    b.locate(LAT, LON, 0.0)
    foot = [(-WALL, -WALL), (5 + WALL, -WALL), (5 + WALL, 4 + WALL), (-WALL, 4 + WALL)]
    b.slab("Floor", st, foot, -0.2, 0.2)
    b.slab("Roof", st, foot, 2.7, 0.2)
    walls = [b.wall(f"Wall {k}", st, *p, *q, 0.0, 2.7) for k, (p, q) in enumerate(zip(foot, foot[1:] + foot[:1]))]
    room = b.space("R", "room", st, [(0, 0), (5, 0), (5, 4), (0, 4)], 0.0, 2.7)
    b.window("W", st, walls[0], (2.5, -WALL, SILL + H / 2), (0, -1, 0), (1, 0, 0), W, H, panes=2, spaces=[room])
    return b.write(path)


def project(tmp: Path, file: dict, rooms: list, name="p", north: float | None = None, **extra) -> Path:
    model = {"files": [file], **({"true_north_deg": north} if north is not None else {})}
    doc = {"version": 1, "name": name, "model": model,
           "location": {"latitude": LAT, "longitude": LON, "timezone": TZ}, "rooms": rooms,
           "sunlight": SUN, "requirements": {"view": "none", "sunlight": "minimum"}, **extra}
    p = tmp / f"{name}.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True))
    return p


def report(p: Path, out: Path, *args) -> dict:
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(out), "-q", "--no-plots", *args], catch_exceptions=False)
    assert r.exit_code in (0, 1), r.output
    return json.loads((out / "report.json").read_text())


def test_a_window_drawn_three_ways_is_one_window_with_one_answer(tmp_path):
    got = {}
    for how in ("two_panes", "one_pane"):
        rep = report(project(tmp_path, {"path": str(obj_window(tmp_path, how)), "layers": OBJ_LAYERS}, ROOM, how),
                     tmp_path / how)
        got[how] = rep["rooms"][0]
    pytest.importorskip("ifcopenshell")
    got["ifc"] = report(project(tmp_path, {"path": str(ifc_window(tmp_path / "w.ifc"))}, [{"ifc_spaces": "*"}], "ifc"),
                        tmp_path / "ifc")["rooms"][0]
    pane = (W - 3 * FRAME) / 2
    for how, room in got.items():
        (w,) = room["sunlight"]["windows"]  # one window, however drawn
        assert w["point_p_m"] == pytest.approx([2.5, 0.0, 1.2], abs=1e-6), how  # the wall's room-side face
        assert w["reveal_depth_m"] == pytest.approx(-Y_GLASS, abs=1e-4), how
        assert w["behind_member"]["rule"] == "pane_centres"
        centres = sorted(p[0] for p in w["behind_member"]["points_m"])
        assert centres == pytest.approx([2.5 - FRAME / 2 - pane / 2, 2.5 + FRAME / 2 + pane / 2], abs=2e-4), how
    hours = {how: room["sunlight"]["hours_h"] for how, room in got.items()}
    assert max(hours.values()) - min(hours.values()) < 2e-3, hours  # the exact method's bound, twice
    drawn = {how: room["sunlight"]["windows"][0]["behind_member"]["hours_as_drawn_h"] for how, room in got.items()}
    assert max(drawn.values()) - min(drawn.values()) < 2e-3, drawn


def seen_from(px: float) -> np.ndarray:
    """Whether the sun is seen from (px, 0, 1.2) on the room-side face, every 10 s of the day (see
    the test below): a ray to the sun passes the wall's opening (its room-side and outer faces),
    the frame's inner edge (the frame's two faces) and does not cross the mullion (both of the bar's
    faces on one side of it); pvlib's SPA with refraction, as the tool's default."""
    day = dt.datetime(2026, 3, 1, tzinfo=zoneinfo.ZoneInfo(TZ))
    t = np.arange(day.timestamp(), day.timestamp() + 86400, 10.0)
    elev, azim = sun_position(t, LAT, LON, refraction=True)
    d = sun_vectors(elev, azim)
    out = d[:, 1] < -1e-9  # the window faces -y (south)
    seen = out & (elev >= 11.0)
    r = lambda y: -y / np.where(out, -d[:, 1], 1.0)  # noqa: E731 the ray's length from y = 0 to the plane y
    x = lambda y: px + r(y) * d[:, 0]  # noqa: E731
    z = lambda y: 1.2 + r(y) * d[:, 2]  # noqa: E731
    for y in (0.0, -WALL):  # the opening in the wall
        seen &= (x(y) > X0) & (x(y) < X1) & (z(y) > SILL) & (z(y) < SILL + H)
    for y in Y_FRAME:  # inside the frame's ring
        seen &= (x(y) > X0 + FRAME) & (x(y) < X1 - FRAME) & (z(y) > SILL + FRAME) & (z(y) < SILL + H - FRAME)
    a, b = x(Y_FRAME[1]) - 2.5, x(Y_FRAME[0]) - 2.5  # clear of the mullion: both its faces on one side
    return seen & (((a >= FRAME / 2) & (b >= FRAME / 2)) | ((a <= -FRAME / 2) & (b <= -FRAME / 2)))


def test_p_behind_a_mullion_hours_against_a_hand_calculation(tmp_path):
    """:func:`seen_from` sampled every 10 s: the tool's exact method agrees to the sampling's 2 x 10 s
    a day. P as drawn (at the bar), and the nearest glass either side (1 cm beyond the bar's
    edges), whose union the report gives beside."""
    p = project(tmp_path, {"path": str(obj_window(tmp_path, "two_panes")), "layers": OBJ_LAYERS}, ROOM)
    rep = report(p, tmp_path / "o", "--set", "sunlight.point_p_behind_member=as_drawn")
    (w,) = rep["rooms"][0]["sunlight"]["windows"]
    expected = seen_from(2.5).sum() * 10.0 / 3600.0
    beside = (seen_from(2.5 - FRAME / 2 - 0.01) | seen_from(2.5 + FRAME / 2 + 0.01)).sum() * 10.0 / 3600.0
    assert beside > expected + 0.5  # the bar hides the sun from P for at least half an hour
    tol = 2 * 10 / 3600  # the samples' 10 s at both ends of the day's interval
    assert rep["rooms"][0]["sunlight"]["hours_h"] == pytest.approx(expected, abs=tol)
    assert w["behind_member"]["hours_as_drawn_h"] == pytest.approx(expected, abs=tol)
    assert w["behind_member"]["hours_nearest_glass_h"] == pytest.approx(beside, abs=2 * tol)


def fzk_as_obj(tmp: Path) -> Path:
    """An OBJ export of the FZK-Haus's geometry as a modeller writes one: every product's faces as
    they are, the glass in objects named ``glass <n>``, the rest ``part <n>`` (IfcSite's terrain
    ``ground``); no element ids, no spaces, no hosts."""
    from en17037cli.io.ifc import read_ifc

    m = read_ifc(FZK)
    objects: dict[str, list] = {}
    for k, part in enumerate(m.parts):
        tris = m.vertices[m.triangles[m.part == k]]
        if part.layer == "ignore" or len(tris) == 0:
            continue
        name = {"window": "glass", "ground": "ground"}.get(part.layer or "", "part")
        objects[f"{name} {k}"] = list(tris)
    return write_obj(tmp / "fzk.obj", objects)


FZK = MODELS / "AC20-FZK-Haus.ifc"


@pytest.mark.skipif(not FZK.is_file(), reason="../shared/data/real-models is absent")
def test_the_fzk_haus_from_its_ifc_and_its_obj_gives_the_same_hours(tmp_path):
    """Same site, north, rooms and defaults: each room's hours on its worst day of the period within
    0.05 h (the OBJ's P is probed from the faces, the IFC's taken from the host wall's face)."""
    pytest.importorskip("ifcopenshell")
    from en17037cli.project import load_project
    from en17037cli.scene import build_scene

    period = {"date": "worst"}
    ifc_p = project(tmp_path, {"path": str(FZK)}, [{"ifc_spaces": "*"}], "ifc", sunlight=period,
                    location={"timezone": "Europe/Berlin"})
    scene = build_scene(load_project(ifc_p, []))
    loc = scene.location
    rooms = [{"name": r.name, "floor_z": float(r.floor_z + scene.origin[2]),  # the spaces' own floors
              "floor": [[float(x), float(y)] for x, y in np.asarray(r.floor.exterior.coords)[:-1] + scene.origin[:2]]}
             for r in scene.rooms if r.windows]
    layers = [{"match": "glass*", "layer": "window"}, {"match": "ground*", "layer": "ground"}, {"match": "*", "layer": "interior"}]
    obj_p = project(tmp_path, {"path": str(fzk_as_obj(tmp_path)), "layers": layers}, rooms, "obj", sunlight=period,
                    north=float(scene.true_north_deg),
                    location={"latitude": loc.latitude, "longitude": loc.longitude, "timezone": "Europe/Berlin"})
    a = {r["name"]: r["sunlight"] for r in report(ifc_p, tmp_path / "a")["rooms"] if r["sunlight"]}
    b = {r["name"]: r["sunlight"] for r in report(obj_p, tmp_path / "b")["rooms"] if r["sunlight"]}
    assert set(a) == set(b) and len(a) == 6
    for name in a:
        assert len(a[name]["windows"]) == len(b[name]["windows"]), name
        assert b[name]["hours_h"] == pytest.approx(a[name]["hours_h"], abs=0.05), name
        assert b[name]["level"] == a[name]["level"], name


def test_the_member_rule_is_in_the_sensitivity_study(tmp_path):
    """`study sensitivity` tries the other two readings of P behind a member on the rooms that have
    one, each at the level of the hours :func:`seen_from` gives (Table A.6's thresholds)."""
    import csv

    from en17037cli import standard
    from en17037cli.studies.sensitivity import sensitivity

    p = project(tmp_path, {"path": str(obj_window(tmp_path, "two_panes")), "layers": OBJ_LAYERS}, ROOM)
    sensitivity(p, tmp_path / "s", log=lambda *_: None)
    rows = {r["value"]: r["level"] for r in csv.DictReader((tmp_path / "s" / "sensitivity.csv").open())
            if r["choice"] == "sunlight.point_p_behind_member"}
    hours = {"as_drawn": seen_from(2.5), "nearest_glass": seen_from(2.5 - FRAME / 2 - 0.01) | seen_from(2.5 + FRAME / 2 + 0.01)}
    th = standard.LevelThresholds(1.5, 3.0, 4.0)
    assert rows == {k: standard.LEVELS[int(standard.level_from_value([v.sum() * 10 / 3600], th)[0])] for k, v in hours.items()}
