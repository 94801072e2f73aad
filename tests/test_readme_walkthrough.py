"""The README's walkthrough, run as written: its project file, its commands in order, on the
model it tells a reader to copy (written here the way the sample script writes it), and the output
it shows. A README that drifts from the tool fails here."""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from en17037cli.samples import BoxRoom
from en17037cli.samples.box import box_room_polygons, write_obj

ROOT = Path(__file__).resolve().parents[1]


def walkthrough() -> str:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    m = re.search(r"<!-- walkthrough.*?-->(.*?)<!-- /walkthrough -->", text, re.S)
    assert m, "README.md: the walkthrough markers are gone"
    return m.group(1)


def blocks(section: str) -> list[tuple[str, str]]:
    """(language, body) of each fenced block, in order."""
    return re.findall(r"```(\w+)\n(.*?)```", section, re.S)


def shell(line: str, cwd: Path) -> subprocess.CompletedProcess:
    """One README command line, ``en17037`` run as ``python -m en17037cli`` (its console script)."""
    args = line.split("#")[0].split()
    assert args[0] == "en17037", line
    env = {**os.environ, "COLUMNS": "100"}
    return subprocess.run([sys.executable, "-m", "en17037cli", *args[1:]], cwd=cwd, capture_output=True, text=True,
                          env=env, timeout=600)


@pytest.fixture(scope="module")
def ran(tmp_path_factory):
    """Every block of the walkthrough in order: the YAML written to my-flat/project.yaml, each
    command run, and each ``text`` block paired with the output of the command before it."""
    cwd = tmp_path_factory.mktemp("walkthrough")
    (cwd / "my-flat").mkdir()
    write_obj(cwd / "my-flat" / "model.obj", box_room_polygons(BoxRoom()))  # sample_projects/synthetic-street/model.obj
    steps, last = [], None
    for lang, body in blocks(walkthrough()):
        if lang == "yaml":
            (cwd / "my-flat" / "project.yaml").write_text(body, encoding="utf-8")
        elif lang == "sh":
            for line in filter(str.strip, body.splitlines()):
                last = (line, shell(line, cwd))
                steps.append((*last, None))
        elif lang == "text":
            assert last is not None, "an output block before any command"
            steps[-1] = (*last, body)
    return cwd, steps


def test_the_model_to_copy_is_the_one_written_here(tmp_path):
    write_obj(tmp_path / "model.obj", box_room_polygons(BoxRoom()))
    assert (tmp_path / "model.obj").read_bytes() == (ROOT / "sample_projects" / "synthetic-street" / "model.obj").read_bytes()


def test_every_command_runs_with_the_exit_code_it_should(ran):
    _, steps = ran
    commands = [line.split("#")[0].split()[1] for line, _, _ in steps]
    assert commands == ["validate", "check", "check", "compare"]
    for line, proc, _ in steps:
        assert "error" not in proc.stderr.lower(), (line, proc.stderr)
        want = {"validate": (0,), "check": (1,), "compare": (0, 1)}[line.split()[1]]
        assert proc.returncode in want, (line, proc.returncode, proc.stdout, proc.stderr)


def test_the_output_shown_is_the_output_printed(ran):
    _, steps = ran
    shown = [(line, proc, text) for line, proc, text in steps if text is not None]
    assert len(shown) == 2
    for line, proc, text in shown:
        printed = [x.rstrip() for x in proc.stdout.splitlines()]
        for expected in filter(str.strip, text.splitlines()):
            assert expected.rstrip() in printed, (line, expected, proc.stdout)


def test_the_verdict_quoted_is_in_the_report(ran):
    cwd, _ = ran
    quote = re.search(r"`report.md`: \*(.*?)\*", walkthrough(), re.S).group(1)
    quote = " ".join(quote.split())
    for name in ("report.md", "report.html"):
        text = " ".join((cwd / "my-flat" / "en17037-report" / "project" / name).read_text(encoding="utf-8").split())
        assert quote in text, name
    assert (cwd / "my-flat" / "fine" / "report.json").is_file()
