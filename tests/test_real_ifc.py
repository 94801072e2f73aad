"""Real BIM exports as users receive them: the corpus of ../shared/data/real-models (README there).

ArchiCAD 20 (FZK-Haus, IFC4), Revit 2011 (Duplex, IFC2X3) and Revit 2015 (SampleHouse4, IFC4, mm)
each run to an answer (exit 0 or 1), every space with a window a room with all its windows, point
P on the room-side face of the wall the window is set in. Counts are the files' own (their
README); the sunlight figures are worked out here from ifcopenshell's raw geometry of the window
and its wall and pvlib's SPA, without the package's geometry or sun (tests/oracles.py).

Skipped only where ../shared/data/real-models is absent. Each file is read once for the module
(a read cache, as a design loop uses it).
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

from en17037cli import pipeline
from en17037cli.cli import cli
from en17037cli.project import load_project
from en17037cli.scene.load import READ_CACHE
from tests.oracles import sun_position, sun_vectors

pytest.importorskip("ifcopenshell")
ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT.parent / "shared" / "data" / "real-models"
pytestmark = pytest.mark.skipif(not MODELS.is_dir(), reason="../shared/data/real-models is absent")
FZK, DUPLEX, HOUSE4 = (MODELS / n for n in ("AC20-FZK-Haus.ifc", "Duplex_A_20110907.ifc", "SampleHouse4.ifc"))
#: A coarse view: the tests judge how the model is read, not the view's resolution.
FAST_VIEW = {"grid_spacing_m": 2.0, "eye_heights_m": [1.2], "angular_resolution_deg": 3.0, "refine_levels": 0}
#: 1 February in the Duplex's Chicago (its IfcSite), the day the README of the corpus quotes.
FEB1 = {"date": "02-01", "period": {"start": "02-01", "end": "02-01"}}


def project_file(tmp: Path, ifc: Path, timezone: str, **extra) -> Path:
    doc = {"version": 1, "name": ifc.stem, "model": {"files": [{"path": str(ifc)}]}, "location": {"timezone": timezone},
           "rooms": [{"ifc_spaces": "*"}], "requirements": {"view": "minimum", "sunlight": "minimum"}, **extra}
    p = tmp / f"{ifc.stem}.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Each corpus file checked once (coarse view, sunlight on 1 February), read once."""
    tmp = tmp_path_factory.mktemp("real")
    token = READ_CACHE.set({})
    try:
        out = {}
        for ifc, tz in ((FZK, "Europe/Berlin"), (DUPLEX, "America/Chicago"), (HOUSE4, "Europe/London")):
            project = load_project(project_file(tmp, ifc, tz, view=FAST_VIEW, sunlight=FEB1), [])
            out[ifc.name] = pipeline.run(project)
        yield out
    finally:
        READ_CACHE.reset(token)


def windows_by_room(result) -> dict[str, int]:
    return {r.room.name: len(r.room.windows) for r in result.rooms}


def test_fzk_haus_archicad_every_windowed_space_with_its_windows(runs):
    """ArchiCAD 20: 7 spaces; the hall (Flur) has no window; the terrace door (a glazed IfcDoor of
    three sliding leaves, glass as thin solids 11 cm apart) is one window, its own frame no error."""
    r = runs["AC20-FZK-Haus.ifc"]
    assert windows_by_room(r) == {"Bad (3)": 1, "Buero (2)": 2, "Küche (6)": 2, "Schlafzimmer (4)": 2, "Wohnen (5)": 3,
                                  "Galerie (7)": 2}
    assert [(lo.name, lo.windows) for lo in r.scene.left_out] == [("Flur (1)", ())]
    assert len(r.scene.windows) == 12 and {w.name for r_ in r.rooms for w in r_.room.windows} == {w.name for w in r.scene.windows}
    door = next(w for w in r.scene.windows if w.name == "Terrassentuer")
    assert abs(door.area_m2 - 3.463) < 0.01  # three leaves of 1.81 x 2.02 m glass, overlapping, counted once
    round_ = next(w for w in r.scene.windows if w.name == "OG-Fenster-1")
    assert abs(round_.area_m2 - np.pi * 0.35 ** 2) < 0.002  # the 0.7 m disc; glass bars over it not counted twice
    assert r.status == "fail" and all(x.status("sunlight") in ("pass", "fail") for x in r.rooms)


