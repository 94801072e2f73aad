"""``check --ifc-out``: the input IFC with the results in ``EN17037_Results`` on every room's IfcSpace
and window (issue 43), read back with ifcopenshell.

Each space's properties are compared with report.json's figures for its room (found by the space's
GlobalId, which the test reads from the file by Name); every entity of the input keeps its id,
class and attributes in the output; the same inputs give the same bytes; in IFC2X3, where an owner
history is mandatory, the new sets take their element's and no other is added.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli

pytest.importorskip("ifcopenshell")
import ifcopenshell  # noqa: E402
import ifcopenshell.geom  # noqa: E402
import ifcopenshell.util.element as ue  # noqa: E402

from en17037cli.samples.ifc import house  # noqa: E402

VIEW = {"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 3.0, "refine_levels": 0,
        "surroundings_min_share": 0}
SUN = {"date": "02-01", "period": {"start": "02-01", "end": "02-01"}}
PREFIX = {"daylight": "Daylight", "view": "View", "sunlight": "Sunlight", "glare": "Glare"}


def check(project: Path, out: Path, *args) -> dict:
    r = CliRunner().invoke(cli, ["check", str(project), "--out", str(out), "-q", "--no-plots", *map(str, args)])
    assert r.exit_code in (0, 1), r.output
    return json.loads((out / "report.json").read_text("utf-8"))


def project(tmp: Path, model: str, **extra) -> Path:
    doc = {"version": 1, "name": "house", "model": {"files": [{"path": model, "transform": {"rotate_deg": -20.0,
                                                                                            "translate_m": [5.0, 7.0, 0.0]}}]},
           "location": {"timezone": "Europe/Amsterdam"}, "rooms": [{"ifc_spaces": "*"}], "view": VIEW, "sunlight": SUN,
           "requirements": {"view": "medium", "sunlight": "medium"}, **extra}
    p = tmp / "project.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return p


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("ifcout")
    ifc = house(tmp / "house.ifc", map_conversion=True)
    p = project(tmp, "house.ifc", report={"ifc": "results.ifc"})
    report = check(p, tmp / "a")
    check(p, tmp / "b", "--ifc-out", tmp / "again.ifc")
    return {"ifc": ifc, "out": tmp / "results.ifc", "again": tmp / "again.ifc", "report": report}


def entity_values(e) -> tuple:
    def norm(v):
        if isinstance(v, ifcopenshell.entity_instance):
            return ("#", v.id()) if v.id() else (v.is_a(), v.wrappedValue)
        if isinstance(v, (tuple, list)):
            return tuple(norm(x) for x in v)
        return v
    return (e.is_a(), *(norm(x) for x in e))


def test_every_space_carries_its_rooms_results(run):
    f = ifcopenshell.open(str(run["out"]))
    original = ifcopenshell.open(str(run["ifc"]))
    rooms = {s.GlobalId: None for s in original.by_type("IfcSpace")}
    by_space = {}
    for room in run["report"]["rooms"]:
        [gid] = room["source"]["ids"]
        assert gid in rooms
        by_space[gid] = room
    assert len(by_space) == 4
    for space in f.by_type("IfcSpace"):
        pset = ue.get_psets(space).get("EN17037_Results")
        room = by_space[space.GlobalId]
        assert pset["Room"] == room["name"] and pset["Status"] == room["status"]
        for c, prefix in PREFIX.items():
            sec = room.get(c)
            if not sec:
                assert f"{prefix}Status" not in pset
                continue
            assert pset[f"{prefix}Status"] == sec["status"] and pset[f"{prefix}Pass"] is (sec["status"] == "pass")
            assert pset[f"{prefix}LevelRequired"] == sec["required"]
            assert pset[f"{prefix}LevelReached"] == (sec["level"] or "")
        sun = room["sunlight"]
        assert (pset["SunlightValue"], pset["SunlightUnit"], pset["SunlightError"]) == \
               (sun["hours_h"], "h", sun["error_estimates"]["hours_error_h"])
        view = room["view"]
        if view["status"] in ("pass", "fail"):
            lim = view["limiting"]
            [by] = [b for b in view["score"]["by_criterion"]
                    if b["criterion"] == lim["criterion"] and b["eye_height_m"] == lim["eye_height_m"]]
            assert (pset.get("ViewValue"), pset["ViewUnit"]) == (by["quantity"], by["unit"])


def window_box(f, w) -> tuple[np.ndarray, np.ndarray]:
    s = ifcopenshell.geom.settings()
    s.set("use-world-coords", True)
    v = np.array(ifcopenshell.geom.create_shape(s, w).geometry.verts).reshape(-1, 3)
    return v.min(axis=0), v.max(axis=0)


def test_every_window_carries_point_p_and_its_hours(run):
    """P in the file's own coordinates (the scene's are mapped, turned and moved) lies at the window;
    its hours are the report's for that window."""
    f = ifcopenshell.open(str(run["out"]))
    hours = {}
    for room in run["report"]["rooms"]:
        for w, s in zip(room["windows"], room["sunlight"]["windows"]):
            for gid in w["source"]["ids"]:
                hours[gid] = (room["name"], s["hours_h"])
    assert len(hours) == 5
    for w in f.by_type("IfcWindow"):
        pset = ue.get_psets(w)["EN17037_Results"]
        assert (pset["Room"], pset["SunlightHours_h"]) == hours[w.GlobalId]
        p = np.array([pset["PointP_X_m"], pset["PointP_Y_m"], pset["PointP_Z_m"]])
        lo, hi = window_box(f, w)
        assert np.all(p >= lo - 0.3) and np.all(p <= hi + 0.3), (w.Name, p, lo, hi)


