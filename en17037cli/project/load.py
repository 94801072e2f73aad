"""Project file: read the YAML, apply ``--set`` overrides, validate, fill defaults, build settings.

:func:`load_project` returns a :class:`~en17037cli.project.settings.Project`: typed settings for
the scene, the engines and the reports, and the resolved document (every default filled in),
which the report repeats under ``inputs``. Nothing here touches geometry.
"""
from __future__ import annotations

import copy
import csv
import datetime as dt
import math
import re
import zoneinfo
from dataclasses import replace
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.practice import PRACTICES
from en17037cli.project.glare_settings import glare_settings
from en17037cli.project.kinds import kind_rules, kind_values
from en17037cli.project.overrides import apply_overrides, moot_overrides
from en17037cli.project.schema import fill_defaults, key_path, validation_errors
from en17037cli.project.settings import (
    Location,
    Project,
    Requirements,
    RoomSpec,
    daylight_settings,
    dwellings_spec,
    model_settings,
    sun_settings,
    view_settings,
)
from en17037cli.project.yaml12 import parse_yaml_or_fail
from en17037cli.schemas import load_schema
from en17037cli.standard import GLARE_DGP_LIMITS, THRESHOLDS, Thresholds


def read_points_csv(path: Path, what: str) -> list[list[float]]:
    """Read ``x, y, z`` rows (no header, or a header that is not numeric) from a CSV file [m]."""
    try:
        with path.open(newline="", encoding="utf-8") as fh:
            rows = [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
    except OSError as exc:
        raise InputError(f"{what}: cannot read {path}: {exc.strerror}") from None
    points = []
    for i, row in enumerate(rows):
        try:
            xyz = [float(c) for c in row[:3]]
        except ValueError:
            if i == 0:
                continue  # header
            raise InputError(f"{path}:{i + 1}: expected three numbers x, y, z, got {row}") from None
        if len(xyz) != 3 or not all(math.isfinite(c) for c in xyz):
            raise InputError(f"{path}:{i + 1}: expected three finite numbers x, y, z, got {row}")
        points.append(xyz)
    if not points:
        raise InputError(f"{path}: no points found; expected rows x, y, z in metres")
    return points


#: Project files larger than this are not parsed [bytes]; a real one is a few kB.
MAX_PROJECT_BYTES = 5 * 1024 * 1024
#: A project document may hold at most this many values once YAML aliases are expanded.
MAX_DOCUMENT_VALUES = 1_000_000


def read_document(path: Path) -> dict:
    """The YAML document of a project file, checked for size, encoding, aliases and numbers.

    Raises
    ------
    InputError
        One line naming the file and what to do.
    """
    try:
        size = path.stat().st_size
    except FileNotFoundError:
        raise InputError(f"{path}: project file not found") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read project file: {exc.strerror}") from None
    if not path.is_file():
        raise InputError(f"{path}: not a file; give the path of a project file (YAML)")
    if size > MAX_PROJECT_BYTES:
        raise InputError(f"{path}: project file is {size / 1e6:.1f} MB, over the {MAX_PROJECT_BYTES // 2**20} MB a project "
                         "file may have; put geometry and viewpoints in separate files (model.files, view_points CSV)")
    try:
        text = path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: not UTF-8 text (byte {exc.start}); save the project file as UTF-8") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read project file: {exc.strerror}") from None
    document = parse_yaml_or_fail(text, str(path))
    if not isinstance(document, dict):
        raise InputError(f"{path}: expected a mapping of keys (version, model, rooms, ...) at the top level")
    if expanded_size(document) > MAX_DOCUMENT_VALUES:
        raise InputError(f"{path}: YAML aliases expand to more than {MAX_DOCUMENT_VALUES:,} values; write the document out "
                         "without nested aliases")
    return document


