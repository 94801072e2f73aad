"""What every model reader returns: triangles with per-face parts, and what the format knows of the building.

A :class:`Mesh` is one model file's geometry: float64 vertices, triangles, and for each triangle
the :class:`Part` it belongs to. A part is the unit that layer rules match: an OBJ object/group/
material combination, a glTF node, an IFC product's geometry of one style, a CityJSON object's
semantic surface. Readers know nothing of layers rules, rooms or the standard; they describe.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

#: Attribute keys a part may carry, and what each means. Layer rules match them by name
#: (``{class: "IfcWindow", layer: window}``); ``match`` globs test every value.
PART_KEYS = {
    "object": "OBJ object (o), glTF node",
    "group": "OBJ group (g), glTF geometry, DXF layer",
    "material": "OBJ material (usemtl), glTF/IFC material or surface style name",
    "file": "the model file's stem (set by the scene, not the reader)",
    "name": "IFC product Name",
    "class": "IFC entity (IfcWindow), CityJSON / CityGML city object type (Building), DXF entity type (3DFACE), "
             "gbXML surface or opening type (ExteriorWall, FixedWindow)",
    "id": "IFC GlobalId, CityJSON object id, CityGML gml:id, gbXML surface or opening id",
    "type": "IFC type object name (IfcWindowType Name), or ObjectType",
    "storey": "IFC building storey Name",
    "surface": "semantic surface: CityJSON WallSurface/RoofSurface/GroundSurface...; IFC 'glazing' or 'frame'",
    "parent": "CityJSON parent object type (a BuildingPart's Building); IFC aggregate's class",
    "colour": "DXF ACI colour number",
    "space": "gbXML: the Name of the space a surface bounds",
    "slope": "CityJSON / CityGML: 'steep' on the steep sides of a ground-type object that rise above the ground "
             "(layer landscape; io/cityjson/relief.py)",
}

#: Layers a reader may propose for a part (the project's rules decide; see scene/layers.py).
LAYER_NAMES = ("window", "interior", "ground", "landscape", "ignore")


@dataclass(frozen=True)
class Part:
    """A named piece of a model file.

    attrs : mapping of :data:`PART_KEYS` (and ``attr.<key>`` for free attributes, e.g. a
        CityJSON attribute ``attr.roofType``) to strings; missing keys are absent, not "".
    layer : the format's default layer for this part (IFC class table, CityJSON type table),
        or None when only the project's rules decide (OBJ, glTF, PLY...).
    obstructs_sun : the format's default; the built-in readers give True for every part, CityJSON
        vegetation included (a layer rule with ``obstructs_sun: false`` lets the sun through).
    window : faces of parts sharing this key form one window (an IfcWindow's GlobalId: its
        panes together); None lets the scene group glazing by edge-connected coplanar faces.
    host : ids (``attrs['id']``) of the objects whose opening this part fills: the wall an
        IfcWindow fills (IfcRelFillsElement -> IfcOpeningElement -> IfcRelVoidsElement), the
        curtain wall of a plate; their faces around the glazing give its reveal (point P). Empty
        where the format does not say.
    assembly : id of the object this part is a piece of (an IfcCurtainWall's plates and members,
        an IfcRoof's slabs: IfcRelAggregates), or None; a host's pieces count as the host.
    """

    attrs: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))
    layer: str | None = None
    obstructs_sun: bool = True
    window: str | None = None
    host: tuple[str, ...] = ()
    assembly: str | None = None

    def __post_init__(self):
        object.__setattr__(self, "attrs", MappingProxyType({k: str(v) for k, v in dict(self.attrs).items() if v not in (None, "")}))
        if self.layer is not None and self.layer not in LAYER_NAMES:
            raise ValueError(f"Part.layer: expected one of {LAYER_NAMES}, got {self.layer!r}")

    @property
    def label(self) -> str:
        """Display name: the first of name, object, group, material, id, class that is set ('' if none)."""
        for key in ("name", "object", "group", "material", "id", "class"):
            if key in self.attrs:
                return self.attrs[key]
        return ""


@dataclass(frozen=True)
class Space:
    """A room as the model file defines it (an IfcSpace, a gbXML Space), in the mesh's frame.

    footprint : (k, 2) float [m], outer ring of the space's floor outline (x, y), counterclockwise
    floor_z, top_z : float [m], bottom and top of the space
    windows : GlobalIds (``Part.window`` keys) of the windows that bound it by the file's own
        space boundaries (IfcRelSpaceBoundary; gbXML: the exterior glazings on its side); empty
        when the file has none
    zones : names of the zones (IfcZone, IfcSpatialZone, gbXML Zone) that group it
    holes : inner rings of the floor outline, (k, 2) float [m] each
    body : (k, 3, 3) float [m], the closed surface of the space's volume (triangles), where the
        format gives it: windows are matched to spaces against it (a sloped ceiling, a roof
        light's well); None: the footprint extruded from ``floor_z`` to ``top_z`` stands for it
    problem : why the space has no usable floor ("" when it has one): reported, never dropped
    kind : what the file calls it ("IfcSpace", "gbXML Space"): a project's ``ifc_spaces`` /
        ``gbxml_spaces`` glob picks spaces of its kind
    usage : what the file says the space is used for, as (where, text) pairs: ("LongName", ...),
        ("Name", ...), ("ObjectType", ...), ("IfcSpaceType", type name), ("classification
        'Uniclass 2015'", "SL_45_10_09 Bedrooms"), ("gbXML spaceType", ...); the scene reads the
        room's kind from them (``scene/kinds.py``)
    """

    id: str
    name: str
    long_name: str
    storey: str
    footprint: np.ndarray
    floor_z: float
    top_z: float
    windows: tuple[str, ...] = ()
    zones: tuple[str, ...] = ()
    holes: tuple[np.ndarray, ...] = ()
    body: np.ndarray | None = None
    problem: str = ""
    kind: str = "IfcSpace"
    usage: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True)
class Site:
    """What a model file says about where it stands. Every field is optional (None: not in the file).

    latitude, longitude : float [deg], north and east positive (IfcSite RefLatitude/RefLongitude)
    elevation_m : float [m] (IfcSite RefElevation)
    true_north_deg : float [deg], azimuth of true north clockwise from the mesh's +Y
        (from the model context's TrueNorth)
    crs : str, e.g. "EPSG:7415", the coordinate reference system of the vertices
    source : str, one line saying where the values came from (for the report)
    reprojected_from : str, the CRS the file's coordinates were in where the reader projected them
        to ``crs`` (CityGML to the project's CRS), else None
    north_warning : str, what is odd about the file's north and how the reader took it (a TrueNorth
        that is not a horizontal direction), else None; warned where the run takes the file's north
    """

    latitude: float | None = None
    longitude: float | None = None
    elevation_m: float | None = None
    true_north_deg: float | None = None
    crs: str | None = None
    source: str = ""
    reprojected_from: str | None = None
    north_warning: str | None = None


@dataclass
class Mesh:
    """Triangles of one model file.

    vertices : (n, 3) float64, in the file's units and axes unless ``units`` / ``up_axis`` say
        the reader already fixed them (IFC and CityJSON give metres, z up)
    triangles : (m, 3) int64, indices into ``vertices``
    part : (m,) int64, index into ``parts`` of each triangle
    parts : list of :class:`Part`
    warnings : what was dropped or could not be read as it is (counted, one line each)
    notes : neutral facts worth a line in the report (LoD fallbacks, objects left out by distance)
    units, up_axis : "m" / "z" when the format fixes them, None when the project decides
    site : what the file says about its location, north and CRS, or None
    spaces : rooms the file defines (IfcSpace, gbXML Space), in the vertices' frame
    windows_left_out : (label, why) of the windows the file defines that give no glazing (no
        geometry, no transparent part): ``validate`` lists them
    summary : one line of what the reader read and left out, with counts (``validate`` prints it),
        or "" (the scene then counts triangles and parts)
    openings_drawn : the format draws windows on top of their walls, in their plane (DXF): the
        scene cuts each window out of the coplanar opaque faces under it once layers are known
    """

    vertices: np.ndarray
    triangles: np.ndarray
    part: np.ndarray
    parts: list[Part]
    warnings: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    units: str | None = None
    up_axis: str | None = None
    site: Site | None = None
    spaces: list[Space] = field(default_factory=list)
    windows_left_out: list[tuple[str, str]] = field(default_factory=list)
    summary: str = ""
    openings_drawn: bool = False

    def __post_init__(self):
        self.vertices = np.asarray(self.vertices, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.asarray(self.triangles, dtype=np.int64).reshape(-1, 3)
        self.part = np.asarray(self.part, dtype=np.int64).reshape(-1)
        if len(self.part) != len(self.triangles):
            raise ValueError(f"Mesh.part: expected one part index per triangle ({len(self.triangles)}), got {len(self.part)}")
