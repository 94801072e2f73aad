"""Every output of a screen, as bytes by file name: the tables (:mod:`~en17037cli.district.write`),
the city model with the results (:mod:`~en17037cli.district.citymodel`), ``summary.json`` and
``report.html`` (:mod:`~en17037cli.district.html`)."""
from __future__ import annotations

from en17037cli import standard
from en17037cli.criteria.sunlight.intervals import day_bounds
from en17037cli.district.citymodel import building_attributes, wall_attributes, write_citygml, write_cityjson, written_name
from en17037cli.district.html import report_html
from en17037cli.district.results import probe_table, status, summaries
from en17037cli.district.write import (
    BUILDING_COLUMNS,
    PROBE_COLUMNS,
    building_rows,
    csv_text,
    geojson_text,
    probe_rows,
    summary_json,
)


def outputs(project, settings, f0, crs, chosen: list, parts: list, problems: dict, where_site: tuple, warnings: list,
            seconds: float, workers: int) -> tuple[dict[str, bytes], dict]:
    """(file name -> bytes, summary) of a screen: see the module docstring."""
    lat, lon, north, source = where_site
    table = probe_table(parts, chosen, settings, project.thresholds)
    shared: dict = {}
    for q in parts:
        shared |= q.shared
    rows = summaries(table, chosen, shared, problems)
    required = project.requirements.sunlight
    state, failing = status(rows, required)
    dates, _, _ = day_bounds(settings.sun.year, settings.sun.period_start, settings.sun.period_end, project.location.timezone)
    probe_dicts = probe_rows(table, dates, north)
    n = len(table)
    timing = {k: round(sum(q.seconds[k] for q in parts), 3) for k in ("probes", "sunlight", "sky_and_view")}
    sun = settings.sun
    day = sun.date if sun.date in ("worst", "best") else f"{sun.year}-{sun.date}"
    facts = {
        "city model": f"{f0.display} ({crs or 'no CRS'})",
        "buildings screened": f"{len(chosen) - len([b for b in chosen if b.problem]) - len(problems)} of {len(chosen)} chosen "
                              f"({len([b for b in chosen if b.problem]) + len(problems)} left out)",
        "probes": f"{n} ({sum(shared.values())} more on walls shared with a neighbour, left out)",
        "site": f"{lat:.5f} N, {lon:.5f} E, true north {north:.2f} deg clockwise from +Y ({source})",
        "sunlight": f"assessed day {day} (period {sun.period_start}..{sun.period_end}), minimum altitude "
                    f"{sun.min_altitude_deg:g} deg; levels of Table A.6",
        "probes placed": f"storeys of {settings.storey_height_m:g} m, every {settings.spacing_m:g} m, window "
                         f"{settings.window_width_m:g} x {settings.window_height_m:g} m with its sill at "
                         f"{settings.sill_height_m:g} m; P {settings.p_above_floor_m:g} m above the floor",
        "status": f"{state}: " + ("every screened building has facade reaching the sunlight level required "
                                  f"({required})" if state == "pass" else
                                  f"{len(failing)} building(s) have no facade reaching {required} sunlight"),
    }
    info = {
        "tool": "en17037cli", "project": project.name, "status": state, "failing": failing,
        "headline": f"{n} probes on the facades of {len(chosen)} buildings; status {state}.", "facts": facts,
        "crs": crs, "site": {"latitude": lat, "longitude": lon, "true_north_deg": north, "source": source},
        "settings": {"storey_height_m": settings.storey_height_m, "spacing_m": settings.spacing_m,
                     "sill_height_m": settings.sill_height_m, "window": {"width_m": settings.window_width_m,
                                                                         "height_m": settings.window_height_m},
                     "shared_wall_tolerance_m": settings.shared_wall_tolerance_m,
                     "sky_resolution_deg": settings.sky_resolution_deg,
                     "view_resolution_deg": settings.view.angular_resolution_deg,
                     "sunlight": {"date": sun.date, "period": [sun.period_start, sun.period_end],
                                  "min_altitude_deg": sun.min_altitude_deg}},
        "counts": {"buildings": len(chosen), "probes": n, "shared_wall_probes": sum(shared.values()),
                   "sunlight_level_probes": {lv: int((table.sun_level == i).sum()) for i, lv in enumerate(standard.LEVELS)}},
        "warnings": warnings,
        "timings_s": {**timing, "total": round(seconds, 3), "per_probe_ms": round(1000 * seconds / max(n, 1), 2),
                      "workers": workers},
    }
    wall_attrs = wall_attributes(table, project.thresholds)
    bld_attrs = building_attributes(rows)
    city = (write_citygml if f0.path.suffix.lower() in (".gml", ".citygml") else write_cityjson)(f0.path, chosen, wall_attrs,
                                                                                                  bld_attrs)
    files = {
        "probes.csv": csv_text(probe_dicts, PROBE_COLUMNS).encode("utf-8"),
        "probes.geojson": geojson_text(probe_dicts, crs).encode("utf-8"),
        "buildings.csv": csv_text(building_rows(rows), BUILDING_COLUMNS).encode("utf-8"),
        "summary.json": summary_json(info).encode("utf-8"),
        "report.html": report_html(project.name, info, table, chosen, rows, warnings).encode("utf-8"),
        written_name(f0.path): city,
    }
    return files, info
