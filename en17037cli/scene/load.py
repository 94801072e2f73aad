"""Reading the model files of a project into one set of world-frame float64 triangles with layers."""
from __future__ import annotations

import contextvars
import hashlib
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals
from en17037cli.io import ReadOptions, is_context, read_model
from en17037cli.io.mesh import Mesh, Space
from en17037cli.project.settings import ModelFile, ModelSettings, Transform
from en17037cli.scene.georef import located_files
from en17037cli.scene.layers import assign_layers, assign_optics
from en17037cli.scene.model import INTERIOR, WINDOW, Geometry

#: Length of one model unit [m].
UNIT_SCALE_M = {"m": 1.0, "cm": 0.01, "mm": 0.001, "ft": 0.3048, "in": 0.0254}

#: Faces smaller than this are degenerate and dropped [m^2].
MIN_FACE_AREA_M2 = 1e-10


def file_hash(path: Path) -> str:
    """``sha256:<hex>`` of a file's bytes."""
    h = hashlib.sha256()
    with path.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return "sha256:" + h.hexdigest()


def to_metres_z_up(vertices: np.ndarray, units: str, up_axis: str) -> np.ndarray:
    """Scale to metres and rotate y-up to z-up: (x, y, z) -> (x, -z, y)."""
    v = vertices * UNIT_SCALE_M[units]
    if up_axis == "y":
        v = np.column_stack([v[:, 0], -v[:, 2], v[:, 1]])
    return v


def transformed(vertices: np.ndarray, t: Transform | None) -> np.ndarray:
    """Vertices (n, 3) [m] rotated about +z by ``t.rotate_deg`` (counterclockwise seen from above), then translated."""
    if t is None:
        return vertices
    a = np.radians(t.rotate_deg)
    c, s = np.cos(a), np.sin(a)
    x, y = vertices[:, 0], vertices[:, 1]
    return np.column_stack([c * x - s * y, s * x + c * y, vertices[:, 2]]) + np.asarray(t.translate_m, dtype=float)


@dataclass
class LoadedFile:
    """One model file read into metres, z up, placed: its triangles, parts and per-part layers."""

    index: int
    spec: ModelFile
    mesh: Mesh
    vertices: np.ndarray  # (n, 3) float64 [m], world frame
    part_layer: np.ndarray  # (parts,) int layer code, -1 ignore
    part_sun: np.ndarray  # (parts,) bool
    part_optics: np.ndarray | None = None  # (parts, 2) reflectance, transmittance from the rules (NaN: default), or None


#: Meshes already read, by (path, size, modification time, options), while a
#: :class:`en17037cli.Session` is active (design loops read the same context many times); None otherwise.
READ_CACHE: contextvars.ContextVar[dict | None] = contextvars.ContextVar("en17037_read_cache", default=None)


def cached_read(path: Path, options: ReadOptions) -> Mesh:
    """:func:`read_model`, or the mesh read before from the same unchanged file with the same options
    while a read cache is active (:data:`READ_CACHE`). Meshes are not changed after reading."""
    cache = READ_CACHE.get()
    if cache is None:
        return read_model(path, options)
    st = path.stat()
    key = (str(path.resolve()), st.st_size, st.st_mtime_ns, options)
    if key not in cache:
        cache[key] = read_model(path, options)
    return cache[key]


def read_file(i: int, spec: ModelFile, model: ModelSettings, where: str, options: ReadOptions, warnings: list) -> LoadedFile:
    """Read model file ``i``, scale it to metres, turn it z-up, place it (``transform``) and layer its parts."""
    mesh = cached_read(spec.path, options)
    warnings.extend(mesh.warnings)
    units = spec.units or mesh.units or model.units
    up = spec.up_axis or mesh.up_axis or model.up_axis
    part_layer, part_sun, unmatched = assign_layers(spec, mesh, f"{where}: model.files[{i}]", spec.path.stem)
    if mesh.openings_drawn:
        mesh = _cut_drawn_openings(mesh, part_layer, UNIT_SCALE_M[units], spec.display)
    if any(p.window for p in mesh.parts):  # keyed windows (IFC) set in walls the file does not cut
        from en17037cli.scene.uncut import cut_uncut_walls

        mesh = cut_uncut_walls(mesh, part_layer, WINDOW, UNIT_SCALE_M[units], spec.display)
    verts = transformed(to_metres_z_up(mesh.vertices, units, up), spec.transform)
    if spec.units or mesh.units is None:  # the project gives the unit: is the model plausible in it?
        from en17037cli.scene.units import check_units

        check_units(verts, mesh.triangles, mesh.part, part_layer, WINDOW, (INTERIOR, WINDOW), units,
                    f"model.files[{i}].units" if spec.units else "model.units", f"{where}: model.files[{i}] ({spec.display})")
    warnings.extend(unmatched)
    return LoadedFile(i, spec, mesh, verts, part_layer, part_sun, assign_optics(spec, mesh, spec.path.stem))


