"""Writers of the report files, in a registry, and writing them all atomically."""
from __future__ import annotations

import json
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

from en17037cli.report.markdown import report_markdown
from en17037cli.report.tables import sunlight_days_csv, view_points_csv


def report_json(report: dict) -> str:
    """``report.json``: the document, indented, UTF-8, no NaN."""
    return json.dumps(report, indent=2, ensure_ascii=False, allow_nan=False) + "\n"


#: file name -> writer (document -> text), in writing order
WRITERS: dict[str, Callable[[dict], str]] = {
    "report.json": report_json,
    "view_points.csv": view_points_csv,
    "sunlight_days.csv": sunlight_days_csv,
    "report.md": report_markdown,
}
REPORT_FILES = tuple(WRITERS)


def remove_reports(out_dir: Path) -> None:
    """Delete the report files of an earlier run in ``out_dir`` (only ours)."""
    for name in REPORT_FILES:
        try:
            (out_dir / name).unlink()
        except FileNotFoundError:
            pass


def write_reports(report: dict, out_dir: Path) -> list[Path]:
    """Write all report files atomically: into a temporary folder beside ``out_dir``, then moved."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    contents = {name: writer(report) for name, writer in WRITERS.items()}
    tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.", dir=out_dir.parent))
    try:
        for name, text in contents.items():
            with open(tmp / name, "w", encoding="utf-8", newline="") as fh:
                fh.write(text)
                fh.flush()
                os.fsync(fh.fileno())
        for name in contents:
            os.replace(tmp / name, out_dir / name)
    except BaseException:
        remove_reports(out_dir)
        raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return [out_dir / n for n in contents]