def test_duplex_revit_2011_stacks_skylights_and_boundaries(runs):
    """Revit 2011: 21 spaces, 10 with windows. Each bedroom's stack of three windows (the file's
    space boundaries name only the lowest) is in its room; the skylights (no transparent style:
    panes from their geometry) light the halls below the roof; no window is left out."""
    r = runs["Duplex_A_20110907.ifc"]
    assert windows_by_room(r) == {"Kitchen (A103)": 1, "Kitchen (B103)": 1, "Living Room (A102)": 2, "Living Room (B102)": 2,
                                  "Bedroom 1 (A202)": 4, "Bedroom 1 (B202)": 4, "Hallway (A201)": 1, "Hallway (B201)": 1,
                                  "Bedroom 2 (A203)": 5, "Bedroom 2 (B203)": 5}
    assert len(r.scene.left_out) == 11 and not any(lo.windows for lo in r.scene.left_out)
    assert len(r.scene.windows) == 26 and not r.scene.windows_left_out
    bedroom = next(x.room for x in r.rooms if x.room.name == "Bedroom 2 (A203)")
    stack = sorted(w.sill_z for w in bedroom.windows if "819mm x 759mm" in w.name)
    assert len(stack) == 3 and np.ptp(stack) > 1.5  # three windows one above the other
    hall = next(x.room for x in r.rooms if x.room.name == "Hallway (A201)")
    assert "Skylight" in hall.windows[0].name and hall.windows[0].normal[2] == pytest.approx(1.0)
    assert any("panes taken from their geometry" in n and "M_Skylight" in n for n in r.scene.notes)


def test_samplehouse4_revit_2015_frames_and_curtain_walls(runs):
    """Revit 2015, millimetres: the windows' frames touch their glass (no error); the two curtain
    walls' six glazed plates open into the living room, whose space reaches 2 cm past the glass: each
    curtain wall one window of its three plates (one opening, its members between them)."""
    r = runs["SampleHouse4.ifc"]
    assert windows_by_room(r) == {"Bedroom (2 - Bedroom)": 1, "Living room (1 - Living room)": 5}
    living = next(x.room for x in r.rooms if x.room.name.startswith("Living"))
    walls = [w for w in living.windows if "System Panel:Glazed" in w.name]
    assert len(walls) == 2 and all(w.name.endswith("(+2 panes)") for w in walls)
    assert [lo.name for lo in r.scene.left_out] == ["Entrance hall (3 - Entrance hall)", "Roof (4 - Roof)"]


@pytest.mark.parametrize("name", ["AC20-FZK-Haus.ifc", "Duplex_A_20110907.ifc", "SampleHouse4.ifc"])
def test_no_landscape_makes_the_view_not_assessable_never_a_pass(runs, name):
    """No surroundings in the file: the layers cannot be judged, the view is not assessable (with
    the reason and what to do), the sight angle and distance still measured, the run fails."""
    r = runs[name]
    assert r.status == "fail" and "view: every room NOT ASSESSABLE" in " ".join(r.warnings)
    for x in r.rooms:
        assert x.status("view") == "not_assessable" and x.level("view") is None
        res = x.assessed("view")
        assert "no landscape" in res.layers_unassessable and "horizontal sight angle" in res.layers_unassessable
        assert np.isfinite(res.eye_heights[0].values.sight.angle_deg).all()


def _shape(e):
    import ifcopenshell.geom as geom

    s = geom.settings()
    s.set("use-world-coords", True)
    g = geom.create_shape(s, e).geometry
    return (np.asarray(g.verts).reshape(-1, 3), np.asarray(g.faces).reshape(-1, 3), np.asarray(g.material_ids),
            [m.transparency for m in g.materials])


