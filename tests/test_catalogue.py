"""A catalogue of bad and awkward inputs: each gives exit 2 and one line naming what to fix, the
same line from ``validate`` as from ``check`` (where no ray is needed), and leaves a foreign file
(``notes.txt``) in the report folder alone, with no report written.

Each case is (id, how to spoil the box-room project, the text the error line must hold). Spoilers
get the project path and may edit the YAML document (``doc``) or write files.
"""
from __future__ import annotations

import struct
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.report.write import REPORT_FILES
from en17037cli.samples import BoxRoom, box_room_project


def doc_edit(fn):
    def spoil(path: Path):
        d = yaml.safe_load(path.read_text())
        fn(d)
        path.write_text(yaml.safe_dump(d, sort_keys=False))
    return spoil


def text_edit(old: str, new: str):
    def spoil(path: Path):
        path.write_text(path.read_text().replace(old, new, 1))
    return spoil


def write_file(name: str, data: bytes | str, retarget: bool = True):
    """Write a model file ``name`` beside the project and make the project load it."""
    def spoil(path: Path):
        p = path.parent / name
        p.write_bytes(data.encode() if isinstance(data, str) else data)
        if retarget:
            d = yaml.safe_load(path.read_text())
            d["model"]["files"][0]["path"] = name
            path.write_text(yaml.safe_dump(d, sort_keys=False))
    return spoil


def obj_edit(fn):
    def spoil(path: Path):
        m = path.parent / "model.obj"
        m.write_text(fn(m.read_text()))
    return spoil


def whole_file(data: bytes):
    def spoil(path: Path):
        path.write_bytes(data)
    return spoil


def files0(d):
    return d["model"]["files"][0]


