"""gbXML reader: spaces with their bounding surfaces and openings, as Revit, ArchiCAD, OpenStudio,
DesignBuilder and IES export them for building performance analysis.

Reads gbXML 0.37 to 7.03 (``.xml``, ``.gbxml``; :mod:`~en17037cli.io.gbxml.parse`), scaled from
``lengthUnit`` to metres, z up. Every ``Surface`` becomes a part with its ``Opening`` children
cut out of it (:func:`~en17037cli.io.openings.polygon_minus_openings`); every opening a part of
its own. ``Part.attrs``: `class` (the ``surfaceType`` or ``openingType``), `id`, `name`
(``Name``), `type` (``CADObjectId``: the authoring tool's family and type) and `space` (the
``Name`` of the space(s) it bounds). Default layers (the project's rules win):

| gbXML | layer |
|---|---|
| glazed openings (`FixedWindow`, `OperableWindow`, `FixedSkylight`, `OperableSkylight`, `SlidingDoor`) with a space on one side only | window (``Part.window`` = the opening's id) |
| glazed openings with a different space on each side (interior glazing) | interior (`surface: interior glazing`) |
| `NonSlidingDoor` | interior |
| `Air` surfaces and openings (virtual boundaries, open passages) | ignore (an Air opening is a hole) |
| `Shade` | landscape |
| every other surface type (walls, roofs, floors, slabs, ceilings, columns) | interior |

Which side a glazing faces is decided by the geometry (:mod:`~en17037cli.io.gbxml.sides`), the
file's surface type confirming only: a window with nothing but shading or the outdoors on one
side is exterior whatever its surface says (Revit writes exterior walls as ``InteriorWall`` with
the same space on both sides), glazing between two different spaces is interior glazing; the
windows reclassified are listed in notes. ``SlidingDoor`` is glazed as OpenStudio's gbXML import
takes it (a glass door).

Spaces (``Space``) become :class:`~en17037cli.io.mesh.Space` (``kind`` "gbXML Space", for a
project's ``gbxml_spaces`` glob): `name` its ``Name`` (``Name (id)`` where spaces share a Name), `storey` its ``BuildingStorey`` Name,
`zones` its ``Zone`` Name; the footprint from the downward faces at the bottom of its
``ShellGeometry`` (else its ``PlanarGeometry``, else its floor surfaces), ``floor_z`` / ``top_z``
the shell's lowest and highest points; `windows` the ids of the exterior glazings whose inner
side is the space (the file's hint; the scene assigns windows by geometry).

Site: ``Campus/Location`` Latitude, Longitude, Elevation (in ``lengthUnit``) and
``CADModelAzimuth`` A, "the angle of the positive Y axis from north" (gbXML 6.01 schema,
clockwise): north lies at -A from +Y, so ``true_north_deg = -A mod 360``.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangulate_polygons
from en17037cli.io.cityjson.semantics import counted
from en17037cli.io.gbxml.parse import Document, SpaceRecord, likely_unit, read_document
from en17037cli.io.gbxml.sides import UP, crossings, glazing_sides
from en17037cli.io.mesh import Mesh, Part, Site, Space
from en17037cli.io.openings import plane_basis, polygon_minus_openings
from en17037cli.io.registry import ReadOptions, register

GLAZED = ("FixedWindow", "OperableWindow", "FixedSkylight", "OperableSkylight", "SlidingDoor")
FLOORS = ("InteriorFloor", "SlabOnGrade", "RaisedFloor", "UndergroundSlab", "ExposedFloor")
EXTERIOR_SURFACES = ("ExteriorWall", "Roof", "ExposedFloor", "RaisedFloor", "UndergroundWall", "SlabOnGrade")
#: An opening lies on its host surface within this distance [m] (authoring tools leave some noise)
OPENING_PLANE_M = 0.05
SPACE_KIND = "gbXML Space"
#: A space's floor faces this close are one floor (coordinates rounded by the exporter) [m] ...
SEAM_M = 1e-3
#: ... and its floor pieces less than twice this apart (a wall of the space's own through it) [m]
JOIN_M = 0.175
#: A footprint whose area differs from the Space's own Area by more than this share is warned [-]
AREA_MISMATCH = 0.1


def _lxml(path: Path):
    try:
        from lxml import etree
    except ImportError:
        raise InputError(f"{path}: reading gbXML needs lxml: pip install 'en17037cli[gbxml]'") from None
    return etree


def _triangles(loops: list[np.ndarray]) -> list[np.ndarray]:
    """(t, 3, 3) triangles of each planar loop, ear-clipped in groups of equal vertex count."""
    out: list = [np.zeros((0, 3, 3))] * len(loops)
    by_k: dict = {}
    for i, lp in enumerate(loops):
        if lp is not None and len(lp) >= 3:
            by_k.setdefault(len(lp), []).append(i)
    for k, idx in by_k.items():
        pts = np.stack([loops[i] for i in idx])
        local = [np.array([[0, 1, 2]])] * len(idx) if k == 3 else triangulate_polygons(pts)
        for j, i in enumerate(idx):
            out[i] = pts[j][local[j]] if len(local[j]) else np.zeros((0, 3, 3))
    return out


def _footprint(shell_tris: np.ndarray):
    """(outer ring (k, 2), holes, z0, z1) of a shell's floor: the faces not steeper than 60 deg, in the
    lower half of the shell's height, with no face of the shell under them (a ray down from just under their centroid crosses nothing: the
    bottom of the volume, for a closed shell exactly, and for one whose walls or ceiling are drawn
    short, as Revit 2025 writes some, still), projected and unioned, at their lowest point (a raked
    floor's lowest point; a stepped floor's lowest step)."""
    import shapely

    if len(shell_tris) == 0:
        return None
    z1 = float(shell_tris[..., 2].max())
    n = np.cross(shell_tris[:, 1] - shell_tris[:, 0], shell_tris[:, 2] - shell_tris[:, 0])
    norm = np.linalg.norm(n, axis=1)
    zc = shell_tris[..., 2].mean(axis=1)
    lo, hi = float(shell_tris[..., 2].min()), z1
    # a floor lies in the lower half of the volume: a roof with nothing of the shell under it (a space
    # drawn without its floor) is its top, not its floor
    gentle = (np.abs(n[:, 2]) > 0.5 * norm) & (norm > 0) & (zc <= lo + 0.5 * (hi - lo) + 1e-9)
    below = shell_tris[gentle].mean(axis=1) - [0.0, 0.0, 0.01]
    flat = np.zeros(len(shell_tris), dtype=bool)
    flat[np.flatnonzero(gentle)] = crossings(below, shell_tris, -UP) == 0
    if not flat.any():
        return None
    z0 = float(shell_tris[flat][..., 2].min())
    plan = shapely.union_all(shapely.make_valid(shapely.polygons(shell_tris[flat][..., :2])))
    plan = _joined(plan)
    polys = [g for g in getattr(plan, "geoms", [plan]) if g.geom_type == "Polygon" and g.area > 0]
    if not polys:
        return None
    poly = shapely.orient_polygons(max(polys, key=lambda g: g.area)) if hasattr(shapely, "orient_polygons") else max(polys, key=lambda g: g.area)
    return (np.asarray(poly.exterior.coords)[:-1], tuple(np.asarray(r.coords)[:-1] for r in poly.interiors), z0, z1)


def _joined(plan):
    """A floor's pieces joined: faces a rounding apart (:data:`SEAM_M`), and pieces of one space a
    wall's thickness apart (Revit 2025: a bedroom's floor in two pieces 0.21 m apart, its Area their
    sum), bridged by the gaps between them that a closing by :data:`JOIN_M` fills; a piece's own
    notches are left as they are."""
    import shapely

    plan = plan.buffer(SEAM_M, join_style="mitre").buffer(-SEAM_M, join_style="mitre")
    pieces = [g for g in shapely.get_parts(plan) if g.geom_type == "Polygon" and g.area > 0]
    if len(pieces) < 2:
        return plan
    closed = plan.buffer(JOIN_M, join_style="mitre").buffer(-JOIN_M, join_style="mitre")
    bridges = [g for g in shapely.get_parts(closed.difference(plan))
               if sum(g.distance(p) < 10 * SEAM_M for p in pieces) >= 2]
    return shapely.union_all([plan, *bridges]).buffer(SEAM_M, join_style="mitre").buffer(-SEAM_M, join_style="mitre")


def _floor_of(s: SpaceRecord, shell: np.ndarray, surfaces):
    """The footprint of a space (:func:`_footprint`): from its shell, else its PlanarGeometry, else its
    floor surfaces; None without any."""
    fp = _footprint(shell)
    if fp is None and s.planar:
        ring = s.planar[0]
        fp = (ring[:, :2], (), float(ring[:, 2].min()), float(ring[:, 2].max()))
    if fp is None:
        floors = [srf.loop for srf in surfaces if s.id in srf.spaces and srf.kind in FLOORS and srf.loop is not None]
        fp = _footprint(np.concatenate(_triangles(floors))) if floors else None
    if fp is not None and len(shell):
        fp = (*fp[:3], float(shell[..., 2].max()))
    return fp


class _Builder:
    def __init__(self):
        self.tris: list[np.ndarray] = []
        self.part: list[np.ndarray] = []
        self.parts: list[Part] = []

    def add(self, part: Part, tris: np.ndarray) -> None:
        if len(tris) == 0:
            return
        self.parts.append(part)
        self.tris.append(tris)
        self.part.append(np.full(len(tris), len(self.parts) - 1))

    def mesh_arrays(self):
        if not self.tris:
            return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
        t = np.concatenate(self.tris)
        return t.reshape(-1, 3), np.arange(3 * len(t)).reshape(-1, 3), np.concatenate(self.part)


@register(".gbxml", ".xml")
def read_gbxml(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read a gbXML file: surfaces and openings as parts, spaces, site (see the module docstring).

    Returns
    -------
    Mesh
        ``vertices`` (n, 3) float64 [m], z up (``units="m"``); parts in file order (each surface,
        then its openings); ``spaces``; ``site`` from Campus/Location.

    Raises
    ------
    InputError
        Malformed XML, not gbXML, no or an unknown ``lengthUnit``, a coordinate that is not a
        number, no surface with geometry.
    """
    path = Path(path)
    options = options or ReadOptions()
    doc = read_document(path, _lxml(path))
    unit_warnings = []
    guess = likely_unit(doc)
    if guess is not None:  # a file that says Feet and writes metres: read in the unit its rooms say
        declared = doc.unit
        doc = read_document(path, _lxml(path), unit=guess[0])
        unit_warnings.append(f"{path.name}: its spaces are {guess[1]:.2f} m tall (the median) read in {declared} (the file's "
                             f"lengthUnit), not rooms; read in {guess[0]} instead ({guess[2]:.2f} m): check the building's size "
                             f"(validate), and ask for an export whose lengthUnit is the unit of its coordinates")
    names = {s.id: s.name for s in doc.spaces}
    sp_index = {s.id: i for i, s in enumerate(doc.spaces)}
    excluded = set(options.exclude)
    surfaces = [s for s in doc.surfaces if s.id not in excluded]

    # shells: the ShellGeometry, else the surfaces that bound the space
    shells = [np.concatenate(_triangles(s.shell)) if s.shell else np.zeros((0, 3, 3)) for s in doc.spaces]
    surf_tris = _triangles([s.loop for s in surfaces])
    for i, s in enumerate(doc.spaces):
        if len(shells[i]) == 0:
            own = [t for t, srf in zip(surf_tris, surfaces) if s.id in srf.spaces]
            shells[i] = np.concatenate(own) if own else np.zeros((0, 3, 3))
    floors = [_floor_of(s, shells[i], surfaces) for i, s in enumerate(doc.spaces)]

    glazed = [(si, o) for si, srf in enumerate(surfaces) for o in srf.openings
              if o.kind in GLAZED and o.loop is not None and len(o.loop) >= 3 and o.id not in excluded]
    centres = np.array([o.loop.mean(axis=0) for _, o in glazed]).reshape(-1, 3)
    normals = np.array([plane_basis(o.loop)[1] for _, o in glazed]).reshape(-1, 3)
    front, back = glazing_sides(centres, normals, shells)
    verdict = {}  # opening id -> ("exterior", space index or -1) | ("interior", (a, b))
    reclassified, interior = [], []
    for k, (si, o) in enumerate(glazed):
        f, b = int(front[k]), int(back[k])
        srf = surfaces[si]
        said = list(dict.fromkeys(x for x in srf.spaces if x in sp_index))
        if (f < 0) != (b < 0):
            verdict[o.id] = ("exterior", max(f, b))
        elif f >= 0 and b >= 0 and f != b:
            verdict[o.id] = ("interior", (f, b))
        elif len(said) == 2:
            verdict[o.id] = ("interior", (sp_index[said[0]], sp_index[said[1]]))
        else:
            verdict[o.id] = ("exterior", sp_index[said[0]] if said else (f if f >= 0 else -1))
        file_says_exterior = srf.kind in EXTERIOR_SURFACES or srf.kind == "Shade"
        if verdict[o.id][0] == "exterior" and not file_says_exterior:
            reclassified.append(f"{o.name} (on {srf.kind} {srf.name}{', the same space on both sides' if len(srf.spaces) == 2 and len(said) == 1 else ''})")
        if verdict[o.id][0] == "interior" and file_says_exterior:
            reclassified.append(f"{o.name} (on {srf.kind} {srf.name}: a space on both sides, interior glazing)")
        if verdict[o.id][0] == "interior":
            a, c = sorted(verdict[o.id][1])
            interior.append(f"{o.name} ({doc.spaces[a].name} | {doc.spaces[c].name})")

    b = _Builder()
    counts: dict = {}
    n_no_geometry = 0
    for srf, tri in zip(surfaces, surf_tris):
        counts[srf.kind] = counts.get(srf.kind, 0) + 1
        if srf.loop is None or len(srf.loop) < 3:
            n_no_geometry += 1
            continue
        space_names = ", ".join(dict.fromkeys(names.get(x, x) for x in srf.spaces))
        base = {"id": srf.id, "name": srf.name, "type": srf.cad, "space": space_names}
        holes = [o.loop for o in srf.openings if o.loop is not None]
        if holes:
            tri, _ = polygon_minus_openings(srf.loop, holes, OPENING_PLANE_M)
        layer = "ignore" if srf.kind == "Air" else "landscape" if srf.kind == "Shade" else "interior"
        b.add(Part({"class": srf.kind, **base}, layer=layer), tri)
        for o in srf.openings:
            counts[o.kind] = counts.get(o.kind, 0) + 1
            if o.loop is None or len(o.loop) < 3 or o.kind == "Air" or o.id in excluded:
                continue
            ot = _triangles([o.loop])[0]
            attrs = {"class": o.kind, "id": o.id, "name": o.name, "type": srf.cad, "space": space_names}
            v = verdict.get(o.id)
            if v is not None and v[0] == "exterior":
                b.add(Part(attrs, layer="window", window=o.id), ot)
            elif v is not None:
                b.add(Part({**attrs, "surface": "interior glazing"}, layer="interior"), ot)
            else:
                b.add(Part(attrs, layer="interior"), ot)
    verts, tris, part = b.mesh_arrays()
    if len(tris) == 0:
        raise InputError(f"{path}: no Surface with PlanarGeometry in the gbXML file; export it with its geometry "
                         "(surfaces and openings as polygons)")
    spaces, no_floor = _spaces(doc, floors, [sh if s.shell else None for s, sh in zip(doc.spaces, shells)], verdict)
    notes, warnings = _notes(path.name, doc, reclassified, interior, no_floor, n_no_geometry)
    windowed = {where for kind, where in verdict.values() if kind == "exterior"}
    warnings += _area_warnings(path.name, doc, [fp if i in windowed else None for i, fp in enumerate(floors)])
    site = _site(path.name, doc)
    glz = sum(1 for v in verdict.values() if v[0] == "exterior")
    surf_counts = ", ".join(f"{k} {n}" for k, n in counts.items() if k not in GLAZED and k not in ("NonSlidingDoor", "Air"))
    open_counts = ", ".join(f"{k} {n}" for k, n in counts.items() if k in GLAZED or k == "NonSlidingDoor")
    summary = (f"gbXML {doc.version} in {doc.unit}: {counted(len(doc.spaces), 'space')}, {counted(len(surfaces), 'surface')} "
               f"({surf_counts}), "
               f"openings: {open_counts or 'none'}; {counted(glz, 'exterior window')} ({sum('interior glazing)' not in r for r in reclassified)} "
               f"reclassified from their surface's type), {counted(len(interior), 'interior glazing')}; left out: Air surfaces and openings "
               f"({counts.get('Air', 0)}){f', {n_no_geometry} surfaces without PlanarGeometry' if n_no_geometry else ''}")
    return Mesh(verts, tris, part, b.parts, unit_warnings + warnings, notes, units="m", up_axis="z", site=site, spaces=spaces, summary=summary)


