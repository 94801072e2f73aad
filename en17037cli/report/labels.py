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


#: Words of the warnings that report a repair of the geometry as read (dropped or partly
#: triangulated faces, a file read with repairs): facts for the technical section, not the summary.
REPAIR_WORDS = ("could not be fully triangulated", "faces dropped", "vertices dropped", "needed repairs to be read",
                "degenerate, NaN or infinite", "the file holds")


def is_repair(warning: str) -> bool:
    """Whether a warning reports a repair of the geometry as read (:data:`REPAIR_WORDS`)."""
    return any(w in warning for w in REPAIR_WORDS)