def expanded_size(node, memo: dict | None = None) -> int:
    """Number of values in a YAML document with every alias expanded, counted without expanding:
    an aliased node is one object, whose size is computed once (linear in the distinct nodes)."""
    memo = {} if memo is None else memo
    key = id(node)
    if key in memo:
        return memo[key]
    memo[key] = 1  # a cycle counts once
    if isinstance(node, dict):
        size = 1 + sum(expanded_size(v, memo) for v in node.values()) + len(node)
    elif isinstance(node, list):
        size = 1 + sum(expanded_size(v, memo) for v in node)
    else:
        size = 1
    memo[key] = size
    return size


def non_finite_numbers(node, at=()) -> list[str]:
    """Key paths of NaN and infinite numbers (``.nan``, ``.inf``, ``1e400``) in a document."""
    if isinstance(node, bool):
        return []
    if isinstance(node, float):
        return [] if math.isfinite(node) else [key_path(at)]
    if isinstance(node, dict):
        return [p for k, v in node.items() for p in non_finite_numbers(v, (*at, k))]
    if isinstance(node, list):
        return [p for i, v in enumerate(node) for p in non_finite_numbers(v, (*at, i))]
    return []


def load_project(path: str | Path, overrides: list[str] | None = None) -> Project:
    """Read, validate and resolve a project file.

    Raises
    ------
    InputError
        With one line per problem, each naming the file and the key.
    """
    path = Path(path)
    document = apply_overrides(read_document(path), overrides or [])
    practice_set = apply_practice(document)
    bad = non_finite_numbers(document)
    if bad:
        raise InputError("\n".join(f"{path}: {k}: not a finite number; give a number such as 1.5" for k in bad))
    errors = validation_errors(document)
    if errors:
        raise InputError("\n".join(f"{path}: {e}" for e in errors))
    schema = load_schema("project")
    config = fill_defaults(copy.deepcopy(document), schema, schema)
    for name, values in THRESHOLDS.items():
        config.setdefault("thresholds", {}).setdefault(name, dict(values))
    if "daylight" in config:  # clause 5.1 is asked at the lowest level unless the project says otherwise
        config["requirements"].setdefault("daylight", "minimum")
    if "glare" in config:  # clause 5.4 likewise; its DGP limits are the standard's unless the project gives its own
        config["requirements"].setdefault("glare", "minimum")
        config["glare"].setdefault("dgp_limits", dict(GLARE_DGP_LIMITS))
    _check_consistency(path, config)
    return replace(_settings(path, config), practice=config["practice"], practice_set=practice_set,
                   kind_rules=kind_rules(config), by_kind=kind_values(path, config),
                   warnings=tuple(moot_overrides(config, overrides or [])))


def apply_practice(document: dict) -> tuple[tuple[str, object], ...]:
    """Set the values of the document's national practice (``practice:``) that it does not give
    itself; return them as (key path, value). Values inside a section the document leaves out
    (``sunlight.date`` without ``sunlight:``) are not set: a practice never turns a check on."""
    practice = PRACTICES.get(document.get("practice", "en17037"))
    if practice is None:
        return ()  # the schema names the unknown practice
    done = []
    for key, value in practice.values.items():
        *parents, last = key.split(".")
        node: object = document
        for part in parents:
            if not isinstance(node, dict) or (part not in node and part in ("view", "sunlight", "location")):
                node = None  # a section the document leaves out: the practice does not add it
                break
            node = node.setdefault(part, {})
        if isinstance(node, dict) and last not in node:
            node[last] = value
            done.append((key, value))
    return tuple(done)


