"""The scene model: every face of the project in one local float64 frame, its windows and rooms.

No YAML and no files here: :mod:`en17037cli.scene.build` makes a :class:`Scene` from a project's
settings; engines read it.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from en17037cli.geometry import triangle_normals
from en17037cli.io.mesh import Part
from en17037cli.project.settings import Location, RoomSpec

if TYPE_CHECKING:
    from shapely import Polygon

#: Layer codes stored per face. ``ignore`` faces are dropped at load time.
LAYERS = ("window", "interior", "ground", "landscape")
WINDOW, INTERIOR, GROUND, LANDSCAPE = range(4)

#: A point lying on a glazing plane (a viewpoint, point P) is moved this far into the room [m].
GLAZING_OFFSET_M = 1e-3


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
    key: str | None = None  # the product the window belongs to (an IfcWindow's GlobalId), where the file says
    host: tuple[str, ...] = ()  # ids of the objects its opening is cut in (the wall), where the file says (Part.host)
    #: [m] how far the opening runs from the glazing to its room with nothing opaque between, beyond
    #: the host (a roof light's light well down to the hall's ceiling), where the room's space says; else 0
    open_depth_m: float = 0.0
    #: [m] how far behind the glazing the room's space begins (its boundary: the wall's room-side face
    #: as the model draws the space), where the room is a space of the model; else None
    space_distance_m: float | None = None
    #: indices into ``Scene.parts`` of every part whose glazing made the window (faces hidden behind
    #: others of it and the panes joined into it included): the elements it stands for (report ``source``)
    parts: tuple[int, ...] = ()

    @property
    def centroid(self) -> np.ndarray:
        """Area centroid (3,) [m]."""
        _, areas = triangle_normals(self.triangles)
        return (self.triangles.mean(axis=1) * areas[:, None]).sum(axis=0) / areas.sum()

    @property
    def sill_z(self) -> float:
        """Lowest point of the glazing [m], local frame."""
        return float(self.triangles[..., 2].min())

    @property
    def head_z(self) -> float:
        """Highest point of the glazing [m], local frame."""
        return float(self.triangles[..., 2].max())

    def facing(self, normal: np.ndarray) -> Window:
        """The same window with ``normal`` as its outward normal."""
        return replace(self, normal=normal)


@dataclass
class Room:
    """A room: floor level and polygon in the local frame, and the windows that bound it (outward
    normals set).

    floor : shapely Polygon, local xy [m]; floor_z, ceiling_z : [m], local
    spec : the room as the project file gives it (explicit points, requirements)
    window_reasons : window name -> why it bounds the room (for ``validate``)
    problem : why no criterion can assess the room (no floor at floor_z, no window), or None
    """

    name: str
    index: int
    floor_z: float
    floor: Polygon
    windows: list[Window]
    spec: RoomSpec
    floor_source: str = "given"
    ceiling_z: float = float("inf")
    ceiling_source: str = ""
    window_reasons: dict[str, str] = field(default_factory=dict)
    problem: str | None = None
    zones: tuple[str, ...] = ()  # the IFC zones (IfcZone, IfcSpatialZone) that group the room
    storey: str = ""  # the IFC building storey of the room's space
    #: why no verdict is given although the criteria ran: windows of the room were quarantined
    #: (:class:`Quarantined`); its levels are computed without them, and it never passes
    withheld: str | None = None
    usage: tuple[tuple[str, str], ...] = ()  # what the model says it is used for (its space's Space.usage)
    #: its uses (practice.ROOM_KINDS) and where they came from, and what they set: (key path, value,
    #: from) each (scene/kinds.py)
    kinds: tuple[str, ...] = ()
    kind_source: str = ""
    by_kind: tuple[tuple[str, object, str], ...] = ()
    space: int | None = None  # index into Scene.spaces of the space (IfcSpace, gbXML Space) it was made from


@dataclass(frozen=True)
class Quarantined:
    """An element of a model that the reader could not place as it stands: kept out of the way
    with a warning instead of stopping the model.

    element : how messages name it (``window 'W1' (IfcWindow 'W1' (GlobalId))``)
    action : what was done with it (``taken as opaque``, ``left out``, ``taken as a window of no room``)
    reason : what was found; advice : what a project file can do about it
    rooms : the rooms whose window it would have been: their verdicts are withheld (never a pass)
    """

    element: str
    action: str
    reason: str
    advice: str
    rooms: tuple[str, ...] = ()


@dataclass(frozen=True)
class LeftOut:
    """A space of the model the project picked that is not a room of the check, and why.

    windows : names of the windows that open into it (by geometry or by the model's space
        boundaries): a space with windows left out is not assessed, and the run cannot pass
    """

    name: str
    reason: str
    windows: tuple[str, ...] = ()


@dataclass
class Geometry:
    """Faces with their layers and parts, and what the files say of the site and their spaces.

    vertices : (n, 3) float64 [m]; triangles : (m, 3) int64
    layer : (m,) int8 layer code; obstructs_sun : (m,) bool
    part : (m,) int64 index into ``parts`` (each part's attributes include ``file``)
    sites : (file, Site, the file's rotation [deg]) of files that say where they stand
    spaces : (file, Space) of files that define rooms (IfcSpace), placed like their file's faces
    optics : (m, 2) float visible reflectance and transmittance a layer rule gives each face (NaN
        where none does: the daylight criterion's defaults apply), or None when no rule gives any
    windows_left_out : (file, window label, why) of windows the files define that give no glazing
    context : (index in model.files, file, first part, end part) of each city model (CityJSON,
        CityGML): its parts are ``parts[first:end]``
    located : (file, :class:`~en17037cli.io.georef.Located`) where each georeferenced file's CRS
        puts it (:mod:`en17037cli.scene.georef`)
    """

    vertices: np.ndarray
    triangles: np.ndarray
    layer: np.ndarray
    obstructs_sun: np.ndarray
    parts: list[Part]
    part: np.ndarray
    notes: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    file_hashes: dict[str, str] = field(default_factory=dict)
    sites: list = field(default_factory=list)
    spaces: list = field(default_factory=list)
    optics: np.ndarray | None = None  # (m, 2) reflectance, transmittance per face from the layer rules (NaN: default)
    read: list = field(default_factory=list)  # (file, one line of what its reader read and left out), for validate
    #: (file, window label, why) of windows the files define that give no glazing (Mesh.windows_left_out)
    windows_left_out: list = field(default_factory=list)
    context: list = field(default_factory=list)  # (model.files index, file, first part, end part) of city models
    located: list = field(default_factory=list)  # (file, Located) where a georeferenced file's CRS puts it
    files: list = field(default_factory=list)  # (model.files index, file, first part, end part) of every file read


@dataclass(kw_only=True)
class Scene(Geometry):
    """All faces of the project in a local float64 frame (world = local + origin) [m], with the
    windows and rooms found in them.

    location : the project's location with what it leaves out taken from the model (IfcSite)
    resolved : what came from where, for the report: key -> {"value": ..., "source": ...}
    """

    origin: np.ndarray
    windows: list[Window]
    rooms: list[Room] = field(default_factory=list)
    true_north_deg: float = 0.0
    location: Location | None = None
    resolved: dict = field(default_factory=dict)
    left_out: list[LeftOut] = field(default_factory=list)  # spaces the project picked that are not rooms, and why
    quarantined: list[Quarantined] = field(default_factory=list)  # elements set aside, what was done and why
    #: what the model's spaces and windows are to each other (see scene/spaces.py): None before rooms are made
    space_windows: object = None
    cache: dict = field(default_factory=dict, repr=False, compare=False)  # lookups built once per scene
    _boxes: tuple = field(default=(None,), repr=False, compare=False)  # cache of window_boxes


    def window_boxes(self) -> tuple[np.ndarray, np.ndarray]:
        """(w, 3), (w, 3) [m]: the lower and upper corners of each window's bounding box, local frame."""
        key = len(self.windows)
        if self._boxes[0] != key:
            lo = np.array([w.triangles.reshape(-1, 3).min(axis=0) for w in self.windows]).reshape(-1, 3)
            hi = np.array([w.triangles.reshape(-1, 3).max(axis=0) for w in self.windows]).reshape(-1, 3)
            self._boxes = (key, lo, hi)
        return self._boxes[1], self._boxes[2]

    def faces_of(self, mask: np.ndarray) -> np.ndarray:
        """(k, 3, 3) float [m] triangles of the faces selected by a boolean mask."""
        return self.vertices[self.triangles[mask]]

    def to_local(self, points) -> np.ndarray:
        return np.asarray(points, dtype=np.float64) - self.origin

    def to_world(self, points) -> np.ndarray:
        return np.asarray(points, dtype=np.float64) + self.origin

    def layer_counts(self) -> dict[str, int]:
        """Faces per layer, in :data:`LAYERS` order."""
        return {name: int(np.count_nonzero(self.layer == code)) for code, name in enumerate(LAYERS)}

    def part_label(self, part: int) -> str:
        """'file: object' label of a part, for messages."""
        p = self.parts[part]
        stem = p.attrs.get("file", "")
        name = p.label or "(unnamed)"
        return f"{stem}: {name}" if stem else name

    def ray_groups(self) -> dict:
        """The face groups the engines trace against, for :class:`~en17037cli.raytrace.RayEngine`:
        ``opaque`` (every face but glazing), ``interior``, ``landscape``, ``sun`` (opaque faces that
        block the sun) and each room's windows (:func:`room_window_group`). Masks are made on
        first use."""
        groups: dict = {
            "opaque": lambda: self.layer != WINDOW,
            "interior": lambda: self.layer == INTERIOR,
            "landscape": lambda: self.layer == LANDSCAPE,
            "sun": lambda: (self.layer != WINDOW) & self.obstructs_sun,
        }
        for room in self.rooms:
            groups[room_window_group(room)] = np.concatenate([w.face_ids for w in room.windows] or [np.zeros(0, np.int64)])
        return groups


def room_window_group(room: Room) -> str:
    """Name of the ray-engine group holding the window faces of ``room``."""
    return f"windows of room {room.index}"
