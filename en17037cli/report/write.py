"""Writers of the report files, in a registry, and writing them all as one set."""
from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from en17037cli.report.folder import commit
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


def write_reports(report: dict, out_dir: Path, project_file: Path) -> list[Path]:
    """Write every report file of ``report`` into ``out_dir`` as one set (see :mod:`.folder`)."""
    contents = {name: writer(report).encode("utf-8") for name, writer in WRITERS.items()}
    return commit(Path(out_dir), Path(project_file), contents)
