"""The screen's tables: ``probes.csv`` and ``probes.geojson`` (one row, one Point feature per
probe, the same columns), ``buildings.csv`` (one row per building) and ``summary.json``.

Numbers are written with fixed decimals (millimetres, hundredths of a percent, seconds of an
hour), so the same inputs give the same bytes. An outside distance with nothing met (open to the
horizon, beyond the model) is ``inf`` in the CSV and ``null`` in the GeoJSON, with
``outside_distance_open: true``. Coordinates are the model's CRS's (x, y, z), as the city model
gives them; the GeoJSON names that CRS in a ``crs`` member (the 2008 GeoJSON form, which QGIS
reads; RFC 7946 readers assume longitude and latitude and will misplace the points).
"""
from __future__ import annotations

import csv
import io
import json
import math

from en17037cli import standard
from en17037cli.district.results import LAYER_NAMES, BuildingSummary, ProbeTable

#: The probes' columns, in order (GeoJSON properties carry them all but x, y, z)
PROBE_COLUMNS = ("building_id", "surface", "storey", "x", "y", "z", "facing_deg", "facade_m2", "sunlight_date",
                 "sunlight_hours_h", "sunlight_hours_h_error", "sunlight_level", "sky_component_pct",
                 "sky_component_pct_error", "outside_distance_m", "outside_distance_m_error", "outside_distance_level",
                 "view_layers", "view_layers_error", "view_layers_level")


def _num(x: float, digits: int):
    """A number rounded to ``digits``, -0 as 0; None for NaN; inf kept (the writers spell it)."""
    x = float(x)
    if math.isnan(x):
        return None
    if math.isinf(x):
        return x
    return round(x, digits) + 0.0


def probe_rows(table: ProbeTable, dates: list, north_deg: float) -> list[dict]:
    """One dict per probe, :data:`PROBE_COLUMNS` as keys; ``facing_deg``: the compass bearing the
    facade faces [deg clockwise from true north]."""
    rows = []
    p = table.probes
    levels = standard.LEVELS
    for i in range(len(table)):  # rows of a table
        n = p.normal[i]
        facing = (math.degrees(math.atan2(n[0], n[1])) - north_deg) % 360.0
        rows.append({
            "building_id": table.building_id[i], "surface": table.surface[i], "storey": int(p.storey[i]),
            "x": _num(p.point[i, 0], 3), "y": _num(p.point[i, 1], 3), "z": _num(p.point[i, 2], 3),
            "facing_deg": _num(facing, 1), "facade_m2": _num(p.area_m2[i], 2),
            "sunlight_date": dates[int(table.day[i])].isoformat() if dates else None,
            "sunlight_hours_h": _num(table.hours_h[i], 4), "sunlight_hours_h_error": _num(table.hours_err_h[i], 4),
            "sunlight_level": levels[int(table.sun_level[i])],
            "sky_component_pct": _num(table.vsc_pct[i], 3), "sky_component_pct_error": _num(table.vsc_err_pct[i], 3),
            "outside_distance_m": _num(table.distance_m[i], 3), "outside_distance_m_error": _num(table.distance_err_m[i], 3),
            "outside_distance_level": levels[int(table.distance_level[i])],
            "view_layers": table.layers_label(i), "view_layers_error": _num(table.layers_err_sr[i], 5),
            "view_layers_level": levels[int(table.layers_level[i])]})
    return rows


def _cell(v) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return "inf" if math.isinf(v) else repr(v)
    return str(v)


def csv_text(rows: list[dict], columns) -> str:
    """A CSV of ``rows`` (RFC 4180, ``\\n`` line ends)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(columns)
    for r in rows:
        w.writerow([_cell(r[c]) for c in columns])
    return buf.getvalue()


def geojson_text(rows: list[dict], crs: str | None) -> str:
    """A FeatureCollection of one Point (x, y, z) per probe, the other columns as properties."""
    feats = []
    for r in rows:
        props = {k: (None if isinstance(v, float) and math.isinf(v) else v) for k, v in r.items() if k not in ("x", "y", "z")}
        props["outside_distance_open"] = isinstance(r["outside_distance_m"], float) and math.isinf(r["outside_distance_m"])
        feats.append({"type": "Feature", "geometry": {"type": "Point", "coordinates": [r["x"], r["y"], r["z"]]},
                      "properties": props})
    doc: dict = {"type": "FeatureCollection", "name": "probes"}
    if crs and crs.upper().startswith("EPSG:"):
        doc["crs"] = {"type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{crs.split(':')[-1]}"}}
    doc["features"] = feats
    return json.dumps(doc, ensure_ascii=False, separators=(",", ":")) + "\n"


#: The buildings' columns, in order
BUILDING_COLUMNS = ("building_id", "probes", "shared_wall_probes", "facade_m2",
                    *(f"sunlight_share_{lv}" for lv in standard.LEVELS), "sunlight_hours_median_h",
                    "sky_component_median_pct", "outside_distance_median_m",
                    *(f"view_layers_share_{lv}" for lv in standard.LEVELS),
                    *(f"outside_distance_share_{lv}" for lv in standard.LEVELS), "left_out")


def building_rows(summaries: list[BuildingSummary]) -> list[dict]:
    """One dict per building, :data:`BUILDING_COLUMNS` as keys."""
    out = []
    for s in summaries:  # one row per building
        row = {"building_id": s.id, "probes": s.probes, "shared_wall_probes": s.shared_probes, "facade_m2": _num(s.facade_m2, 2)}
        row |= {f"sunlight_share_{k}": _num(v, 4) for k, v in s.sunlight_share.items()}
        row |= {"sunlight_hours_median_h": _num(s.sunlight_hours_median_h, 4),
                "sky_component_median_pct": _num(s.sky_component_median_pct, 3),
                "outside_distance_median_m": _num(s.outside_distance_median_m, 3)}
        row |= {f"view_layers_share_{k}": _num(v, 4) for k, v in s.layers_share.items()}
        row |= {f"outside_distance_share_{k}": _num(v, 4) for k, v in s.distance_share.items()}
        row["left_out"] = s.problem
        out.append(row)
    return out


def summary_json(info: dict) -> str:
    """``summary.json``: what was screened, where, with which settings, the status, the warnings
    and the timings (the one place timings are written)."""
    def clean(v):
        if isinstance(v, float):
            return None if math.isnan(v) or math.isinf(v) else v
        if isinstance(v, dict):
            return {k: clean(x) for k, x in v.items()}
        if isinstance(v, list | tuple):
            return [clean(x) for x in v]
        return v

    return json.dumps(clean(info), indent=2, ensure_ascii=False) + "\n"


__all__ = ["BUILDING_COLUMNS", "LAYER_NAMES", "PROBE_COLUMNS", "building_rows", "csv_text", "geojson_text", "probe_rows",
           "summary_json"]
