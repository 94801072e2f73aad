"""Mutation tests (docs/mutation.md): placeholder, filled below."""
from __future__ import annotations
