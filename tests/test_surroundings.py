"""A model with a few landscape objects but no surroundings in front of a room (issue 35): ArchiCAD
13's family house has a tree, an awning, two ladders and a fireplace as IfcBuildingElementProxy
(landscape by default); 4 of its rooms failed view on the layers at level 'none', and nothing said
the model had no surroundings there (a model with no landscape at all says so). The box room of
en17037cli/samples, its street building shrunk to a shed or replaced by an awning on its own
facade, gives the closed forms."""
from __future__ import annotations

import json
import math

import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli
from en17037cli.criteria.view.surroundings import MIN_DEPTH_M, horizon_share
from en17037cli.project import load_project
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.scene.build import build_scene

VIEW = {"grid_spacing_m": 1.0, "eye_heights_m": [1.2]}


def scene_of(tmp_path, b: BoxRoom):
    return build_scene(load_project(box_room_project(tmp_path, b, sunlight=None, view=VIEW)))


@pytest.mark.parametrize("length", [4.0, 20.0, 400.0])
def test_the_horizon_a_street_building_covers_is_its_angle_seen_from_the_window(tmp_path, length):
    """A building of length L whose face lies s = 25 m in front of the window's centre, centred on
    it, covers 2 atan(L / 2s) of the 180 deg in front: the exact union of its faces' intervals."""
    b = BoxRoom(building_length=length)
    sc = scene_of(tmp_path, b)
    (w,) = sc.rooms[0].windows
    assert abs(horizon_share(sc, w) - 2 * math.atan(length / 2 / b.street) / math.pi) < 1e-12


def run(project, *sets) -> dict:
    args = ["check", str(project), "--out", str(project.parent / "r"), "--no-plots", "-q", "--set", "requirements.sunlight=none"]
    r = CliRunner().invoke(cli, args + [a for s in sets for a in ("--set", s)], catch_exceptions=False)
    assert r.exit_code in (0, 1), r.output
    return json.loads((project.parent / "r" / "report.json").read_text())["rooms"][0]["view"]


def shed_project(tmp_path, east_m: float = 8.0):
    """The box room whose only landscape is a 4 m shed 25 m away (the box room's building, shrunk),
    ``east_m`` east of the window's axis: from most points of the room the window does not show it."""
    from en17037cli.samples.box import box_room_polygons, write_obj

    b = BoxRoom(building_length=4.0)
    project = box_room_project(tmp_path, b, sunlight=None, view=VIEW)
    objects = box_room_polygons(b)
    objects["building"] = [[(x + east_m, y, z) for x, y, z in poly] for poly in objects["building"]]
    write_obj(tmp_path / "model.obj", objects)
    return project


def test_a_room_whose_only_surroundings_are_a_shed_is_not_assessable(tmp_path):
    """The shed (x 6 to 10 m, y -25 to -35 m) covers from its far corner at atan(6/35) to its near one at
    atan(10/25): 6.7 % of the horizon in front of the window.
    Before: the room failed at 'none' on the layers, nothing saying the model had no surroundings
    there; now not assessable, the reason naming the share and the key (validate says it before any
    ray); ``view.surroundings_min_share: 0`` judges the layers on what there is: 'none', as before."""
    project = shed_project(tmp_path / "p")
    sc = build_scene(load_project(project))
    assert abs(horizon_share(sc, sc.rooms[0].windows[0]) - (math.atan(10 / 25) - math.atan(6 / 35)) / math.pi) < 1e-12
    judged = run(project, "view.surroundings_min_share=0")
    assert judged["status"] == "fail" and judged["level"] == "none", judged
    assert judged["eye_heights"][0]["level_by_criterion"]["layers"] == "none", judged["eye_heights"][0]["level_by_criterion"]
    view = run(project)
    assert view["status"] == "not_assessable", view
    assert ("the model has no surroundings in front of the room's windows (its landscape standing 2 m or more covers 7% of "
            "the horizon in front of them, 25% needed to judge the layers; the landscape layer holds 1 object(s): 'building'; "
            "what lies flat or low, terrain, markings, bicycles, is no surroundings)") in view["reason"]
    assert view["error_estimates"]["method"]["solid_angle_sr"].startswith("not traced")
    r = CliRunner().invoke(cli, ["validate", str(project)], catch_exceptions=False)
    assert "view: room 'box room' NOT ASSESSABLE: the view layers cannot be assessed: the model has no surroundings" in r.output


