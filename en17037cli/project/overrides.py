"""``--set key.path=value`` overrides of a project document."""
from __future__ import annotations

import yaml

from en17037cli.errors import InputError
from en17037cli.project.yaml12 import parse_yaml


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
