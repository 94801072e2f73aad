"""Shared fixtures: box-room scenes built in code (en17037cli.samples) whose answers are known."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from en17037cli.criteria.sunlight.assess import assess_room as assess_sunlight
from en17037cli.criteria.view.assess import assess_points
from en17037cli.criteria.view.assess import assess_room as assess_view
from en17037cli.criteria.view.frames import room_geometry
from en17037cli.criteria.view.rays import ViewRays
from en17037cli.criteria.view.viewpoints import viewpoints
from en17037cli.project import load_project
from en17037cli.raytrace import RayEngine
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.scene import build_scene


class Built:
    """A project, its scene and a ray engine, for engine-level tests.

    The view runs in ``view.refine: exact`` unless the overrides say otherwise: these tests hold the
    exact mode to closed forms; tests/test_view_decided.py holds the decided mode to the exact one.
    """

    def __init__(self, path, overrides=()):
        overrides = list(overrides)
        if not any(o.startswith("view.refine=") for o in overrides):
            overrides.append("view.refine=exact")
        self.project = load_project(path, overrides)
        self.scene = build_scene(self.project)
        self.engine = RayEngine(self.scene.vertices, self.scene.triangles, self.scene.ray_groups())
        self.view_rays = ViewRays(self.engine, self.scene)
        self.room = self.scene.rooms[0]

    @property
    def view_cfg(self):
        return self.project.view

    @property
    def sun_cfg(self):
        return self.project.sunlight

    @property
    def thresholds(self):
        return self.project.thresholds

    def view_points(self, points_world, frame_depth_m: float | None = None):
        """:class:`~en17037cli.criteria.view.results.ViewPoints` of world points (n, 3) [m]."""
        depth = self.view_cfg.frame_depth_m if frame_depth_m is None else frame_depth_m
        rg = room_geometry(self.scene, self.room, depth)
        local = self.scene.to_local(np.asarray(points_world, dtype=float))
        return assess_points(self.view_rays, rg, local, self.view_cfg, self.thresholds)

    def _room_with(self, **spec_changes):
        if not spec_changes:
            return self.room
        spec = dataclasses.replace(self.room.spec, **{k: np.asarray(v, dtype=float) for k, v in spec_changes.items()})
        return dataclasses.replace(self.room, spec=spec)

    def view_room(self, view_points=None):
        """:class:`~en17037cli.criteria.view.results.ViewResult` of the room; ``view_points`` (n, 3) [m]
        world replaces the grid."""
        room = self._room_with(**({} if view_points is None else {"view_points": view_points}))
        plan = viewpoints(self.scene, room, self.view_cfg)
        return assess_view(self.view_rays, self.scene, room, self.view_cfg, self.thresholds, plan)

    def sunlight(self, sun_points=None):
        """:class:`~en17037cli.criteria.sunlight.results.SunlightResult` of the room; ``sun_points``
        (k, 3) [m] world replaces the rule's points P."""
        room = self._room_with(**({} if sun_points is None else {"sun_points": sun_points}))
        return assess_sunlight(self.engine, self.scene, room, self.sun_cfg, self.project.location, self.thresholds)


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
