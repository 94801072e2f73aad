"""``check --bcf``: the rooms and criteria that fail or cannot be assessed as BCF 2.1 topics (issue 43).

Checked against buildingSMART's own BCF 2.1 schemas (tests/data/bcf-2.1, validated with xmlschema)
and against the IFC file itself read with ifcopenshell: every selected component is an IfcSpace or
a window of the file; the topics are exactly the open (room, criterion) pairs of report.json, each
GUID the uuid5 of the space's GlobalId (read from the file by the space's Name) and the criterion;
two runs write the same bytes; point P of a sunlight topic lies at its window in the file's own
coordinates although the file is placed by an IfcMapConversion and the project turns and moves it.
"""
from __future__ import annotations

import io
import re
import uuid
import zipfile
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from en17037cli.cli import cli

pytest.importorskip("ifcopenshell")
xmlschema = pytest.importorskip("xmlschema")
import ifcopenshell  # noqa: E402
import ifcopenshell.geom  # noqa: E402

from en17037cli.samples.ifc import house  # noqa: E402

XSD = Path(__file__).parent / "data" / "bcf-2.1"
MODELS = Path(__file__).resolve().parents[2] / "shared" / "data" / "real-models"
#: The topic GUIDs' namespace as the module documents it: uuid5 of the tool's URL in the URL namespace
NAMESPACE = uuid.uuid5(uuid.NAMESPACE_URL, "https://github.com/en17037cli/en17037cli/bcf-topics")
VIEW = {"grid_spacing_m": 1.5, "eye_heights_m": [1.2], "angular_resolution_deg": 3.0, "refine_levels": 0}
SUN = {"date": "02-01", "period": {"start": "02-01", "end": "02-01"}}
TRANSFORM = {"rotate_deg": 30.0, "translate_m": [100.0, -40.0, 2.0]}


def schemas():
    return {n: xmlschema.XMLSchema(str(XSD / f"{n}.xsd")) for n in ("markup", "visinfo", "version")}


def project(tmp: Path, model: str, **extra) -> Path:
    doc = {"version": 1, "name": "house", "model": {"files": [{"path": model, "transform": TRANSFORM}]},
           "location": {"timezone": "Europe/Amsterdam"}, "rooms": [{"ifc_spaces": "*"}], "view": VIEW, "sunlight": SUN,
           "requirements": {"view": "medium", "sunlight": "high"}, **extra}
    p = tmp / "project.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return p


def check(*args) -> None:
    r = CliRunner().invoke(cli, ["check", *map(str, args), "-q"])
    assert r.exit_code in (0, 1), r.output


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The sample house (IfcMapConversion, the project turning and moving it) checked twice, pictures on."""
    tmp = tmp_path_factory.mktemp("bcf")
    ifc = house(tmp / "house.ifc", map_conversion=True)
    p = project(tmp, "house.ifc", report={"bcf": "topics.bcf"})
    check(p, "--out", tmp / "a")
    check(p, "--out", tmp / "b", "--bcf", tmp / "again.bcf")
    import json

    return {"ifc": ifc, "bcf": (tmp / "topics.bcf").read_bytes(), "again": (tmp / "again.bcf").read_bytes(),
            "report": json.loads((tmp / "a" / "report.json").read_text("utf-8")), "out": tmp / "a"}


def members(data: bytes) -> dict[str, bytes]:
    with zipfile.ZipFile(io.BytesIO(data)) as z:
        return {i.filename: z.read(i) for i in z.infolist()}


def test_same_inputs_same_bytes_and_fixed_zip_entries(run):
    assert run["bcf"] == run["again"]
    with zipfile.ZipFile(io.BytesIO(run["bcf"])) as z:
        infos = z.infolist()
    assert infos[0].filename == "bcf.version"
    assert {i.date_time for i in infos} == {(1980, 1, 1, 0, 0, 0)}
    folders = {i.filename for i in infos if i.filename.endswith("/")}
    assert folders == {i.filename.split("/")[0] + "/" for i in infos[1:]}  # a folder entry per topic (encoding guide)


def test_every_file_validates_against_the_bcf_2_1_schemas(run):
    xsd = schemas()
    files = members(run["bcf"])
    xsd["version"].validate(io.BytesIO(files["bcf.version"]))
    markups = [n for n in files if n.endswith("/markup.bcf")]
    assert markups
    for name in markups:
        xsd["markup"].validate(io.BytesIO(files[name]))
        xsd["visinfo"].validate(io.BytesIO(files[name.replace("markup.bcf", "viewpoint.bcfv")]))


def test_topics_are_the_open_room_criteria_with_stable_guids(run):
    f = ifcopenshell.open(str(run["ifc"]))
    space = {s.Name: s.GlobalId for s in f.by_type("IfcSpace")}
    expected = {}
    for room in run["report"]["rooms"]:
        name = re.search(r"\(([^()]*)\)$", room["name"]).group(1)  # the test reads its own house's names
        for c in ("daylight", "view", "sunlight", "glare"):
            sec = room.get(c)
            if sec and sec["status"] in ("fail", "not_assessable", "not_assessed"):
                expected[str(uuid.uuid5(NAMESPACE, f"{space[name]}/{c}"))] = (room, c, sec)
    files = members(run["bcf"])
    got = {n.split("/")[0] for n in files if n.endswith("/markup.bcf")}
    assert expected and got == set(expected)
    md = (run["out"] / "report.md").read_text("utf-8")
    for guid, (room, _, sec) in expected.items():
        markup = files[f"{guid}/markup.bcf"].decode()
        assert f"<Title>{room['name']}: " in markup and f"{sec['required']} required</Title>" in markup
        why = re.search(r"<Description>EN 17037 [0-9.]+ [^(]*\([a-z]+ required\): (.*?)\. Viewpoint:", markup, re.S).group(1)
        assert why.replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&") in md.replace("\\", "")
        assert f.by_guid(re.search(r'IfcProject="([^"]+)"', markup).group(1)).is_a("IfcProject")
        assert "<CreationDate>2026-01-01T00:00:00</CreationDate>" in markup  # the model's own date, never the clock
        assert files[f"{guid}/snapshot.png"].startswith(b"\x89PNG")


def test_selected_components_are_spaces_and_windows_of_the_file(run):
    f = ifcopenshell.open(str(run["ifc"]))
    files = members(run["bcf"])
    seen = set()
    for name, data in files.items():
        if name.endswith(".bcfv"):
            sel = re.search(r"<Selection>(.*?)</Selection>", data.decode(), re.S).group(1)
            ids = re.findall(r'IfcGuid="([^"]+)"', sel)
            classes = [f.by_guid(i).is_a() for i in ids]
            assert classes.count("IfcSpace") == 1 and set(classes) <= {"IfcSpace", "IfcWindow", "IfcDoor", "IfcPlate"}
            seen |= set(ids)
    assert {w.GlobalId for w in f.by_type("IfcWindow")} <= seen


def window_box(f, name: str) -> tuple[np.ndarray, np.ndarray]:
    """The bounding box [m] of an IfcWindow in the file's own coordinates (no map conversion)."""
    s = ifcopenshell.geom.settings()
    s.set("use-world-coords", True)
    w = next(x for x in f.by_type("IfcWindow") if x.Name == name)
    v = np.array(ifcopenshell.geom.create_shape(s, w).geometry.verts).reshape(-1, 3)
    return v.min(axis=0), v.max(axis=0)