@pytest.fixture(scope="module")
def duplex_raw():
    """The Duplex by ifcopenshell alone: its site, a space's floor, a window's glass and its wall."""
    import ifcopenshell

    f = ifcopenshell.open(str(DUPLEX))

    def window(suffix):
        w = next(e for e in f.by_type("IfcWindow") + f.by_type("IfcDoor") if e.Name.endswith(suffix))
        v, fc, mid, tr = _shape(w)
        glass = v[fc[np.isin(mid, [i for i, t in enumerate(tr) if t > 0.5])]].reshape(-1, 3)
        host = w.FillsVoids[0].RelatingOpeningElement.VoidsElements[0].RelatingBuildingElement
        return glass, host

    site = f.by_type("IfcSite")[0]
    dms = lambda c: c[0] + c[1] / 60 + c[2] / 3600 + (c[3] if len(c) > 3 else 0) / 3.6e9  # noqa: E731
    floor = {s.Name: _shape(s)[0][:, 2].min() for s in f.by_type("IfcSpace")}
    return f, window, (dms(site.RefLatitude), dms(site.RefLongitude)), floor


def sun_on_feb1(lat, lon, step_s=10.0):
    """Sun vectors (x east, y north: the Duplex has no TrueNorth) every ``step_s`` over 1 February
    in Chicago, and where the sun stands at least 11 deg high (sunlight.min_altitude_deg)."""
    t0 = dt.datetime(2026, 2, 1, tzinfo=zoneinfo.ZoneInfo("America/Chicago")).timestamp()
    el, az = sun_position(t0 + np.arange(0, 86400, step_s), lat, lon, refraction=True)
    return sun_vectors(el, az), el >= 11.0


def aperture_hours(p, axis, sign, plane, lo, hi, sun, up, step_s=10.0):
    """Hours the sun is seen from P through a rectangular pane in the plane ``x[axis] = plane``
    spanning lo..hi in the two other axes (the frame not modelled): rays from P towards the sun
    (sign: the pane's outward direction along the axis) crossing the plane inside the rectangle."""
    s = sun
    t = (plane - p[axis]) / np.where(sign * s[:, axis] > 0, s[:, axis], np.nan)
    hit = p + t[:, None] * s
    other = [k for k in range(3) if k != axis]
    inside = np.all([(hit[:, k] >= lo[i]) & (hit[:, k] <= hi[i]) for i, k in enumerate(other)], axis=0)
    return float(np.sum(inside & up & (t > 0)) * step_s / 3600)


def test_duplex_sunlight_by_hand_orientation_and_reveal(runs, duplex_raw):
    """Sunlight on 1 February in Chicago, worked out from the file's raw geometry (ifcopenshell)
    and pvlib's SPA, against the tool's figures:

    * Living Room (A102), its 4.8 m south window: P on the wall's inner face (y of the wall's room
      side), 1.2 m above the space's floor; facing due south the jambs never cut it, so its hours
      are the sun's time above 11 deg: within 20 s (the independent sum samples every 10 s).
    * Bedroom 1 (A202), its 2.8 m east window in a 0.38 m reveal: the north jamb cuts the sun off
      before noon. The model here takes the glass's outline as the opening; the frame's sight
      line lies a little inside it (the glass sits in a rebate), so the tool's hours lie at most
      5 min below, never above (2 cm at the jamb move the cut-off by ~0.4 deg of azimuth).
    * Living Room (B102), due north: no sun.
    * Hallway (A201), under a skylight: the roof light's pane (1.14 m across) sits 0.63 m above
      the hall's ceiling, so from its centre the sun must stand above atan(0.63 / 0.57) = 48 deg;
      Chicago's sun peaks at 31 deg on 1 February: no sun.
    """
    f, window, (lat, lon), floor = duplex_raw
    sun, up = sun_on_feb1(lat, lon)
    rooms = {x.room.name: x for x in runs["Duplex_A_20110907.ifc"].rooms}
    origin = runs["Duplex_A_20110907.ifc"].scene.origin

    glass, wall = window("146016")  # south: outward -y
    y_in = _shape(wall)[0][:, 1].max()  # the room lies to the north of its wall
    p = np.array([glass[:, 0].mean(), y_in, max(floor["A102"] + 1.2, glass[:, 2].min() + 0.3)])
    want = aperture_hours(p, 1, -1, glass[:, 1].min(), (glass[:, 0].min(), glass[:, 2].min()),
                          (glass[:, 0].max(), glass[:, 2].max()), sun, up)
    got = rooms["Living Room (A102)"].assessed("sunlight")
    i = [w.name.endswith("146016") for w in rooms["Living Room (A102)"].room.windows].index(True)
    assert np.allclose(got.points_local[i] + origin, p, atol=2e-3)  # P on the wall's room-side face
    assert abs(float(got.window_hours[i, 0]) - want) <= 20 / 3600 and 7.5 < want < 7.8
    assert abs(want - float(up.sum()) * 10 / 3600) <= 20 / 3600  # due south: every hour above 11 deg

    glass, wall = window("181096")  # east: outward +x
    x_in = _shape(wall)[0][:, 0].min()
    p = np.array([x_in, glass[:, 1].mean(), max(floor["A202"] + 1.2, glass[:, 2].min() + 0.3)])
    want = aperture_hours(p, 0, 1, glass[:, 0].max(), (glass[:, 1].min(), glass[:, 2].min()),
                          (glass[:, 1].max(), glass[:, 2].max()), sun, up)
    room = rooms["Bedroom 1 (A202)"]
    k = [w.name.endswith("181096") for w in room.room.windows].index(True)
    got = float(room.assessed("sunlight").window_hours[k, 0])
    assert want - 5 / 60 <= got <= want + 20 / 3600 and 2.5 < want < 3.0

    assert rooms["Living Room (B102)"].assessed("sunlight").hours[0] == 0.0
    assert rooms["Hallway (A201)"].assessed("sunlight").hours[0] == 0.0
    assert np.degrees(np.arcsin(sun[:, 2])).max() < np.degrees(np.arctan2(0.63, 0.57))


