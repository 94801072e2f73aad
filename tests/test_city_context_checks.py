"""A city model at another height than the model, and city objects running through a room: both
warned, with the project key that fixes each (scene/context.py).

Box room (en17037cli.samples.BoxRoom, without its street building): x in [-2, 2], y in [0, 6],
floor z 0, ceiling 3 m, a south window at y = 0 (x in [-1, 1], z in [0.8, 2.2]); placed at
(85000, 446000) in EPSG:7415 like tests/test_cityjson_scene.py.
"""
from __future__ import annotations

import json
from pathlib import Path

import yaml
from click.testing import CliRunner
from test_cityjson_scene import PLACE, SUN, VIEW, box_solid

from en17037cli.cli import cli
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.scene.context import HEIGHT_TOLERANCE_M

X0, Y0 = PLACE[:2]


def surface_block(x0, x1, y0, y1, z0, h, scale=0.001):
    """Vertices and MultiSurface boundaries of a LoD1 block given as surfaces (top and four sides)."""
    v, faces, _ = box_solid(x0, x1, y0, y1, h, scale)
    v = [[x, y, z + round(z0 / scale)] for x, y, z in v]
    return v, faces[1:]  # no bottom


def write_city(path: Path, objects: dict, dz: float = 0.0) -> Path:
    """A CityJSON 2.0 file in EPSG:7415 whose heights are those given plus ``dz`` (its datum) [m].

    objects : {id: ("Building", (x0, x1, y0, y1, height)) or (type, (x0, x1, y0, y1, z0, height)) as surfaces}
    with x, y relative to the box room's placement [m].
    """
    vertices, cos = [], {}
    for oid, (cls, dims) in objects.items():
        if cls == "Building":
            x0, x1, y0, y1, h = dims
            v, faces, sem = box_solid(x0, x1, y0, y1, h)
            geom = {"type": "Solid", "lod": "2.2", "boundaries": [[[[i + len(vertices) for i in r] for r in f] for f in faces]],
                    "semantics": sem}
        else:
            v, faces = surface_block(*dims)
            geom = {"type": "MultiSurface", "lod": "1", "boundaries": [[[i + len(vertices) for i in r] for r in f] for f in faces]}
        vertices += v
        cos[oid] = {"type": cls, "geometry": [geom]}
    doc = {"type": "CityJSON", "version": "2.0", "transform": {"scale": [0.001] * 3, "translate": [X0, Y0, dz]},
           "metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/7415"}, "CityObjects": cos,
           "vertices": vertices}
    path.write_text(json.dumps(doc))
    return path


def project(tmp_path: Path, objects: dict, dz: float = 0.0, floor_z: float = 0.0, **city_keys) -> Path:
    """The box room at PLACE (its floor at ``floor_z``) with the city model around it."""
    path = box_room_project(tmp_path / "p", BoxRoom(building_height=0), sunlight=SUN, view=VIEW)
    write_city(path.parent / "context.city.json", objects, dz)
    doc = yaml.safe_load(path.read_text())
    doc["model"]["files"][0]["transform"] = {"translate_m": [X0, Y0, floor_z]}
    doc["model"]["files"].append({"path": "context.city.json", **city_keys})
    doc["rooms"][0]["floor_z"] = floor_z
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def warnings_of(path: Path) -> list[str]:
    r = CliRunner().invoke(cli, ["validate", str(path), "--json"], catch_exceptions=False)
    assert r.exit_code == 0, r.output
    return json.loads(r.output)["warnings"]


def hours(path: Path, out: Path) -> float:
    r = CliRunner().invoke(cli, ["check", str(path), "--out", str(out), "-q"], catch_exceptions=False)
    assert r.exit_code in (0, 1), r.output
    return json.loads((out / "report.json").read_text())["rooms"][0]["sunlight"]["hours_h"]


#: Buildings around the room, as a 3D BAG or a Swiss LoD2 tile draws them: a 10 m street block 25 m
#: south, two houses east and west.
STREET = {"street": ("Building", (-200.0, 200.0, -35.0, -25.0, 10.0)),
          "east": ("Building", (12.0, 20.0, 0.0, 8.0, 7.0)), "west": ("Building", (-20.0, -12.0, 0.0, 8.0, 7.0))}


