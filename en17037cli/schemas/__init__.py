"""The JSON Schemas of the project file and of report.json, shipped with the package.

``schemas/`` at the repository root holds the same files for readers of the repository;
``tests/test_schemas.py`` keeps the two copies identical.
"""
from __future__ import annotations

import json
from functools import cache
from importlib import resources


@cache
def load_schema(name: str) -> dict:
    """The JSON Schema ``name`` (``project`` or ``report``)."""
    text = resources.files("en17037cli.schemas").joinpath(f"{name}.schema.json").read_text("utf-8")
    return json.loads(text)
