"""IFC models made in code with ifcopenshell.api: a small two-storey house and an apartment block.

Written like real exports: walls with openings (IfcOpeningElement voiding the wall, filled by the
window), windows with an opaque frame and glass panes as thin solids (6 mm), a window split into
two panes by a mullion, a round window whose frame and pane are polygons of many segments, spaces
with extruded footprints, slabs, a roof, a site with its latitude and longitude, a rotated true
north, zones grouping spaces, and optionally an IfcMapConversion to EPSG:28992. GlobalIds derive
from names and the header carries a fixed time stamp, so two runs write byte-identical files.

Frame: metres, z up, +y the project's north before ``TrueNorth``. Needs ifcopenshell (the ``ifc``
extra); imported inside the functions.
"""
from __future__ import annotations

import uuid
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

#: Namespace of the sample's GlobalIds (uuid5 of an element's name)
_NS = uuid.UUID("6f1c1b8e-6b0e-4d3a-9a47-0c3f5b2d7e11")
#: Glass panes are thin solids this thick [m] ...
GLASS_M = 0.006
#: ... in a frame this wide (face) and deep (across the wall) [m].
FRAME_M, FRAME_DEPTH_M = 0.06, 0.08
#: Walls are this thick [m].
WALL_M = 0.3


@dataclass
class Builder:
    """A thin layer over ifcopenshell.api for axis-aligned buildings in world coordinates."""

    schema: str = "IFC4"
    f: object = None
    body: object = None
    storeys: dict = field(default_factory=dict)
    styles: dict = field(default_factory=dict)
    named_ids: list = field(default_factory=list)

    def __post_init__(self):
        import ifcopenshell.api
        import ifcopenshell.api.owner.settings

        self.api = ifcopenshell.api
        self.f = ifcopenshell.api.run("project.create_file", version=self.schema)
        ifcopenshell.api.owner.settings.factory_reset()  # the user and application of this file only (none in IFC4)
        if self.schema == "IFC2X3":  # IFC2X3 needs an owner history on every rooted entity
            self._owner()
        self.project = self.entity("IfcProject", "Sample project")
        units = [self.api.run("unit.add_si_unit", self.f, unit_type=t) for t in ("LENGTHUNIT", "AREAUNIT", "VOLUMEUNIT")]
        self.api.run("unit.assign_unit", self.f, units=units)  # metres, in this order
        model = self.api.run("context.add_context", self.f, context_type="Model")
        self.context = model
        self.body = self.api.run("context.add_context", self.f, context_type="Model", context_identifier="Body",
                                 target_view="MODEL_VIEW", parent=model)
        self.site = self.entity("IfcSite", "Site")
        self.building = self.entity("IfcBuilding", "House")
        self.api.run("aggregate.assign_object", self.f, relating_object=self.project, products=[self.site])
        self.api.run("aggregate.assign_object", self.f, relating_object=self.site, products=[self.building])
        self.styles["glass"] = self.surface_style("Glass", (0.6, 0.8, 0.9), 0.9)
        self.styles["frame"] = self.surface_style("Frame", (0.9, 0.9, 0.9), 0.0)

    def _owner(self):
        """The user and application of the owner histories IFC2X3 needs. ifcopenshell.api finds them
        in the file (its default ``owner.settings``); nothing global is patched, so an IFC4 file
        written later in the same process has no owner history."""
        person = self.f.createIfcPerson(None, "Sample", None)
        org = self.f.createIfcOrganization(None, "en17037cli", None)
        self.f.createIfcPersonAndOrganization(person, org)
        self.f.createIfcApplication(org, "0.1", "en17037cli samples", "en17037cli")

    # --- entities ---------------------------------------------------------------------------
    def entity(self, ifc_class: str, name: str, **kw):
        import ifcopenshell.guid

        e = self.api.run("root.create_entity", self.f, ifc_class=ifc_class, name=name, **kw)
        e.GlobalId = ifcopenshell.guid.compress(uuid.uuid5(_NS, f"{ifc_class}:{name}").hex)
        self.named_ids.append(e.GlobalId)
        return e

    def surface_style(self, name: str, rgb, transparency: float):
        style = self.api.run("style.add_style", self.f, name=name)
        colour = self.f.createIfcColourRgb(None, *rgb)
        self.f.createIfcSurfaceStyleRendering(colour, transparency, None, None, None, None, None, None, "NOTDEFINED")
        style.Styles = [self.f.by_type("IfcSurfaceStyleRendering")[-1]]
        return style

    def storey(self, name: str, elevation: float):
        s = self.entity("IfcBuildingStorey", name)
        s.Elevation = elevation
        self.api.run("aggregate.assign_object", self.f, relating_object=self.building, products=[s])
        self.storeys[name] = s
        return s

    def place(self, product, storey=None):
        """World placement (identity) and containment in a storey."""
        self.api.run("geometry.edit_object_placement", self.f, product=product, matrix=np.eye(4))
        if storey is not None:
            self.api.run("spatial.assign_container", self.f, products=[product], relating_structure=storey)

    def represent(self, product, items, style: str | None = None, styles: list | None = None):
        import ifcopenshell.util.shape_builder as sb

        rep = sb.ShapeBuilder(self.f).get_representation(self.body, items)
        for k, item in enumerate(items):
            s = styles[k] if styles is not None else style
            if s is not None:
                self.api.run("style.assign_item_style", self.f, item=item, style=self.styles[s])
        self.api.run("geometry.assign_representation", self.f, product=product, representation=rep)
        return rep

    # --- geometry ---------------------------------------------------------------------------
    def prism(self, outer, z0: float, height: float, holes=()):
        """An extrusion along +z of a polygon (k, 2) [m] from z0, with holes."""
        import ifcopenshell.util.shape_builder as sb

        b = sb.ShapeBuilder(self.f)
        prof = b.profile(b.polyline([tuple(map(float, p)) for p in outer], closed=True),
                         inner_curves=[b.polyline([tuple(map(float, p)) for p in h], closed=True) for h in holes])
        return b.extrude(prof, float(height), position=(0.0, 0.0, float(z0)))

    def plate(self, outer_uv, holes_uv, origin, u, v, n, depth: float):
        """An extrusion of a polygon in the plane (origin, u, v) along n by depth [m] (a frame, a pane)."""
        import ifcopenshell.util.shape_builder as sb

        b = sb.ShapeBuilder(self.f)
        prof = b.profile(b.polyline([tuple(map(float, p)) for p in outer_uv], closed=True),
                         inner_curves=[b.polyline([tuple(map(float, p)) for p in h], closed=True) for h in holes_uv])
        return b.extrude(prof, float(depth), position=tuple(map(float, origin)), extrusion_vector=(0.0, 0.0, 1.0),
                         position_z_axis=tuple(map(float, n)), position_x_axis=tuple(map(float, u)))

    def wall(self, name: str, storey, x0, y0, x1, y1, z0: float, height: float, thickness: float = WALL_M):
        """A straight wall from (x0, y0) to (x1, y1), its thickness to the left of that direction."""
        d = np.array([x1 - x0, y1 - y0], float)
        d /= np.linalg.norm(d)
        left = np.array([-d[1], d[0]]) * thickness
        outline = [(x0, y0), (x1, y1), (x1 + left[0], y1 + left[1]), (x0 + left[0], y0 + left[1])]
        w = self.entity("IfcWall", name)
        self.place(w, storey)
        self.represent(w, [self.prism(outline, z0, height)])
        return w

    def slab(self, name: str, storey, outline, z0: float, thickness: float, ifc_class="IfcSlab", predefined=None):
        s = self.entity(ifc_class, name, **({"predefined_type": predefined} if predefined else {}))
        self.place(s, storey)
        self.represent(s, [self.prism(outline, z0, thickness)])
        return s

    def space(self, name: str, long_name: str, storey, outline, z0: float, height: float):
        s = self.entity("IfcSpace", name)
        s.LongName = long_name
        self.place(s)
        self.api.run("aggregate.assign_object", self.f, relating_object=storey, products=[s])
        self.represent(s, [self.prism(outline, z0, height)])
        return s

    def window(self, name: str, storey, wall, centre, n, u, width: float, height: float, panes: int = 1,
               round_segments: int = 0, spaces=(), glass: bool = True):
        """A window in ``wall``: an opening through it, a frame and glass panes (thin solids).

        centre : (3,) [m] the opening's centre on the wall's outer face; n : (3,) outward normal;
        u : (3,) horizontal axis of the window; ``panes`` > 1 splits the glass by mullions;
        ``round_segments`` > 0 makes a round window of that many segments (diameter ``width``);
        ``glass`` False leaves the glass out (frames only, as old IFC2x exports draw windows).
        """
        centre, n, u = (np.asarray(a, float) for a in (centre, n, u))
        v = np.cross(n, u)
        hw, hh = width / 2, height / 2
        if round_segments:
            t = np.linspace(0, 2 * np.pi, round_segments, endpoint=False)
            circle = lambda r: np.column_stack([r * np.cos(t), r * np.sin(t)])  # noqa: E731
            outer, inner = circle(hw), circle(hw - FRAME_M)
            panes_uv = [inner]
        else:
            outer = np.array([(-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh)])
            iw = width - 2 * FRAME_M - (panes - 1) * FRAME_M
            pw = iw / panes
            panes_uv = []
            for k in range(panes):
                a = -hw + FRAME_M + k * (pw + FRAME_M)
                panes_uv.append(np.array([(a, -hh + FRAME_M), (a + pw, -hh + FRAME_M), (a + pw, hh - FRAME_M), (a, hh - FRAME_M)]))
            inner = None
        # the opening, through the whole wall
        op = self.entity("IfcOpeningElement", f"Opening {name}")
        self.place(op)
        pad = 0.02
        self.represent(op, [self.plate(outer * (1 if round_segments else 1.0), [], centre + pad * n, u, v, -n, WALL_M + 2 * pad)])
        self.api.run("feature.add_feature", self.f, feature=op, element=wall)
        win = self.entity("IfcWindow", name)
        self.place(win, storey)
        front = centre - 0.02 * n  # the frame's outer face, 2 cm inside the wall's outer face
        holes = [inner] if round_segments else panes_uv
        frame = self.plate(outer, holes, front, u, v, -n, FRAME_DEPTH_M)
        glazing = [self.plate(p, [], front - (FRAME_DEPTH_M / 2 - GLASS_M / 2) * n, u, v, -n, GLASS_M)
                   for p in panes_uv] if glass else []
        self.represent(win, [frame, *glazing], styles=["frame"] + ["glass"] * len(glazing))
        self.api.run("feature.add_filling", self.f, opening=op, element=win)
        for sp in spaces:  # the file's own space boundaries, as exporters write them
            gid = self.entity_id(f"boundary {name} {sp.Name}")
            self.named_ids.append(gid)
            e = self.f.create_entity("IfcRelSpaceBoundary", GlobalId=gid,
                                     RelatingSpace=sp, RelatedBuildingElement=win, PhysicalOrVirtualBoundary="PHYSICAL",
                                     InternalOrExternalBoundary="EXTERNAL")
            if self.schema == "IFC2X3":
                e.OwnerHistory = self.f.by_type("IfcOwnerHistory")[0] if self.f.by_type("IfcOwnerHistory") else None
        return win

    def _sort_sets(self):
        """SET attributes (unordered in the schema) written in step-id order: ifcopenshell keeps them in
        Python sets, whose order varies from run to run."""
        import ifcopenshell

        schema = ifcopenshell.ifcopenshell_wrapper.schema_by_name(self.f.schema)
        sets: dict = {}
        for e in self.f:
            cls = e.is_a()
            if cls not in sets:
                decl = schema.declaration_by_name(cls)
                sets[cls] = [i for i, a in enumerate(decl.all_attributes())
                             if hasattr(a.type_of_attribute(), "type_of_aggregation_string")
                             and a.type_of_attribute().type_of_aggregation_string() == "set"]
            for i in sets[cls]:
                v = e[i]
                if v and all(isinstance(x, ifcopenshell.entity_instance) for x in v):
                    e[i] = sorted(v, key=lambda x: x.id())

    def entity_id(self, name: str) -> str:
        import ifcopenshell.guid

        return ifcopenshell.guid.compress(uuid.uuid5(_NS, name).hex)

    def zone(self, name: str, spaces):
        z = self.entity("IfcZone", name)
        self.api.run("group.assign_group", self.f, products=list(spaces), group=z)
        return z

    def locate(self, latitude: float, longitude: float, true_north_deg: float, map_conversion: tuple | None = None):
        """IfcSite RefLatitude/RefLongitude, the context's TrueNorth (azimuth of true north clockwise
        from +y [deg]) and optionally an IfcMapConversion (eastings, northings, rotation [deg] of
        the project's x axis counterclockwise from the map's)."""
        import ifcopenshell.util.geolocation as gl

        self.site.RefLatitude = gl.dd2dms(latitude, use_us=True)
        self.site.RefLongitude = gl.dd2dms(longitude, use_us=True)
        self.site.RefElevation = 0.0
        a = np.radians(true_north_deg)
        self.context.TrueNorth = self.f.createIfcDirection((float(np.sin(a)), float(np.cos(a))))
        if map_conversion and self.schema != "IFC2X3":
            e, n, rot = map_conversion
            crs = self.f.createIfcProjectedCRS(Name="EPSG:28992", Description="Amersfoort / RD New")
            r = np.radians(rot)
            self.f.createIfcMapConversion(SourceCRS=self.context, TargetCRS=crs, Eastings=float(e), Northings=float(n),
                                          OrthogonalHeight=0.0, XAxisAbscissa=float(np.cos(r)), XAxisOrdinate=float(np.sin(r)),
                                          Scale=1.0)

    def write(self, path: Path) -> Path:
        h = self.f.header.file_name
        h.name, h.time_stamp = Path(path).name, "2026-01-01T00:00:00"  # no path, no clock: the same bytes every run
        for o in self.f.by_type("IfcOwnerHistory"):
            o.CreationDate = 1767225600  # 2026-01-01
        self._sort_sets()
        named = set(self.named_ids)
        for e in self.f.by_type("IfcRoot"):  # relationships the api made get ids from their (deterministic) step ids
            if e.GlobalId not in named:
                e.GlobalId = self.entity_id(f"{e.is_a()}#{e.id()}")
        self.f.write(str(path))
        return Path(path)


