"""National practices built on EN 17037: the project values each sets, for every room and per room
kind, each with where its source says so (beside :mod:`en17037cli.standard`, whose thresholds and
rules they adjust; a project file picks one with ``practice:``).
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from en17037cli.standard import level_index


@dataclass(frozen=True)
class Practice:
    """A national practice built on EN 17037: the project values it sets, and where it says so.

    values : key path -> value, for the whole project (``sunlight.date``, ``requirements.sunlight``)
    kinds : room kind (:data:`ROOM_KINDS`) -> key path -> value, for the rooms of that kind (key paths
        under ``requirements.`` and ``thresholds.daylight_*``); ``kinds_source``: where it says so
    """

    name: str
    source: str
    values: dict
    kinds: dict = field(default_factory=dict)
    kinds_source: str = ""


#: What a room is used for, as a practice or a project file sets requirements per use; the scene
#: finds each room's from the project's rules, the model and its names (``scene/kinds.py``).
ROOM_KINDS = ("bedroom", "living_room", "kitchen", "office", "other")

#: National practices, by the name a project file gives (``practice:``). Each sets project values
#: (``key.path: value``) that the project file itself does not give; a value it gives wins. Per room
#: kind, a practice's values win over the project-wide ones, and the project file's ``by_kind`` over
#: the practice's. Only practices whose source states the values plainly are here
#: (docs/project-file.md lists the others).
PRACTICES: dict[str, Practice] = {
    "en17037": Practice("en17037", "EN 17037:2018+A1:2021, clauses 5.2 and 5.3 and Annex A", {}),
    "gb-br209-2022": Practice(
        "gb-br209-2022",
        "BR 209:2022, Site layout planning for daylight and sunlight (BRE, 3rd edition), section 3.3, which carries "
        "the UK National Annex of BS EN 17037: at least one main habitable room of each dwelling, preferably the "
        "living room, should receive at least 1.5 h of sunlight on 21 March",
        {"sunlight.date": "03-21", "requirements.sunlight": "minimum", "requirements.sunlight_rooms": "any"},
        # the UK National Annex's target illuminance E_T per room kind, over standard.DAYLIGHT_SHARES
        # ["target"] of the reference plane for standard.DAYLIGHT_HOURS_FRACTION of the daylight hours,
        # stands for the minimum level; it asks no minimum target over 95 % of the plane (0 lx, which
        # every point reaches); medium and high stay those of EN 17037 Table A.1
        {kind: {"thresholds.daylight_target_lx.minimum": lx, "thresholds.daylight_minimum_target_lx.minimum": 0.0}
         for kind, lx in (("bedroom", 100.0), ("living_room", 150.0), ("kitchen", 200.0))},
        "BR 209:2022, Appendix C, which carries the UK National Annex of BS EN 17037 for daylight provision in "
        "dwellings: target illuminances of 100 lx in bedrooms, 150 lx in living rooms and 200 lx in kitchens, "
        "exceeded over at least half of the reference plane for at least half of the daylight hours; a room of "
        "several uses takes the highest of its uses' targets"),
}


def highest_of_uses(uses: Sequence[dict[str, object]]) -> dict[str, tuple[object, int]]:
    """What a room of several uses is asked, key by key: the highest of its uses' values (BR 209:2022,
    Appendix C, for the UK National Annex's targets: a room of several uses takes the highest; read the
    same way for requirements): the highest level of :data:`~en17037cli.standard.LEVELS` for a
    requirement, the largest value for a threshold (every threshold is met with ``>=``: a larger one
    asks more).

    Parameters
    ----------
    uses : per use, key path -> value (a level's name, or a threshold in its unit)

    Returns
    -------
    key path -> (value, index in ``uses`` of the first use that asks it)
    """
    def rank(value) -> float:
        return float(level_index(value) if isinstance(value, str) else value)

    out: dict[str, tuple[object, int]] = {}
    for i, use in enumerate(uses):
        for key, value in use.items():
            if key not in out or rank(value) > rank(out[key][0]):
                out[key] = (value, i)
    return out
