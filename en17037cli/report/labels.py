"""How reports name statuses, and which criterion sections of report.json hold results."""
from __future__ import annotations

#: report.json status -> how people read it
STATUS_LABEL = {"pass": "PASS", "fail": "FAIL", "not_assessed": "NOT ASSESSED", "not_assessable": "NOT ASSESSABLE"}


def assessed(section: dict | None) -> dict | None:
    """A room's criterion section when it holds results (the criterion assessed the room), else None."""
    return section if section and section["status"] in ("pass", "fail") else None


def unassessed(section: dict | None) -> dict | None:
    """A room's criterion section when the criterion did not assess a room that requires it, else None."""
    return section if section and section["status"] not in ("pass", "fail") else None
