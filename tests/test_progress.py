"""A long run says what it is about to do and shows the time left, on a terminal and in a CI log.

The estimate is rough by design (docs/performance.md); what is tested is that it is said before
the work, from the preflight's own counts, and that a log without a terminal sees the run move.
"""
from __future__ import annotations

from click.testing import CliRunner

from en17037cli import budget, pipeline, terminal
from en17037cli.cli import cli
from en17037cli.project import load_project
from en17037cli.samples import BoxRoom, box_room_project


def test_the_estimate_comes_before_the_work_from_the_preflights_counts(tmp_path, monkeypatch):
    p = box_room_project(tmp_path / "b", BoxRoom(), view={"grid_spacing_m": 1.0})
    said: list[str] = []
    monkeypatch.setattr(pipeline, "ANNOUNCE_S", 0.0)
    result = pipeline.run(load_project(p, []), notify=said.append)
    (line,) = said
    est = budget.estimate_seconds(result.project, result.scene, budget.Cost(points=0, cells=0))
    assert line.startswith("1 room, ") and "about" in line and "view ~" in line and "sunlight ~" in line
    assert est["sunlight"] == budget.SECONDS_PER_POINT_P * 1  # one window
    monkeypatch.setattr(pipeline, "ANNOUNCE_S", 1e9)  # a short run says nothing
    said.clear()
    pipeline.run(load_project(p, []), notify=said.append)
    assert said == []


def test_progress_lines_in_a_log_without_a_terminal(tmp_path, monkeypatch):
    """CliRunner's stderr is no terminal: the check writes plain progress lines (here every time:
    LINE_EVERY_S set to 0), each with the share done and the time left; --quiet writes none."""
    monkeypatch.setattr(terminal, "LINE_EVERY_S", 0.0)
    monkeypatch.setattr(pipeline, "ANNOUNCE_S", 0.0)
    p = box_room_project(tmp_path / "b", BoxRoom(), view={"grid_spacing_m": 1.0})
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / "o"), "--no-plots"], catch_exceptions=False)
    lines = [x for x in r.stderr.splitlines() if x.startswith(("view:", "sunlight:"))]
    assert lines and all("% (" in x and "left" in x for x in lines), r.stderr
    assert "note: 1 room, " in r.stderr
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / "q"), "--no-plots", "-q"], catch_exceptions=False)
    assert "left" not in r.stderr and "note:" not in r.stderr
