"""CityGML reader: city models (every German state's LoD2, Berlin, Vienna, Helsinki, Japan's PLATEAU) as context.

Reads CityGML 1.0, 2.0 and 3.0 (``.gml``, ``.citygml``) with lxml's streaming parser: one
``cityObjectMember`` at a time is parsed, walked (:mod:`~en17037cli.io.citygml.walk`), cut to
the context radius and dropped from the tree, so a city-wide file costs memory for what is kept
only. Coordinates are float64; ``srsName`` in every form real files use
(:mod:`~en17037cli.io.citygml.crs`), projected with pyproj to the CRS of the project's other
files where it differs (a CRS in degrees always is).

Parts and layers are those of the CityJSON reader (one table for both,
:mod:`~en17037cli.io.cityjson.semantics`): one :class:`~en17037cli.io.mesh.Part` per (city
object, thematic surface type; the steep sides of ground-type objects on landscape parts of their
own, :mod:`~en17037cli.io.cityjson.relief`), ``Part.attrs``: `class` (``Building``, ``BuildingPart``,
``TINRelief``...), `id` (the object's ``gml:id``, usable in layer rules and ``exclude``),
`parent` (the enclosing object's class), `surface` (``WallSurface``, ``RoofSurface``, ``Window``...)
and `attr.<name>` (text-only properties such as ``bldg:function`` and generic attributes).

Options: ``ReadOptions.lod`` (``"highest"``, or a LoD such as ``"2"``, with fallback to a lower
one, per object; CityGML LoDs are whole numbers, a request "2.2" reads LoD 2),
``ReadOptions.exclude`` (``gml:id`` of objects, with the objects inside them) and
``ReadOptions.near`` (objects whose vertices all lie farther in plan are left out while streaming),
``ReadOptions.crs`` (the file's CRS, over what the file says) and ``ReadOptions.target_crs``.

Not read: appearances (textures, materials), ``RasterRelief`` grids, ``gml:Tin`` given by control
points only (counted), curves and points (counted), ADE properties (walked through: their polygons
count for the enclosing object).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.citygml.crs import CrsResolver
from en17037cli.io.citygml.walk import Walk, local, walk_member
from en17037cli.io.cityjson.relief import steep_sides
from en17037cli.io.cityjson.semantics import choose_lod, counted, default_layer, lod_label, parse_lod_request
from en17037cli.io.cityjson.triangulate import triangulate_surfaces
from en17037cli.io.mesh import Mesh, Part, Site
from en17037cli.io.registry import ReadOptions, register

#: Member elements streamed one at a time (CityGML 1.0-3.0, GML feature collections)
MEMBERS = ("cityObjectMember", "featureMember", "member")
#: Top-level elements dropped as they end (appearances of the whole model)
DROPPED = ("appearanceMember",)


def _lxml(path: Path):
    try:
        from lxml import etree
    except ImportError:
        raise InputError(f"{path}: reading CityGML needs lxml: pip install 'en17037cli[citygml]'") from None
    return etree


class _Collector:
    """Kept polygons of all members as flat arrays (vertices in the target CRS), and the counts."""

    def __init__(self, path: Path, options: ReadOptions):
        self.path = path
        self.options = options
        req = parse_lod_request(path, options.lod)
        self.req = req[:1] if isinstance(req, tuple) else req  # CityGML LoDs are whole numbers
        self.crs = CrsResolver(path, options.crs, options.target_crs)
        self.blocks: list[np.ndarray] = []
        self.ring_len: list[int] = []
        self.s_nrings: list[int] = []
        self.s_part: list[int] = []
        self.parts: list[Part] = []
        self.part_index: dict = {}
        self.default_srs: str | None = None
        self.n_objects = 0
        self.by_lod: dict = {}
        self.n_far = self.n_fallback = self.n_skipped = 0
        self.unknown: dict = {}
        self.excluded: set = set()
        self.hrefs = self.curves = self.no_tin = 0

    def add(self, w: Walk) -> None:
        """Choose each object's LoD, place its polygons, cut to the radius, keep."""
        self.excluded |= w.excluded
        for o in w.objects:
            self.n_objects += 1
            if not o.polys:
                continue
            keys = sorted({(lod, 0) for lod, *_ in o.polys})
            chosen, fallback = choose_lod([(k,) for k in keys], self.req)
            if chosen is None:
                self.n_skipped += 1
                continue
            self.n_fallback += bool(fallback)
            chosen_polys = [p for p in o.polys if (p[0], 0) == chosen]
            placed = [(surface, solid, rings, self._place(srs, tokens)) for _, surface, solid, srs, rings, tokens in chosen_polys]
            label = lod_label(chosen)
            self.by_lod[(o.cls, label)] = self.by_lod.get((o.cls, label), 0) + 1
            if self.options.near is not None and self._far(np.concatenate([v for *_, v in placed])):
                self.n_far += 1
                continue
            if default_layer(o.cls, None, False)[1] is False:
                self.unknown[o.cls] = self.unknown.get(o.cls, 0) + 1
            for surface, solid, rings, v in placed:
                self._keep(o, surface, solid, rings, v)

    def _place(self, srs, tokens) -> np.ndarray:
        if isinstance(tokens, np.ndarray):
            v = tokens
        else:
            try:
                v = np.array(tokens, dtype=np.float64).reshape(-1, 3)
            except ValueError:
                raise InputError(f"{self.path}: a posList holds something else than numbers; validate the file "
                                 "(e.g. with citygml-tools validate)") from None
        p = self.crs.placement(srs or self.default_srs, v[0, :2] if len(v) else None)
        return v if p is None else p.apply(v)

    def _far(self, v: np.ndarray) -> bool:
        (px, py), radius = self.options.near
        lo, hi = v[:, :2].min(axis=0), v[:, :2].max(axis=0)
        dx = max(lo[0] - px, px - hi[0], 0.0)
        dy = max(lo[1] - py, py - hi[1], 0.0)
        return bool(np.hypot(dx, dy) > radius)

    def _part(self, o, surface, solid: bool) -> int:
        layer, _ = default_layer(o.cls, surface, solid)
        key = (self.n_objects, surface, layer)  # n_objects: the serial number of the object being kept
        i = self.part_index.get(key)
        if i is None:
            attrs = {"class": o.cls, "id": o.oid}
            if o.parent_cls:
                attrs["parent"] = o.parent_cls
            if surface:
                attrs["surface"] = surface
            attrs.update(o.attrs)
            i = self.part_index[key] = len(self.parts)
            self.parts.append(Part(attrs, layer=layer, obstructs_sun=True))
        return i

    def _keep(self, o, surface, solid, rings, v) -> None:
        """Append the polygons (rings closed as GML writes them: the repeated last vertex dropped)."""
        part = self._part(o, surface, solid)
        lens = np.fromiter((k for poly in rings for k in poly), dtype=np.int64)
        if lens.sum() != len(v):
            raise InputError(f"{self.path}: object '{o.oid}': its rings and coordinates do not match "
                             "(a posList with a wrong srsDimension?); validate the file")
        start = np.cumsum(lens) - lens
        closed = (lens > 1) & np.all(v[start] == v[np.maximum(start + lens - 1, 0)], axis=1)
        keep = np.ones(len(v), dtype=bool)
        keep[(start + lens - 1)[closed]] = False
        self.blocks.append(v[keep])
        self.ring_len.extend((lens - closed).tolist())
        self.s_nrings.extend(len(poly) for poly in rings)
        self.s_part.extend([part] * len(rings))

    def finish(self, notes: list, warnings: list):
        name = self.path.name
        if not self.blocks:
            return np.zeros((0, 3)), np.zeros((0, 3), np.int64), np.zeros(0, np.int64), []
        vertices = np.concatenate(self.blocks)
        ring_len = np.array(self.ring_len, dtype=np.int64)
        s_nrings = np.array(self.s_nrings, dtype=np.int64)
        tris, surf, n_degenerate, n_failed = triangulate_surfaces(vertices, np.arange(len(vertices)), ring_len, s_nrings,
                                                                  np.ones(len(s_nrings), dtype=bool))
        if n_degenerate:
            warnings.append(f"{name}: {counted(n_degenerate, 'polygon')} with fewer than 3 vertices dropped")
        if n_failed:
            warnings.append(f"{name}: {counted(n_failed, 'polygon')} could not be fully triangulated "
                            "(self-intersecting or degenerate); their remaining area was dropped")
        order = np.argsort(surf, kind="stable")
        tris, part = tris[order], np.array(self.s_part, dtype=np.int64)[surf[order]]
        part, self.parts = steep_sides(vertices, tris, part, self.parts, name, notes)
        used = np.zeros(len(vertices), dtype=bool)
        used[tris.ravel()] = True
        vmap = np.cumsum(used) - 1
        used_parts = np.zeros(len(self.parts), dtype=bool)
        used_parts[part] = True
        pmap = np.cumsum(used_parts) - 1
        return vertices[used], vmap[tris], pmap[part], [p for p, u in zip(self.parts, used_parts) if u]