def _settings(path: Path, config: dict) -> Project:
    """The typed :class:`Project` of a resolved, consistent document."""
    directory = path.resolve().parent
    requirements = Requirements(**config["requirements"])
    rooms = []
    for i, room in enumerate(config.get("rooms", [])):
        vp = room.get("view_points")
        if isinstance(vp, str):
            vp = [vp]
        if vp and all(isinstance(v, str) for v in vp):
            vp = [p for f in vp for p in read_points_csv((directory / f).resolve(), f"{path}: rooms[{i}].view_points")]
        req = Requirements(**{**config["requirements"], **room.get("requirements", {})})
        rooms.append(RoomSpec(
            name=room.get("name", ""), index=i, floor_z=float(room.get("floor_z", 0.0)), ifc_spaces=room.get("ifc_spaces"),
            gbxml_spaces=room.get("gbxml_spaces"), auto=bool(room.get("auto", False)),
            auto_all_storeys="auto" in room and "floor_z" not in room,
            inside=None if "inside" not in room else np.asarray(room["inside"], dtype=float),
            floor=None if "floor" not in room else np.asarray(room["floor"], dtype=float),
            windows=None if "windows" not in room else tuple(room["windows"]),
            ceiling_z=None if "ceiling_z" not in room else float(room["ceiling_z"]),
            window_margin_m=float(room["window_margin_m"]),
            view_points=None if vp is None else np.asarray(vp, dtype=float),
            sun_points=None if "sun_points" not in room else np.asarray(room["sun_points"], dtype=float),
            requirements=req, own_requirements=tuple(room.get("requirements", {}))))
    loc = config.get("location")
    return Project(
        path=path.resolve(), name=config["name"], model=model_settings(config["model"], directory), rooms=tuple(rooms),
        location=None if loc is None else Location(loc.get("latitude"), loc.get("longitude"), loc["timezone"],
                                                   loc.get("elevation_m", 0.0)),
        view=view_settings(config["view"]) if "view" in config else None,
        sunlight=sun_settings(config["sunlight"]) if "sunlight" in config else None,
        daylight=daylight_settings(config["daylight"], directory) if "daylight" in config else None,
        glare=glare_settings(config["glare"], directory, config.get("daylight")) if "glare" in config else None,
        requirements=requirements, thresholds=Thresholds.from_dict(config["thresholds"]), config=config,
        dwellings=dwellings_spec(config.get("dwellings")))


def _check_consistency(path: Path, config: dict) -> None:
    """Rules a JSON Schema cannot express; each raises a one-line :class:`InputError`."""
    for i, r in enumerate(config.get("rooms", [])):
        clash = [k for k in ("name", "floor", "inside", "view_points", "sun_points") if k in r] if "auto" in r else []
        if clash:
            raise InputError(f"{path}: rooms[{i}].{clash[0]}: not with auto (one entry stands for every room the walls "
                             "enclose, which the plan names); write the room out instead")
        for key in ("ifc_spaces", "gbxml_spaces"):
            if key not in r:
                continue
            clash = [k for k in ("name", "floor_z", "floor", "view_points", "sun_points") if k in r]
            if clash:
                raise InputError(f"{path}: rooms[{i}].{clash[0]}: not with {key} (one entry stands for every matched "
                                 "space, which gives its name and floor); write the room out instead")
    names = [r["name"] for r in config.get("rooms", []) if "name" in r]
    dupes = sorted({n for n in names if names.count(n) > 1})
    if dupes:
        raise InputError(f"{path}: rooms: room name '{dupes[0]}' is used twice; give each room its own name")
    for i, f in enumerate(config["model"]["files"]):
        p = (path.parent / f["path"])
        if not p.is_file():
            raise InputError(f"{path}: model.files[{i}].path: file not found: {p}")
    for key in THRESHOLDS:
        t = config["thresholds"][key]
        if not t["minimum"] <= t["medium"] <= t["high"]:
            raise InputError(f"{path}: thresholds.{key}: expected minimum <= medium <= high, got {t}")
    view = config.get("view") or {}
    if view.get("sight_angle_method") == "fan" and view.get("mullions_block") is False:
        raise InputError(f"{path}: view.mullions_block: false needs view.sight_angle_method: plan (the fan's rays stop "
                         "at a mullion); remove one of the two")
    if "location" in config:
        tz = config["location"]["timezone"]
        try:
            zoneinfo.ZoneInfo(tz)
        except (zoneinfo.ZoneInfoNotFoundError, ValueError, OSError):
            raise InputError(f"{path}: location.timezone: unknown IANA time zone {tz!r}; use a name such as Europe/Amsterdam") from None
    if "sunlight" in config:
        if "location" not in config:
            raise InputError(f"{path}: location: required for the sunlight check (latitude, longitude, timezone); or remove the sunlight section")
        sun = config["sunlight"]
        year = sun["year"]
        try:
            start, end = (dt.date.fromisoformat(f"{year}-{sun['period'][k]}") for k in ("start", "end"))
        except ValueError as exc:
            raise InputError(f"{path}: sunlight.period: not a date in {year}: {exc}") from None
        if end < start:
            raise InputError(f"{path}: sunlight.period: end {sun['period']['end']} is before start {sun['period']['start']}")
        if sun["date"] not in ("worst", "best"):
            try:
                d = dt.date.fromisoformat(f"{year}-{sun['date']}")
            except ValueError as exc:
                raise InputError(f"{path}: sunlight.date: not a date in {year}: {exc}") from None
            if not start <= d <= end:
                raise InputError(f"{path}: sunlight.date: {sun['date']} is outside the period {sun['period']['start']}..{sun['period']['end']}")
    dwellings = config.get("dwellings")
    pattern = dwellings.get("by_pattern") if isinstance(dwellings, dict) else None
    if pattern is not None:
        try:
            rx = re.compile(pattern)
        except re.error as exc:
            raise InputError(f"{path}: dwellings.by_pattern: not a regular expression ({exc})") from None
        if "dwelling" not in rx.groupindex:
            raise InputError(f"{path}: dwellings.by_pattern: needs a named group (?P<dwelling>...) that names the dwelling")
    if "daylight" in config:
        _check_daylight(path, config["daylight"])
    if "glare" in config:
        _check_glare(path, config)
    if "view" in config:
        st = config["view"]["distance_statistic"]
        if st.startswith("p") and not 0 <= int(st[1:]) <= 100:
            raise InputError(f"{path}: view.distance_statistic: percentile must be 0..100, got {st}")



