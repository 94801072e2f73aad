"""The flat view of runs: one row per room and criterion, for ``summary.csv`` / ``summary.json``,
JUnit, the terminal and ``compare``. Made from report.json documents; traces no ray.

A row's ``status`` is the room's own (as in report.json). Its ``verdict`` is the part it plays in
the exit code: the status for view; for sunlight, ``pass`` where the room's dwelling meets the
sunlight rule (EN 17037 clause 5.3 asks it of a dwelling, not of each room) or where the rule does
not ask the room (not a main room), else the room's status. A run fails (exit 1) exactly when one
of its rows' verdicts is not ``pass``.
"""
from __future__ import annotations

import csv
import io
import json
from dataclasses import dataclass, field

from en17037cli.version import __version__

#: Columns of ``summary.csv`` and the keys of each row of ``summary.json``, in order.
COLUMNS = ("project", "variant", "room", "criterion", "level", "required", "status", "verdict", "dwelling",
           "dwelling_status", "hours_h", "assessed_date", "share", "hours_error_h", "max_solid_angle_error_sr",
           "max_horizontal_sight_angle_error_deg", "max_outside_distance_error_m", "time_s", "exit_code", "message",
           "report")
#: Columns that hold wall times: the only ones that differ between runs of the same inputs.
TIME_COLUMNS = ("time_s",)
#: Criteria of a room, in report order.
CRITERIA = ("view", "sunlight", "daylight", "glare")
#: Status of a row that stands for a run that did not finish (bad input, internal error).
ERROR = "error"
#: The summary file's format, in ``summary.json``.
SUMMARY_VERSION = "1.0"


@dataclass
class RunRecord:
    """One run (a project, or a project with a variant's overrides) as the summary, JUnit, the
    terminal and GitHub annotations see it.

    project : the project file as given; variant : its name, "" for none
    report_dir : the run's report folder ("" where none was written)
    exit_code : 0 met, 1 missed, 2 bad input, 3 internal error; message : why, for 2 and 3
    rows : :func:`room_rows` of its report
    regressions : with a baseline, (room, criterion) -> what got worse; None without one
    """

    project: str
    variant: str = ""
    report_dir: str = ""
    exit_code: int = 0
    message: str = ""
    rows: list[dict] = field(default_factory=list)
    status: str | None = None
    counts: dict | None = None
    warnings: list[str] = field(default_factory=list)
    time_s: float = 0.0
    regressions: dict[tuple[str, str], str] | None = None

    @property
    def label(self) -> str:
        """How the run is named on the terminal and in JUnit: ``project`` or ``project [variant]``."""
        return f"{self.project} [{self.variant}]" if self.variant else self.project


def _dwellings(report: dict) -> dict[str, tuple[str, str | None, bool]]:
    """room name -> (dwelling name, "" for the whole project, its sunlight status, whether the rule
    asks the room)."""
    from en17037cli.dwellings import WHOLE_PROJECT

    out = {}
    for d in report.get("dwellings", []):
        sun = d["sunlight"]
        judged = set(d["main_rooms"]) if sun["rule"] == "any" else set(d["rooms"])
        name = "" if d["grouped_by"] == WHOLE_PROJECT else d["name"]
        for room in d["rooms"]:
            out[room] = (name, sun["status"], room in judged)
    return out


def view_share(section: dict) -> float | None:
    """The smallest share, over the eye heights, of a room's viewpoints reaching its required level
    (the level reached where none is required): the figure compared with ``view.area_fraction``."""
    level = section["required"] if section["required"] != "none" else section["level"]
    shares = [e["share_by_level"]["view"][level] for e in section.get("eye_heights", [])]
    return min(shares) if shares else None


def daylight_share(section: dict) -> float | None:
    """The share of the reference plane that limits a room's daylight level (the ``limiting`` value
    of report.json: the share reaching the target or minimum target illuminance of the level
    measured to), compared with 50 % or 95 % (clause 5.1, Table A.1)."""
    lim = section.get("limiting") or {}
    return lim.get("value")


