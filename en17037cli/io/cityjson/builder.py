"""The part and face builder: CityObjects' geometries flattened into rings, then triangles with parts.

Geometry (§3.2 Arrays to represent boundaries): MultiSurface and CompositeSurface (boundaries
nested 3 deep: surface > ring > vertex index), Solid (4: shell > surface > ring > index),
MultiSolid and CompositeSolid (5), and GeometryInstance (§3.4 Geometry templates: a template
placed by its 4x4 row-major ``transformationMatrix`` M at the reference point, the vertex
``boundaries[0]``: ``world = M[:3, :3] @ v + M[:3, 3] + reference_point``). MultiPoint and
MultiLineString carry no surfaces and are left out by the caller. Surfaces become triangles in
:mod:`~en17037cli.io.cityjson.triangulate`.

Parts: one :class:`~en17037cli.io.mesh.Part` per (CityObject, semantic surface type) with its
default layer (:func:`~en17037cli.io.cityjson.semantics.default_layer`); the semantic surface of
each face comes from the geometry's ``semantics`` (§3.3). The steep sides of ground-type objects
then get landscape parts of their own (:mod:`~en17037cli.io.cityjson.relief`). Geometries whose ``semantics.values``
do not match their surfaces lose their semantics (counted warning).

``ReadOptions.near = ((x, y), r)`` leaves out, before triangulation, each object whose vertex
bounding box lies entirely farther than ``r`` from ``(x, y)`` in plan (counted note).
"""
from __future__ import annotations

from itertools import chain
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.cityjson.documents import SOLID_TYPES, SURFACE_DEPTH
from en17037cli.io.cityjson.relief import steep_sides
from en17037cli.io.cityjson.semantics import counted, default_layer
from en17037cli.io.cityjson.triangulate import triangulate_surfaces
from en17037cli.io.mesh import Part


def _flatten(nested, depth: int) -> list:
    """The surfaces (or semantic values) of a boundary array with ``depth`` levels above them (§3.2)."""
    if depth == 0:
        return nested
    if depth == 1:
        return [s for shell in nested for s in shell]
    return [s for solid in nested for shell in solid for s in shell]


