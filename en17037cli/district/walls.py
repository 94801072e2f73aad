"""The buildings of a city model and their wall surfaces, as the screen probes them.

A *building* is a top-level ``Building`` (CityJSON: a ``Building`` object without parents;
CityGML: a ``bldg:Building`` feature) with its parts (``BuildingPart`` and their children); its
*walls* are the surfaces labelled ``WallSurface`` of its and its parts' geometry at the LoD the
context reader reads (``model.files[0].lod``, per object, :func:`~en17037cli.io.cityjson.semantics.choose_lod`),
so the probes stand on the faces the rays see. A geometry without semantic surfaces gives its
vertical polygons (a normal within :data:`WALL_MAX_NZ` of horizontal) as walls.

Each wall keeps where it is in the file (:attr:`Wall.handle`), for the city model written back
with the results (:mod:`~en17037cli.district.citymodel`): CityJSON (object id, geometry index, the
surface's position in the boundaries); CityGML the building's id and the ``WallSurface``'s number
among its walls (or the object's id and polygon number where the wall has no thematic surface). CityGML is read by
:mod:`~en17037cli.district.walls_gml`; :func:`~en17037cli.district.city.read_buildings` reads either.

References: CityJSON 2.0 §3.2 (boundaries), §3.3 (semantics); CityGML 2.0 §10.3 (building model).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.cityjson.documents import SOLID_TYPES, SURFACE_DEPTH, all_vertices, check_header, load_documents
from en17037cli.io.cityjson.semantics import choose_lod, lod_key, parse_lod_request

#: Surfaces whose unit normal's vertical component is at most this are walls where a geometry says
#: no semantics (about 15 deg from vertical; LoD2 walls are vertical)
WALL_MAX_NZ = 0.26
#: City object types whose geometry belongs to a building
BUILDING_TYPES = frozenset(("Building", "BuildingPart"))
#: A solid whose faces' area vectors sum to more than this share of their total area is not closed
#: (a missing roof or wall: the sum is that face's area vector; T-junctions and round-off leave 1e-6)
CLOSURE_TOLERANCE = 1e-3


@dataclass
class Wall:
    """One wall surface: its polygons [m, the model's CRS] (each an outer ring (k, 3) then holes),
    its label for the outputs and where it is in the file."""

    key: str
    obj: str
    polygons: list
    handle: tuple


@dataclass
class CityBuilding:
    """A building to screen: its id, its objects (its own faces), walls and ground.

    z_ground : lowest point of its walls [m]; centre : (2,) centre of their plan's box [m]
    problem : why it is left out (no walls, a solid that is not closed), or None
    open_objects : ids of its objects whose solid is not closed (:func:`closure`)
    """

    id: str
    objects: tuple
    walls: list = field(default_factory=list)
    z_ground: float = 0.0
    centre: np.ndarray = field(default_factory=lambda: np.zeros(2))
    problem: str | None = None
    open_objects: list = field(default_factory=list)

    def finish(self) -> CityBuilding:
        """Set ground and centre from the walls, or the problem where it has none or a solid is open."""
        pts = [r for w in self.walls for poly in w.polygons for r in poly[:1]]
        if not pts:
            self.problem = ("it has no wall surface (no WallSurface and no vertical polygon at the LoD read); screen another "
                            "LoD (model.files[0].lod) or leave it out (model.files[0].exclude)")
            return self
        if self.open_objects:
            self.problem = (f"its solid {self.open_objects[0]} is not closed (its faces' area vectors do not sum to zero: a face "
                            "is missing), so what is inside it is not known and shared walls cannot be told; validate the "
                            "tile (val3dity) or leave the building out (model.files[0].exclude)")
        v = np.concatenate(pts)
        self.z_ground = float(v[:, 2].min())
        self.centre = 0.5 * (v[:, :2].min(axis=0) + v[:, :2].max(axis=0))
        return self


def newell_normal(ring: np.ndarray) -> np.ndarray:
    """Unit normal (3,) of a ring (k, 3) by Newell's method (its area vector, normalised); zeros
    for a degenerate ring. The ring's order gives its side: counterclockwise seen from outside."""
    r = np.asarray(ring, dtype=float)
    r = r - r.mean(axis=0)
    n = np.cross(r, np.roll(r, -1, axis=0)).sum(axis=0)
    length = np.linalg.norm(n)
    return n / length if length > 0 else n


def area_vector(polygon: list) -> np.ndarray:
    """Area vector (3,) [m²] of a polygon (outer ring, then holes wound the other way): half the sum
    of r_i x r_(i+1) over its rings, about their mean (Newell)."""
    out = np.zeros(3)
    for ring in polygon:
        r = np.asarray(ring, dtype=float)
        r = r - r.mean(axis=0)
        out += 0.5 * np.cross(r, np.roll(r, -1, axis=0)).sum(axis=0)
    return out


def is_closed(polygons: list) -> bool:
    """Whether polygons bound a solid closed but perhaps for its floor: their area vectors sum to
    zero within :data:`CLOSURE_TOLERANCE` of their total area (the divergence theorem; blind to
    T-junctions), or to an upward vector (the faces missing face down: a floor, which 3dfier's LoD1
    solids leave out; what the screen asks of a solid, whether a point lies inside it, is answered
    by the first face above the point, so a missing floor does not matter)."""
    vecs = np.array([area_vector(p) for p in polygons]).reshape(-1, 3)
    total = np.linalg.norm(vecs, axis=1).sum()
    rest = vecs.sum(axis=0)
    return total <= 0 or (float(np.hypot(rest[0], rest[1])) <= CLOSURE_TOLERANCE * total and rest[2] >= -CLOSURE_TOLERANCE * total)


def is_wall_polygon(ring: np.ndarray) -> bool:
    """A polygon standing upright enough to be a wall (:data:`WALL_MAX_NZ`)."""
    n = newell_normal(ring)
    return bool(np.any(n)) and abs(float(n[2])) <= WALL_MAX_NZ


def read_buildings_json(path: Path, lod: str = "highest", exclude=(), crs: str | None = None) -> tuple[list[CityBuilding], str | None]:
    """The Building objects of a CityJSON file (or CityJSONSeq) with their walls, in file order, and its CRS."""
    from en17037cli.io.cityjson.documents import header_site

    req = parse_lod_request(path, lod)
    docs = load_documents(path)
    header = docs[0][1]
    check_header(path, header)
    site = header_site(path, header)
    vertices, base, count = all_vertices(path, docs)
    objects: dict = {}
    where: dict = {}
    for di, (_, doc) in enumerate(docs):
        for oid, obj in (doc.get("CityObjects") or {}).items():
            if isinstance(obj, dict):
                objects.setdefault(oid, obj)
                where.setdefault(oid, di)
    excluded = set(exclude)
    out = []
    for oid, obj in objects.items():
        if obj.get("type") != "Building" or obj.get("parents") or oid in excluded:
            continue
        members = _members(oid, objects, excluded)
        b = CityBuilding(oid, tuple(members))
        for m in members:
            di = where[m]
            walls, solids = _walls_of(path, m, objects[m], vertices, base[di], count[di], req)
            b.walls.extend(walls)
            if any(not is_closed(polys) for polys in solids):
                b.open_objects.append(m)
        out.append(b.finish())
    return out, crs or (site.crs if site is not None else None)


def _members(oid: str, objects: dict, excluded: set) -> list[str]:
    """The building and its descendants of building types (``children``, depth first, in order)."""
    out, stack = [], [oid]
    while stack:
        o = stack.pop()
        if o in out or o in excluded or o not in objects or objects[o].get("type") not in BUILDING_TYPES:
            continue
        out.append(o)
        kids = objects[o].get("children") or []
        stack.extend(reversed([k for k in kids if isinstance(k, str)]))
    return out


def surface_paths(gtype: str, boundaries) -> list[tuple]:
    """The position of every surface in a geometry's boundaries (§3.2), in order: (i,), (shell, i)
    or (solid, shell, i) for MultiSurface, Solid, MultiSolid (and their composites)."""
    depth = SURFACE_DEPTH[gtype]
    if depth == 0:
        return [(i,) for i in range(len(boundaries))]
    if depth == 1:
        return [(s, i) for s, shell in enumerate(boundaries) for i in range(len(shell))]
    return [(a, s, i) for a, solid in enumerate(boundaries) for s, shell in enumerate(solid) for i in range(len(shell))]


def at(nested, path: tuple):
    """The item of a nested list at ``path``."""
    for i in path:
        nested = nested[i]
    return nested


def _walls_of(path: Path, oid: str, obj: dict, vertices: np.ndarray, base: int, count: int, req) -> tuple[list[Wall], list]:
    """The walls of one object's geometry at the LoD chosen for it, and the polygons of each of its
    solids' shells (for :func:`is_closed`)."""
    geoms = [(lod_key(g.get("lod")), gi, g) for gi, g in enumerate(obj.get("geometry") or [])
             if isinstance(g, dict) and g.get("type") in SURFACE_DEPTH]
    if not geoms:
        return [], []
    chosen, _ = choose_lod(geoms, req)
    out: list[Wall] = []
    shells: dict = {}
    for key, gi, g in geoms:
        if key != chosen:
            continue
        try:
            paths = surface_paths(g["type"], g["boundaries"])
            sem = g.get("semantics") if isinstance(g.get("semantics"), dict) else None
            types = [s.get("type") if isinstance(s, dict) else None for s in (sem or {}).get("surfaces") or []]
            for p in paths:
                idx = [np.asarray(r, dtype=np.int64) for r in at(g["boundaries"], p)]
                if len(idx[0]) < 3 or any(np.any((i < 0) | (i >= count)) for i in idx):
                    continue
                rings = [vertices[base + i] for i in idx]
                if g["type"] in SOLID_TYPES:
                    shells.setdefault((gi, *p[:-1]), []).append(rings)
                value = at(sem["values"], p) if sem is not None and sem.get("values") is not None else None
                kind = types[value] if isinstance(value, int) and 0 <= value < len(types) else None
                if kind == "WallSurface" or (sem is None and is_wall_polygon(rings[0])):
                    out.append(Wall(f"{oid}#{gi}/{'/'.join(map(str, p))}", oid, [rings], ("cityjson", oid, gi, p)))
        except (KeyError, TypeError, IndexError):
            raise InputError(f"{path}: object '{oid}' geometry[{gi}]: boundaries or semantics not nested as a {g['type']} "
                             "(§3.2, §3.3); validate the file with cjval") from None
    return out, list(shells.values())