def _cut_drawn_openings(mesh: Mesh, part_layer: np.ndarray, unit_m: float, name: str) -> Mesh:
    """The mesh with each window cut out of the coplanar opaque faces it is drawn on (DXF), and a note."""
    from en17037cli.io.openings import PLANE_TOLERANCE_M, cut_openings

    v, t, p, n = cut_openings(mesh.vertices, mesh.triangles, mesh.part, part_layer == WINDOW,
                              (part_layer >= 0) & (part_layer != WINDOW), PLANE_TOLERANCE_M / unit_m)
    if n == 0:
        return mesh
    note = (f"{name}: {n} window plane{'s' * (n != 1)} drawn on coplanar opaque faces (walls drawn whole with the "
            "windows on top, as EnergyPlus writes them): the openings cut in those faces")
    return replace(mesh, vertices=v, triangles=t, part=p, notes=[*mesh.notes, note])


#: Compound CRSs whose horizontal part is another code: files in either line up in plan.
HORIZONTAL_CRS = {"EPSG:7415": "EPSG:28992"}  # Amersfoort / RD New + NAP height -> RD New


def _plan_crs(code: str) -> str:
    """The horizontal CRS of a code: 'EPSG:2263+6360' -> 'EPSG:2263', EPSG:7415 -> EPSG:28992."""
    code = code.split("+")[0].strip()
    return HORIZONTAL_CRS.get(code, code)


def check_crs(files: list[LoadedFile], where: str) -> str | None:
    """The one CRS the georeferenced files share (a file's own ``crs`` key wins over what it says,
    a file its reader projected is in the CRS it was projected to), or None when none says;
    different CRSs are an input error naming both files."""
    said = [(f.spec.display, f.mesh.site.crs if f.mesh.site and f.mesh.site.reprojected_from
             else f.spec.crs or (f.mesh.site.crs if f.mesh.site else None)) for f in files]
    said = [(d, c) for d, c in said if c]
    if not said:
        return None
    first = said[0]
    for d, c in said[1:]:
        if _plan_crs(c) != _plan_crs(first[1]):
            raise InputError(f"{where}: model.files: {first[0]} is in {first[1]} but {d} is in {c}; give both in one CRS "
                             "(reproject one, or set the 'crs' key of a file whose own is wrong)")
    return first[1]


def read_summary(mesh: Mesh) -> str:
    """What a file's reader read and left out, one line: the reader's own (spaces, openings, objects
    by LoD...), else its triangles, objects and spaces counted."""
    if mesh.summary:
        return mesh.summary
    n, k = len(mesh.triangles), len(mesh.parts)
    spaces = f", {len(mesh.spaces)} space{'s' * (len(mesh.spaces) != 1)}" if mesh.spaces else ""
    return f"{n} triangle{'s' * (n != 1)} in {k} part{'s' * (k != 1)} (named objects, each with its layer){spaces}"


def building_footprint(files: list[LoadedFile]):
    """Plan of the model's own building [m, world xy]: its horizontal interior faces (slabs, floors,
    roofs) unioned, or the convex hull of its interior faces where none is horizontal; None without any."""
    import shapely

    tris = [f.vertices[f.mesh.triangles[f.part_layer[f.mesh.part] == INTERIOR]] for f in files]
    tris = np.concatenate(tris) if tris else np.zeros((0, 3, 3))
    if len(tris) == 0:
        return None
    normals, areas = triangle_normals(tris)
    flat = (np.abs(normals[:, 2]) > 0.99) & (areas > MIN_FACE_AREA_M2)
    if np.any(flat):
        return shapely.union_all(shapely.make_valid(shapely.polygons(tris[flat][..., :2])))
    return shapely.convex_hull(shapely.multipoints(tris.reshape(-1, 3)[:, :2]))


def load_geometry(model: ModelSettings, where: str) -> Geometry:
    """Read every model file into world-frame float64 triangles with layers (:class:`Geometry`).

    The model's own files are read first; city models (context) then, with what lies farther than
    ``context_radius_m`` from the model's windows left out before triangulation, and the buildings
    that overlap the model's own plan left out (``exclude_overlapping``). ``where`` names the project
    file in messages. Degenerate, NaN and infinite faces are dropped with one counted warning.
    """
    notes: list[str] = []
    warnings: list[str] = []
    hashes = {}
    own, context = [], []
    for i, spec in enumerate(model.files):  # the model's own files first
        if spec.all_ignored:
            notes.append(f"{spec.display}: every face goes to 'ignore'; file not loaded")
            continue
        hashes[spec.display] = file_hash(spec.path)
        if is_context(spec.path):
            context.append((i, spec))
        else:
            own.append(read_file(i, spec, model, where, ReadOptions(exclude=spec.exclude), warnings))
    if context:
        near_xy, footprint = _context_bounds(own)
        target = check_crs(own, where)  # city models in another CRS are projected to the model's (CityGML)
        for i, spec in context:  # city models: cut to the radius, without the model's own building
            options = ReadOptions(lod=spec.lod, exclude=spec.exclude,
                                  near=None if near_xy is None else (near_xy, spec.context_radius_m),
                                  crs=spec.crs, target_crs=target)
            f = read_file(i, spec, model, where, options, warnings)
            if spec.exclude_overlapping and footprint is not None:
                f = _without_the_building(f, footprint, notes)
            own.append(f)
    for f in own:
        notes.extend(f.mesh.notes)
    check_crs(own, where)
    return _assemble(own, notes, warnings, hashes, where)