def test_sunlight_camera_stands_at_point_p_in_the_files_coordinates(run):
    """P lies on the window's room-side face: within the window's box grown by the wall (0.3 m),
    in the file's coordinates, although the scene's are mapped (IfcMapConversion), turned and moved."""
    f = ifcopenshell.open(str(run["ifc"]))
    files = members(run["bcf"])
    n = 0
    for name, data in files.items():
        text = data.decode() if name.endswith("markup.bcf") else ""
        if "exposure to sunlight" in text:
            window = re.search(r"Viewpoint: point P of window '([^']+)'", text).group(1)
            vp = files[name.replace("markup.bcf", "viewpoint.bcfv")].decode()
            point = np.array([float(x) for x in re.findall(r"<CameraViewPoint>\s*<X>(.*?)</X>\s*<Y>(.*?)</Y>\s*<Z>(.*?)</Z>",
                                                            vp)[0]])
            direction = np.array([float(x) for x in re.findall(
                r"<CameraDirection>\s*<X>(.*?)</X>\s*<Y>(.*?)</Y>\s*<Z>(.*?)</Z>", vp)[0]])
            lo, hi = window_box(f, window)
            assert np.all(point >= lo - 0.3) and np.all(point <= hi + 0.3), (window, point, lo, hi)
            # looking out through the window: level (a wall window), towards its glass
            assert abs(direction[2]) < 1e-6 and (0.5 * (lo + hi) - point) @ direction > 0
            n += 1
    assert n == sum(r["sunlight"]["status"] != "pass" for r in run["report"]["rooms"]) >= 3


def test_a_folder_for_the_bcf_file_is_a_one_line_error_before_any_work(tmp_path):
    """report.bcf naming a folder: exit 2, one line naming the key, no report written."""
    from en17037cli.samples import BoxRoom, box_room_project

    p = box_room_project(tmp_path / "box", BoxRoom(), sunlight=SUN, view=None)
    doc = yaml.safe_load(p.read_text("utf-8")) | {"report": {"bcf": "topics"}}
    p.write_text(yaml.safe_dump(doc), encoding="utf-8")
    (tmp_path / "box" / "topics").mkdir()
    r = CliRunner().invoke(cli, ["check", str(p), "--out", str(tmp_path / "r")])
    assert r.exit_code == 2 and "report.bcf" in r.output and "is a folder" in r.output
    assert not (tmp_path / "r").exists()


