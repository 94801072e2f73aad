"""Room kinds in the project file: the rules that name a room's kind (``room_kinds``) and what each
kind asks (``by_kind``, over the practice's values per kind, :data:`~en17037cli.practice.PRACTICES`).

The scene finds each room's kinds (``scene/kinds.py``); :func:`room_spec` then gives the room what
its kinds ask: a room of several uses takes the highest of them
(:func:`~en17037cli.practice.highest_of_uses`), and what the room's own ``rooms[]`` entry requires
wins. Per room kind, the project file's ``by_kind`` wins over the practice's values, which win over
the project-wide ``requirements`` and ``thresholds``.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from en17037cli.errors import InputError
from en17037cli.practice import PRACTICES, ROOM_KINDS, highest_of_uses
from en17037cli.project.settings import RoomSpec
from en17037cli.standard import THRESHOLDS, Thresholds

#: The checks a kind may require a level of (``requirements.<check>``).
CHECKS = ("view", "sunlight", "daylight", "glare")


@dataclass(frozen=True)
class KindRule:
    """One ``room_kinds`` rule: rooms whose name, or a text the model gives their space (LongName,
    ObjectType, classification...), matches the glob ``match`` (case-insensitive) are of ``kinds``."""

    match: str
    kinds: tuple[str, ...]
    index: int


@dataclass(frozen=True)
class KindValues:
    """What the rooms of one kind are asked.

    values : key path -> value for every requirement of :data:`CHECKS` and every threshold
        (``thresholds.<name>.<level>``): the kind's own where it (or the practice for it) sets one,
        the project's elsewhere
    set : key path -> where the kind's own values come from (``by_kind.kitchen``, ``practice
        gb-br209-2022, kitchen``)
    """

    values: dict[str, object]
    set: dict[str, str]


def kind_rules(config: dict) -> tuple[KindRule, ...]:
    """The ``room_kinds`` rules of a resolved document, in order (the first that matches decides)."""
    return tuple(KindRule(r["match"], (r["kind"],) if isinstance(r["kind"], str) else tuple(r["kind"]), i)
                 for i, r in enumerate(config.get("room_kinds", ())))


def flat(node: dict, prefix: str = "") -> dict[str, object]:
    """``{"thresholds": {"daylight_target_lx": {"minimum": 100}}}`` -> ``{"thresholds.daylight_target_lx.minimum": 100}``."""
    out: dict[str, object] = {}
    for k, v in node.items():
        out |= flat(v, f"{prefix}{k}.") if isinstance(v, dict) else {f"{prefix}{k}": v}
    return out


def _section(key: str) -> str:
    """The project section a key path of a kind's values belongs to (``requirements.daylight`` and
    ``thresholds.daylight_target_lx.minimum``: daylight)."""
    part = key.split(".")[1]
    return "daylight" if part.startswith("daylight") else part


def kind_values(path: Path, config: dict) -> dict[str, KindValues]:
    """Per room kind that sets anything, what its rooms are asked (:class:`KindValues`), from the
    practice's values per kind and the document's ``by_kind`` (which wins, key by key).

    A practice's requirement of a check the project does not run is left out (a practice never turns
    a check on); the document's own is an input error, as is a kind's threshold set that is not in
    order (minimum <= medium <= high).
    """
    practice = PRACTICES[config["practice"]]
    base = {f"requirements.{c}": config["requirements"].get(c, "none") for c in CHECKS}
    base |= flat({"thresholds": {k: config["thresholds"][k] for k in THRESHOLDS}})
    out = {}
    for kind in ROOM_KINDS:
        own: dict[str, tuple[object, str]] = {
            k: (v, f"practice {practice.name}, {kind}") for k, v in practice.kinds.get(kind, {}).items()
            if _section(k) in config}  # a practice never turns a check on, nor speaks of one that does not run
        for k, v in flat(config.get("by_kind", {}).get(kind, {})).items():
            if k.startswith("requirements.") and _section(k) not in config:
                raise InputError(f"{path}: by_kind.{kind}.{k}: the project has no '{_section(k)}' section; add it, "
                                 "or remove the requirement")
            own[k] = (v, f"by_kind.{kind}")
        if not own:
            continue
        values = base | {k: v for k, (v, _) in own.items()}
        for name in THRESHOLDS:
            t = [values[f"thresholds.{name}.{lv}"] for lv in ("minimum", "medium", "high")]
            if not t[0] <= t[1] <= t[2]:
                by = sorted({src for k, (_, src) in own.items() if k.startswith(f"thresholds.{name}.")})
                raise InputError(f"{path}: {by[0] if by else 'by_kind.' + kind}: thresholds.{name} of a {kind}: expected "
                                 f"minimum <= medium <= high, got {t}; give the kind's {name} in order under by_kind")
        out[kind] = KindValues(values, {k: src for k, (_, src) in own.items()})
    return out


def room_spec(spec: RoomSpec, kinds: tuple[str, ...], by_kind: dict[str, KindValues]) -> tuple[RoomSpec, tuple]:
    """``spec`` with what the room's ``kinds`` ask: per key, the highest of its uses that set
    anything (:func:`~en17037cli.practice.highest_of_uses`; a use that sets nothing adds nothing),
    the room entry's own requirements winning; and what they set, as (key path, value, from) for
    every key one of its uses sets (the report's and ``validate``'s list)."""
    uses = [k for k in kinds if k in by_kind]
    if not uses:
        return spec, ()
    best = highest_of_uses([by_kind[k].values for k in uses])
    requirements = replace(spec.requirements, **{c: str(best[f"requirements.{c}"][0]) for c in CHECKS
                                                 if c not in spec.own_requirements})
    thresholds = Thresholds.from_dict({name: {lv: best[f"thresholds.{name}.{lv}"][0] for lv in ("minimum", "medium", "high")}
                                       for name in THRESHOLDS})
    told = []
    for key in sorted({k for u in uses for k in by_kind[u].set}, key=lambda k: k.replace("minimum_target", "~")):  # targets first
        value, i = best[key]
        check = key.split(".")[1]
        if key.startswith("requirements.") and check in spec.own_requirements:
            told.append((key, getattr(spec.requirements, check), f"rooms[{spec.index}].requirements"))
            continue
        kind = uses[i]
        told.append((key, value, by_kind[kind].set.get(key, f"the project's value, which {kind} keeps")))
    return replace(spec, requirements=requirements, thresholds=thresholds), tuple(told)
