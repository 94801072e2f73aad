"""Project file: read the YAML, apply ``--set`` overrides, validate, fill defaults.

The result is a :class:`Project` whose ``config`` is the resolved configuration (every default
filled in), which the report repeats under ``inputs``. Nothing here touches geometry.
"""
from __future__ import annotations

import copy
import csv
import datetime as dt
import json
import re
import zoneinfo
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources
from pathlib import Path

import jsonschema
import yaml

from en17037cli.errors import InputError
from en17037cli.standard import THRESHOLDS


@lru_cache(maxsize=None)
def load_schema(name: str) -> dict:
    """The JSON Schema ``name`` (``project`` or ``report``) shipped with the package."""
    text = resources.files("en17037cli").joinpath("schemas", f"{name}.schema.json").read_text("utf-8")
    return json.loads(text)


@dataclass
class Project:
    path: Path
    config: dict
    view_points: dict[str, object] = field(default_factory=dict)  # room name -> (n, 3) list or None

    @property
    def directory(self) -> Path:
        return self.path.parent

    def resolve(self, relative: str) -> Path:
        return (self.directory / relative).resolve()


def _key_path(parts) -> str:
    out = ""
    for p in parts:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out or "(top level)"


def _describe(error: jsonschema.ValidationError) -> str:
    v = error.validator
    inst = error.instance
    if v == "required":
        missing = [k for k in error.validator_value if isinstance(inst, dict) and k not in inst]
        return f"missing required key '{missing[0] if missing else error.validator_value}'"
    if v == "additionalProperties":
        allowed = sorted(error.schema.get("properties", {}))
        extra = sorted(set(inst) - set(allowed)) if isinstance(inst, dict) else []
        return f"unknown key '{extra[0] if extra else '?'}' (allowed: {', '.join(allowed)})"
    if v == "type":
        return f"expected {error.validator_value}, got {json.dumps(inst, default=str)}"
    if v == "enum":
        return f"expected one of {', '.join(map(str, error.validator_value))}, got {json.dumps(inst, default=str)}"
    if v == "const":
        return f"expected {json.dumps(error.validator_value)}, got {json.dumps(inst, default=str)}"
    if v == "oneOf" and isinstance(inst, dict) and "path" in inst:
        return "give exactly one of 'layer' (whole file) or 'layers' (rules by name)"
    if v in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
        op = {"minimum": ">=", "maximum": "<=", "exclusiveMinimum": ">", "exclusiveMaximum": "<"}[v]
        return f"expected a value {op} {error.validator_value}, got {inst}"
    if v == "pattern":
        return f"{json.dumps(inst)} does not have the expected form (pattern {error.validator_value})"
    if v == "anyOf" and isinstance(inst, str) and error.path and error.path[-1] == "date":
        return f"expected a date MM-DD, 'worst' or 'best', got {json.dumps(inst)}"
    if v in ("minItems", "maxItems"):
        return f"expected {'at least' if v == 'minItems' else 'at most'} {error.validator_value} items, got {len(inst)}"
    return error.message


def validation_errors(document: dict, schema_name: str = "project") -> list[str]:
    """One line per schema violation: ``key.path: what is expected``, sorted by key path."""
    validator = jsonschema.Draft202012Validator(load_schema(schema_name))
    errors = sorted(validator.iter_errors(document), key=lambda e: (list(map(str, e.absolute_path)), e.validator))
    return [f"{_key_path(e.absolute_path)}: {_describe(e)}" for e in errors]


def _fill_defaults(node, schema: dict, root: dict):
    """Fill ``default`` values of the schema into ``node`` (objects only, recursively)."""
    if "$ref" in schema:
        ref = schema["$ref"].split("/")[-1]
        schema = root["$defs"][ref]
    if isinstance(node, dict) and "properties" in schema:
        for key, sub in schema["properties"].items():
            if key not in node and "default" in sub:
                node[key] = copy.deepcopy(sub["default"])
            if key in node:
                _fill_defaults(node[key], sub, root)
    elif isinstance(node, list) and "items" in schema:
        for item in node:
            _fill_defaults(item, schema["items"], root)
    return node


class YamlLoader(yaml.SafeLoader):
    """PyYAML's safe loader with YAML 1.2 floats: ``1e-6`` is a number, not the string '1e-6'."""


YamlLoader.yaml_implicit_resolvers = {k: [r for r in v if r[0] != "tag:yaml.org,2002:float"]
                                      for k, v in yaml.SafeLoader.yaml_implicit_resolvers.items()}
YamlLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"""^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+]?[0-9]+)?
                |[-+]?(?:[0-9][0-9_]*)(?:[eE][-+]?[0-9]+)
                |\.[0-9_]+(?:[eE][-+]?[0-9]+)?
                |[-+]?\.(?:inf|Inf|INF)
                |\.(?:nan|NaN|NAN))$""", re.X),
    list("-+0123456789."))


def parse_yaml(text: str):
    """Parse YAML text with :class:`YamlLoader`."""
    return yaml.load(text, Loader=YamlLoader)  # noqa: S506 - a SafeLoader subclass