def test_a_model_without_ifc_ids_names_its_objects(tmp_path):
    """An OBJ box room: components carry the objects' names (no IfcGuid), the camera the scene's frame."""
    from en17037cli.samples import BoxRoom, box_room_project

    p = box_room_project(tmp_path / "box", BoxRoom(), sunlight=SUN, view=None)
    check(p, "--out", tmp_path / "r", "--bcf", tmp_path / "box.bcf", "--no-plots", "--set", "requirements.sunlight=high")
    files = members((tmp_path / "box.bcf").read_bytes())
    xsd = schemas()
    vps = [n for n in files if n.endswith(".bcfv")]
    assert vps
    for n in vps:
        xsd["visinfo"].validate(io.BytesIO(files[n]))
        assert "<AuthoringToolId>glazing</AuthoringToolId>" in files[n].decode() and "IfcGuid" not in files[n].decode()
    assert not any(n.endswith("snapshot.png") for n in files)  # no pictures, no snapshot


@pytest.mark.skipif(not (MODELS / "SampleHouse4.ifc").is_file(), reason="the real models are absent")
def test_a_real_export_revit_2015(tmp_path):
    """SampleHouse4 (Revit 2015, mm): topics validate; each names the room's IfcSpace and the
    curtain walls' glazed IfcPlate among its windows."""
    doc = {"version": 1, "name": "sh4", "model": {"files": [{"path": str(MODELS / "SampleHouse4.ifc")}]},
           "location": {"timezone": "Europe/London"}, "rooms": [{"ifc_spaces": "*"}], "view": VIEW, "sunlight": SUN,
           "requirements": {"view": "minimum", "sunlight": "high"}}
    (tmp_path / "p.yaml").write_text(yaml.safe_dump(doc), encoding="utf-8")
    check(tmp_path / "p.yaml", "--out", tmp_path / "r", "--bcf", tmp_path / "sh4.bcf", "--no-plots")
    f = ifcopenshell.open(str(MODELS / "SampleHouse4.ifc"))
    files = members((tmp_path / "sh4.bcf").read_bytes())
    xsd = schemas()
    plates = 0
    for n, data in files.items():
        if n.endswith(".bcfv"):
            xsd["visinfo"].validate(io.BytesIO(data))
            classes = [f.by_guid(i).is_a() for i in re.findall(r'IfcGuid="([^"]+)"', data.decode())]
            assert "IfcSpace" in classes and set(classes) <= {"IfcSpace", "IfcWindow", "IfcDoor", "IfcPlate"}
            plates = max(plates, classes.count("IfcPlate"))
        elif n.endswith(".bcf"):
            xsd["markup"].validate(io.BytesIO(data))
    assert plates == 6  # the living room's two curtain walls, three glazed panels each


def test_affine_inverse_undoes_a_map_conversion_by_hand():
    """E = e + s (x a - y b), N = n + s (x b + y a), H = h + z with a = cos 30, b = sin 30, s = 2:
    the map point of (1, 2, 3) is taken back to (1, 2, 3), the map direction of +x back to +x."""
    from en17037cli.bim.frames import affine_inverse

    a, b, s = np.cos(np.radians(30)), np.sin(np.radians(30)), 2.0
    forward = lambda v: np.column_stack([85000 + s * (v[:, 0] * a - v[:, 1] * b), 446000 + s * (v[:, 0] * b + v[:, 1] * a),
                                         10 + v[:, 2]])  # noqa: E731
    mapped = np.array([[85000 + s * (1 * a - 2 * b), 446000 + s * (1 * b + 2 * a), 13.0]])
    p, d = affine_inverse(forward, mapped, np.array([[a, b, 0.0]]))
    assert np.allclose(p, [[1, 2, 3]], atol=1e-9) and np.allclose(d, [[1, 0, 0]], atol=1e-9)


def test_a_bcf_library_opens_it_and_reads_the_topics_and_their_components(run, tmp_path):
    """IfcOpenShell's BCF library (bcf-client, the reader BlenderBIM/Bonsai uses) loads the file and
    finds each topic's title, viewpoint and selected components: the room's IfcSpace among them."""
    bcfxml = pytest.importorskip("bcf.v2.bcfxml")
    path = tmp_path / "topics.bcf"
    path.write_bytes(run["bcf"])
    f = ifcopenshell.open(str(run["ifc"]))
    spaces = {s.GlobalId for s in f.by_type("IfcSpace")}
    with bcfxml.BcfXml.load(path) as bcf:
        topics = bcf.topics
        assert set(topics) == {n.split("/")[0] for n in members(run["bcf"]) if n.endswith("/markup.bcf")}
        for guid, handler in topics.items():
            assert handler.topic.guid == guid and handler.topic.title.endswith("required")
            (viewpoint,) = handler.viewpoints.values()
            selected = {c.ifc_guid for c in viewpoint.visualization_info.components.selection.component}
            assert selected & spaces, handler.topic.title
            assert all(f.by_guid(g).is_a() in ("IfcSpace", "IfcWindow", "IfcDoor", "IfcPlate", "IfcCurtainWall")
                       for g in selected)
