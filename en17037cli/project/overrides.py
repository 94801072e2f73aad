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


#: (key path, (setting that makes it moot, its value, the value under which it counts), why): a key that has no effect while the
#: other setting has that value. One rule per line; the schema's descriptions say the same.
MOOT = (
    ("sunlight.timestep_min", ("sunlight.method", "exact", "sampled"),
     "sunlight.method is exact (every change of visibility found, polished to tolerance_s); the timestep "
     "is used by sunlight.method: sampled only"),
    ("daylight.aggregation", ("daylight.method", "daylight_factor", "climate_based"),
     "daylight.method is daylight_factor (one overcast sky); aggregation is used by climate_based only"),
    ("daylight.sky_subdivision", ("daylight.method", "daylight_factor", "climate_based"),
     "daylight.method is daylight_factor (one overcast sky, no sky patches); it is used by climate_based only"),
    ("daylight.sun_subdivision", ("daylight.method", "daylight_factor", "climate_based"),
     "daylight.method is daylight_factor (no sun); it is used by climate_based only"),
    *((f"daylight.radiance.{k}", ("daylight.method", "daylight_factor", "climate_based"),
       f"daylight.method is daylight_factor (one overcast sky); radiance.{k} is used by climate_based only")
      for k in ("replicates", "climate_rays")),
    *((f"daylight.radiance.{k}", ("daylight.method", "climate_based", "daylight_factor"),
       f"daylight.method is climate_based (replicates of climate_rays paths per point); radiance.{k} is used by "
       "daylight_factor only") for k in ("rays", "max_rays", "rel_tolerance", "abs_tolerance_pct", "stop_clear_of_thresholds")),
)


def _get(config: dict, path: str):
    node: object = config
    for part in path.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node


def moot_overrides(config: dict, overrides: list[str], source: str = "--set") -> list[str]:
    """One warning per override that changes nothing under the resolved ``config``: its key is moot
    while another setting has the value :data:`MOOT` names (``sunlight.timestep_min`` under the exact
    method), or it is ``daylight.weather`` while ``median_diffuse_lx`` is given to the daylight factor
    method. Each warning names the override, says why and what would make it count."""
    out = []
    for item in overrides:
        key = item.split("=", 1)[0].strip()
        for moot, (other, value, needed), why in MOOT:
            if key == moot and _get(config, other) == value:
                out.append(f"{source} {item}: no effect: {why}; add --set {other}={needed} for it to count")
        if key == "daylight.weather" and _get(config, "daylight.method") == "daylight_factor" \
                and _get(config, "daylight.median_diffuse_lx") is not None:
            out.append(f"{source} {item}: no effect: daylight.median_diffuse_lx is given, and the daylight "
                       "factor method takes E_v,d,med from it, not from the weather file; remove median_diffuse_lx "
                       "for the weather file to count")
    return out
