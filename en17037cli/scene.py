"""Scene: the project's geometry in one float64 frame near the rooms, with layers, windows and rooms.

Data flow: :func:`build_scene` takes a :class:`~en17037cli.project.Project`, reads each model
file, scales it to metres, turns y-up files to z-up, assigns every face a layer, drops
degenerate faces, shifts everything to a local origin (float64) and finds the windows
(edge-connected sets of coplanar ``window`` faces) and each room's floor and windows.
Engines receive a Scene and never read files.
"""
from __future__ import annotations

import fnmatch
import hashlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals
from en17037cli.io import read_model

#: Layer codes stored per face. ``ignore`` faces are dropped at load time.
LAYERS = ("window", "interior", "ground", "landscape")
WINDOW, INTERIOR, GROUND, LANDSCAPE = range(4)

#: Length of one model unit [m].
UNIT_SCALE_M = {"m": 1.0, "cm": 0.01, "mm": 0.001, "ft": 0.3048, "in": 0.0254}

#: Faces smaller than this are degenerate and dropped [m^2].
MIN_FACE_AREA_M2 = 1e-10
#: Window faces whose normals differ by less than this are coplanar [deg] ...
COPLANAR_ANGLE_DEG = 1.0
#: ... and whose planes are closer than this [m].
COPLANAR_OFFSET_M = 1e-3
#: Vertices closer than this are one vertex when finding windows [m].
WELD_M = 1e-5


@dataclass
class Window:
    """One opening: an edge-connected set of coplanar window faces.

    triangles : (k, 3, 3) float [m], local frame
    normal : (3,) unit normal, pointing out of the room that owns the window
    """

    name: str
    index: int
    face_ids: np.ndarray
    triangles: np.ndarray
    normal: np.ndarray
    area_m2: float

    @property
    def centroid(self) -> np.ndarray:
        _, areas = triangle_normals(self.triangles)
        return (self.triangles.mean(axis=1) * areas[:, None]).sum(axis=0) / areas.sum()

    @property
    def sill_z(self) -> float:
        return float(self.triangles[..., 2].min())

    @property
    def head_z(self) -> float:
        return float(self.triangles[..., 2].max())


@dataclass
class Room:
    """A room: floor level and polygon in the local frame, and its windows (outward normals set)."""

    name: str
    index: int
    floor_z: float
    floor: object  # shapely Polygon, local xy [m]
    windows: list
    config: dict
    floor_source: str = "given"


@dataclass
class Scene:
    """All faces of the project in a local float64 frame (world = local + origin) [m]."""

    origin: np.ndarray
    vertices: np.ndarray
    triangles: np.ndarray
    layer: np.ndarray
    obstructs_sun: np.ndarray
    names: list
    name_id: np.ndarray
    windows: list
    rooms: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    file_hashes: dict = field(default_factory=dict)
    true_north_deg: float = 0.0

    def faces_of(self, mask: np.ndarray) -> np.ndarray:
        """(k, 3, 3) float [m] triangles of the faces selected by a boolean mask."""
        return self.vertices[self.triangles[mask]]

    def to_local(self, points) -> np.ndarray:
        return np.asarray(points, dtype=np.float64) - self.origin

    def to_world(self, points) -> np.ndarray:
        return np.asarray(points, dtype=np.float64) + self.origin