def test_a_city_at_sea_level_heights_is_warned_with_the_offset_that_fixes_it(tmp_path):
    """Heights above sea level (the ground 420 m up) around a model drawn at z 0: one warning with
    the translation; applied, the warning goes and the sun is the street's at the model's level."""
    path = project(tmp_path, STREET, dz=420.0)
    w = [x for x in warnings_of(path) if "the city model's ground" in x]
    assert len(w) == 1
    assert ("model.files[1] (context.city.json): the city model's ground near the building lies at z 420.00 m, "
            "420.00 m above the model's lowest floor (z 0.00 m, its lowest storey;") in w[0]
    assert w[0].endswith("set model.files[1].transform: {translate_m: [0, 0, -420]}")
    doc = yaml.safe_load(path.read_text())
    doc["model"]["files"][1]["transform"] = {"translate_m": [0, 0, -420]}
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    assert not [x for x in warnings_of(path) if "context.city.json" in x]
    # the street 25 m south, 10 m high, as at z 0 (a file at its own level gives the same hours)
    assert hours(path, tmp_path / "o") == hours(project(tmp_path / "z", STREET), tmp_path / "o0")


def test_the_ground_from_terrain_surfaces_and_below_the_floor(tmp_path):
    """A tile of ground surfaces only (LandUse lots, 0.2 m slabs) 5 m below the floor of a model
    placed at z 3: the offset raises the city, and keeps the file's own translation."""
    lots = {f"lot{k}": ("LandUse", (x, x + 9.0, -40.0, 40.0, 0.0, 0.2)) for k, x in enumerate((-30.0, 12.0, 22.0))}
    path = project(tmp_path, lots, dz=-2.0, floor_z=3.0, transform={"rotate_deg": 0, "translate_m": [0.0, 0.0, 0.5]})
    w = [x for x in warnings_of(path) if "the city model's ground" in x]
    # the lots' lowest points at -2 + 0.5 = -1.5 m, the floor at 3 m: 4.5 m below; 0.5 + 4.5 = 5
    assert "lies at z -1.50 m, 4.50 m below the model's lowest floor (z 3.00 m" in w[0]
    assert "a raised ground floor" in w[0] and w[0].endswith("{translate_m: [0, 0, 5]}")


def test_a_city_within_the_tolerance_is_silent(tmp_path):
    """A raised ground floor: the street's ground 0.8 m below the floor, within the tolerance."""
    assert HEIGHT_TOLERANCE_M == 1.0
    assert not [x for x in warnings_of(project(tmp_path, STREET, dz=-0.8)) if "context.city.json" in x]


def test_a_city_object_through_the_room_is_named_with_its_exclude_key(tmp_path):
    """A PlantCover block 1.1 m tall (as LoD1 tiles draw a planted strip) standing in the room, a
    lot 5 cm above the floor under all of it, and a hedge outside: only the block is named."""
    objects = {**STREET, "NL.green": ("PlantCover", (-1.5, 1.5, 2.0, 5.0, 0.0, 1.1)),
               "NL.lot": ("LandUse", (-10.0, 10.0, -5.0, 10.0, 0.0, 0.05)),
               "NL.hedge": ("PlantCover", (-10.0, 10.0, -3.0, -2.0, 0.0, 1.5))}
    path = project(tmp_path, objects)
    w = [x for x in warnings_of(path) if "runs through" in x]
    assert w == ["project.yaml: model.files[1] (context.city.json): PlantCover 'NL.green' runs through 1 room(s) ('box room'): "
                 "its faces lie inside them, 0.10-1.10 m above their floors, where it hides the view and the sun (the city "
                 "model overlaps the building, or stands at another height); leave it out with model.files[1].exclude: "
                 "['NL.green'], or place the file (model.files[1].transform)"]
    doc = yaml.safe_load(path.read_text())
    doc["model"]["files"][1]["exclude"] = ["NL.green"]
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    assert not [x for x in warnings_of(path) if "context.city.json" in x]
