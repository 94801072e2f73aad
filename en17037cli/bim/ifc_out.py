"""A run's results written back into the IFC (``check --ifc-out FILE``): a copy of the input file
with a property set ``EN17037_Results`` on every IfcSpace that is a room of the check and on every
element of its windows, so an IFC viewer can colour rooms by the result and show a window's hours.

The property set's name is this tool's own, not a buildingSMART ``Pset_`` one (IFC4 ADD2 TC1,
7.4.3.2: the prefix is reserved for the standard's sets). Properties are written with
ifcopenshell's API (``pset.add_pset``, ``pset.edit_pset``: IfcLabel for text, IfcReal for numbers,
IfcBoolean for pass/fail); numbers carry their unit in their name (``_m``, ``_h``) or in the
``<Criterion>Unit`` property, never the file's length unit. Lengths are metres in the file's own
coordinates (:meth:`~en17037cli.bim.frames.ModelFiles.to_file`).

Nothing else of the file changes: entities keep their ids and attributes, the header is the
input's. The new property sets and relationships get GlobalIds derived from their element's (UUID 5:
the same on every run) and no owner history of their own (IFC4: optional; IFC2X3, where it is
mandatory: the element's own), so the same inputs give the same bytes.

A space's properties, per criterion ``C`` of ``Daylight``, ``View``, ``Sunlight``, ``Glare`` that
the room has: ``CStatus`` (pass, fail, not_assessable, not_assessed), ``CPass``, ``CLevelReached``
(none, minimum, medium, high; empty where not assessable), ``CLevelRequired``, and the key figure:
``CValue`` with ``CUnit``, ``CError`` and ``CQuantity``, where the criterion passes or fails (what
it is: the hours of sunlight on the assessed day; the view criterion that limits the room, at its eye height, reached by the share of
points the standard asks; the share of the reference plane reaching the limiting target; the DGP
exceeded in 5 % of the usage hours); and ``Status``, ``Room``, ``Tool``. A window element's:
``Room``, ``PointP_X_m``, ``PointP_Y_m``, ``PointP_Z_m``, ``SunlightHours_h``, ``SunlightDate``,
``SunlightStatus`` (where its P is not assessable, with ``SunlightReason``).
"""
from __future__ import annotations

import uuid

import numpy as np

from en17037cli.bim.frames import ModelFiles
from en17037cli.report.verdicts import CRITERION_WORDS
from en17037cli.version import __version__

#: The property set's name (this tool's own: no buildingSMART Pset_ prefix).
PSET = "EN17037_Results"
#: report.json criterion -> the properties' prefix
PREFIX = {"daylight": "Daylight", "view": "View", "sunlight": "Sunlight", "glare": "Glare"}
#: Namespace of the GlobalIds of what is written (uuid5 of the element's GlobalId and the entity's class)
NAMESPACE = uuid.uuid5(uuid.NAMESPACE_URL, "https://github.com/en17037cli/en17037cli/ifc-results")
#: view criterion -> the error estimate of its quantity in error_estimates
VIEW_ERRORS = {"horizontal_sight_angle": "max_horizontal_sight_angle_error_deg", "outside_distance": "max_outside_distance_error_m"}


def key_figure(criterion: str, section: dict) -> dict:
    """``Value``, ``Unit``, ``Error``, ``Quantity`` of a criterion's key figure (see the module
    docstring); empty where the section holds no figure (not assessed)."""
    err = section.get("error_estimates") or {}
    lim = section.get("limiting") or {}
    if criterion == "sunlight" and "hours_h" in section:
        return {"Value": section["hours_h"], "Unit": "h", "Error": err.get("hours_error_h"),
                "Quantity": f"hours of sunlight on {section['assessed_date']}"}
    if criterion == "view" and lim.get("criterion"):
        by = [b for b in (section.get("score") or {}).get("by_criterion", ())
              if b["criterion"] == lim["criterion"] and b["eye_height_m"] == lim.get("eye_height_m")]
        if not by:
            return {}
        words = CRITERION_WORDS[lim["criterion"]]
        return {"Value": by[0]["quantity"], "Unit": by[0]["unit"], "Error": err.get(VIEW_ERRORS.get(lim["criterion"], "")),
                "Quantity": f"{words} reached by {lim['needed']:.0%} of the points at {lim['eye_height_m']:g} m eye height"}
    if criterion == "daylight" and lim.get("criterion"):
        target = "minimum target" if lim["criterion"] == "daylight_minimum_target" else "target"
        return {"Value": lim["value"], "Unit": "share of the reference plane", "Error": err.get("max_share_error"),
                "Quantity": f"share of the reference plane reaching the {target} illuminance of {lim['level']}"}
    if criterion == "glare" and section.get("dgp_5pct") is not None:
        return {"Value": section["dgp_5pct"], "Unit": "DGP", "Error": err.get("dgp_error"),
                "Quantity": "daylight glare probability exceeded in 5 % of the usage hours at the worst view"}
    return {}