def test_point_p_on_the_host_walls_room_side_face(runs, duplex_raw):
    """Every wall window of the Duplex: P lies on the room-side face of the wall it is set in
    (ifcopenshell's geometry of that wall), whatever stands in the room (a stair rail overlaps a
    bedroom window's jamb by 5 cm); the reveal is the glass-to-face distance, under 0.42 m."""
    f, window, _, _ = duplex_raw
    r = runs["Duplex_A_20110907.ifc"]
    checked = 0
    for x in r.rooms:
        res = x.assessed("sunlight")
        for k, w in enumerate(x.room.windows):
            if abs(w.normal[2]) > 0.5 or not np.isfinite(res.points_local[k]).all():
                continue  # roof lights; windows whose A.3 height lies above their head
            glass, wall = window(w.name.rsplit(":", 1)[-1])
            axis = int(np.argmax(np.abs(w.normal)))
            wv = _shape(wall)[0][:, axis]
            face = wv.min() if w.normal[axis] > 0 else wv.max()  # the face away from the outside
            p = res.points_local[k] + r.scene.origin
            assert abs(p[axis] - face) < 1e-3, (x.room.name, w.name)
            assert 0.3 < res.reveal_depths_m[k] < 0.42
            checked += 1
    assert checked == 20  # 26 windows: 2 roof lights, and the 4 lowest of the stacks (their A.3 height lies above them)


def test_check_and_validate_as_a_user_runs_them(tmp_path):
    """The CLI on the Duplex: exit 1 (the view is not assessable without surroundings), never 2;
    validate lists every space (a room, or why not) and every window with its room."""
    p = project_file(tmp_path, DUPLEX, "America/Chicago", view=FAST_VIEW, sunlight=FEB1)
    v = CliRunner().invoke(cli, ["validate", str(p)], catch_exceptions=False)
    assert v.exit_code == 0, v.output
    import ifcopenshell

    f = ifcopenshell.open(str(DUPLEX))
    for s in f.by_type("IfcSpace"):
        assert f"'{s.LongName} ({s.Name})'" in v.output
    for w in f.by_type("IfcWindow"):
        assert f"window '{w.Name}':" in v.output
    assert "warning: view: every room NOT ASSESSABLE" in v.output
    out = tmp_path / "out"
    c = CliRunner().invoke(cli, ["check", str(p), "--out", str(out), "-q", "--no-plots"], catch_exceptions=False)
    assert c.exit_code == 1, c.output
    report = json.loads((out / "report.json").read_text())
    assert report["summary"]["spaces_with_windows_not_assessed"] == 0 and len(report["spaces_left_out"]) == 11
    assert {room["view"]["status"] for room in report["rooms"]} == {"not_assessable"}