def _file_hash(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return "sha256:" + h.hexdigest()


def _to_metres_z_up(vertices: np.ndarray, units: str, up_axis: str) -> np.ndarray:
    """Scale to metres and rotate y-up to z-up: (x, y, z) -> (x, -z, y)."""
    v = vertices * UNIT_SCALE_M[units]
    if up_axis == "y":
        v = np.column_stack([v[:, 0], -v[:, 2], v[:, 1]])
    return v


def _face_names(name: tuple) -> list:
    """Every name a glob may match for a face: object, group (whole and per word), material."""
    out = []
    for part in name:
        if part:
            out.append(part)
            out.extend(part.split())
    return out or [""]


def _assign_layers(spec: dict, mesh, where: str, stem: str):
    """Per-face layer code (-1 for ignore) and obstructs_sun flag from the file's layer rules."""
    mesh_names = [tuple(p.attrs.get(k, "") for k in ("object", "group", "material")) for p in mesh.parts]
    n_names = len(mesh_names)
    if "layer" in spec:
        code = LAYERS.index(spec["layer"]) if spec["layer"] != "ignore" else -1
        by_name = np.full(n_names, code)
        sun = np.full(n_names, bool(spec.get("obstructs_sun", True)))
    else:
        by_name = np.empty(n_names, dtype=int)
        sun = np.empty(n_names, dtype=bool)
        for i, name in enumerate(mesh_names):
            candidates = _face_names(tuple(name) + (stem,))
            for rule in spec["layers"]:
                if any(fnmatch.fnmatchcase(c, rule["match"]) for c in candidates):
                    by_name[i] = LAYERS.index(rule["layer"]) if rule["layer"] != "ignore" else -1
                    sun[i] = bool(rule.get("obstructs_sun", True))
                    break
            else:
                first = int(np.flatnonzero(mesh.part == i)[0]) if np.any(mesh.part == i) else 0
                label = ", ".join(f"'{p}'" for p in name if p) or "(no name)"
                raise InputError(
                    f"{where}.layers: face {first} ({label}) matches no layer rule; "
                    "add a rule for it or end the list with {match: \"*\", layer: ...}"
                )
    return by_name[mesh.part], sun[mesh.part]


def load_geometry(project):
    """Read every model file into world-frame float64 triangles with layers.

    Returns (vertices, triangles, layer, obstructs_sun, names, name_id, notes, warnings, hashes).
    """
    model = project.config["model"]
    all_v, all_t, all_l, all_s, all_id, names, notes, warnings, hashes = [], [], [], [], [], [], [], [], {}
    offset = 0
    dropped = 0
    for i, spec in enumerate(model["files"]):
        where = f"{project.path.name}: model.files[{i}]"
        path = project.resolve(spec["path"])
        if spec.get("layer") == "ignore" or (
            "layers" in spec and all(r["layer"] == "ignore" for r in spec["layers"])
        ):
            notes.append(f"{spec['path']}: every face goes to 'ignore'; file not loaded")
            continue
        hashes[spec["path"]] = _file_hash(path)
        mesh = read_model(path)
        mesh_names = [tuple(p.attrs.get(k, "") for k in ("object", "group", "material")) for p in mesh.parts]
        warnings.extend(mesh.warnings)
        units = spec.get("units", mesh.units or model["units"])
        up = spec.get("up_axis", mesh.up_axis or model["up_axis"])
        verts = _to_metres_z_up(mesh.vertices, units, up)
        layer, sun = _assign_layers(spec, mesh, where, path.stem)
        tris = mesh.triangles
        keep = layer >= 0
        tri_v = verts[tris]
        finite = np.all(np.isfinite(tri_v), axis=(1, 2))
        _, areas = triangle_normals(np.where(finite[:, None, None], tri_v, 0.0))
        good = finite & (areas > MIN_FACE_AREA_M2)
        dropped += int(np.count_nonzero(keep & ~good))
        keep &= good
        all_v.append(np.where(np.isfinite(verts), verts, 0.0))
        all_t.append(tris[keep] + offset)
        all_l.append(layer[keep])
        all_s.append(sun[keep])
        all_id.append(mesh.part[keep] + len(names))
        names.extend(n + (path.stem,) for n in mesh_names)
        offset += len(verts)
    if dropped:
        warnings.append(f"{dropped} degenerate, NaN or infinite faces dropped")
    if not all_v:
        raise InputError(f"{project.path.name}: model.files: no geometry loaded (every file is 'ignore')")
    return (np.concatenate(all_v), np.concatenate(all_t).astype(np.int64), np.concatenate(all_l).astype(np.int8),
            np.concatenate(all_s), names, np.concatenate(all_id), notes, warnings, hashes)


def find_windows(vertices: np.ndarray, triangles: np.ndarray, face_ids: np.ndarray, names: list, name_id: np.ndarray) -> list:
    """Group window faces into windows: edge-connected components of coplanar faces.

    Vertices are welded within :data:`WELD_M`; two faces sharing an edge join when their normals
    differ by less than :data:`COPLANAR_ANGLE_DEG` and their planes by less than
    :data:`COPLANAR_OFFSET_M`. Components are labelled by vectorised min-label propagation.
    """
    if len(face_ids) == 0:
        return []
    tri = triangles[face_ids]
    keys = np.round(vertices / WELD_M).astype(np.int64)
    _, welded = np.unique(keys, axis=0, return_inverse=True)
    welded = welded.reshape(-1)
    t = welded[tri]
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(tri)), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    e, o = edges[order], owner[order]
    same = np.all(e[1:] == e[:-1], axis=1)
    a, b = o[:-1][same], o[1:][same]
    tv = vertices[tri]
    normals, _ = triangle_normals(tv)
    cos_ok = np.abs(np.einsum("ij,ij->i", normals[a], normals[b])) >= np.cos(np.radians(COPLANAR_ANGLE_DEG))
    offset_ok = np.abs(np.einsum("ij,ij->i", normals[a], tv[b].mean(axis=1) - tv[a].mean(axis=1))) <= COPLANAR_OFFSET_M
    a, b = a[cos_ok & offset_ok], b[cos_ok & offset_ok]
    label = np.arange(len(tri))
    while True:  # min-label propagation; converges in at most the component diameter
        new = label.copy()
        np.minimum.at(new, a, label[b])
        np.minimum.at(new, b, label[a])
        new = new[new]
        if np.array_equal(new, label):
            break
        label = new
    windows = []
    roots = np.unique(label)
    base_names = []
    for root in roots:
        members = np.flatnonzero(label == root)
        obj, group, mtl, stem = (list(names[name_id[face_ids[members[0]]]]) + [""] * 4)[:4]
        base_names.append(obj or group or mtl or stem or "window")
    counts = {n: base_names.count(n) for n in base_names}
    seen: dict = {}
    for k, root in enumerate(roots):  # one small loop per window, not per face
        members = np.flatnonzero(label == root)
        tris = tv[members]
        n, areas = triangle_normals(tris)
        normal = (n * areas[:, None]).sum(axis=0)
        normal /= np.linalg.norm(normal)
        name = base_names[k]
        if counts[name] > 1:
            seen[name] = seen.get(name, 0) + 1
            name = f"{name} #{seen[name]}"
        windows.append(Window(name=name, index=k, face_ids=face_ids[members], triangles=tris,
                              normal=normal, area_m2=float(areas.sum())))
    return windows