def space_properties(entry: dict) -> dict:
    """The ``EN17037_Results`` properties of a room's IfcSpace (see the module docstring)."""
    out: dict = {"Room": entry["name"], "Status": entry["status"], "Tool": f"en17037cli {__version__}"}
    for criterion, prefix in PREFIX.items():
        sec = entry.get(criterion)
        if not sec:
            continue
        out |= {f"{prefix}Status": sec["status"], f"{prefix}Pass": sec["status"] == "pass",
                f"{prefix}LevelReached": sec.get("level") or "", f"{prefix}LevelRequired": sec["required"]}
        if sec["status"] in ("pass", "fail"):  # a level not assessable has no key figure to show (layers not traced...)
            out |= {f"{prefix}{k}": v for k, v in key_figure(criterion, sec).items()}
    return {k: v for k, v in out.items() if v is not None}


def window_properties(entry: dict, k: int, point_file: np.ndarray | None) -> dict:
    """The ``EN17037_Results`` properties of the elements of window ``k`` of a room."""
    out: dict = {"Room": entry["name"]}
    sun = entry.get("sunlight") or {}
    ws = sun.get("windows") or []
    w = ws[k] if k < len(ws) else None
    if w is not None:
        if point_file is not None:
            out |= {"PointP_X_m": round(float(point_file[0]), 4), "PointP_Y_m": round(float(point_file[1]), 4),
                    "PointP_Z_m": round(float(point_file[2]), 4)}
        if w.get("hours_h") is not None:
            out |= {"SunlightHours_h": w["hours_h"], "SunlightDate": sun["assessed_date"]}
        if w.get("status"):
            out |= {"SunlightStatus": w["status"], "SunlightReason": w.get("reason", "")[:255]}
    return out


def _guid(gid: str, what: str) -> str:
    import ifcopenshell.guid

    return ifcopenshell.guid.compress(uuid.uuid5(NAMESPACE, f"{gid}/{what}").hex)


def put(f, element, properties: dict) -> None:
    """Add (or edit, on a file written before) the element's ``EN17037_Results`` with ``properties``."""
    import ifcopenshell.api

    pset = ifcopenshell.api.run("pset.add_pset", f, product=element, name=PSET)
    ifcopenshell.api.run("pset.edit_pset", f, pset=pset, properties=properties)


def _settle(f, last_id: int, owners: dict) -> None:
    """The entities added after ``last_id``: GlobalIds from their element's, no owner history of
    their own (IFC2X3: the element's), the owner histories the API made removed."""
    new = [e for e in f if e.id() > last_id]
    made = [e for e in new if e.is_a("IfcOwnerHistory")]
    for e in new:
        if not e.is_a("IfcRoot"):
            continue
        if e.is_a("IfcRelDefinesByProperties"):
            element = e.RelatedObjects[0]
            e.GlobalId = _guid(element.GlobalId, "IfcRelDefinesByProperties")
            pset = e.RelatingPropertyDefinition
            pset.GlobalId = _guid(element.GlobalId, PSET)
            for x in (e, pset):
                x.OwnerHistory = owners.get(element.GlobalId) if f.schema == "IFC2X3" else None
    for oh in made:
        f.remove(oh)


def results_ifc(result, report: dict, file: str, files: ModelFiles | None = None) -> bytes:
    """The IFC ``file`` (as the project writes it) with the run's results in ``EN17037_Results``
    on its spaces and windows (see the module docstring), as bytes."""
    files = files or ModelFiles(result.project)
    f = files.ifc(file)
    last = max((e.id() for e in f), default=0)
    owners: dict = {}
    for entry in report["rooms"]:
        src = entry["source"]
        if src["format"] == "ifc" and src["file"] == file and src["ids"]:
            space = f.by_guid(src["ids"][0])
            owners[space.GlobalId] = getattr(space, "OwnerHistory", None)
            put(f, space, space_properties(entry))
        ps = [w.get("point_p_m") for w in (entry.get("sunlight") or {}).get("windows", ())]
        for k, w in enumerate(entry["windows"]):
            p = ps[k] if k < len(ps) else None
            pf = None if p is None else files.to_file(file, np.array(p, float), np.array([0.0, 0.0, 1.0]))[0][0]
            props = window_properties(entry, k, pf)
            for gid in w["source"]["ids"]:
                el = _element(f, gid) if w["source"]["format"] == "ifc" and _file_of(w["source"], gid) == file else None
                if el is not None and el.GlobalId not in owners:  # a window in two rooms: the first room's
                    owners[el.GlobalId] = getattr(el, "OwnerHistory", None)
                    put(f, el, props)
    _settle(f, last, owners)
    files.forget(file)  # this copy is changed: the next caller opens its own
    return f.to_string().encode("utf-8")


def _file_of(source: dict, gid: str) -> str:
    e: dict = next((x for x in source["elements"] if x.get("id") == gid), {})
    return e.get("file", source["file"])


def _element(f, gid: str):
    try:
        return f.by_guid(gid)
    except RuntimeError:  # not an element of this file
        return None


def ifc_files_with_results(report: dict) -> list[str]:
    """The IFC files (as the project writes them) holding a room's space or one of its windows, in order."""
    out: dict[str, None] = {}
    for entry in report["rooms"]:
        for src in (entry["source"], *(w["source"] for w in entry["windows"])):
            if src["format"] == "ifc" and src["ids"]:
                out[src["file"]] = None
                out |= {e["file"]: None for e in src["elements"] if "file" in e}
    return list(out)