CASES = [
    # --- schema: keys, types, enums, ranges ---------------------------------------------------
    ("unknown-top-key", doc_edit(lambda d: d.update(colour="red")), "(top level): unknown key 'colour'"),
    ("missing-model", doc_edit(lambda d: d.pop("model")), "missing required key 'model'"),
    ("missing-rooms", doc_edit(lambda d: d.pop("rooms")), "missing required key 'rooms'"),
    ("empty-rooms", doc_edit(lambda d: d.update(rooms=[])), "rooms: expected at least 1 items, got 0"),
    ("version-2", doc_edit(lambda d: d.update(version=2)), "version: expected 1, got 2"),
    ("unknown-view-key", doc_edit(lambda d: d["view"].update(grid=1)), "view: unknown key 'grid'"),
    ("unknown-sun-key", doc_edit(lambda d: d["sunlight"].update(step=5)), "sunlight: unknown key 'step'"),
    ("unknown-room-key", doc_edit(lambda d: d["rooms"][0].update(area=20)), "rooms[0]: unknown key 'area'"),
    ("floor-z-string", doc_edit(lambda d: d["rooms"][0].update(floor_z="ground")), "rooms[0].floor_z: expected number"),
    ("room-without-name", doc_edit(lambda d: d["rooms"][0].pop("name")), "rooms[0]: a room needs 'name' and 'floor_z', or 'ifc_spaces'"),
    ("duplicate-room", doc_edit(lambda d: d["rooms"].append(dict(d["rooms"][0]))), "room name 'box room' is used twice"),
    ("layer-enum", doc_edit(lambda d: files0(d)["layers"][0].update(layer="walls")), "layers[0].layer: expected one of"),
    ("layer-and-layers", doc_edit(lambda d: files0(d).update(layer="interior")), "give 'layer' (one layer for the whole file) or 'layers' (rules by name), not both"),
    ("units-enum", doc_edit(lambda d: d["model"].update(units="yards")), "model.units: expected one of m, cm, mm, ft, in"),
    ("up-axis-enum", doc_edit(lambda d: d["model"].update(up_axis="x")), "model.up_axis: expected one of z, y"),
    ("latitude-range", doc_edit(lambda d: d["location"].update(latitude=95)), "location.latitude: expected a value <= 90"),
    ("longitude-range", doc_edit(lambda d: d["location"].update(longitude=-200)), "location.longitude: expected a value >= -180"),
    ("negative-spacing", doc_edit(lambda d: d["view"].update(grid_spacing_m=-1)), "view.grid_spacing_m: expected a value > 0"),
    ("area-fraction-2", doc_edit(lambda d: d["view"].update(area_fraction=2)), "view.area_fraction: expected a value <= 1"),
    ("refine-levels-9", doc_edit(lambda d: d["view"].update(refine_levels=9)), "view.refine_levels: expected a value <= 8"),
    ("refine-levels-float", doc_edit(lambda d: d["view"].update(refine_levels=1.5)), "view.refine_levels: expected integer"),
    ("distance-method", doc_edit(lambda d: d["view"].update(distance_method="diagonal")), "view.distance_method: expected one of"),
    ("distance-statistic", doc_edit(lambda d: d["view"].update(distance_statistic="p101")), "view.distance_statistic"),
    ("eye-heights-empty", doc_edit(lambda d: d["view"].update(eye_heights_m=[])), "view.eye_heights_m: expected at least 1"),
    ("timestep-zero", doc_edit(lambda d: d["sunlight"].update(timestep_min=0)), "sunlight.timestep_min: expected a value >= 0.0166"),
    ("date-format", doc_edit(lambda d: d["sunlight"].update(date="21 March")), "sunlight.date: expected a date MM-DD, 'worst' or 'best'"),
    ("date-feb-30", doc_edit(lambda d: d["sunlight"].update(date="02-30")), "sunlight.date: not a date in 2026"),
    ("date-outside-period", doc_edit(lambda d: d["sunlight"].update(date="04-01")), "sunlight.date: 04-01 is outside the period"),
    ("period-reversed", doc_edit(lambda d: d["sunlight"].update(period={"start": "03-21", "end": "02-01"})),
     "sunlight.period: end 02-01 is before start 03-21"),
    ("year-1900", doc_edit(lambda d: d["sunlight"].update(year=1900)), "sunlight.year: expected a value >= 1950"),
    ("min-altitude-91", doc_edit(lambda d: d["sunlight"].update(min_altitude_deg=91)), "sunlight.min_altitude_deg: expected a value <= 90"),
    ("sunlight-without-location", doc_edit(lambda d: d.pop("location")), "location: required for the sunlight check"),
    ("unknown-timezone", doc_edit(lambda d: d["location"].update(timezone="Europe/Atlantis")), "unknown IANA time zone 'Europe/Atlantis'"),
    ("timezone-path", doc_edit(lambda d: d["location"].update(timezone="../../etc/passwd")), "unknown IANA time zone"),
    ("requirement-enum", doc_edit(lambda d: d["requirements"].update(view="excellent")), "requirements.view: expected one of"),
    ("thresholds-order", doc_edit(lambda d: d.update(thresholds={"sunlight_hours": {"minimum": 3, "medium": 2, "high": 4}})),
     "thresholds.sunlight_hours: expected minimum <= medium <= high"),
    ("floor-two-points", doc_edit(lambda d: d["rooms"][0].update(floor=[[0, 0], [1, 1]])), "rooms[0].floor: expected at least 3 items"),
    ("floor-bow-tie", doc_edit(lambda d: d["rooms"][0].update(floor=[[-2, 0], [2, 6], [2, 0], [-2, 6]])),
     "rooms[0] 'box room'.floor: not a simple polygon with area"),
    ("view-points-2d", doc_edit(lambda d: d["rooms"][0].update(view_points=[[0, 1]])), "rooms[0].view_points"),
    ("view-points-missing-csv", doc_edit(lambda d: d["rooms"][0].update(view_points="grid.csv")), "cannot read"),
    ("sun-points-count", doc_edit(lambda d: d["rooms"][0].update(sun_points=[[0, 1, 1.2], [0, 2, 1.2]])),
     "sun_points has 2 points for 1 windows ('glazing')"),
    ("windows-glob-none", doc_edit(lambda d: d["rooms"][0].update(windows=["skylight*"])), "no window matches ['skylight*']"),
    ("window-margin-negative", doc_edit(lambda d: d["rooms"][0].update(window_margin_m=-1)), "window_margin_m: expected a value >= 0"),
    # --- numbers ----------------------------------------------------------------------------
    ("nan-floor-z", text_edit("floor_z: 0.0", "floor_z: .nan"), "rooms[0].floor_z: not a finite number"),
    ("inf-latitude", text_edit("latitude: 52.0", "latitude: .inf"), "location.latitude: not a finite number"),
    ("overflow-threshold", doc_edit(lambda d: d["view"].update(layer_threshold_sr=1e400)), "view.layer_threshold_sr: not a finite number"),
    ("nan-in-list", doc_edit(lambda d: d["view"].update(eye_heights_m=[1.2, float("nan")])), "view.eye_heights_m[1]: not a finite number"),
    ("grid-budget", doc_edit(lambda d: d["view"].update(grid_spacing_m=1e-4)), "viewpoints and"),
    ("floor-in-mm", doc_edit(lambda d: d["rooms"][0].update(floor=[[-2000, 0], [2000, 0], [2000, 6000], [-2000, 6000]])),
     "check the floor's units"),
    ("sun-sample-budget", doc_edit(lambda d: d["sunlight"].update(method="sampled", timestep_min=0.0167, period={"start": "01-01", "end": "12-31"})),
     "sun samples a room"),
    # --- project files ----------------------------------------------------------------------
    ("empty-file", whole_file(b""), "expected a mapping of keys"),
    ("yaml-list", whole_file(b"- 1\n- 2\n"), "expected a mapping of keys"),
    ("not-yaml", whole_file(b"version: [1\nname: x\n"), "not valid YAML"),
    ("binary-file", whole_file(bytes(range(256)) * 4), "not UTF-8 text"),
    ("latin1", whole_file("version: 1\nname: Caf\u00e9\n".encode("latin-1")), "not UTF-8 text"),
    ("tab-indent", whole_file(b"version: 1\nmodel:\n\tfiles: []\n"), "not valid YAML"),
    # --- model files ------------------------------------------------------------------------
    ("model-missing", doc_edit(lambda d: files0(d).update(path="nope.obj")), "model.files[0].path: file not found"),
    ("model-is-folder", doc_edit(lambda d: files0(d).update(path=".")), "model.files[0].path: file not found"),
    ("model-format", write_file("model.dwg", b"AC1027"), "unsupported model format '.dwg'"),
    ("obj-corrupt-vertex", obj_edit(lambda t: "v 1 2\n" + t), "corrupt OBJ vertex line"),
    ("obj-corrupt-face", obj_edit(lambda t: t + "f a b c\n"), "corrupt OBJ face line"),
    ("obj-index-out-of-range", obj_edit(lambda t: t + "f 1 2 99999\n"), "face refers to a vertex that does not exist"),
    ("obj-empty", write_file("empty.obj", "# nothing\n"), "no faces found"),
    ("obj-no-glazing", obj_edit(lambda t: t.replace("o glazing", "o glass")), "matches no layer rule"),
    ("no-window-layer", doc_edit(lambda d: [r.update(layer="interior") for r in files0(d)["layers"] if r["match"] == "glazing"]),
     "no face is on the 'window' layer: no glazing was found"),
    ("all-ignored", doc_edit(lambda d: files0(d).update(layers=[{"match": "*", "layer": "ignore"}])),
     "no geometry loaded (every file is 'ignore')"),
    ("stl-cut-short", write_file("cut.stl", b"\0" * 80 + struct.pack("<I", 12) + b"\0" * 593), "binary STL header says 12 triangles"),
    ("stl-tiny", write_file("tiny.stl", b"\0" * 20), "not an STL file"),
    ("ply-garbage", write_file("bad.ply", b"ply\nformat nonsense\n"), "cannot read model file"),
    ("glb-garbage", write_file("bad.glb", b"glTF\x02\x00\x00\x00garbage"), "cannot read model file"),
    ("glazing-on-uncut-wall", obj_edit(lambda t: t + "o room\nv -1 0 0.8\nv 1 0 0.8\nv 1 0 2.2\nv -1 0 2.2\nf -4 -3 -2 -1\n"),
     "lies on 'model: room', an opaque face within 1 mm of the glazing"),
]


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_bad_input_gives_one_line_and_exit_2(tmp_path, case):
    _, spoil, expected = case
    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight={"date": "worst"}, view={"grid_spacing_m": 1.0})
    spoil(path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("a user's own file")
    lines = {}
    for cmd in ("check", "validate"):
        args = [cmd, str(path)] + (["--out", str(out)] if cmd == "check" else [])
        r = CliRunner().invoke(cli, args, catch_exceptions=False)
        assert r.exit_code == 2, f"{cmd}: {r.output}"
        got = r.output.strip().splitlines()
        assert len(got) >= 1 and all(g.startswith("error: ") for g in got), r.output
        assert any(expected in g for g in got), f"{cmd}: {r.output}"
        lines[cmd] = got
    assert lines["check"] == lines["validate"]  # validate says what check says, in the same words
    assert (out / "notes.txt").read_text() == "a user's own file"
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]  # no report, no manifest, no temporary folder
    assert not any((out / n).exists() for n in REPORT_FILES)


def test_the_catalogue_holds_at_least_sixty_cases():
    assert len(CASES) >= 60