def derive_floor(scene: Scene, floor_z: float, near: np.ndarray, where: str):
    """The floor polygon at ``floor_z``: union of horizontal interior faces within 2 cm of it,
    the part nearest to the room's windows (``near``, (k, 2) [m])."""
    import shapely

    mask = scene.layer == INTERIOR
    tris = scene.faces_of(mask)
    normals, areas = triangle_normals(tris)
    flat = (np.abs(normals[:, 2]) > 0.999) & np.all(np.abs(tris[..., 2] - floor_z) < 0.02, axis=1) & (areas > 0)
    if not np.any(flat):
        raise InputError(f"{where}: no horizontal interior faces at floor_z; check floor_z or give 'floor' as a polygon [[x, y], ...]")
    polys = shapely.polygons(tris[flat][..., :2])
    union = shapely.union_all(shapely.make_valid(polys)).buffer(1e-6).buffer(-1e-6)
    parts = [union] if union.geom_type == "Polygon" else [g for g in getattr(union, "geoms", []) if g.geom_type == "Polygon"]
    if not parts:
        raise InputError(f"{where}: the floor at floor_z has no area; give 'floor' as a polygon [[x, y], ...]")
    pts = shapely.points(near)
    dist = [float(np.min(shapely.distance(p, pts))) for p in parts]
    return parts[int(np.argmin(dist))]


