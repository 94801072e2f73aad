"""The criteria of EN 17037 this tool checks, in the order they run and are reported.

Each implements :class:`~en17037cli.criteria.base.Criterion`; adding one is one line here.
"""
from __future__ import annotations

from en17037cli.criteria.base import Context, Criterion, Unassessed
from en17037cli.criteria.daylight import DaylightCriterion
from en17037cli.criteria.glare import GlareCriterion
from en17037cli.criteria.sunlight import SunlightCriterion
from en17037cli.criteria.view import ViewCriterion

#: name -> criterion, in run and report order
CRITERIA: dict[str, Criterion] = {c.name: c for c in (ViewCriterion(), SunlightCriterion(), DaylightCriterion(),
                                                       GlareCriterion())}

__all__ = ["CRITERIA", "Context", "Criterion", "Unassessed"]