@register(".gml", ".citygml", context=True)
def read_citygml(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read a CityGML 1.0, 2.0 or 3.0 file into triangles with one part per city object and surface type.

    Parameters
    ----------
    path : a ``.gml`` / ``.citygml`` file whose root is a ``CityModel``
    options : ``lod``, ``exclude``, ``near``, ``crs``, ``target_crs`` (module docstring); None for the defaults

    Returns
    -------
    Mesh
        ``vertices`` (n, 3) float64 [m] in the target CRS (else the file's), z up; ``triangles``
        in file order; ``parts`` in file order; ``units="m"``, ``up_axis="z"``; ``site`` with the CRS.

    Raises
    ------
    InputError
        One line naming the file and the fix: not XML, not CityGML, an unknown CRS, a CRS in
        degrees with nothing to project it to, numbers that are not numbers.
    """
    path = Path(path)
    options = options or ReadOptions()
    etree = _lxml(path)
    c = _Collector(path, options)
    exclude = set(options.exclude)
    tags = [f"{{*}}{t}" for t in (*MEMBERS, *DROPPED, "Envelope")]
    n_members = 0
    w = Walk()
    try:
        it = etree.iterparse(str(path), events=("end",), tag=tags, huge_tree=True, remove_blank_text=True)
        root = None
        for _, el in it:
            if root is None:
                root = el.getroottree().getroot()
                if local(root.tag) != "CityModel":
                    raise InputError(f"{path}: XML but not CityGML (root element '{local(root.tag)}', expected "
                                     "CityModel); export the city model as CityGML")
            name = local(el.tag)
            parent = el.getparent()
            if name == "Envelope":
                if c.default_srs is None and parent is not None and parent.getparent() is root:
                    c.default_srs = el.get("srsName")
                continue
            if name in MEMBERS:
                n_members += 1
                w = Walk(templates=w.templates)
                walk_member(el, w, exclude)
                c.add(w)
                c.hrefs += w.hrefs
                c.curves += w.curves
                c.no_tin += w.no_triangles
            el.clear()
            if parent is not None:  # drop what streamed past: memory holds only the kept arrays
                while el.getprevious() is not None:
                    del parent[0]
    except etree.XMLSyntaxError as exc:
        line = exc.lineno if exc.lineno else "?"
        raise InputError(f"{path}:{line}: not well-formed XML ({exc.msg}); the file is cut short or corrupt, "
                         "export it again") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read model file: {exc.strerror or exc}") from None
    if root is None:
        _check_root(path, etree)
    notes: list[str] = list(c.crs.notes)
    warnings: list[str] = []
    v, tris, part, parts = c.finish(notes, warnings)
    _notes(c, path.name, options, notes, exclude)
    if len(tris) == 0 and c.n_objects == 0 and not c.excluded and not c.n_far:  # (all left out by the project: an empty context)
        raise InputError(f"{path}: no city object with surfaces in the CityGML file; export it with its geometry")
    crs_name = c.crs.out_name
    src = sorted(c.crs.reprojected)
    site = (Site(crs=crs_name, source=f"{path.name}: srsName" + (f", projected from {', '.join(src)}" if src else ""),
                 reprojected_from=", ".join(src) or None) if crs_name and crs_name.startswith("EPSG:") else None)
    lods = ", ".join(f"{cls} LoD {lod}: {n}" for (cls, lod), n in sorted(c.by_lod.items()))
    summary = (f"{counted(n_members, 'city object member')}, {counted(c.n_objects, 'object')}; with surfaces, by class and "
               f"LoD read: {lods or 'none'}; {counted(len(tris), 'triangle')} kept")
    return Mesh(v, tris, part, parts, warnings, notes, units="m", up_axis="z", site=site, summary=summary)


def _check_root(path: Path, etree) -> None:
    """A file with no member at all: is it CityGML (an empty city model) or something else?"""
    try:
        for _, el in etree.iterparse(str(path), events=("start",)):
            if local(el.tag) != "CityModel":
                raise InputError(f"{path}: XML but not CityGML (root element '{local(el.tag)}', expected CityModel); "
                                 "export the city model as CityGML")
            return
    except etree.XMLSyntaxError as exc:
        raise InputError(f"{path}:{exc.lineno or '?'}: not well-formed XML ({exc.msg}); the file is cut short or corrupt, "
                         "export it again") from None


def _notes(c: _Collector, name: str, options: ReadOptions, notes: list, exclude: set) -> None:
    if c.curves:
        notes.append(f"{name}: {counted(c.curves, 'curve or point geometry', 'curve or point geometries')} "
                     "(terrain intersections, footprint edges) left out: no surfaces")
    if c.no_tin:
        notes.append(f"{name}: {counted(c.no_tin, 'TIN')} given by control points only (no triangles) left out")
    if c.n_fallback:
        notes.append(f"{name}: LoD {options.lod} requested; {counted(c.n_fallback, 'object')} fell back to a lower LoD")
    if c.n_skipped:
        notes.append(f"{name}: {counted(c.n_skipped, 'object')} without surface geometry at or below LoD {options.lod} left out")
    if c.n_far:
        (px, py), radius = options.near
        notes.append(f"{name}: {counted(c.n_far, 'object')} lying entirely farther than {radius:g} m from "
                     f"({px:g}, {py:g}) left out")
    if c.unknown:
        detail = ", ".join(f"{k}: {v}" for k, v in c.unknown.items())
        notes.append(f"{name}: {counted(sum(c.unknown.values()), 'object')} of types that are not in the class table "
                     f"given layer landscape ({detail})")
    if exclude:
        listed = exclude & c.excluded
        missing = sorted(exclude - c.excluded)
        if c.excluded:
            notes.append(f"{name}: {counted(len(c.excluded), 'object')} left out by exclude ({len(listed)} listed, "
                         f"{len(c.excluded) - len(listed)} inside them)")
        if missing:
            notes.append(f"{name}: {counted(len(missing), 'excluded id')} not in the file: "
                         f"{', '.join(missing[:5])}{' ...' if len(missing) > 5 else ''}")