def test_the_buildings_own_awning_is_not_its_surroundings(tmp_path):
    """An awning on the facade on the landscape layer (as ArchiCAD's proxies read), 1.5 m deep:
    nearer than MIN_DEPTH_M, it is the building's own, and the room has no surroundings. Before:
    the room's layers reached minimum on the awning's underside."""
    from en17037cli.samples.box import box_room_polygons, write_obj

    objects = box_room_polygons(BoxRoom(building_height=0))
    objects["awning"] = [[(-1.5, 0.0, 2.4), (1.5, 0.0, 2.4), (1.5, -1.5, 2.4), (-1.5, -1.5, 2.4)]]
    assert 1.5 < MIN_DEPTH_M
    (tmp_path / "a").mkdir()
    write_obj(tmp_path / "a" / "model.obj", objects)
    doc = yaml.safe_load(box_room_project(tmp_path / "tmp", BoxRoom(), sunlight=None, view=VIEW).read_text())
    doc["model"]["files"] = [{"path": "model.obj", "layers": [{"match": "glazing", "layer": "window"},
                                                              {"match": "ground", "layer": "ground"},
                                                              {"match": "awning", "layer": "landscape"},
                                                              {"match": "*", "layer": "interior"}]}]
    (tmp_path / "a" / "project.yaml").write_text(yaml.safe_dump(doc))
    sc = build_scene(load_project(tmp_path / "a" / "project.yaml"))
    assert horizon_share(sc, sc.rooms[0].windows[0]) == 0.0
    view = run(tmp_path / "a" / "project.yaml")
    assert view["status"] == "not_assessable" and "covers 0% of the horizon" in view["reason"], view


def test_a_street_keeps_its_layers_judged(tmp_path):
    """The guard: the sample's 400 m street building (92 % of the horizon) is surroundings."""
    project = box_room_project(tmp_path / "p", BoxRoom(), sunlight=None, view=VIEW)
    assert run(project)["status"] in ("pass", "fail")


def lying_project(tmp_path, extra: dict):
    """The box room with no street building: its landscape the objects ``extra`` (name -> polygons)."""
    from en17037cli.samples.box import box_room_polygons, write_obj

    objects = {**box_room_polygons(BoxRoom(building_height=0)), **extra}
    (tmp_path / "a").mkdir()
    write_obj(tmp_path / "a" / "model.obj", objects)
    doc = yaml.safe_load(box_room_project(tmp_path / "tmp", BoxRoom(), sunlight=None, view=VIEW).read_text())
    doc["model"]["files"] = [{"path": "model.obj", "layers": [{"match": "glazing", "layer": "window"},
                                                              {"match": "ground", "layer": "ground"},
                                                              *({"match": k, "layer": "landscape"} for k in extra),
                                                              {"match": "*", "layer": "interior"}]}]
    (tmp_path / "a" / "project.yaml").write_text(yaml.safe_dump(doc))
    return tmp_path / "a" / "project.yaml"


def _slab(x0, x1, y0, y1, z0, z1):
    """The six faces of a box [m]."""
    from en17037cli.samples.box import _rect_x, _rect_y, _rect_z

    return [_rect_z(z0, x0, x1, y0, y1), _rect_z(z1, x0, x1, y0, y1), _rect_y(y0, x0, x1, z0, z1), _rect_y(y1, x0, x1, z0, z1),
            _rect_x(x0, y0, y1, z0, z1), _rect_x(x1, y0, y1, z0, z1)]


def test_terrain_and_low_objects_on_the_landscape_layer_are_no_surroundings(tmp_path):
    """Revit's topography, parking bays and bicycles exported as IfcBuildingElementProxy read as
    landscape (FM_ARC_DigitalHub): here a terrain slab 0.3 m thick from 3 m to 200 m in front of the
    window, 400 m wide, and a row of 1 m bicycle stands 400 m long 10 m out. Before: the terrain
    alone covered 2 atan(200 / 3) / pi = 99 % of the horizon, and the room's layers were judged on
    ground read as landscape. Now neither stands (flat; lower than MIN_HEIGHT_M): 0 %, not
    assessable, the reason saying what does not count; a tree 8 m tall (x -3 to 3 m, 20 m out) is
    surroundings again: 2 atan(3 / 20) / pi of the horizon from its near face."""
    from en17037cli.criteria.view.surroundings import MIN_HEIGHT_M

    terrain = _slab(-200.0, 200.0, -200.0, -3.0, -0.3, 0.0)
    stands = _slab(-200.0, 200.0, -11.0, -10.0, 0.0, 1.0)
    assert 1.0 < MIN_HEIGHT_M
    p = lying_project(tmp_path, {"terrain": terrain, "stands": stands})
    sc = build_scene(load_project(p))
    assert horizon_share(sc, sc.rooms[0].windows[0]) == 0.0
    view = run(p)
    assert view["status"] == "not_assessable" and "covers 0% of the horizon" in view["reason"], view
    assert "what lies flat or low, terrain, markings, bicycles, is no surroundings" in view["reason"]
    tree = _slab(-3.0, 3.0, -26.0, -20.0, 0.0, 8.0)
    (tmp_path / "t").mkdir()
    sc = build_scene(load_project(lying_project(tmp_path / "t", {"terrain": terrain, "stands": stands, "tree": tree})))
    assert abs(horizon_share(sc, sc.rooms[0].windows[0]) - 2 * math.atan(3 / 20) / math.pi) < 1e-12