def _check_daylight(path: Path, d: dict) -> None:
    """The daylight section's rules: where E_v,d,med and the hourly sky come from."""
    w = d.get("weather")
    if w is not None and not (path.parent / w).is_file():
        raise InputError(f"{path}: daylight.weather: file not found: {path.parent / w}; give an EPW weather file of the site")
    if d["method"] == "climate_based" and w is None:
        raise InputError(f"{path}: daylight.weather: required by daylight.method: climate_based (an EPW file of the site); "
                         "or use method: daylight_factor with median_diffuse_lx")
    if d["method"] == "daylight_factor" and w is None and d.get("median_diffuse_lx") is None:
        raise InputError(f"{path}: daylight.median_diffuse_lx: the daylight factor method needs E_v,d,med: give "
                         "median_diffuse_lx [lx] (EN 17037 Table A.3 lists it for European capitals) or a weather file (EPW)")


def _check_glare(path: Path, config: dict) -> None:
    """The glare section's rules: a weather file that exists, something to assess, a usage time
    that is a time span, point-in-time checks that are moments, and a site."""
    g = config["glare"]
    w = g.get("weather")
    if w is not None and not (path.parent / w).is_file():
        raise InputError(f"{path}: glare.weather: file not found: {path.parent / w}; give an EPW weather file of the site")
    if w is None and not g["times"]:
        raise InputError(f"{path}: glare.weather: the annual glare check needs an EPW weather file of the site; give "
                         "glare.weather, or glare.times for point-in-time checks only")
    if "location" not in config:
        raise InputError(f"{path}: location: required for the glare check (timezone; latitude and longitude unless the "
                         "model gives them); or remove the glare section")
    start, end = g["usage"]["start"], g["usage"]["end"]
    if not start < end:
        raise InputError(f"{path}: glare.usage: start {start} is not before end {end}; give the usage time as "
                         "{start: '08:00', end: '18:00'}")
    for i, t in enumerate(g["times"]):
        try:
            dt.datetime.fromisoformat(t)
        except ValueError:
            raise InputError(f"{path}: glare.times[{i}]: {t!r} is not a date and time; write it as 2026-12-21T12:00") from None
    lim = g["dgp_limits"]
    if not lim["minimum"] >= lim["medium"] >= lim["high"]:
        raise InputError(f"{path}: glare.dgp_limits: expected minimum >= medium >= high (a higher level allows less "
                         f"glare), got {lim}")
