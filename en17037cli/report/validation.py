"""What ``en17037 validate --json`` prints: the same findings as its text, as one JSON document."""
from __future__ import annotations

from en17037cli.report.numbers import json_number
from en17037cli.scene.site import compass_bearing, location_lines


def validation_document(project_file, project, scene, pf, cost, budget: int) -> dict:
    """The scene as ``check`` will see it: faces per layer, what each file's reader read, the site
    and north taken and where from, the estimated cost, each room's floor, ceiling and windows
    (with why each bounds it and the compass bearing each faces, clockwise from true north) and the
    criteria that cannot assess it, windows in no room, dwellings, warnings and notes.

    ``pf`` is the run's :class:`~en17037cli.preflight.Preflight`, ``cost`` its
    :class:`~en17037cli.budget.Cost` and ``budget`` the viewpoints it may have. Heights are in the
    model's frame [m]; areas [m²].
    """
    z0 = float(scene.origin[2])
    bounding = {w.name for room in scene.rooms for w in room.windows}
    rooms = []
    for room in scene.rooms:
        entry = {"name": room.name, "storey": room.storey or None, "problem": room.problem, "kind": kind_entry(room)}
        if not room.problem:
            entry.update({
                "floor_area_m2": json_number(room.floor.area, 3), "floor_z_m": json_number(room.floor_z + z0, 3),
                "floor_source": room.floor_source, "ceiling_z_m": json_number(room.ceiling_z + z0, 3),
                "ceiling_source": room.ceiling_source,
                "windows": [{"name": w.name, "area_m2": json_number(w.area_m2, 3),
                             "outward_normal": [json_number(c, 4) for c in w.normal],
                             "bearing_deg": bearing_number(compass_bearing(w.normal, scene.true_north_deg)),
                             "faces": len(w.face_ids),
                             "reason": room.window_reasons.get(w.name)} for w in room.windows]})
        entry["not_assessable"] = {crit: rooms_[room.name] for crit, rooms_ in pf.unassessable.items() if room.name in rooms_}
        rooms.append(entry)
    doc = {
        "project": str(project_file), "valid": True,
        "faces_per_layer": scene.layer_counts(),
        "read": [{"file": display, "summary": line} for display, line in getattr(scene, "read", [])],
        "site": location_lines(project, scene),
        "estimated_cost": {"viewpoints": int(cost.points), "sampling_cells": json_number(cost.cells, 0), "budget_viewpoints": budget},
        "rooms": rooms,
        "spaces_left_out": [str(getattr(s, "name", s)) for s in scene.left_out],
        "windows_in_no_room": [w.name for w in scene.windows if w.name not in bounding],
        "dwellings": ([{"name": d.name, "source": d.source, "rooms": list(d.rooms), "main_rooms": list(d.main_rooms)}
                       for d in pf.dwellings] if project.dwellings is not None else []),
        "warnings": list(pf.warnings), "notes": list(scene.notes),
    }
    return doc


def kind_entry(room) -> dict:
    """What ``room`` is used for (``scene/kinds.py``), where that came from, and what its kinds set:
    key path -> the room's value and where it comes from (report.json and ``validate --json``)."""
    return {"uses": list(room.kinds), "source": room.kind_source,
            "set": {key: {"value": value, "from": src} for key, value, src in room.by_kind}}


def kind_text(kind: dict) -> str:
    """``living room + kitchen (LongName 'Wohnküche': name table 'wohn', 'kuche'); daylight target 200 lx
    at minimum (practice gb-br209-2022, kitchen)``: a room's :func:`kind_entry` in words (``validate``,
    report.md and report.html)."""
    said: dict[str, list[str]] = {}  # where from -> what, in the order of the keys
    for key, v in kind["set"].items():
        parts = key.split(".")
        if parts[0] != "thresholds":
            said.setdefault(v["from"], []).append(f"{parts[1]} required {v['value']}")
        elif parts[1] == "daylight_minimum_target_lx" and v["value"] == 0:
            said.setdefault(v["from"], []).append(f"no daylight minimum target at {parts[2]}")
        else:
            what = {"daylight_target_lx": "daylight target", "daylight_minimum_target_lx": "daylight minimum target"}
            said.setdefault(v["from"], []).append(f"{what.get(parts[1], parts[1])} {v['value']:g} lx at {parts[2]}")
    return (f"{' + '.join(k.replace('_', ' ') for k in kind['uses'])} ({kind['source']})"
            + "".join(f"; {', '.join(what)} ({src})" for src, what in said.items()))


def bearing_number(b: float | None):
    """A compass bearing [deg] to 0.1 deg in [0, 360) (359.96 is 0.0), None for a roof light."""
    return None if b is None else json_number(round(b, 1) % 360.0, 1)
