"""The CSV tables of a report: one row per viewpoint (``view_points.csv``) and per day (``sunlight_days.csv``)."""
from __future__ import annotations

import csv
import io

from en17037cli.report.labels import assessed


def source_ids(room: dict) -> str:
    """The ids of the elements a room was made from (its IfcSpace's GlobalId...), space-separated
    (ids hold no spaces: IFC GlobalIds, gbXML xsd:IDs, CityJSON ids), for the CSVs; "" for a room
    the project file draws."""
    return " ".join(room.get("source", {}).get("ids", ()))


def view_points_csv(report: dict) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["room", "eye_height_m", "x_m", "y_m", "z_m", "horizontal_sight_angle_deg", "horizontal_sight_angle_error_deg",
                "outside_distance_m", "outside_distance_unobstructed", "window_solid_angle_sr", "sky_sr", "landscape_sr",
                "ground_sr", "layers", "level_sight_angle", "level_distance", "level_layers", "level", "near_threshold",
                "room_source_ids"])
    for room in report["rooms"]:
        view = room["view"]  # assessed, or not assessable with its values (the layers of a model without landscape)
        if not view or not view.get("eye_heights"):
            continue
        for e in view["eye_heights"]:
            for p in e["points"]:
                lc = p["level_by_criterion"]
                w.writerow([room["name"], e["eye_height_m"], *p["point"], p["horizontal_sight_angle_deg"],
                            p["horizontal_sight_angle_error_deg"], "" if p["outside_distance_m"] is None else p["outside_distance_m"],
                            p["outside_distance_unobstructed"], p["window_solid_angle_sr"], p["solid_angle_sr"]["sky"],
                            p["solid_angle_sr"]["landscape"], p["solid_angle_sr"]["ground"], "+".join(p["layers"]),
                            lc["horizontal_sight_angle"], lc["outside_distance"], lc["layers"], p["level"], p["near_threshold"],
                            source_ids(room)])
    return buf.getvalue()


def sunlight_days_csv(report: dict) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["room", "date", "hours_h", "error_h", "assessed", "intervals", "room_source_ids"])
    for room in report["rooms"]:
        s = assessed(room["sunlight"])
        if not s:
            continue
        for d in s["days"]:
            w.writerow([room["name"], d["date"], d["hours_h"], d["error_h"], d["date"] == s["assessed_date"],
                        ";".join(f"{a[11:19]}-{b[11:19]}" for a, b in d["intervals"]), source_ids(room)])
    return buf.getvalue()


def daylight_points_csv(report: dict) -> str:
    """``daylight_points.csv``: one row per point of each room's reference plane (clause 5.1): its
    daylight factor (method 1, with its sky component and its bound and the reflected components
    and their interval) or its share of the daylight hours reaching each target illuminance of
    Table A.1 (method 2, ``share_of_hours_<lx>lx``), with their error estimates."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    lux = sorted({float(k) for room in report["rooms"] if assessed(room.get("daylight"))
                  for p in room["daylight"]["points"][:1] for k in p.get("share_of_hours", {})})
    split = ("sky_component_pct", "sky_component_bound_pct", "reflected_pct", "reflected_error_pct")
    w.writerow(["room", "method", "x_m", "y_m", "z_m", "daylight_factor_pct", "daylight_factor_error_pct", *split,
                *[f"share_of_hours_{lx:g}lx" for lx in lux], *[f"share_of_hours_{lx:g}lx_error" for lx in lux], "room_source_ids"])
    for room in report["rooms"]:
        sec = assessed(room.get("daylight"))
        if not sec:
            continue
        for p in sec["points"]:
            sh, se = p.get("share_of_hours", {}), p.get("share_of_hours_error", {})
            w.writerow([room["name"], sec["method"], *p["point"], p.get("daylight_factor_pct", ""),
                        p.get("daylight_factor_error_pct", ""), *[p.get(k, "") for k in split],
                        *[sh.get(f"{lx:g}", "") for lx in lux], *[se.get(f"{lx:g}", "") for lx in lux], source_ids(room)])
    return buf.getvalue()


def rooms_csv(report: dict) -> str:
    """``rooms.csv``: one row per room and check: level, requirement, status, what limits it and
    the continuous score with its margins (view: the limiting eye height and criterion), and where
    the room comes from (its ``source``: format, file, element ids)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["room", "check", "level", "required", "status", "limiting_criterion", "limiting_eye_height_m",
                "limiting_value", "limiting_needed", "limiting_margin", "score", "score_quantity", "score_unit",
                "margin_up", "margin_down", "source_format", "source_file", "source_ids"])
    blank = lambda v: "" if v is None else v  # noqa: E731
    for room in report["rooms"]:
        for key in ("view", "sunlight", "daylight", "glare"):
            sec = room.get(key)
            if sec is None:
                continue
            lim, sc = sec.get("limiting") or {}, sec.get("score") or {}
            if key == "view" and sc.get("by_criterion"):
                low = min(sc["by_criterion"], key=lambda p: (p["score"], p["eye_height_m"]))
                sc = sc | {"quantity": low["quantity"], "unit": f"{low['unit']} ({low['criterion'].replace('_', ' ')}, "
                           f"{low['eye_height_m']:g} m)", "margin_up": low["margin_up"], "margin_down": low["margin_down"]}
            w.writerow([room["name"], key, blank(sec["level"]), sec["required"], sec["status"], lim.get("criterion", ""),
                        blank(lim.get("eye_height_m")), blank(lim.get("value")), blank(lim.get("needed")),
                        blank(lim.get("margin")), blank(sc.get("value")), blank(sc.get("quantity")), sc.get("unit", ""),
                        blank(sc.get("margin_up")), blank(sc.get("margin_down")), room.get("source", {}).get("format", ""),
                        room.get("source", {}).get("file", ""), source_ids(room)])
    return buf.getvalue()
