"""The JSON Schemas: the repository's copies are the package's, and reports validate against them."""
from __future__ import annotations

from pathlib import Path

import pytest

from en17037cli.schemas import load_schema

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("name", ["project", "report"])
def test_repository_schemas_are_the_package_schemas(name):
    """``schemas/`` (for readers of the repository) and ``en17037cli/schemas/`` (shipped) must not drift."""
    repo = (ROOT / "schemas" / f"{name}.schema.json").read_bytes()
    shipped = (ROOT / "en17037cli" / "schemas" / f"{name}.schema.json").read_bytes()
    assert repo == shipped, f"schemas/{name}.schema.json differs from en17037cli/schemas/{name}.schema.json; copy one over the other"
    assert load_schema(name)["$schema"].endswith("2020-12/schema")