def _spaces(doc: Document, floors, bodies, verdict) -> tuple[list[Space], list[str]]:
    """:class:`Space` of each gbXML space (``floors``: :func:`_floor_of`; ``bodies``: the closed
    shell, or None where the space has none), those without a floor with their ``problem`` (the
    scene lists them as left out, with their windows: never a silent pass); the names of those."""
    hints: dict = {}
    for oid, (kind, where) in verdict.items():
        if kind == "exterior" and where >= 0:
            hints.setdefault(where, []).append(oid)
    out, no_floor = [], []
    seen: dict = {}
    for s in doc.spaces:
        seen[s.name] = seen.get(s.name, 0) + 1
    for i, s in enumerate(doc.spaces):
        fp = floors[i]
        # a Name shared by several spaces: the room is "Name (id)" (room_name's 'LongName (Name)')
        name, long_name = (s.id, s.name) if seen[s.name] > 1 else (s.name, "")
        usage = (("Name", s.name),) + ((("gbXML spaceType", s.space_type),) if s.space_type else ())
        if fp is None:  # kept, with its problem: a space with windows and no floor is never silently gone
            no_floor.append(s.name)
            out.append(Space(id=s.id, name=name, long_name=long_name, storey=doc.storeys.get(s.storey, ""),
                             footprint=np.zeros((0, 2)), floor_z=0.0, top_z=0.0, windows=tuple(sorted(hints.get(i, ()))),
                             zones=tuple(z for z in (doc.zones.get(s.zone),) if z), kind=SPACE_KIND, body=bodies[i],
                             problem="no floor in its ShellGeometry, PlanarGeometry or floor surfaces", usage=usage))
            continue
        ring, holes, z0, z1 = fp
        out.append(Space(id=s.id, name=name, long_name=long_name, storey=doc.storeys.get(s.storey, ""), footprint=ring,
                         floor_z=z0, top_z=z1, windows=tuple(sorted(hints.get(i, ()))),
                         zones=tuple(z for z in (doc.zones.get(s.zone),) if z), holes=holes, kind=SPACE_KIND,
                         body=bodies[i], usage=usage))  # the closed shell is the volume: windows match it
    return out, no_floor