def build_scene(project) -> Scene:
    """Load the project's geometry and resolve windows and rooms (see module docstring)."""
    import shapely

    verts, tris, layer, sun, names, name_id, notes, warnings, hashes = load_geometry(project)
    win_mask = layer == WINDOW
    if not np.any(win_mask):
        raise InputError(f"{project.path.name}: model.files: no face is on the 'window' layer; assign the glazing to layer: window")
    # Local origin: centre of the windows' bounding box, float64 (see trimesh/ray/ray_pyembree.py).
    wv = verts[tris[win_mask]].reshape(-1, 3)
    origin = 0.5 * (wv.min(axis=0) + wv.max(axis=0))
    local = verts - origin
    windows = find_windows(local, tris, np.flatnonzero(win_mask), names, name_id)
    check_glazing_over_opaque(local, tris, layer, windows, names, name_id, project.path.name)
    scene = Scene(origin=origin, vertices=local, triangles=tris, layer=layer, obstructs_sun=sun, names=names,
                  name_id=name_id, windows=windows, notes=notes, warnings=warnings, file_hashes=hashes,
                  true_north_deg=float(project.config["model"]["true_north_deg"]))
    for i, rc in enumerate(project.config["rooms"]):
        where = f"{project.path.name}: rooms[{i}] '{rc['name']}'"
        chosen = [w for w in windows if any(fnmatch.fnmatchcase(w.name, g) for g in rc["windows"])]
        if not chosen:
            known = ", ".join(f"'{w.name}'" for w in windows)
            raise InputError(f"{where}.windows: no window matches {rc['windows']}; windows found: {known}")
        floor_z = float(rc["floor_z"]) - origin[2]
        if "floor" in rc:
            poly = shapely.Polygon(np.asarray(rc["floor"], dtype=float) - origin[:2])
            if not poly.is_valid or poly.area <= 0:
                raise InputError(f"{where}.floor: not a simple polygon with area; list its corners in order")
            source = "given"
        else:
            near = np.array([w.centroid[:2] for w in chosen])
            poly = derive_floor(scene, floor_z, near, where)
            source = "derived from horizontal interior faces at floor_z"
        centre = np.array([poly.centroid.x, poly.centroid.y, floor_z + 1.5])
        oriented = []
        for w in chosen:  # one step per window: orient the normal away from the room
            n = w.normal if np.dot(w.normal, w.centroid - centre) >= 0 else -w.normal
            oriented.append(Window(w.name, w.index, w.face_ids, w.triangles, n, w.area_m2))
        scene.rooms.append(Room(name=rc["name"], index=i, floor_z=floor_z, floor=poly, windows=oriented,
                                config=rc, floor_source=source))
    return scene


#: An opaque face this close to a window's plane lies in it [m] ...
UNCUT_DISTANCE_M = 1e-3
#: ... and covering more than this share of the window's area makes it a modelling error.
UNCUT_SHARE = 0.01


def object_label(names: list, name_id: int) -> str:
    """'file: object' label of a face's name tuple (object, group, material, file stem)."""
    obj, group, mtl, stem = (list(names[name_id]) + [""] * 4)[:4]
    return f"{stem}: {obj or group or mtl or '(unnamed)'}" if stem else (obj or group or mtl or "(unnamed)")


def check_glazing_over_opaque(vertices, triangles, layer, windows, names, name_id, where: str) -> None:
    """Raise InputError where glazing lies over an opaque face that has no opening cut for it.

    An opaque face within :data:`UNCUT_DISTANCE_M` of a window's plane, whose overlap with the
    window covers more than :data:`UNCUT_SHARE` of the window's area, hides the glazing from every
    ray (a silent zero view). Walls whose opening is cut around a glazing in the same plane only
    touch its outline and pass. Vectorised over faces; one shapely overlap per window.
    """
    import shapely

    from en17037cli.geometry import window_axes

    opaque = np.flatnonzero(layer != WINDOW)
    if len(opaque) == 0:
        return
    for w in windows:  # one pass per window
        c, n = w.centroid, w.normal
        s_v = (vertices - c) @ n  # per vertex first: no (m, 3, 3) copy of a large scene
        near = opaque[np.all(np.abs(s_v[triangles[opaque]]) <= UNCUT_DISTANCE_M, axis=1)]
        if len(near) == 0:
            continue
        a, up = window_axes(n)
        rel_w = w.triangles - c
        win = shapely.union_all(shapely.polygons(np.stack([rel_w @ a, rel_w @ up], axis=-1))).buffer(0)
        rel = vertices[triangles[near]] - c
        faces = shapely.polygons(np.stack([rel @ a, rel @ up], axis=-1))
        overlap = shapely.area(shapely.intersection(shapely.make_valid(faces), win))
        ids = name_id[near]
        per_object = np.bincount(ids, overlap, len(names))
        worst = int(np.argmax(per_object))
        if per_object[worst] > UNCUT_SHARE * w.area_m2:
            win_label = object_label(names, int(name_id[w.face_ids[0]]))
            raise InputError(
                f"{where}: window '{w.name}' ({win_label}) lies on '{object_label(names, worst)}', an opaque face "
                f"within {UNCUT_DISTANCE_M * 1000:.0f} mm of the glazing covering {100 * per_object[worst] / w.area_m2:.0f}% "
                "of it: no ray could pass; cut the opening in that wall, or move the glazing off the wall plane")


def layer_counts(scene: Scene) -> dict:
    """Faces per layer, in :data:`LAYERS` order."""
    return {name: int(np.count_nonzero(scene.layer == code)) for code, name in enumerate(LAYERS)}
