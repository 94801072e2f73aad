"""Dwellings: rooms grouped for the sunlight rule of EN 17037 clause 5.3.

The clause asks sunlight of at least one habitable room of a dwelling, so a building of forty
flats is judged flat by flat. Rooms group into dwellings by the project's ``dwellings:`` key: a
list of dwellings with globs on room names, one dwelling per IFC zone, or a named group of a
regular expression on room names; a room in no dwelling is a dwelling of its own. Without the
key the project is one dwelling (what ``requirements.sunlight_rooms: any`` always meant).
"""
from __future__ import annotations

import fnmatch
import re
from dataclasses import dataclass

from en17037cli.errors import InputError
from en17037cli.project.settings import DwellingsSpec
from en17037cli.scene.model import Room

#: Where the one dwelling of a project without ``dwellings:`` comes from (report.json ``grouped_by``).
WHOLE_PROJECT = "the whole project (no dwellings: key)"


@dataclass(frozen=True)
class Dwelling:
    """A dwelling: its rooms and the main rooms that may satisfy the sunlight rule (room names),
    and where the grouping came from."""

    name: str
    rooms: tuple[str, ...]
    main_rooms: tuple[str, ...]
    source: str


def _match(globs, names) -> list[str]:
    return [n for n in names if any(fnmatch.fnmatchcase(n, g) for g in globs)]


def _main(where: str, dwelling: str, rooms: list[str], globs) -> tuple[str, ...]:
    if globs is None:
        return tuple(rooms)
    main = _match(globs, rooms)
    if not main:
        raise InputError(f"{where}: main_rooms {list(globs)} match no room of dwelling '{dwelling}' "
                         f"(its rooms: {', '.join(rooms)})")
    return tuple(main)


def group_dwellings(spec: DwellingsSpec | None, rooms: list[Room], where: str) -> list[Dwelling]:
    """The dwellings of a project, in the order of their first room.

    Raises
    ------
    InputError
        A glob that matches no room, a dwelling without rooms, a room in two dwellings, main
        rooms that match none of a dwelling's rooms, a grouping that finds nothing.
    """
    names = [r.name for r in rooms]
    if spec is None:
        return [Dwelling("project", tuple(names), tuple(names), WHOLE_PROJECT)]
    groups: dict[str, tuple[list[str], object, str]] = {}
    if spec.listed:
        for i, d in enumerate(spec.listed):
            found = []
            for g in d.rooms:
                hit = _match([g], names)
                if not hit:
                    raise InputError(f"{where}: dwellings[{i}] '{d.name}'.rooms: '{g}' matches no room; rooms: {', '.join(names)}")
                found += [n for n in hit if n not in found]
            if d.name in groups:
                raise InputError(f"{where}: dwellings[{i}]: dwelling name '{d.name}' is used twice")
            groups[d.name] = (found, d.main_rooms, "listed")
    elif spec.ifc_zones is not None:
        for r in rooms:
            for z in r.zones:
                if fnmatch.fnmatchcase(z, spec.ifc_zones):
                    groups.setdefault(z, ([], spec.main_rooms, f"IfcZone '{z}'"))[0].append(r.name)
        if not groups:
            raise InputError(f"{where}: dwellings.ifc_zones: no room belongs to a zone matching '{spec.ifc_zones}'; "
                             "list the dwellings instead, or check the model's IfcZone names (validate lists them)")
    else:
        rx = re.compile(spec.by_pattern or "")
        for n in names:
            m = rx.search(n)
            if m and m.group("dwelling"):
                groups.setdefault(m.group("dwelling"), ([], spec.main_rooms, "pattern"))[0].append(n)
        if not groups:
            raise InputError(f"{where}: dwellings.by_pattern: '{spec.by_pattern}' finds a dwelling in no room name")
    owner: dict[str, str] = {}
    for name, (found, _, _) in groups.items():
        for n in found:
            if n in owner:
                raise InputError(f"{where}: dwellings: room '{n}' is in dwelling '{owner[n]}' and in '{name}'; "
                                 "a room belongs to one dwelling")
            owner[n] = name
    out = [Dwelling(name, tuple(found), _main(f"{where}: dwellings '{name}'", name, found, main), source)
           for name, (found, main, source) in groups.items()]
    out += [Dwelling(n, (n,), (n,), "a room in no dwelling") for n in names if n not in owner]
    order = {n: i for i, n in enumerate(names)}
    return sorted(out, key=lambda d: min(order[n] for n in d.rooms))
