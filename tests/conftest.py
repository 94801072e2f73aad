"""Shared fixtures: box-room scenes built in code (en17037cli.samples) whose answers are known."""
from __future__ import annotations

import numpy as np
import pytest

from en17037cli.project import load_project
from en17037cli.raytrace import RayEngine
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.scene import build_scene


class Built:
    """A project, its scene and a ray engine, for engine-level tests."""

    def __init__(self, path, overrides=()):
        self.project = load_project(path, list(overrides))
        self.scene = build_scene(self.project)
        self.engine = RayEngine(self.scene)
        self.room = self.scene.rooms[0]

    @property
    def view_cfg(self):
        return self.project.config["view"]

    @property
    def sun_cfg(self):
        return self.project.config["sunlight"]

    @property
    def thresholds(self):
        return self.project.config["thresholds"]


@pytest.fixture
def build(tmp_path):
    """build(BoxRoom(...), offset=(...), overrides=[...], **project kwargs) -> Built."""
    made = []

    def _build(box: BoxRoom | None = None, offset=(0.0, 0.0, 0.0), overrides=(), sub="p", **kw):
        path = box_room_project(tmp_path / sub, box or BoxRoom(), offset=offset, **kw)
        b = Built(path, overrides)
        made.append(b)
        return b

    yield _build
    for b in made:
        b.engine.close()


@pytest.fixture
def box_project(tmp_path):
    return box_room_project(tmp_path / "box", BoxRoom(), sunlight={"date": "worst"}, view={"grid_spacing_m": 1.0})


def assert_close(actual, expected, tol, what=""):
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    assert np.all(np.abs(actual - expected) <= tol), f"{what}: {actual} vs {expected} (tol {tol})"
