"""Regressions between two designs: ``en17037 compare BEFORE AFTER`` and ``check --baseline``.

Two report.json documents are matched room by room (by name) and criterion, and dwelling by
dwelling for the sunlight rule. A pair is **worse** when its level or its status went down
(levels none < minimum < medium < high, a level not reached below none; statuses NOT ASSESSED,
NOT ASSESSABLE < FAIL < PASS), **better** when one went up and neither down, **changed** when
only a figure (hours, share) or the level required changed, else **same**. A room or criterion only
in AFTER is **added**, one only in BEFORE **removed**. A regression is a pair that got worse, or
one added whose verdict fails the check (a new failure); a room removed is listed, not a
regression (a renamed room would otherwise fail every comparison). Reads files, traces no ray.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

from en17037cli.errors import InputError
from en17037cli.report.labels import STATUS_LABEL
from en17037cli.report.numbers import fmt_duration
from en17037cli.report.summary import room_rows

#: Order of levels; a level not reached (not assessed) ranks below none.
LEVEL_RANK = {None: -1, "none": 0, "minimum": 1, "medium": 2, "high": 3}
#: Order of statuses.
STATUS_RANK = {None: 3, "pass": 2, "fail": 1, "not_assessable": 0, "not_assessed": 0}
#: How the comparison names the criteria (and the dwellings' sunlight rule).
TITLES = {"view": "view out (5.2)", "sunlight": "sunlight (5.3)", "daylight": "daylight provision (5.1)",
          "glare": "protection from glare (5.4)",
          "dwelling": "sunlight rule of the dwelling"}
#: Changes, in the order tables list them.
CHANGES = ("worse", "added", "removed", "better", "changed", "same")


@dataclass
class Change:
    """One room and criterion (or one dwelling's sunlight rule) in both reports.

    name : the room (or dwelling); criterion : ``view``, ``sunlight`` or ``dwelling``
    change : worse, better, changed, same, added, removed; regression : it fails the comparison
    before, after : the row in each report (see :func:`entries`), None where absent
    what : what changed, e.g. ``["level medium → minimum", "status PASS → FAIL"]``
    """

    name: str
    criterion: str
    change: str
    regression: bool
    before: dict | None
    after: dict | None
    what: list[str] = field(default_factory=list)


@dataclass
class Comparison:
    before: str
    after: str
    before_status: str
    after_status: str
    changes: list[Change]

    @property
    def regressions(self) -> list[Change]:
        return [c for c in self.changes if c.regression]

    def count(self, change: str) -> int:
        return sum(c.change == change for c in self.changes)

    @property
    def exit_code(self) -> int:
        """1 when anything got worse (a regression), else 0."""
        return 1 if self.regressions else 0


def load_report(path: Path, which: str) -> dict:
    """A report.json document: ``path`` is the file or a report folder holding it; ``which`` names
    the argument in errors (``BEFORE``, ``--baseline``)."""
    path = Path(path)
    file = path / "report.json" if path.is_dir() else path
    try:
        text = file.read_text("utf-8")
    except FileNotFoundError:
        where = f"{path} holds no report.json" if path.is_dir() else f"{file} not found"
        raise InputError(f"{which} {path}: {where}; give a report.json or a report folder written by en17037 check") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{which} {file}: cannot read it ({getattr(exc, 'strerror', None) or exc}); give a report.json") from None
    try:
        doc = json.loads(text)
    except ValueError as exc:
        raise InputError(f"{which} {file}: not JSON ({exc}); give a report.json written by en17037 check") from None
    if not isinstance(doc, dict) or "schema_version" not in doc or not isinstance(doc.get("rooms"), list):
        raise InputError(f"{which} {file}: not an en17037 report (no schema_version and rooms); give a report.json "
                         "written by en17037 check")
    return doc


def entries(report: dict) -> dict[tuple[str, str], dict]:
    """(room, criterion) -> summary row (see :func:`~en17037cli.report.summary.room_rows`), and
    (dwelling, ``dwelling``) -> its sunlight rule (status, hours of the room that decides it)."""
    from en17037cli.dwellings import WHOLE_PROJECT

    out = {(r["room"], r["criterion"]): r for r in room_rows(report)}
    for d in report.get("dwellings", []):
        sun = d["sunlight"]
        if sun["status"] is not None:
            name = "(whole project)" if d["grouped_by"] == WHOLE_PROJECT else d["name"]
            out[(name, "dwelling")] = {"level": None, "required": sun["required"], "status": sun["status"],
                                            "verdict": sun["status"], "hours_h": sun.get("hours_h", sun.get("hours")), "share": None, "decided_by": sun["room"],
                                            "rooms": list(d["rooms"])}
    return out


def _fmt(value) -> str:
    return "-" if value is None else json.dumps(value) if isinstance(value, float) else str(value)


def _duration(hours) -> str:
    return "-" if hours is None else fmt_duration(hours)


def _status(s) -> str:
    return STATUS_LABEL.get(s, "-") if s else "-"


def classify(before: dict, after: dict) -> tuple[str, list[str]]:
    """(change, what changed) of one pair of rows."""
    what = []
    lb, la = LEVEL_RANK[before["level"]], LEVEL_RANK[after["level"]]
    sb, sa = STATUS_RANK[before["status"]], STATUS_RANK[after["status"]]
    if before["level"] != after["level"]:
        what.append(f"level {_fmt(before['level'])} → {_fmt(after['level'])}")
    if before["status"] != after["status"]:
        what.append(f"status {_status(before['status'])} → {_status(after['status'])}")
    if before["required"] != after["required"]:
        what.append(f"required {_fmt(before['required'])} → {_fmt(after['required'])}")
    b, a = before.get("hours_h"), after.get("hours_h")
    if b != a:  # durations for people: "3 h 20 min → 2 h (-1 h 20 min)"
        delta = ""
        if isinstance(a, float | int) and isinstance(b, float | int):
            delta = f" ({'+' if a >= b else '-'}{fmt_duration(abs(a - b))})"
        what.append(f"hours {_duration(b)} → {_duration(a)}{delta}")
    b, a = before.get("share"), after.get("share")
    if b != a:
        delta = f" ({round(a - b, 6):+g})" if isinstance(a, float | int) and isinstance(b, float | int) else ""
        what.append(f"share {_fmt(b)} → {_fmt(a)}{delta}")
    if before.get("decided_by") != after.get("decided_by"):
        what.append(f"decided by {_fmt(before.get('decided_by'))} → {_fmt(after.get('decided_by'))}")
    if la < lb or sa < sb:
        return "worse", what
    if la > lb or sa > sb:
        return "better", what
    return ("changed" if what else "same"), what


def compare_reports(before: dict, after: dict, before_label: str = "before", after_label: str = "after") -> Comparison:
    """Every room and criterion (and dwelling) of two reports, matched by name (see the module docstring)."""
    b, a = entries(before), entries(after)
    changes = []
    for key, row in a.items():
        if key in b:
            change, what = classify(b[key], row)
            changes.append(Change(key[0], key[1], change, change == "worse", b[key], row, what))
        else:
            what = [f"level {_fmt(row['level'])}, status {_status(row['status'])}"]
            changes.append(Change(key[0], key[1], "added", row["verdict"] != "pass", None, row, what))
    for key, row in b.items():
        if key not in a:
            changes.append(Change(key[0], key[1], "removed", False, row, None,
                                  [f"was level {_fmt(row['level'])}, status {_status(row['status'])}"]))
    return Comparison(before_label, after_label, before["status"], after["status"], changes)


def headline(c: Comparison) -> str:
    """One line: the statuses and the counts of each kind of change."""
    n = len(c.regressions)
    return (f"status {c.before_status.upper()} → {c.after_status.upper()}; {n} regression{'s' * (n != 1)}, "
            f"{c.count('better')} better, {c.count('changed')} changed, {c.count('same')} unchanged, "
            f"{c.count('added')} added, {c.count('removed')} removed")


def table_rows(c: Comparison, everything: bool = False) -> list[tuple[str, str, str, str, str, str]]:
    """(change, room, criterion, level, status, figures) for each pair that changed (or every pair),
    regressions first."""
    order = {k: i for i, k in enumerate(CHANGES)}
    rows = []
    for ch in sorted(c.changes, key=lambda ch: (not ch.regression, order[ch.change])):
        if ch.change == "same" and not everything:
            continue
        b, a = ch.before or {}, ch.after or {}
        both = ch.before and ch.after and (b.get("level") or a.get("level"))
        level = f"{_fmt(b.get('level'))} → {_fmt(a.get('level'))}" if both else _fmt((a or b).get("level"))
        status = (f"{_status(b.get('status'))} → {_status(a.get('status'))}" if ch.before and ch.after
                  else _status((a or b).get("status")))
        figures = "; ".join(w for w in ch.what if w.startswith(("hours", "share", "required", "decided")))
        label = ch.change + (" (regression)" if ch.regression and ch.change == "added" else "")
        rows.append((label, ch.name, TITLES[ch.criterion], level, status, figures))
    return rows


def _md(s: str) -> str:
    return s.replace("|", "\\|")


def comparison_markdown(c: Comparison, everything: bool = False) -> str:
    """A Markdown table of the changes, for a pull-request comment."""
    lines = [f"### EN 17037: `{_md(c.before)}` → `{_md(c.after)}`", "", headline(c) + ".", ""]
    rows = table_rows(c, everything)
    if not rows:
        return "\n".join(lines + ["No room's level, status, hours or share changed."]) + "\n"
    lines += ["| change | room | criterion | level | status | figures |", "|---|---|---|---|---|---|"]
    for label, *rest in rows:
        label = f"**{label}**" if label.startswith(("worse", "added (regression)")) else label
        lines.append("| " + " | ".join(_md(x) for x in (label, *rest)) + " |")
    return "\n".join(lines) + "\n"


def comparison_json(c: Comparison) -> str:
    """The comparison as JSON: statuses, counts and every pair with what changed."""
    doc = {"before": c.before, "after": c.after, "status": {"before": c.before_status, "after": c.after_status},
           "regressions": len(c.regressions), "counts": {k: c.count(k) for k in CHANGES},
           "changes": [{"name": ch.name, "criterion": ch.criterion, "change": ch.change, "regression": ch.regression,
                        "what": ch.what,
                        "before": None if ch.before is None else {k: ch.before.get(k) for k in ("level", "status", "hours_h", "share")},
                        "after": None if ch.after is None else {k: ch.after.get(k) for k in ("level", "status", "hours_h", "share")}}
                       for ch in c.changes]}
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def regressed_pairs(c: Comparison) -> dict[tuple[str, str], str]:
    """(room, criterion) -> what got worse, a dwelling's regression standing for the sunlight of
    each of its rooms: what JUnit marks failed under a baseline."""
    out: dict[tuple[str, str], str] = {}
    for ch in c.regressions:
        what = "; ".join(ch.what) if ch.change != "added" else "new, " + "; ".join(ch.what)
        if ch.criterion == "dwelling":
            for room in (ch.after or {}).get("rooms", []):
                out.setdefault((room, "sunlight"), f"dwelling '{ch.name}': {what}")
        else:
            out[(ch.name, ch.criterion)] = what
    return out
