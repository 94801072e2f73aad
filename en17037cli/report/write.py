"""Writers of the report files, in a registry, and writing them all as one set (with the pictures)."""
from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from en17037cli.criteria.glare.report import glare_hours_csv, glare_points_csv
from en17037cli.report.folder import commit
from en17037cli.report.html import report_html
from en17037cli.report.json_text import dumps_indented
from en17037cli.report.markdown import report_markdown
from en17037cli.report.tables import daylight_points_csv, rooms_csv, sunlight_days_csv, view_points_csv


def report_json(report: dict, figures=()) -> str:
    """``report.json``: the document, indented, UTF-8, no NaN (``json.dumps(report, indent=2,
    ensure_ascii=False, allow_nan=False)``, written by :func:`~.json_text.dumps_indented`)."""
    return dumps_indented(report) + "\n"


#: file name -> writer (document, pictures -> text), in writing order; the pictures
#: (:class:`~en17037cli.report.figures.Figure`) are written beside them under ``figures/``
WRITERS: dict[str, Callable[..., str]] = {
    "report.json": report_json,
    "view_points.csv": lambda report, figures=(): view_points_csv(report),
    "sunlight_days.csv": lambda report, figures=(): sunlight_days_csv(report),
    "daylight_points.csv": lambda report, figures=(): daylight_points_csv(report),
    "glare_points.csv": lambda report, figures=(): glare_points_csv(report),
    "glare_hours.csv": lambda report, figures=(): glare_hours_csv(report),
    "rooms.csv": lambda report, figures=(): rooms_csv(report),
    "report.md": report_markdown,
    "report.html": report_html,
}
REPORT_FILES = tuple(WRITERS)


def write_reports(report: dict, out_dir: Path, project_file: Path, figures=()) -> list[Path]:
    """Write every report file of ``report`` and its pictures into ``out_dir`` as one set (see :mod:`.folder`)."""
    contents = {name: writer(report, figures).encode("utf-8") for name, writer in WRITERS.items()}
    contents |= {f.name: f.png for f in figures}
    return commit(Path(out_dir), Path(project_file), contents)
