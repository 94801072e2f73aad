"""en17037 batch: runs, variants, the summary, exit codes, units of work, threads, and the same
summary on the local pool and on a Dask LocalCluster."""
from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli import batch as b
from en17037cli.cli import cli
from en17037cli.errors import InputError
from en17037cli.raytrace import RayEngine, available_cores, default_threads
from en17037cli.report.summary import COLUMNS, TIME_COLUMNS, summary_csv
from en17037cli.report.write import REPORT_FILES
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.samples.block import Block, block_project

#: Coarse settings: a box room checks in about 0.2 s. One eye height, a 1.5 m grid (6 points in the
#: 4 x 6 m room), 3 deg cells refined once, three days of sunlight.
VIEW = {"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 3, "refine_levels": 1}
SUN = {"period": {"start": "02-01", "end": "02-03"}, "date": "worst"}


def invoke(*args, **kw):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False, **kw)


@pytest.fixture
def box(tmp_path):
    return box_room_project(tmp_path / "box", BoxRoom(), view=VIEW, sunlight=SUN)


@pytest.fixture
def block(tmp_path):
    """Six rooms: three south rooms facing the street, three north rooms facing open ground."""
    return block_project(tmp_path / "block", Block(storeys=1, rooms_per_side=3), view=VIEW, sunlight=SUN)


def untimed_csv(text: str) -> list[list[str]]:
    keep = [i for i, c in enumerate(COLUMNS) if c not in TIME_COLUMNS]
    return [[row[i] for i in keep] for row in csv.reader(text.splitlines())]


def untimed_json(doc):
    """A summary or report document without its wall times."""
    if isinstance(doc, dict):
        return {k: untimed_json(v) for k, v in doc.items() if k not in ("time_s", "timings_s")}
    if isinstance(doc, list):
        return [untimed_json(v) for v in doc]
    return doc


# --- variants and runs --------------------------------------------------------------------------

def test_variants_file_gives_named_override_sets(tmp_path):
    f = tmp_path / "variants.yaml"
    f.write_text("- name: as-drawn\n- name: wide\n  set: {view.grid_spacing_m: 1.0, sunlight.date: '03-21', rooms.0.windows: [W1]}\n"
                 "- name: turned\n  set: ['model.true_north_deg=15']\n")
    v = b.load_variants(f)
    assert [x.name for x in v] == ["as-drawn", "wide", "turned"]
    assert v[0].overrides == ()
    # values are written as YAML flow and read back as they were: a date stays a string, a list a list
    assert v[1].overrides == ('view.grid_spacing_m=1.0', 'sunlight.date="03-21"', 'rooms.0.windows=["W1"]')
    assert v[2].overrides == ("model.true_north_deg=15",)


@pytest.mark.parametrize("text, message", [
    ("name: a\n", "expected a YAML list of variants"),
    ("- name: a\n- name: a\n", "[1]: name 'a' is used twice; give each variant its own name"),
    ("- name: 'a b'\n", "[0]: name 'a b': give each variant a name of letters, digits"),
    ("- name: a\n  sets: {x: 1}\n", "[0]: expected a mapping with 'name' and 'set' (and nothing else)"),
    ("- name: a\n  set: 3\n", "[0] 'a': set: expected a mapping key.path: value, or a list of 'key.path=value'"),
    ("- name: a\n  set: {x: [1\n", "not valid YAML"),
])
def test_bad_variants_file_is_one_line_exit_2(box, tmp_path, text, message):
    f = tmp_path / "variants.yaml"
    f.write_text(text)
    r = invoke("batch", box, "--variants", f, "--out", tmp_path / "out")
    assert r.exit_code == 2 and r.output.count("\n") == 1, r.output
    assert r.output.startswith(f"error: --variants {f}") and message in r.output
    assert not (tmp_path / "out").exists()  # nothing written before the work


def test_report_folders_per_run(tmp_path):
    a = box_room_project(tmp_path / "a", BoxRoom())
    c = box_room_project(tmp_path / "c" / "d", BoxRoom())
    specs = b.plan_runs([str(a), str(c)], [b.Variant("x"), b.Variant("y", ("view.grid_spacing_m=1",))], ("sunlight.date=worst",))
    assert [(s.folder, s.variant, s.overrides) for s in specs] == [
        ("a/x", "x", ("sunlight.date=worst",)), ("a/y", "y", ("sunlight.date=worst", "view.grid_spacing_m=1")),
        ("c/d/x", "x", ("sunlight.date=worst",)), ("c/d/y", "y", ("sunlight.date=worst", "view.grid_spacing_m=1"))]
    assert len({s.key for s in specs}) == 4 and len({s.batch for s in specs}) == 1
    assert [s.folder for s in b.plan_runs([str(a), str(tmp_path / "other.yaml")])] == ["project", "other"]
    with pytest.raises(InputError, match="given twice"):
        b.plan_runs([str(a), str(tmp_path / "a" / ".." / "a" / "project.yaml")])