#: The house's rooms: name, long name, storey, outline (x0, y0, x1, y1) inside the walls [m], zone.
HOUSE_SPACES = (
    ("0.01", "Living", "Ground floor", (0.3, 0.3, 5.95, 7.7), "Flat A"),
    ("0.02", "Kitchen", "Ground floor", (6.05, 0.3, 9.7, 7.7), "Flat A"),
    ("1.01", "Bedroom west", "First floor", (0.3, 0.3, 4.95, 7.7), "Flat B"),
    ("1.02", "Bedroom east", "First floor", (5.05, 0.3, 9.7, 7.7), "Flat B"),
)


def house(path: Path, schema: str = "IFC4", map_conversion: bool = False, true_north_deg: float = 20.0,
          round_segments: int = 96, with_spaces: bool = True) -> Path:
    """Write the sample house: 10 x 8 m, two storeys of 3 m, 0.3 m walls; ground floor: living
    room (a 3 m south window of two panes split by a mullion, a west window) and kitchen (a north
    window); first floor: two bedrooms (a south window; a round east window of ``round_segments``
    segments). Zones 'Flat A' (ground floor) and 'Flat B' (first floor); ``with_spaces=False``
    leaves out the spaces, their boundaries and the zones (a file exported without rooms)."""
    b = Builder(schema)
    storeys = {"Ground floor": b.storey("Ground floor", 0.0), "First floor": b.storey("First floor", 3.0)}
    b.locate(52.0116, 4.3571, true_north_deg, (85000.0, 446000.0, 10.0) if map_conversion else None)
    foot = [(0, 0), (10, 0), (10, 8), (0, 8)]
    b.place(b.site)  # the site's own body is the terrain (ground)
    b.represent(b.site, [b.prism([(-60, -60), (70, -60), (70, 68), (-60, 68)], -0.25, 0.2)])
    for name, outline, h in (("Neighbour south", [(-30, -28), (40, -28), (40, -18), (-30, -18)], 9.0),
                             ("Neighbour north", [(-20, 22), (30, 22), (30, 32), (-20, 32)], 12.0)):
        n = b.entity("IfcBuildingElementProxy", name)  # context buildings: landscape
        b.place(n)
        b.represent(n, [b.prism(outline, 0.0, h)])
    walls, spaces = {}, {}
    for s, (name, z) in enumerate((("Ground floor", 0.0), ("First floor", 3.0))):
        st = storeys[name]
        b.slab(f"Slab {s}", st, foot, z - 0.2, 0.2, predefined="FLOOR")
        # outer walls, counterclockwise seen from above, thickness inwards (to the left)
        for k, (p, q) in enumerate(zip(foot, foot[1:] + foot[:1])):
            walls[(s, k)] = b.wall(f"Wall {s}.{k}", st, *p, *q, z, 2.8)
        xp = 6.0 if s == 0 else 5.0
        b.wall(f"Partition {s}", st, xp + 0.05, 0.3, xp + 0.05, 7.7, z, 2.8, thickness=0.1)
    for name, long_name, storey, (x0, y0, x1, y1), _ in HOUSE_SPACES if with_spaces else ():
        z = 0.0 if storey == "Ground floor" else 3.0
        spaces[name] = b.space(name, long_name, storeys[storey], [(x0, y0), (x1, y0), (x1, y1), (x0, y1)], z, 2.8)
    b.slab("Roof", storeys["First floor"], foot, 5.8, 0.2, ifc_class="IfcRoof") if schema == "IFC2X3" else \
        b.slab("Roof", storeys["First floor"], foot, 5.8, 0.2, predefined="ROOF")
    S, N, W, E = (0, -1, 0), (0, 1, 0), (-1, 0, 0), (1, 0, 0)
    g, f1 = storeys["Ground floor"], storeys["First floor"]
    b.window("W living south", g, walls[(0, 0)], (2.5, 0.0, 1.4), S, (1, 0, 0), 3.0, 1.6, panes=2, spaces=[spaces["0.01"]] if with_spaces else [])
    b.window("W living west", g, walls[(0, 3)], (0.0, 4.0, 1.5), W, (0, -1, 0), 1.2, 1.2, spaces=[spaces["0.01"]] if with_spaces else [])
    b.window("W kitchen north", g, walls[(0, 2)], (7.75, 8.0, 1.55), N, (-1, 0, 0), 1.5, 1.1, spaces=[spaces["0.02"]] if with_spaces else [])
    b.window("W bedroom south", f1, walls[(1, 0)], (2.25, 0.0, 4.5), S, (1, 0, 0), 1.5, 1.2, spaces=[spaces["1.01"]] if with_spaces else [])
    b.window("W bedroom round", f1, walls[(1, 1)], (10.0, 4.0, 4.6), E, (0, 1, 0), 1.0, 1.0, round_segments=round_segments,
             spaces=[spaces["1.02"]] if with_spaces else [])
    if with_spaces:
        b.zone("Flat A", [spaces["0.01"], spaces["0.02"]])
        b.zone("Flat B", [spaces["1.01"], spaces["1.02"]])
    return b.write(path)


