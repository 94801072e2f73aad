"""Validation of a project document against ``project.schema.json``, with one line per problem, and
the schema's defaults filled in."""
from __future__ import annotations

import copy
import json

import jsonschema

from en17037cli.schemas import load_schema


def key_path(parts) -> str:
    """``rooms[0].floor_z`` from a path of keys and indices."""
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
    if v == "oneOf" and isinstance(inst, dict) and error.path and isinstance(error.path[-1], int) and "layer" not in inst \
            and "path" not in inst:
        return ("a room needs 'name' and 'floor_z', or 'ifc_spaces' / 'gbxml_spaces' (one room per IfcSpace / gbXML Space "
                "of the model)")
    if v == "not" and isinstance(inst, dict) and "path" in inst:
        return "give 'layer' (one layer for the whole file) or 'layers' (rules by name), not both"
    if v == "anyOf" and isinstance(inst, dict) and "layer" in inst:
        return "a layer rule needs 'match' or a key to match (class, name, id, type, storey, surface, parent, attributes)"
    if v == "anyOf" and not error.path and isinstance(inst, dict):
        return ("missing required key 'rooms' (the rooms check assesses), or 'screen' (the facades 'en17037 screen' "
                "probes in a city model)")
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
    return [f"{key_path(e.absolute_path)}: {_describe(e)}" for e in errors]


def fill_defaults(node, schema: dict, root: dict):
    """Fill ``default`` values of the schema into ``node`` (objects only, recursively)."""
    if "$ref" in schema:
        ref = schema["$ref"].split("/")[-1]
        schema = root["$defs"][ref]
    if isinstance(node, dict) and "properties" in schema:
        for key, sub in schema["properties"].items():
            if key not in node and "default" in sub:
                node[key] = copy.deepcopy(sub["default"])
            if key in node:
                fill_defaults(node[key], sub, root)
    elif isinstance(node, list) and "items" in schema:
        for item in node:
            fill_defaults(item, schema["items"], root)
    return node