# --- the command --------------------------------------------------------------------------------

def test_batch_runs_every_project_and_variant_and_records_failures(box, block, tmp_path):
    bad = tmp_path / "bad" / "project.yaml"  # not there
    variants = tmp_path / "variants.yaml"
    variants.write_text("- name: medium\n- name: minimum\n  set: {requirements.view: minimum}\n")
    out = tmp_path / "out"
    r = invoke("batch", box, block, bad, "--variants", variants, "--out", out, "--jobs", 2, "--junit", out / "junit.xml")
    # the bad project is bad input (2), which beats the failing runs (1)
    assert r.exit_code == 2, r.output
    assert "[6/6]" in r.output and "6 runs: 2 pass, 2 fail, 2 bad input, 0 internal error" in r.output
    assert f"error: {bad} [medium]: {bad}: project file not found" in r.output
    rows = list(csv.DictReader((out / "summary.csv").open()))
    assert tuple(rows[0]) == COLUMNS
    by = {(Path(x["project"]).parent.name, x["variant"], x["room"], x["criterion"]): x for x in rows}
    # the box room: a 25 m street keeps the outside distance at 'medium'; 3 of the 4 points of the
    # 1.5 m grid see sky, landscape and ground through the 2 m wide window: medium on 75 %, just the
    # area fraction, and all of them reach minimum
    v = by[("box", "medium", "box room", "view")]
    assert (v["level"], v["required"], v["status"], v["verdict"], v["share"], v["exit_code"]) == \
        ("medium", "medium", "pass", "pass", "0.75", "0")
    assert by[("box", "minimum", "box room", "view")]["share"] == "1.0"
    s = by[("box", "medium", "box room", "sunlight")]
    assert (s["level"], s["assessed_date"], s["hours_h"], s["status"]) == ("medium", "2026-02-01", "3.3366", "pass")  # exact method (sampled: 3.3365)
    assert float(s["hours_error_h"]) < 0.01 and float(v["max_solid_angle_error_sr"]) > 0 and float(v["time_s"]) > 0
    # the block's north rooms see nothing of the street and no sun: the run fails, its south rooms pass
    assert by[("block", "minimum", "1.N01", "sunlight")]["level"] == "none"
    assert by[("block", "minimum", "1.N01", "sunlight")]["verdict"] == "fail"
    assert by[("block", "minimum", "1.S01", "view")]["status"] == "pass"
    assert {x["exit_code"] for x in rows if x["project"] == str(block)} == {"1"}
    e = by[("bad", "minimum", "", "")]
    assert (e["status"], e["exit_code"], e["report"]) == ("error", "2", "")
    assert e["message"] == f"{bad}: project file not found"
    # one report folder per finished run, the same files check writes
    for folder in ("box/medium", "box/minimum", "block/medium", "block/minimum"):
        assert sorted(p.name for p in (out / folder).iterdir() if not p.name.startswith(".")) == sorted(REPORT_FILES)
    assert not (out / "bad").exists()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["exit_code"] == 2 and [x["exit_code"] for x in summary["runs"]] == [0, 0, 1, 1, 2, 2]
    assert summary["runs"][0]["summary"]["rooms_view_pass"] == 1 and len(summary["rows"]) == len(rows)
    assert (out / "junit.xml").read_text().count("<testcase ") == len(rows)


def test_a_batch_run_writes_what_check_writes(box, tmp_path):
    r = invoke("batch", box, "--out", tmp_path / "batch", "--jobs", 1, "-q")
    assert r.exit_code == 0 and r.output == ""
    c = invoke("check", box, "--out", tmp_path / "check", "-q", "--no-plots")  # batch draws no pictures
    assert c.exit_code == 0
    for name in REPORT_FILES:
        mine, theirs = (tmp_path / "batch" / "project" / name).read_bytes(), (tmp_path / "check" / name).read_bytes()
        if name == "report.json":
            mine, theirs = (untimed_json(json.loads(x)) for x in (mine, theirs))
        assert mine == theirs, name


def test_the_batch_folder_is_refused_when_it_is_a_report_folder(box, tmp_path):
    assert invoke("check", box, "--out", tmp_path / "r", "-q").exit_code == 0
    r = invoke("batch", box, "--out", tmp_path / "r")
    assert r.exit_code == 2 and r.output.count("\n") == 1
    assert f"error: --out {tmp_path / 'r'}: it is the report folder of {box}; choose another folder for the batch" in r.output


def test_a_run_whose_folder_is_foreign_fails_alone(box, tmp_path):
    out = tmp_path / "out"
    (out / "project").mkdir(parents=True)
    (out / "project" / "report.json").write_text("{}")  # a user's own file
    r = invoke("batch", box, "--out", out, "--jobs", 1, "-q")
    assert r.exit_code == 2
    row = next(csv.DictReader((out / "summary.csv").open()))
    assert row["status"] == "error" and "report.json there was written by someone else" in row["message"]
    assert (out / "project" / "report.json").read_text() == "{}"