def apply_overrides(document: dict, overrides: list[str], source: str = "--set") -> dict:
    """Apply ``key.path=value`` overrides (value parsed as YAML), creating objects as needed.

    List items are addressed by index: ``rooms.0.floor_z=3``.
    """
    for item in overrides:
        if "=" not in item:
            raise InputError(f"{source} {item!r}: expected key.path=value, e.g. sunlight.timestep_min=1")
        key, raw = item.split("=", 1)
        try:
            value = parse_yaml(raw)
        except yaml.YAMLError:
            value = raw
        parts = [p for p in key.strip().split(".") if p]
        if not parts:
            raise InputError(f"{source} {item!r}: empty key path")
        node = document
        for i, part in enumerate(parts):
            last = i == len(parts) - 1
            if isinstance(node, list):
                if not part.isdigit() or int(part) >= len(node):
                    raise InputError(f"{source} {item!r}: '{part}' is not an index of {'.'.join(parts[:i])}")
                if last:
                    node[int(part)] = value
                else:
                    node = node[int(part)]
            elif isinstance(node, dict):
                if last:
                    node[part] = value
                else:
                    node = node.setdefault(part, {})
            else:
                raise InputError(f"{source} {item!r}: {'.'.join(parts[:i])} is not an object")
    return document


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
        if len(xyz) != 3:
            raise InputError(f"{path}:{i + 1}: expected three numbers x, y, z, got {row}")
        points.append(xyz)
    if not points:
        raise InputError(f"{path}: no points found; expected rows x, y, z in metres")
    return points


def load_project(path: str | Path, overrides: list[str] | None = None) -> Project:
    """Read, validate and resolve a project file.

    Raises
    ------
    InputError
        With one line per problem, each naming the file and the key.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(f"{path}: project file not found") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read project file: {exc.strerror}") from None
    try:
        document = parse_yaml(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f":{mark.line + 1}" if mark else ""
        raise InputError(f"{path}{where}: not valid YAML: {getattr(exc, 'problem', exc)}") from None
    if not isinstance(document, dict):
        raise InputError(f"{path}: expected a mapping of keys (version, model, rooms, ...) at the top level")
    document = apply_overrides(document, overrides or [])
    errors = validation_errors(document)
    if errors:
        raise InputError("\n".join(f"{path}: {e}" for e in errors))
    if len(document["rooms"]) > 1:
        for i, room in enumerate(document["rooms"]):
            if "windows" not in room:
                raise InputError(f"{path}: rooms[{i}].windows: required when the project has several rooms; list the window names (globs) of room '{room['name']}'")
    schema = load_schema("project")
    config = _fill_defaults(copy.deepcopy(document), schema, schema)
    for name, values in THRESHOLDS.items():
        config.setdefault("thresholds", {}).setdefault(name, dict(values))
    _check_consistency(path, config)
    project = Project(path=path.resolve(), config=config)
    for i, room in enumerate(config["rooms"]):
        vp = room.get("view_points")
        if isinstance(vp, str):
            vp = [vp]
        if vp and all(isinstance(v, str) for v in vp):
            project.view_points[room["name"]] = [p for f in vp for p in read_points_csv(project.resolve(f), f"{path}: rooms[{i}].view_points")]
        elif vp is not None:
            project.view_points[room["name"]] = vp
    return project


def _check_consistency(path: Path, config: dict) -> None:
    """Rules a JSON Schema cannot express; each raises a one-line :class:`InputError`."""
    names = [r["name"] for r in config["rooms"]]
    dupes = sorted({n for n in names if names.count(n) > 1})
    if dupes:
        raise InputError(f"{path}: rooms: room name '{dupes[0]}' is used twice; give each room its own name")
    for i, f in enumerate(config["model"]["files"]):
        p = (path.parent / f["path"])
        if not p.is_file():
            raise InputError(f"{path}: model.files[{i}].path: file not found: {p}")
    for key in ("horizontal_sight_angle_deg", "outside_distance_m", "sunlight_hours"):
        t = config["thresholds"][key]
        if not t["minimum"] <= t["medium"] <= t["high"]:
            raise InputError(f"{path}: thresholds.{key}: expected minimum <= medium <= high, got {t}")
    if "sunlight" in config:
        if "location" not in config:
            raise InputError(f"{path}: location: required for the sunlight check (latitude, longitude, timezone); or remove the sunlight section")
        tz = config["location"]["timezone"]
        try:
            zoneinfo.ZoneInfo(tz)
        except (zoneinfo.ZoneInfoNotFoundError, ValueError):
            raise InputError(f"{path}: location.timezone: unknown IANA time zone {tz!r}; use a name such as Europe/Amsterdam") from None
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
    if "view" in config:
        st = config["view"]["distance_statistic"]
        if st.startswith("p") and not 0 <= int(st[1:]) <= 100:
            raise InputError(f"{path}: view.distance_statistic: percentile must be 0..100, got {st}")

