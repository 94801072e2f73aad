"""Mutation tests (issue 39): which faces of an IFC element are glass (``io/ifc_glazing.py``): the
style rules on stand-in materials, the IFC relations on stand-in entities and the panes found from
geometry on hand-built windows (frames, plates, one solid of frame and glass).
"""
from __future__ import annotations

from types import SimpleNamespace

import pytest

from en17037cli.io import ifc_glazing as g

NAN = float("nan")


class _Product:
    def __init__(self, cls):
        self.cls = cls

    def is_a(self, name=None):
        return self.cls if name is None else name == self.cls


@pytest.mark.parametrize("name, cls, default", [
    ("DefaultMaterial", "IfcWall", True), ("DefaultMaterial7", "IfcWall", True), ("IfcWindow", "IfcWindow", True),
    ("IfcWindow", "IfcDoor", False), ("IfcWindow frame", "IfcWindow", False), ("Glass", "IfcWindow", False),
    ("", "IfcWindow", False), (None, "IfcWindow", False), ("Ifc", "IfcWindow", False)])
def test_default_material_by_hand(name, cls, default):
    assert g.is_default_material(SimpleNamespace(name=name), _Product(cls)) is default


@pytest.mark.parametrize("t, name, glass", [
    (0.6, "frame", True), (0.5, "frame", True), (0.49, "Glass", False), (0.01, "x", False),
    (0.0, "Clear GLAS", True), (0.0, "steel", False), (NAN, "Verre clair", True), (NAN, "vetro", True),
    (NAN, "vidrio", True), (NAN, "Glazed unit", True), (NAN, "Vitrage", True), (NAN, "glazing", True),
    (NAN, "frame", None), (NAN, None, None)])
def test_glass_by_style_by_hand(t, name, glass):
    assert g.glass_by_style(SimpleNamespace(transparency=t, name=name)) is glass


def test_glass_by_style_without_a_transparency_attribute():
    assert g.glass_by_style(SimpleNamespace(name="frame")) is None
    assert g.glass_by_style(SimpleNamespace(name="glass")) is True
    assert g.glass_by_style(SimpleNamespace()) is None


@pytest.mark.parametrize("t, name, opaque", [
    (0.05, "panel", True), (0.099, None, True), (0.1, "panel", False), (0.0, "panel", False), (0.05, "Glass", False),
    (NAN, "panel", False), (0.7, "panel", False)])
def test_opaque_by_style_by_hand(t, name, opaque):
    assert g.opaque_by_style(SimpleNamespace(transparency=t, name=name)) is opaque
