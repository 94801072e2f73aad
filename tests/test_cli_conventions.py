"""What a user sees first: help without error prefixes, results on stdout and diagnostics on
stderr, ``--json`` for scripts, hours in one human format, and a ``--set`` that changes nothing
saying why. The console script runs in a subprocess, as a shell would run it."""
from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from en17037cli.project.overrides import MOOT, moot_overrides
from en17037cli.samples import BoxRoom, box_room_project

QUICK = ["--set", "view.eye_heights_m=[1.2]", "--set", "view.angular_resolution_deg=3", "--set", "view.refine_levels=1",
         "--set", "sunlight.period.end=02-03", "--set", "sunlight.date=02-02"]


def en17037(*args, cwd=None) -> subprocess.CompletedProcess:
    """The command as a shell runs it: ``python -m en17037cli`` (the console script's entry point)."""
    return subprocess.run([sys.executable, "-m", "en17037cli", *map(str, args)], capture_output=True, text=True, cwd=cwd,
                          timeout=300)


@pytest.fixture(scope="module")
def box(tmp_path_factory) -> Path:
    return box_room_project(tmp_path_factory.mktemp("box"), BoxRoom(), sunlight={"date": "worst"},
                            view={"grid_spacing_m": 1.0})


@pytest.fixture(scope="module")
def checked(box, tmp_path_factory):
    """``check`` run once with stdout redirected, as ``en17037 check p.yaml > log.txt`` would."""
    out = tmp_path_factory.mktemp("out")
    return en17037("check", box, "--out", out, "--no-plots", *QUICK), out


@pytest.mark.parametrize("args", [(), ("--help",), ("-h",), ("check", "--help")])
def test_help_is_on_stdout_with_exit_0_and_no_error_prefix(args):
    proc = en17037(*args)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("Usage: en17037") and proc.stderr == ""
    assert "error" not in proc.stdout.lower().split("options:")[0]


@pytest.mark.parametrize("args, names", [(("schema",), "en17037 schema --help"), (("nonsense",), "en17037 --help"),
                                         (("check",), "en17037 check --help")])
def test_usage_errors_are_one_line_naming_the_help_to_read(args, names):
    proc = en17037(*args)
    assert proc.returncode == 2 and proc.stdout == ""
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and lines[0].endswith(f"(see {names})"), proc.stderr


def test_check_writes_the_verdict_to_stdout_and_diagnostics_to_stderr(checked):
    proc, out = checked
    assert proc.returncode in (0, 1), proc.stderr
    report = json.loads((out / "report.json").read_text())
    room = report["rooms"][0]
    verdict = {0: "PASS", 1: "FAIL"}[proc.returncode]
    assert f"status: {verdict}" in proc.stdout and room["name"] in proc.stdout
    assert "status:" not in proc.stderr and "│" not in proc.stderr  # no table on stderr


def test_hours_read_as_h_min_for_people_and_decimal_in_fields_named_h(checked):
    proc, out = checked
    report = json.loads((out / "report.json").read_text())
    hours = report["rooms"][0]["sunlight"]["hours_h"]
    h, m = divmod(round(hours * 60), 60)
    human = f"{h} h {m} min" if h and m else (f"{h} h" if h else f"{m} min")
    for text in (proc.stdout, (out / "report.md").read_text(), (out / "report.html").read_text()):
        assert human in text
        assert f"{hours:.4f}" not in text and not re.search(r"\d\.\d{3,} h\b", text)
    assert "hours" not in report["rooms"][0]["sunlight"]  # the decimal field says its unit
    header = (out / "sunlight_days.csv").read_text().splitlines()[0].split(",")
    assert "hours_h" in header and "hours" not in header


def test_json_flags_print_one_json_document_on_stdout(box, checked, tmp_path):
    proc = en17037("check", box, "--out", tmp_path / "r", "--no-plots", "--json", *QUICK)
    doc = json.loads(proc.stdout)
    assert doc == json.loads((tmp_path / "r" / "report.json").read_text())
    assert proc.returncode == (0 if doc["status"] == "pass" else 1)
    proc = en17037("validate", box, "--json")
    doc = json.loads(proc.stdout)
    assert proc.returncode == 0 and doc["valid"] is True and [r["name"] for r in doc["rooms"]] == ["box room"]
    _, before = checked
    proc = en17037("compare", before / "report.json", tmp_path / "r" / "report.json", "--json")
    assert proc.returncode in (0, 1) and isinstance(json.loads(proc.stdout), dict), proc.stderr


def test_a_set_that_changes_nothing_says_why(box, tmp_path):
    proc = en17037("check", box, "--out", tmp_path / "r", "--no-plots", "--only", "sunlight", *QUICK,
                   "--set", "sunlight.timestep_min=1")
    line = [x for x in proc.stderr.splitlines() if "timestep_min" in x]
    assert len(line) == 1 and "no effect" in line[0] and "sunlight.method is exact" in line[0], proc.stderr
    assert "--set sunlight.method=sampled" in line[0]
    warnings = json.loads((tmp_path / "r" / "report.json").read_text())["warnings"]
    assert any("sunlight.timestep_min=1: no effect" in w for w in warnings)
    proc = en17037("validate", box, *QUICK, "--set", "sunlight.timestep_min=1", "--set", "sunlight.method=sampled")
    assert proc.returncode == 0 and "no effect" not in proc.stderr


@pytest.mark.parametrize("key, other, moot_value, needed", [(k, o, v, n) for k, (o, v, n), _ in MOOT])
def test_every_moot_rule_warns_only_under_its_setting(key, other, moot_value, needed):
    section, leaf = other.split(".")
    config = {section: {leaf: moot_value}}
    assert len(moot_overrides(config, [f"{key}=1"])) == 1
    config[section][leaf] = needed
    assert moot_overrides(config, [f"{key}=1"]) == []
    assert moot_overrides(config, [f"{other}={needed}"]) == []


def test_weather_is_moot_only_when_the_median_is_given():
    config = {"daylight": {"method": "daylight_factor", "median_diffuse_lx": 13300}}
    assert "median_diffuse_lx is given" in moot_overrides(config, ["daylight.weather=x.epw"])[0]
    del config["daylight"]["median_diffuse_lx"]
    assert moot_overrides(config, ["daylight.weather=x.epw"]) == []
