"""The scenes whose reports are pinned byte for byte (timings aside) by ``tests/test_golden.py``.

A refactoring must leave every report of these scenes unchanged. A deliberate change of a report
is made by regenerating the pinned files (``python tests/golden/scenes.py``) in the same commit,
whose message says why the reports changed.
"""
from __future__ import annotations

import gzip
import json
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent

#: name -> sample project path (relative to the repository) or a box-room recipe
SAMPLES = {
    "seed-office": "sample_projects/seed-office/project.yaml",
    "synthetic-street": "sample_projects/synthetic-street/project.yaml",
    "seed-office-glare": "sample_projects/seed-office/project-glare.yaml",
}
#: Weather files the samples need that ``make samples`` writes (deterministic): sample -> (path, latitude, longitude)
SAMPLE_WEATHER = {"seed-office-glare": ("sample_projects/seed-office/weather/delft-synthetic.epw", 52.0116, 4.3571)}
#: box-room scenes of the tests: BoxRoom keyword arguments and box_room_project keyword arguments
BOXES = {
    "box-reveal-mullions": ({"wall_thickness": 0.3, "mullions": [-0.35, 0.35], "depth": 5.0},
                            {"sunlight": {"date": "worst"}, "view": {"grid_spacing_m": 1.0}}),
    "box-triangle-window": ({"triangle_window": True}, {"sunlight": {"date": "03-21"}, "view": {"grid_spacing_m": 1.0}}),
    "box-double-glazing-gap": ({"second_pane": 0.02, "gap": 0.02},
                               {"sunlight": {"date": "best"}, "view": {"grid_spacing_m": 1.5, "distance_method": "solid_angle"}}),
    "box-georeferenced-rotated": ({"wall_thickness": 0.2},
                                  {"offset": [85000.0, 446000.0, 3.0], "rotate_deg": 30.0,
                                   "sunlight": {"date": "worst", "timestep_min": 5},
                                   "view": {"grid_spacing_m": 1.0, "distance_statistic": "p25"}}),
}
REPORT_FILES = ("report.json", "view_points.csv", "sunlight_days.csv", "report.md")


def normalise(name: str, text: str) -> str:
    """Report text with the run-dependent parts removed: ``timings_s`` of report.json."""
    if name == "report.json":
        doc = json.loads(text)
        doc.pop("timings_s", None)
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
    return text


def project_path(name: str, work: Path) -> Path:
    """The project file of scene ``name``; box rooms are written into ``work``."""
    if name in SAMPLES:
        if name in SAMPLE_WEATHER and not (ROOT / SAMPLE_WEATHER[name][0]).is_file():
            from en17037cli.samples.weather import synthetic_epw

            path, lat, lon = SAMPLE_WEATHER[name]
            (ROOT / path).parent.mkdir(parents=True, exist_ok=True)
            synthetic_epw(ROOT / path, lat=lat, lon=lon)
        return ROOT / SAMPLES[name]
    from en17037cli.samples import BoxRoom, box_room_project

    box_kw, proj_kw = BOXES[name]
    box_kw = {k: tuple(v) if isinstance(v, list) else v for k, v in box_kw.items()}
    proj_kw = dict(proj_kw)
    if "offset" in proj_kw:
        proj_kw["offset"] = tuple(proj_kw["offset"])
    return box_room_project(work / name, BoxRoom(**box_kw), **proj_kw)


def run_reports(name: str, work: Path) -> dict[str, str]:
    """Run ``en17037 check`` on scene ``name``; return its normalised report files."""
    path = project_path(name, work)
    out = work / f"{name}-out"
    shutil.rmtree(out, ignore_errors=True)
    proc = subprocess.run([sys.executable, "-m", "en17037cli", "check", str(path), "--out", str(out), "-q"],
                          capture_output=True, text=True)
    assert proc.returncode in (0, 1), proc.stderr
    return {f: normalise(f, (out / f).read_text("utf-8")) for f in REPORT_FILES}


def pinned(name: str) -> dict[str, str]:
    """The pinned report files of scene ``name``."""
    with gzip.open(HERE / f"{name}.json.gz", "rt", encoding="utf-8") as fh:
        return json.load(fh)


def write_pinned(name: str, files: dict[str, str]) -> None:
    data = json.dumps(files, sort_keys=True, ensure_ascii=False).encode("utf-8")
    # mtime=0: the gzip file itself is deterministic
    with open(HERE / f"{name}.json.gz", "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0) as fh:
        fh.write(data)


if __name__ == "__main__":
    import tempfile

    names = sys.argv[1:] or [*SAMPLES, *BOXES]
    with tempfile.TemporaryDirectory() as tmp:
        for n in names:
            write_pinned(n, run_reports(n, Path(tmp)))
            print(f"pinned {n}")
