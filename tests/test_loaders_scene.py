"""Model loading and scene building: n-gons, formats, units, axes, georeferenced coordinates."""
import numpy as np
import pytest
import trimesh

from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals
from en17037cli.io import read_model
from en17037cli.io.obj import read_obj
from en17037cli.project import load_project
from en17037cli.samples import BoxRoom, box_room_project
from en17037cli.scene import LANDSCAPE, build_scene

CUBE_OBJ = """o cube
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 2 3
f 1 3 4
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
"""


def test_twelve_face_obj(tmp_path):
    p = tmp_path / "cube.obj"
    p.write_text(CUBE_OBJ)
    m = read_obj(p)
    assert m.triangles.shape == (12, 3)
    assert [dict(p.attrs) for p in m.parts] == [{"object": "cube"}]


def test_concave_ngon_obj_loads_with_its_true_area(tmp_path):
    p = tmp_path / "l.obj"
    p.write_text("v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\ng floor plate\nusemtl concrete\nf 3/1/1 4/1/1 5/1/1 6/1/1 1/1/1 2/1/1\n")
    m = read_obj(p)
    _, areas = triangle_normals(m.vertices[m.triangles])
    assert abs(areas.sum() - 3.0) < 1e-12
    assert [dict(p.attrs) for p in m.parts] == [{"group": "floor plate", "material": "concrete"}]


def test_negative_indices_and_corrupt_lines(tmp_path):
    p = tmp_path / "neg.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n")
    assert read_obj(p).triangles.tolist() == [[0, 1, 2]]
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 zero\n")
    with pytest.raises(InputError, match=r"bad.obj:1: corrupt OBJ vertex line"):
        read_obj(bad)


@pytest.mark.parametrize("ext", ["ply", "stl", "off", "glb"])
def test_other_formats_through_trimesh_keep_area(tmp_path, ext):
    box = trimesh.creation.box(extents=(2.0, 3.0, 4.0))
    p = tmp_path / f"box.{ext}"
    box.export(p)
    m = read_model(p)
    _, areas = triangle_normals(m.vertices[m.triangles])
    assert abs(areas.sum() - box.area) < 1e-9


def _scene(tmp_path, offset=(0.0, 0.0, 0.0), box=None, sub="p"):
    path = box_room_project(tmp_path / sub, box or BoxRoom(), offset=offset)
    return build_scene(load_project(path))


def test_georeferenced_scene_loads_to_the_same_local_geometry(tmp_path):
    a = _scene(tmp_path, sub="a")
    b = _scene(tmp_path, offset=(85000.0, 446000.0, 0.0), sub="b")
    assert np.allclose(b.origin - a.origin, [85000.0, 446000.0, 0.0], atol=1e-9)
    assert a.triangles.shape == b.triangles.shape
    # local coordinates agree to far better than float32's resolution near the rooms
    assert np.max(np.abs(a.vertices[a.triangles] - b.vertices[b.triangles])) < 1e-6
    wa, wb = a.rooms[0].windows[0], b.rooms[0].windows[0]
    assert np.allclose(wa.normal, wb.normal) and abs(wa.area_m2 - wb.area_m2) < 1e-9


def test_units_and_y_up_are_converted(tmp_path):
    import yaml

    path = box_room_project(tmp_path / "mm", BoxRoom())
    # rewrite the model in millimetres, y-up: (x, y, z)_z-up = (x, -z, y)_y-up
    text = []
    for line in (tmp_path / "mm" / "model.obj").read_text().splitlines():
        if line.startswith("v "):
            x, y, z = map(float, line.split()[1:])
            line = f"v {x * 1000} {z * 1000} {-y * 1000}"
        text.append(line)
    (tmp_path / "mm" / "model.obj").write_text("\n".join(text))
    doc = yaml.safe_load(path.read_text())
    doc["model"]["units"] = "mm"
    doc["model"]["up_axis"] = "y"
    path.write_text(yaml.safe_dump(doc))
    s = build_scene(load_project(path))
    ref = _scene(tmp_path, sub="ref")
    assert np.allclose(s.vertices[s.triangles], ref.vertices[ref.triangles], atol=1e-9)
    assert np.allclose(s.rooms[0].windows[0].normal, [0, -1, 0])


def test_windows_rooms_and_floor(tmp_path):
    s = _scene(tmp_path)
    counts = s.layer_counts()
    assert counts["window"] == 2 and counts["landscape"] == 10
    room = s.rooms[0]
    assert [w.name for w in room.windows] == ["glazing"]
    assert abs(room.floor.area - 24.0) < 1e-9  # 4 m x 6 m box, derived from the floor faces
    assert abs(room.windows[0].area_m2 - 2.8) < 1e-12


def test_degenerate_and_nan_faces_are_dropped_with_a_note(tmp_path):
    path = box_room_project(tmp_path / "d", BoxRoom())
    with open(tmp_path / "d" / "model.obj", "a") as fh:
        fh.write("o building\nv 0 0 0\nv 1 1 1\nv 2 2 2\nf -3 -2 -1\nv nan 0 0\nv 0 1 0\nv 0 0 1\nf -3 -2 -1\n")
    s = build_scene(load_project(path))
    assert "2 degenerate, NaN or infinite faces dropped" in s.warnings
    assert np.count_nonzero(s.layer == LANDSCAPE) == 10


def test_paper_viewpoint_grids_load_as_given():
    from pathlib import Path

    root = Path(__file__).resolve().parents[1] / "sample_projects" / "seed-office"
    p = load_project(root / "project-paper-grid.yaml")
    pts = p.rooms[0].view_points
    assert pts.shape == (2800, 3)
    assert sorted(set(np.round(pts[:, 2] - 9.3, 3))) == [1.2, 1.7]


def test_a_rule_naming_objects_is_not_matched_by_the_files_name():
    """``glass*`` in a file called ``glasshouse.obj`` places its glass, not every wall (each wall
    matched the file's name: the whole model went on the window layer, no room had walls); a rule
    that names no object of a file still places the whole file by its name."""
    from en17037cli.io.mesh import Mesh, Part
    from en17037cli.project.settings import LayerRule, ModelFile
    from en17037cli.scene.layers import assign_layers, layer_code

    def mesh(*names):
        return Mesh(vertices=np.zeros((3, 3)), triangles=np.zeros((len(names), 3), int), part=np.arange(len(names)),
                    parts=[Part(attrs={"object": n}) for n in names])

    rules = (LayerRule(match="glass*", layer="window"), LayerRule(match="*window*", layer="window"),
             LayerRule(match="*", layer="interior"))
    spec = ModelFile(path=None, display="glasshouse.obj", rules=rules, layer=None, obstructs_sun=True, units=None, up_axis=None)
    by_part, _, _ = assign_layers(spec, mesh("glass A", "walls", "slab"), "p.yaml", "glasshouse")
    assert [int(x) for x in by_part] == [layer_code("window"), layer_code("interior"), layer_code("interior")]
    by_part, _, _ = assign_layers(spec, mesh("Mesh", "Mesh.001"), "p.yaml", "ref_room_window")
    assert [int(x) for x in by_part] == [layer_code("window")] * 2