def _area_warnings(name: str, doc: Document, floors) -> list[str]:
    """A warning naming the spaces whose footprint as read differs from the Space's own Area by more
    than :data:`AREA_MISMATCH`: the reading, or the file, is off there (check the rooms' floors);
    ``floors``: None for the spaces not to check (those without a window)."""
    import shapely

    off = []
    for s, fp in zip(doc.spaces, floors):
        if fp is None or s.area_m2 is None:
            continue
        a = shapely.Polygon(fp[0], fp[1]).area
        if abs(a - s.area_m2) > AREA_MISMATCH * s.area_m2:
            off.append(f"'{s.name}' {a:.1f} m² (Area {s.area_m2:.1f} m²)")
    if not off:
        return []
    return [f"{name}: the floor read of {counted(len(off), 'space')} differs from the Area the file gives by more "
            f"than {AREA_MISMATCH:.0%}: {'; '.join(off[:8])}{' ...' if len(off) > 8 else ''}; check those rooms' floors "
            "(validate --plan DIR draws them)"]


def _notes(name: str, doc: Document, reclassified, interior, no_floor, n_no_geometry) -> tuple[list, list]:
    notes, warnings = [], []
    more = lambda xs: f"{'; '.join(xs[:8])}{' ...' if len(xs) > 8 else ''}"  # noqa: E731
    if reclassified:
        notes.append(f"{name}: {len(reclassified)} glazing(s) reclassified by what lies on their two sides (the surface type "
                     f"says otherwise; nothing but shading or the outdoors on one side: an exterior window): {more(reclassified)}")
    if interior:
        notes.append(f"{name}: {len(interior)} glazing(s) between two spaces: interior glazing (layer interior), not a "
                     f"window of either room: {more(interior)}")
    if no_floor:
        warnings.append(f"{name}: {len(no_floor)} space(s) without a floor (no ShellGeometry, PlanarGeometry or floor "
                        f"surface) cannot be rooms: {more(no_floor)}")
    if n_no_geometry:
        warnings.append(f"{name}: {n_no_geometry} surface(s) without PlanarGeometry left out")
    return notes, warnings


def _site(name: str, doc: Document) -> Site | None:
    north = None if doc.azimuth is None else (-doc.azimuth) % 360.0
    if doc.latitude is None and north is None:
        return None
    src = ["latitude and longitude from Campus/Location"] if doc.latitude is not None else []
    if north is not None:
        src.append(f"true north from CADModelAzimuth {doc.azimuth:g} deg")
    return Site(latitude=doc.latitude, longitude=doc.longitude,
                elevation_m=None if doc.elevation is None else doc.elevation * doc.scale, true_north_deg=north,
                source=f"{name}: " + "; ".join(src))