# --- units of work and threads -------------------------------------------------------------------

def test_a_project_split_into_groups_of_rooms_gives_the_same_reports(block, tmp_path):
    """Six rooms in groups of two (three units of work and a join) against one unit: identical."""
    recs = {}
    for n in (2, 8):
        ex = b.make_executor(jobs=1)
        try:
            recs[n] = b.run_batch(b.plan_runs([str(block)], rooms_per_task=n), ex, tmp_path / f"out{n}")
        finally:
            ex.close()
    assert untimed_csv(summary_csv(recs[2])) == untimed_csv(summary_csv(recs[8]))
    one, split = (json.loads((tmp_path / f"out{n}" / "project" / "report.json").read_text()) for n in (8, 2))
    assert untimed_json(one) == untimed_json(split)
    assert split["rays_traced"] == one["rays_traced"] > 0
    assert set(split["timings_s"]) == {"load", "build", "view", "sunlight", "report", "total"}
    for name in ("report.md", "view_points.csv", "sunlight_days.csv"):
        assert (tmp_path / "out2" / "project" / name).read_bytes() == (tmp_path / "out8" / "project" / name).read_bytes()


def test_threads_are_the_cores_shared_by_the_jobs(monkeypatch):
    cores = available_cores()
    ex = b.make_executor(jobs=2)
    try:
        assert ex.submit(b.worker_threads).result() == max(1, cores // 2)
    finally:
        ex.close()
    monkeypatch.setenv("EN17037_THREADS", "3")
    assert default_threads() == 3
    with RayEngine(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)) as engine:
        assert engine.threads == 3
    monkeypatch.setenv("EN17037_THREADS", "many")
    with pytest.raises(InputError, match="EN17037_THREADS=many: not a positive whole number"):
        default_threads()


# --- Dask -----------------------------------------------------------------------------------------

def test_dask_local_cluster_gives_the_local_pools_summary(box, block, tmp_path):
    """Two workers (threads of this process, so that the test can count what they built); the block
    goes out in three groups of two rooms. The summary must be the local pool's, byte for byte
    apart from wall times, and each worker builds a run's scene and engine at most once."""
    pytest.importorskip("distributed")
    specs_args = ([str(box), str(block)],)
    ex = b.make_executor(jobs=2)
    try:
        local = b.run_batch(b.plan_runs(*specs_args, rooms_per_task=2), ex, tmp_path / "pool")
    finally:
        ex.close()
    b.BUILDS.clear()
    ex = b.make_executor(jobs=2, scheduler="local", processes=False)
    try:
        assert ex.workers == 2
        threads = [ex.client.submit(b.worker_threads, workers=[w], pure=False).result() for w in ex.client.scheduler_info()["workers"]]
        assert threads == [max(1, available_cores() // 2)] * 2
        on_dask = b.run_batch(b.plan_runs(*specs_args, rooms_per_task=2), ex, tmp_path / "dask")
    finally:
        ex.close()
    assert untimed_csv(summary_csv(on_dask)) == untimed_csv(summary_csv(local))
    assert [r.exit_code for r in on_dask] == [0, 1]
    assert max(b.BUILDS.values()) == 1  # no worker built a run twice
    assert len({key for _, key in b.BUILDS}) == 2
    for folder in ("box", "block"):
        pool, dask = (json.loads((tmp_path / w / folder / "report.json").read_text()) for w in ("pool", "dask"))
        assert untimed_json(pool) == untimed_json(dask)
        for name in ("report.md", "view_points.csv", "sunlight_days.csv"):
            assert (tmp_path / "pool" / folder / name).read_bytes() == (tmp_path / "dask" / folder / name).read_bytes()


def test_scheduler_that_is_not_there_is_bad_input(box, tmp_path, monkeypatch):
    pytest.importorskip("distributed")
    from en17037cli.scale import dask

    monkeypatch.setattr(dask, "CONNECT_TIMEOUT_S", 1)  # nothing listens on port 9 (discard): no need to wait long
    r = invoke("batch", box, "--out", tmp_path / "out", "--scheduler", "tcp://127.0.0.1:9")
    assert r.exit_code == 2 and r.output.startswith("error: --scheduler tcp://127.0.0.1:9: cannot reach a Dask scheduler")


def test_variants_of_one_project_on_the_cli(box, tmp_path):
    variants = tmp_path / "v.yaml"
    variants.write_text(yaml.safe_dump([{"name": "south"}, {"name": "east", "set": {"model.true_north_deg": 90}}]))
    r = invoke("batch", box, "--variants", variants, "--out", tmp_path / "out", "--jobs", 1, "-q")
    assert r.exit_code == 0
    rows = {(x["variant"], x["criterion"]): x for x in csv.DictReader((tmp_path / "out" / "summary.csv").open())}
    # turning north by 90 deg makes the window face east: less sun on the worst day than facing south
    assert float(rows[("east", "sunlight")]["hours_h"]) < float(rows[("south", "sunlight")]["hours_h"]) == 3.3366
