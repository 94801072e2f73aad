"""The report document (``report.json``): built from a run's typed results; traces no ray.

Numbers are rounded to fixed decimals so that the same inputs give byte-identical files apart
from ``timings_s``. Each criterion writes its own section of a room
(:meth:`~en17037cli.criteria.base.Criterion.report`); this module writes the rest.
"""
from __future__ import annotations

from en17037cli.criteria import CRITERIA, Unassessed
from en17037cli.pipeline import RunResult
from en17037cli.practice import PRACTICES
from en17037cli.report.numbers import json_number, json_xyz
from en17037cli.report.sources import Sources
from en17037cli.report.validation import kind_entry
from en17037cli.version import __version__

SCHEMA_VERSION = "2.0"  # 2.0: decimal hours in fields named *_h (hours -> hours_h)


def dwelling_entry(d, rule: str) -> dict:
    """A dwelling in report.json: its rooms, and how it meets the sunlight rule."""
    return {"name": d.dwelling.name, "rooms": list(d.dwelling.rooms), "main_rooms": list(d.dwelling.main_rooms),
            "grouped_by": d.dwelling.source,
            "sunlight": {"rule": rule, "status": d.status, "required": d.required, "room": d.room,
                         "hours_h": json_number(d.hours, 4), "shortfall_h": json_number(d.shortfall_h, 4)}}


def site_entry(scene) -> dict:
    """Where the model stands and which way is north, as the run used them (given, or from the model)."""
    loc = scene.location
    return {"latitude": None if loc is None else loc.latitude, "longitude": None if loc is None else loc.longitude,
            "timezone": None if loc is None else loc.timezone, "true_north_deg": json_number(scene.true_north_deg, 6)}


def summary(result: RunResult) -> dict:
    """Counts for people and pipelines: rooms meeting view (and daylight, where it runs or is
    required), dwellings meeting sunlight."""
    view = [r.status("view") for r in result.rooms if r.status("view") is not None]
    sun = [d.status for d in result.dwellings if d.status is not None]
    out = {"rooms": len(result.rooms), "rooms_view_required": len(view), "rooms_view_pass": view.count("pass"),
           "dwellings": len(result.dwellings), "dwellings_sunlight_required": len(sun),
           "dwellings_sunlight_pass": sun.count("pass")}
    for c in ("daylight", "glare"):
        st = [r.status(c) for r in result.rooms if r.status(c) is not None]
        if st:
            out |= {f"rooms_{c}_required": len(st), f"rooms_{c}_pass": st.count("pass")}
    if result.scene.spaces:  # rooms from a model's spaces: the ones with windows that could not be assessed
        out["spaces_with_windows_not_assessed"] = sum(1 for lo in result.scene.left_out if lo.windows)
    return out


def spaces_entry(scene) -> dict:
    """The model's spaces the project picked that are not rooms of the check, and why (models with spaces only)."""
    return {"spaces_left_out": [{"name": lo.name, "reason": lo.reason, "windows": list(lo.windows)} for lo in scene.left_out]}


def practice_entry(project) -> dict:
    """The practice the project follows, its source, the values it set, and those it set per room kind."""
    practice = PRACTICES[project.practice]
    out = {"name": project.practice, "source": practice.source, "set": {k: v for k, v in project.practice_set}}
    kinds = {kind: {k: kv.values[k] for k, src in kv.set.items() if src.startswith("practice ")}
             for kind, kv in project.by_kind.items()}
    kinds = {kind: v for kind, v in kinds.items() if v}
    return out | ({"kinds": kinds, "kinds_source": practice.kinds_source} if kinds else {})


def build_report(result: RunResult) -> dict:
    """The ``report.json`` document (validates against ``schemas/report.schema.json``).

    Building it is the run's ``report`` stage: its time and the total close ``timings_s``.
    """
    project, scene, ctx = result.project, result.scene, result.context
    resolved = {"resolved": scene.resolved} if scene.resolved else {}
    rooms = []
    notes = list(scene.notes)
    sources = Sources(scene, project)
    for r in result.rooms:
        room = r.room
        entry = {
            "name": room.name,
            "source": sources.room(room),
            "status": "pass",
            "floor_area_m2": json_number(room.floor.area, 4),
            "floor_source": room.floor_source,
            "kind": kind_entry(room),
            "windows": [{"name": w.name, "source": sources.window(w), "area_m2": json_number(w.area_m2, 4),
                         "outward_normal": json_xyz(w.normal, 6), "sill_z_m": json_number(w.sill_z + scene.origin[2], 4),
                         "head_z_m": json_number(w.head_z + scene.origin[2], 4)}
                        for w in room.windows],
        }
        if room.problem is not None:
            entry["problem"] = room.problem
        for name, criterion in CRITERIA.items():
            res = r.results.get(name)
            if isinstance(res, Unassessed):
                entry[name] = {"level": None, "required": r.required(name), "status": res.status, "reason": res.reason}
            else:
                entry[name] = None if res is None else criterion.report(ctx, room, res)
                if res is not None and room.withheld is not None:  # computed without quarantined windows: no verdict
                    reached = r.level_without_withheld(name)
                    entry[name] |= {"level": None, "status": "not_assessable",
                                    "reason": f"{room.withheld}; without them it reaches {reached}"
                                    if reached else room.withheld}
        if any(r.status(c) not in (None, "pass") for c in CRITERIA):
            entry["status"] = "fail"
        if entry.get("glare") is None:
            entry.pop("glare", None)  # neither run nor required: the reports of projects without 5.4 stay as they were
        elif entry.get("sunlight"):
            from en17037cli.criteria.glare.report import with_sunlight

            entry["glare"] = with_sunlight(entry["glare"], entry["sunlight"])
        rooms.append(entry)
    for r in result.rooms:
        for name, criterion in CRITERIA.items():
            if r.assessed(name) is not None:
                notes.extend(criterion.notes(r.results[name]))
    doc = {
        "schema_version": SCHEMA_VERSION,
        "tool": {"name": "en17037cli", "version": __version__},
        "project": {"name": project.config.get("name"), "file": project.path.name,
                    **({"description": project.config["description"]} if project.config.get("description") else {})},
        "inputs": {"config": project.config, "model_files": scene.file_hashes, "local_origin_m": json_xyz(scene.origin, 6),
                   "checks_run": list(result.checks_run), "site": site_entry(scene), **resolved},
        "practice": practice_entry(project),
        "status": result.status,
        "summary": summary(result),
        "dwellings": [dwelling_entry(d, project.requirements.sunlight_rooms) for d in result.dwellings],
        "rooms": rooms,
        **(spaces_entry(scene) if scene.spaces else {}),
        "quarantined": [{"element": q.element, "action": q.action, "reason": q.reason, "advice": q.advice,
                         "rooms": list(q.rooms)} for q in scene.quarantined],
        "warnings": list(result.warnings),
        "notes": notes,
        "rays_traced": int(result.rays_traced),
    }
    result.timer.stage("report")
    t = result.timer.t
    doc["timings_s"] = {k: round(v, 3) for k, v in t.items()} | {"total": round(sum(t.values()), 3)}
    ref = [res.reference_s for r in result.rooms if (res := r.assessed("glare")) is not None and res.reference]
    if ref:  # part of the glare stage, not added to the total: what the reference check of 5.4 cost
        doc["timings_s"]["glare_reference_check"] = round(sum(ref), 3)
    return doc