class Builder:
    """Collects surfaces of all objects as flat lists, then triangulates them with numpy.

    Per geometry: its object, vertex base (offset of its vertex block) and limit (the block's
    length, for the range check); per surface: ring count and part; per ring: the local vertex
    indices as the file gives them. Nothing is looked at per vertex in Python.
    """

    def __init__(self, path: Path, vertices: np.ndarray, by_id: dict):
        self.path = path
        self.blocks = [vertices]
        self.nverts = len(vertices)
        self.by_id = by_id
        self.parts: list[Part] = []
        self.part_index: dict = {}
        self.obj_ids: list[str] = []  # kept objects, in order
        self.obj_where: list[str] = []
        self.g_obj: list[int] = []
        self.g_base: list[int] = []
        self.g_limit: list[int] = []
        self.g_nsurf: list[int] = []
        self.g_label: list[str] = []
        self.s_nrings: list[int] = []
        self.s_part: list[int] = []
        self.rings: list = []
        self.ring_len: list[int] = []
        self.bad_semantics = 0
        self.tpl_range: dict = {}

    # -- objects and parts

    def start_object(self, oid: str, obj: dict, cls: str, where: str) -> None:
        self.obj = len(self.obj_ids)
        self.obj_ids.append(oid)
        self.obj_where.append(where)
        attrs = {"class": cls, "id": oid}
        parents = obj.get("parents")
        if isinstance(parents, list) and parents:
            ptype = self.by_id.get(parents[0], {}).get("type") if isinstance(parents[0], str) else None
            if isinstance(ptype, str):
                attrs["parent"] = ptype
        self.attrs = attrs
        a = obj.get("attributes")
        scalar = (str, int, float, bool)
        self.free = {f"attr.{k}": v for k, v in a.items() if isinstance(v, scalar)} if isinstance(a, dict) else {}
        self.cls = cls

    def part_for(self, surface, solid: bool) -> int:
        surface = surface if isinstance(surface, str) else None
        layer, _ = default_layer(self.cls, surface, solid)
        key = (self.obj, surface, layer)
        i = self.part_index.get(key)
        if i is None:
            attrs = dict(self.attrs)
            if surface is not None:
                attrs["surface"] = surface
            attrs.update(self.free)
            i = self.part_index[key] = len(self.parts)
            self.parts.append(Part(attrs, layer=layer, obstructs_sun=True))
        return i

    # -- geometries

    def add_geometry(self, g: dict, gi: int, base: int, limit: int, label: str | None = None) -> None:
        gtype = g["type"]
        depth = SURFACE_DEPTH[gtype]
        solid = gtype in SOLID_TYPES
        oid = self.obj_ids[-1]
        label = label or f"object '{oid}' geometry[{gi}] ({gtype})"
        try:
            surfaces = _flatten(g["boundaries"], depth)
            nrings = list(map(len, surfaces))
            rings = list(chain.from_iterable(surfaces))
            ring_len = list(map(len, rings))
        except (KeyError, TypeError):
            raise InputError(f"{self.path}{self.obj_where[-1]}: {label}: 'boundaries' are not nested as a {gtype} "
                             f"({depth + 3} levels of arrays, §3.2); validate the file with cjval") from None
        n = len(surfaces)
        self.s_part.extend(self._semantic_parts(g, depth, n, solid))
        self.g_obj.append(self.obj)
        self.g_base.append(base)
        self.g_limit.append(limit)
        self.g_nsurf.append(n)
        self.g_label.append(label)
        self.s_nrings.extend(nrings)
        self.rings.extend(rings)
        self.ring_len.extend(ring_len)

    def _semantic_parts(self, g: dict, depth: int, n: int, solid: bool) -> list[int]:
        """Part index of each of the geometry's ``n`` surfaces from its semantics (§3.3)."""
        sem = g.get("semantics")
        if not isinstance(sem, dict):
            return [self.part_for(None, solid)] * n
        surfs = sem.get("surfaces") or []
        values = sem.get("values")
        if values is None:
            return [self.part_for(None, solid)] * n
        try:
            flat = _flatten(values, depth)
            ok = len(flat) == n and all(v is None or (type(v) is int and 0 <= v < len(surfs)) for v in flat)
        except TypeError:
            ok = False
        if not ok:
            self.bad_semantics += 1
            return [self.part_for(None, solid)] * n
        pm = [self.part_for(s.get("type") if isinstance(s, dict) else None, solid) for s in surfs]
        none = None
        out = []
        for v in flat:
            if v is None:
                if none is None:
                    none = self.part_for(None, solid)
                out.append(none)
            else:
                out.append(pm[v])
        return out

    def add_instance(self, tpl: dict, inst: dict, gi: int, tverts: np.ndarray, base: int, limit: int) -> None:
        """A GeometryInstance (§3.4): the template's vertices placed by its matrix at the reference point."""
        oid = self.obj_ids[-1]
        where = f"{self.path}{self.obj_where[-1]}: object '{oid}' geometry[{gi}] (GeometryInstance)"
        try:
            ref = inst["boundaries"][0]
            m = np.array(inst["transformationMatrix"], dtype=np.float64).reshape(4, 4)
        except (KeyError, IndexError, TypeError, ValueError):
            raise InputError(f"{where}: needs \"boundaries\": [reference vertex] and a 16-number \"transformationMatrix\"; "
                             "validate the file with cjval") from None
        if not isinstance(ref, int) or isinstance(ref, bool) or not 0 <= ref < limit:
            raise InputError(f"{where}: reference point {ref!r} is not a vertex of the file ({limit} vertices); "
                             "validate the file with cjval")
        t = inst["template"]
        lo, hi = self._template_range(t, tpl, tverts, oid)
        placed = tverts[lo:hi] @ m[:3, :3].T + m[:3, 3] + self.blocks[0][base + ref]
        self.blocks.append(placed)
        label = f"object '{oid}' geometry[{gi}] (GeometryInstance of template {t})"
        self.add_geometry(tpl, gi, self.nverts - lo, hi, label=label)
        self.nverts += len(placed)

    def _template_range(self, t: int, tpl: dict, tverts: np.ndarray, oid: str) -> tuple[int, int]:
        """[lo, hi) of the template vertices template ``t`` uses (checked once per template)."""
        r = self.tpl_range.get(t)
        if r is None:
            try:
                surfaces = _flatten(tpl["boundaries"], SURFACE_DEPTH[tpl["type"]])
                idx = np.fromiter(chain.from_iterable(chain.from_iterable(surfaces)), dtype=np.int64)
            except (KeyError, TypeError, ValueError):
                raise InputError(f"{self.path}: geometry-templates[{t}] ({tpl.get('type')}): 'boundaries' are not "
                                 "nested as its type says (§3.2); validate the file with cjval") from None
            if len(idx) == 0:
                r = (0, 0)
            elif idx.min() < 0 or idx.max() >= len(tverts):
                raise InputError(f"{self.path}: geometry-templates[{t}] (used by object '{oid}') refers to template "
                                 f"vertex {int(idx.max())} but there are {len(tverts)} vertices-templates; "
                                 "validate the file with cjval")
            else:
                r = (int(idx.min()), int(idx.max()) + 1)
            self.tpl_range[t] = r
        return r

    # -- numpy stage

    def finish(self, near, notes: list, warnings: list):
        """Vertices, triangles, part per triangle and parts, after range checks and near-culling."""
        name = self.path.name
        if self.bad_semantics:
            warnings.append(f"{name}: {counted(self.bad_semantics, 'geometry', 'geometries')} with semantics.values "
                            "that do not match their surfaces: their semantics ignored")
        vertices = np.concatenate(self.blocks) if len(self.blocks) > 1 else self.blocks[0]
        ring_len = np.array(self.ring_len, dtype=np.int64)
        s_nrings = np.array(self.s_nrings, dtype=np.int64)
        g_nsurf = np.array(self.g_nsurf, dtype=np.int64)
        try:
            local = np.fromiter(chain.from_iterable(self.rings), dtype=np.int64, count=int(ring_len.sum()))
        except (TypeError, ValueError):
            self._raise_bad_nesting()
        ring_surf = np.repeat(np.arange(len(s_nrings)), s_nrings)
        surf_geom = np.repeat(np.arange(len(g_nsurf)), g_nsurf)
        ring_geom = surf_geom[ring_surf]
        vert_geom = np.repeat(ring_geom, ring_len)
        limit = np.array(self.g_limit, dtype=np.int64)[vert_geom]
        bad = (local < 0) | (local >= limit)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            gi = int(vert_geom[i])
            raise InputError(f"{self.path}{self.obj_where[self.g_obj[gi]]}: {self.g_label[gi]} refers to vertex "
                             f"{int(local[i])} but there are {int(limit[i])} vertices; the file is corrupt, "
                             "validate it with cjval")
        gidx = local + np.array(self.g_base, dtype=np.int64)[vert_geom]
        del local, limit, bad

        surf_keep = np.ones(len(s_nrings), dtype=bool)
        g_obj = np.array(self.g_obj, dtype=np.int64)
        if near is not None and len(gidx):
            keep_obj = self._near(vertices, gidx, g_obj[vert_geom], near, notes)
            surf_keep &= keep_obj[g_obj[surf_geom]]
        tris, tri_surf, n_degenerate, n_failed = triangulate_surfaces(vertices, gidx, ring_len, s_nrings, surf_keep)
        if n_degenerate:
            warnings.append(f"{name}: {counted(n_degenerate, 'surface')} with fewer than 3 vertices dropped")
        if n_failed:
            warnings.append(f"{name}: {counted(n_failed, 'polygon')} could not be fully triangulated "
                            "(self-intersecting or degenerate); their remaining area was dropped")
        s_part = np.array(self.s_part, dtype=np.int64)
        order = np.argsort(tri_surf, kind="stable")
        tris, part = tris[order], s_part[tri_surf[order]]
        part, self.parts = steep_sides(vertices, tris, part, self.parts, name, notes)
        # keep only what the triangles use: vertices in file order, parts in file order
        used = np.zeros(len(vertices), dtype=bool)
        used[tris.ravel()] = True
        vmap = np.cumsum(used) - 1
        used_parts = np.zeros(len(self.parts), dtype=bool)
        used_parts[part] = True
        pmap = np.cumsum(used_parts) - 1
        parts = [p for p, u in zip(self.parts, used_parts) if u]
        return vertices[used], vmap[tris], pmap[part], parts

    def _raise_bad_nesting(self):
        """Find the first geometry whose rings hold something else than vertex indices and name it."""
        g = 0
        s_start = 0
        r_start = 0
        for gi, ns in enumerate(self.g_nsurf):
            nr = sum(self.s_nrings[s_start:s_start + ns])
            for ring in self.rings[r_start:r_start + nr]:
                if not all(type(v) is int for v in ring):
                    raise InputError(f"{self.path}{self.obj_where[self.g_obj[gi]]}: {self.g_label[gi]}: 'boundaries' "
                                     "are not nested as its type says (rings must be lists of vertex indices, §3.2); "
                                     "validate the file with cjval")
            s_start += ns
            r_start += nr
            g = gi
        raise InputError(f"{self.path}: {self.g_label[g]}: 'boundaries' hold something else than vertex indices; "
                         "validate the file with cjval")

    def _near(self, vertices, gidx, vert_obj, near, notes) -> np.ndarray:
        """Per kept object: does its vertex bounding box come within the radius of the point (in plan)?"""
        try:
            (px, py), radius = near
            px, py, radius = float(px), float(py), float(radius)
        except (TypeError, ValueError):
            raise InputError(f"{self.path}: near must be ((x, y), radius_m), got {near!r}") from None
        n_obj = len(self.obj_ids)
        starts = np.flatnonzero(np.r_[True, vert_obj[1:] != vert_obj[:-1]])
        objs = vert_obj[starts]
        xy = vertices[gidx, :2]
        lo = np.minimum.reduceat(xy, starts, axis=0)
        hi = np.maximum.reduceat(xy, starts, axis=0)
        dx = np.maximum(np.maximum(lo[:, 0] - px, px - hi[:, 0]), 0.0)
        dy = np.maximum(np.maximum(lo[:, 1] - py, py - hi[:, 1]), 0.0)
        keep = np.ones(n_obj, dtype=bool)
        keep[objs] = np.hypot(dx, dy) <= radius
        dropped = int(n_obj - keep.sum())
        if dropped:
            notes.append(f"{self.path.name}: {counted(dropped, 'object')} lying entirely farther than {radius:g} m "
                         f"from ({px:g}, {py:g}) left out")
        return keep