def room_rows(report: dict, times: dict[str, dict[str, float]] | None = None) -> list[dict]:
    """One row per room and criterion of a report.json document (criteria neither run nor
    required are left out), in report order; ``times``: room -> criterion -> wall time [s]."""
    dwellings = _dwellings(report)
    rows = []
    for room in report["rooms"]:
        for crit in CRITERIA:
            sec = room.get(crit)
            if sec is None:
                continue
            status = sec["status"]
            assessed = status in ("pass", "fail")
            dwelling, d_status, judged = dwellings.get(room["name"], ("", None, True)) if crit == "sunlight" else ("", None, True)
            verdict = status
            if crit == "sunlight" and (d_status == "pass" or not judged):
                verdict = "pass"
            err = sec.get("error_estimates") or {}
            t = (times or {}).get(room["name"], {}).get(crit)
            rows.append({
                "room": room["name"], "criterion": crit, "level": sec["level"], "required": sec["required"],
                "status": status, "verdict": verdict, "dwelling": dwelling, "dwelling_status": d_status,
                "hours_h": sec.get("hours_h", sec.get("hours")) if assessed else None, "assessed_date": sec.get("assessed_date") if assessed else None,
                "share": (view_share(sec) if crit == "view" else daylight_share(sec) if crit == "daylight" else None)
                if assessed else None,
                "hours_error_h": err.get("hours_error_h"),
                "max_solid_angle_error_sr": err.get("max_solid_angle_error_sr"),
                "max_horizontal_sight_angle_error_deg": err.get("max_horizontal_sight_angle_error_deg"),
                "max_outside_distance_error_m": err.get("max_outside_distance_error_m"),
                "time_s": None if t is None else round(t, 3),
                "message": "" if assessed else sec.get("reason", ""),
            })
    return rows


def record_rows(rec: RunRecord) -> list[dict]:
    """The rows of a run with its project, variant, exit code and folder, every column present; a
    run that did not finish, or has no room, is one row."""
    base = {"project": rec.project, "variant": rec.variant, "exit_code": rec.exit_code, "report": rec.report_dir}
    rows = rec.rows
    if not rows:
        status = ERROR if rec.exit_code >= 2 else rec.status
        rows = [{"room": "", "criterion": "", "status": status, "verdict": status, "message": rec.message}]
    return [{c: (base | r).get(c) for c in COLUMNS} for r in rows]


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return json.dumps(value)  # shortest repr that reads back the same
    return str(value)


def summary_csv(records: list[RunRecord]) -> str:
    """``summary.csv``: :data:`COLUMNS`, one row per room and criterion of every run."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(COLUMNS)
    for rec in records:
        for row in record_rows(rec):
            w.writerow([_cell(row[c]) for c in COLUMNS])
    return buf.getvalue()


def worst_exit_code(records: list[RunRecord]) -> int:
    """The worst exit code of the runs: 3 beats 2 beats 1 beats 0 (0 for no run)."""
    return max((r.exit_code for r in records), default=0)


def summary_json(records: list[RunRecord]) -> str:
    """``summary.json``: every run (exit code, message, counts, folder, time) and every row."""
    code = worst_exit_code(records)
    doc = {
        "tool": {"name": "en17037cli", "version": __version__},
        "summary_version": SUMMARY_VERSION,
        "exit_code": code,
        "runs": [{"project": r.project, "variant": r.variant, "report": r.report_dir, "exit_code": r.exit_code,
                  "status": ERROR if r.exit_code >= 2 else r.status, "message": r.message, "summary": r.counts,
                  "warnings": list(r.warnings), "time_s": round(r.time_s, 3)} for r in records],
        "rows": [row for r in records for row in record_rows(r)],
    }
    return json.dumps(doc, indent=2, ensure_ascii=False, allow_nan=False) + "\n"