#: The apartment block's rooms per flat: (LongName, width along the façade [m]).
BLOCK_ROOMS = (("Living", 3.6), ("Bedroom", 3.0), ("Bedroom 2", 2.4))


def block(path: Path, storeys: int = 6, flats_per_storey: int = 12, schema: str = "IFC4") -> Path:
    """Write an apartment block: ``storeys`` storeys of 3 m, ``flats_per_storey`` flats each
    (half on the south façade, half on the north, either side of a 1.6 m corridor), three rooms
    per flat (:data:`BLOCK_ROOMS`, 5.5 m deep) each with one 1.2 x 1.5 m window (sill 0.9 m) in
    the 0.3 m outer wall; partitions of 0.1 m between rooms; from the first floor up, a balcony
    (1.5 m deep, 0.2 m slab, 1.0 m railing) in front of every living room, shading the window
    below it; a neighbouring block 25 m to the south (a proxy: landscape). Spaces are named
    ``<storey>.<flat>.<room>`` (e.g. '2.07.1'), LongName from :data:`BLOCK_ROOMS`, and grouped
    in one zone per flat ('Flat 2.07'). Defaults: 6 x 12 x 3 = 216 rooms.
    """
    per_side = -(-flats_per_storey // 2)
    flat_w = sum(w for _, w in BLOCK_ROOMS)
    length, depth, room_d = per_side * flat_w + 2 * WALL_M, 2 * 5.5 + 1.6 + 2 * WALL_M + 2 * 0.1, 5.5
    b = Builder(schema)
    b.building.Name = "Block"
    b.locate(52.0116, 4.3571, 0.0, None)
    b.place(b.site)
    b.represent(b.site, [b.prism([(-60, -80), (length + 60, -80), (length + 60, depth + 60), (-60, depth + 60)], -0.25, 0.2)])
    n = b.entity("IfcBuildingElementProxy", "Neighbour block")
    b.place(n)
    b.represent(n, [b.prism([(0, -37), (length, -37), (length, -25), (0, -25)], 0.0, 15.0)])
    foot = [(0, 0), (length, 0), (length, depth), (0, depth)]
    S, N = (0, -1, 0), (0, 1, 0)
    height = 3.0 * storeys
    for s in range(storeys):
        z = 3.0 * s
        st = b.storey(f"Storey {s}", z)
        b.slab(f"Slab {s}", st, foot, z - 0.2, 0.2, predefined="FLOOR")
        walls = [b.wall(f"Wall {s}.{k}", st, *p, *q, z, 2.8) for k, (p, q) in enumerate(zip(foot, foot[1:] + foot[:1]))]
        ys = WALL_M + room_d  # the corridor's walls
        b.wall(f"Corridor south {s}", st, WALL_M, ys, length - WALL_M, ys, z, 2.8, thickness=0.1)
        b.wall(f"Corridor north {s}", st, length - WALL_M, depth - ys, WALL_M, depth - ys, z, 2.8, thickness=0.1)
        for f in range(flats_per_storey):
            side, i = f % 2, f // 2  # south flats even, north flats odd
            x = WALL_M + i * flat_w
            flat = f"{s}.{f + 1:02d}"
            spaces = []
            for r, (long_name, w) in enumerate(BLOCK_ROOMS):
                x0, x1 = x + (0.05 if r or i else 0.0), x + w - 0.05
                y0, y1 = (WALL_M, WALL_M + room_d) if side == 0 else (depth - WALL_M - room_d, depth - WALL_M)
                sp = b.space(f"{flat}.{r + 1}", long_name, st, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)], z, 2.8)
                spaces.append(sp)
                if r < len(BLOCK_ROOMS) - 1 or i < per_side - 1:  # a partition at the room's east side
                    b.wall(f"Partition {flat}.{r + 1}", st, x + w + 0.05, y0, x + w + 0.05, y1, z, 2.8, thickness=0.1)
                cx = x + w / 2
                if side == 0:
                    b.window(f"W {flat}.{r + 1}", st, walls[0], (cx, 0.0, z + 1.65), S, (1, 0, 0), 1.2, 1.5, spaces=[sp])
                else:
                    b.window(f"W {flat}.{r + 1}", st, walls[2], (cx, depth, z + 1.65), N, (-1, 0, 0), 1.2, 1.5, spaces=[sp])
                x += w
            x = WALL_M + i * flat_w
            if s > 0:  # the living room's balcony, its slab level with the floor
                w0 = BLOCK_ROOMS[0][1]
                y_out, y_in = (-1.5, 0.0) if side == 0 else (depth + 1.5, depth)
                outline = [(x, min(y_out, y_in)), (x + w0, min(y_out, y_in)), (x + w0, max(y_out, y_in)), (x, max(y_out, y_in))]
                b.slab(f"Balcony {flat}", st, outline, z - 0.2, 0.2, predefined="BASESLAB")
                rail = b.entity("IfcRailing", f"Railing {flat}")
                b.place(rail, st)
                ry = y_out if side == 0 else y_out - 0.05
                b.represent(rail, [b.prism([(x, ry), (x + w0, ry), (x + w0, ry + 0.05), (x, ry + 0.05)], z, 1.0)])
            b.zone(f"Flat {flat}", spaces)
    b.slab("Roof", b.storeys[f"Storey {storeys - 1}"], foot, height - 0.2, 0.2, predefined="ROOF")
    return b.write(path)