def test_every_other_entity_is_unchanged_and_the_bytes_repeat(run):
    a, b = ifcopenshell.open(str(run["ifc"])), ifcopenshell.open(str(run["out"]))
    for e in a:
        assert entity_values(b.by_id(e.id())) == entity_values(e)
    added = {e.is_a() for e in b if e.id() > max(x.id() for x in a)}
    assert added == {"IfcPropertySet", "IfcRelDefinesByProperties", "IfcPropertySingleValue"}
    assert run["out"].read_bytes() == run["again"].read_bytes()
    psets = [p for p in b.by_type("IfcPropertySet") if p.Name == "EN17037_Results"]
    assert len({p.GlobalId for p in psets}) == len(psets) == 9  # 4 spaces, 5 windows


def test_ifc2x3_sets_take_their_elements_owner_history(tmp_path):
    ifc = house(tmp_path / "house.ifc", schema="IFC2X3")
    check(project(tmp_path, "house.ifc"), tmp_path / "r", "--ifc-out", tmp_path / "out.ifc")
    a, b = ifcopenshell.open(str(ifc)), ifcopenshell.open(str(tmp_path / "out.ifc"))
    assert len(b.by_type("IfcOwnerHistory")) == len(a.by_type("IfcOwnerHistory"))
    for space in b.by_type("IfcSpace"):
        rel = next(r for r in space.IsDefinedBy if r.RelatingPropertyDefinition.Name == "EN17037_Results")
        assert rel.OwnerHistory == space.OwnerHistory == rel.RelatingPropertyDefinition.OwnerHistory


def test_a_second_run_on_the_output_edits_the_set(run, tmp_path):
    """The output checked again (its own results in it) keeps one EN17037_Results per element."""
    import shutil

    shutil.copy(run["out"], tmp_path / "house.ifc")
    check(project(tmp_path, "house.ifc"), tmp_path / "r", "--ifc-out", tmp_path / "twice.ifc")
    f = ifcopenshell.open(str(tmp_path / "twice.ifc"))
    for e in [*f.by_type("IfcSpace"), *f.by_type("IfcWindow")]:
        assert sum(r.RelatingPropertyDefinition.Name == "EN17037_Results" for r in e.IsDefinedBy) == 1


def test_a_project_without_ifc_is_a_one_line_error_before_any_work(tmp_path):
    from en17037cli.samples import BoxRoom, box_room_project

    p = box_room_project(tmp_path / "box", BoxRoom(), sunlight=SUN, view=None)
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / "r"), "--ifc-out", str(tmp_path / "x.ifc")])
    assert r.exit_code == 2 and "--ifc-out" in r.output and "no IFC model file" in r.output
    assert not (tmp_path / "r").exists() and not (tmp_path / "x.ifc").exists()


def test_one_output_per_ifc_file_that_holds_rooms_or_windows():
    """Only files holding a room's space or window get a copy; a window element of another file counts."""
    from en17037cli.bim.ifc_out import ifc_files_with_results

    def src(fmt, file, ids=("x",), elements=()):
        return {"format": fmt, "file": file, "ids": list(ids), "elements": list(elements)}

    report = {"rooms": [
        {"source": src("ifc", "a.ifc"), "windows": [{"source": src("ifc", "a.ifc", elements=[{"id": "y", "file": "c.ifc"}])}]},
        {"source": src("project", "p.yaml", ids=()), "windows": [{"source": src("ifc", "b.ifc")}, {"source": src("obj", "m.obj")}]}]}
    assert ifc_files_with_results(report) == ["a.ifc", "c.ifc", "b.ifc"]