def _context_bounds(files: list[LoadedFile]):
    """Centre of the model's windows (else of all its vertices) [m, world xy] and its building's plan."""
    win = [f.vertices[f.mesh.triangles[f.part_layer[f.mesh.part] == WINDOW]].reshape(-1, 3) for f in files]
    win = np.concatenate(win) if win else np.zeros((0, 3))
    pts = win if len(win) else (np.concatenate([f.vertices for f in files]) if files else np.zeros((0, 3)))
    centre = None if len(pts) == 0 else tuple(0.5 * (pts[:, :2].min(axis=0) + pts[:, :2].max(axis=0)))
    return centre, building_footprint(files)


def _without_the_building(f: LoadedFile, footprint, notes: list) -> LoadedFile:
    """The city model ``f`` without the buildings whose plan overlaps ``footprint`` by half or more."""
    from en17037cli.io.cityjson import footprint_overlap, without_objects

    placed = replace(f.mesh, vertices=f.vertices)
    ids = footprint_overlap(placed, footprint, 0.5)
    if not ids:
        return f
    notes.append(f"{f.spec.display}: {len(ids)} building(s) overlapping the model's own plan left out "
                 f"(exclude_overlapping): {', '.join(ids[:5])}{' ...' if len(ids) > 5 else ''}")
    mesh = without_objects(placed, ids)
    return replace(f, mesh=mesh, vertices=mesh.vertices)


def placed_space(space: Space, spec: ModelFile) -> Space:
    """A file's space moved like the file's faces (``transform``; IFC spaces are in metres, z up)."""
    t = spec.transform
    if t is None:
        return space
    move = lambda xy: transformed(np.column_stack([xy, np.zeros(len(xy))]), t)[:, :2]  # noqa: E731
    dz = float(t.translate_m[2])
    body = None if space.body is None else transformed(space.body.reshape(-1, 3), t).reshape(space.body.shape)
    return replace(space, footprint=move(space.footprint), holes=tuple(move(h) for h in space.holes),
                   floor_z=space.floor_z + dz, top_z=space.top_z + dz, body=body)


def _assemble(files: list[LoadedFile], notes, warnings, hashes, where: str) -> Geometry:
    all_v, all_t, all_l, all_s, all_p, all_o, parts = [], [], [], [], [], [], []
    context, spans = [], []
    offset = 0
    dropped = glazing_parts = 0
    for f in files:  # one pass per model file
        mesh, verts = f.mesh, f.vertices
        glazing_parts += int(np.count_nonzero(f.part_layer == WINDOW))
        layer, sun = f.part_layer[mesh.part], f.part_sun[mesh.part]
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
        all_o.append(np.full((int(np.count_nonzero(keep)), 2), np.nan) if f.part_optics is None else f.part_optics[mesh.part[keep]])
        all_p.append(mesh.part[keep] + len(parts))
        spans.append((f.index, f.spec.display, len(parts), len(parts) + len(mesh.parts)))
        if is_context(f.spec.path):
            context.append(spans[-1])
        parts.extend(replace(p, attrs={**p.attrs, "file": f.spec.path.stem}) for p in mesh.parts)
        offset += len(verts)
    if dropped:
        warnings.append(f"{dropped} degenerate, NaN or infinite faces dropped")
    if not all_v:
        raise InputError(f"{where}: model.files: no geometry loaded (every file is 'ignore')")
    g = Geometry(np.concatenate(all_v), np.concatenate(all_t).astype(np.int64), np.concatenate(all_l).astype(np.int8),
                 np.concatenate(all_s), parts, np.concatenate(all_p), notes, warnings, hashes,
                 sites=[(f.spec.display, f.mesh.site, f.spec.transform.rotate_deg if f.spec.transform else 0.0)
                        for f in files if f.mesh.site is not None],
                 spaces=[(f.spec.display, placed_space(sp, f.spec)) for f in files for sp in f.mesh.spaces],
                 optics=np.concatenate(all_o) if any(f.part_optics is not None for f in files) else None,
                 read=[(f.spec.display, read_summary(f.mesh)) for f in files],
                 windows_left_out=[(f.spec.display, *w) for f in files for w in f.mesh.windows_left_out],
                 context=context, located=located_files(files), files=spans)
    if glazing_parts and not np.any(g.layer == WINDOW):
        raise InputError(f"{where}: model.files: every face of the {glazing_parts} object(s) on the 'window' layer is "
                         "degenerate, NaN or infinite (zero area); re-export the glazing")
    return g
