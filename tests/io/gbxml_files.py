"""gbXML documents written by the tests: the box room of en17037cli.samples as a gbXML space."""
from __future__ import annotations

import math
from pathlib import Path

from en17037cli.samples import BoxRoom
from en17037cli.samples.box import box_room_polygons

FT = 0.3048


def poly_loop(ring, scale: float = 1.0, turn_deg: float = 0.0) -> str:
    c, s = math.cos(math.radians(turn_deg)), math.sin(math.radians(turn_deg))
    pts = "".join(f"<CartesianPoint><Coordinate>{(c * x - s * y) / scale!r}</Coordinate><Coordinate>{(s * x + c * y) / scale!r}"
                  f"</Coordinate><Coordinate>{z / scale!r}</Coordinate></CartesianPoint>" for x, y, z in ring)
    return f"<PolyLoop>{pts}</PolyLoop>"


def surface(sid: str, kind: str, ring, spaces=(), openings=(), name: str | None = None, **kw) -> str:
    adj = "".join(f'<AdjacentSpaceId spaceIdRef="{s}"/>' for s in spaces)
    ops = "".join(f'<Opening openingType="{k}" id="{oid}"><PlanarGeometry>{poly_loop(r, **kw)}</PlanarGeometry>'
                  f"<Name>{oname}</Name></Opening>" for oid, k, r, oname in openings)
    return (f'<Surface surfaceType="{kind}" id="{sid}">{adj}<PlanarGeometry>{poly_loop(ring, **kw)}</PlanarGeometry>{ops}'
            f"<Name>{name or sid}</Name></Surface>")


def box_shell(x0, x1, y0, y1, z0, z1):
    c = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)]
    t = [(x, y, z1) for x, y, _ in c]
    return [c[::-1], t] + [[c[i], c[(i + 1) % 4], t[(i + 1) % 4], t[i]] for i in range(4)]


def space(sid: str, name: str, shell, storey: str = "st1", space_type: str = "", **kw) -> str:
    loops = "".join(poly_loop(r, **kw) for r in shell)
    st = f' spaceType="{space_type}"' if space_type else ""
    return (f'<Space id="{sid}"{st} buildingStoreyIdRef="{storey}" zoneIdRef="z1"><Area>1</Area>'
            f'<ShellGeometry id="{sid}-shell"><ClosedShell>{loops}</ClosedShell></ShellGeometry><Name>{name}</Name></Space>')


def document(spaces: list[str], surfaces: list[str], unit: str | None = "Meters", version: str = "0.37",
             azimuth: float | None = None, lat=52.0, lon=4.36) -> str:
    unit_attr = f' lengthUnit="{unit}"' if unit else ""
    az = "" if azimuth is None else f"<CADModelAzimuth>{azimuth!r}</CADModelAzimuth>"
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n<gbXML xmlns="http://www.gbxml.org/schema" version="{version}"'
            f' temperatureUnit="C"{unit_attr} areaUnit="SquareMeters" volumeUnit="CubicMeters" useSIUnitsForResults="true">'
            f'<Campus id="c1"><Location><Latitude>{lat}</Latitude><Longitude>{lon}</Longitude>{az}</Location>'
            f'<Building id="b1" buildingType="Office"><BuildingStorey id="st1"><Name>Ground floor</Name><Level>0</Level>'
            f"</BuildingStorey>{''.join(spaces)}</Building>{''.join(surfaces)}</Campus>"
            '<Zone id="z1"><Name>Flat 1</Name></Zone></gbXML>\n')


def box_room_gbxml(b: BoxRoom | None = None, facade_kind: str = "ExteriorWall", unit: str = "Meters", turn_deg: float = 0.0,
                   azimuth: float | None = None, space_name: str = "box room", space_type: str = "") -> str:
    """The box room as one gbXML Space (``space_name``, ``space_type`` its spaceType attribute): its six surfaces (the facade whole, the glazing an Opening 'glazing' of it),
    the street building as Shade surfaces and the ground as a Shade named 'ground'. ``facade_kind`` InteriorWall
    writes the facade as Revit sometimes does: an interior wall with the room on both of its sides."""
    b = b or BoxRoom()
    scale = {"Meters": 1.0, "Feet": FT}[unit]
    kw = {"scale": scale, "turn_deg": turn_deg}
    polys = box_room_polygons(b)
    hw, d, h = b.width / 2, b.depth, b.height
    (wx0, wx1), (wz0, wz1) = b.window_x, b.window_z
    facade = [(-hw, 0.0, 0.0), (hw, 0.0, 0.0), (hw, 0.0, h), (-hw, 0.0, h)]
    glazing = [(wx0, 0.0, wz0), (wx1, 0.0, wz0), (wx1, 0.0, wz1), (wx0, 0.0, wz1)]
    on_both = ("sp1", "sp1") if facade_kind == "InteriorWall" else ("sp1",)
    surfs = [surface("s-facade", facade_kind, facade, on_both, [("o-1", "FixedWindow", glazing, "glazing")], **kw),
             surface("s-floor", "SlabOnGrade", [(-hw, 0, 0), (-hw, d, 0), (hw, d, 0), (hw, 0, 0)], ("sp1",), **kw),
             surface("s-roof", "Roof", [(-hw, 0, h), (hw, 0, h), (hw, d, h), (-hw, d, h)], ("sp1",), **kw),
             surface("s-west", "ExteriorWall", [(-hw, 0, 0), (-hw, 0, h), (-hw, d, h), (-hw, d, 0)], ("sp1",), **kw),
             surface("s-east", "ExteriorWall", [(hw, 0, 0), (hw, d, 0), (hw, d, h), (hw, 0, h)], ("sp1",), **kw),
             surface("s-back", "ExteriorWall", [(hw, d, 0), (-hw, d, 0), (-hw, d, h), (hw, d, h)], ("sp1",), **kw)]
    surfs += [surface(f"sh-{k}", "Shade", ring, name=f"street building {k}", **kw) for k, ring in enumerate(polys.get("building", []))]
    surfs += [surface("sh-ground", "Shade", polys["ground"][0], name="ground", **kw)]
    return document([space("sp1", space_name, box_shell(-hw, hw, 0.0, d, 0.0, h), space_type=space_type, **kw)], surfs,
                    unit=unit, azimuth=azimuth)


def write(directory: Path, text: str, name: str = "model.xml") -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    p = directory / name
    p.write_text(text, encoding="utf-8")
    return p


# --- a house as Revit 2008-2010 exported it: feet, no version, no storeys, an AnalyticalShell ----------

def _rect(x0, y0, x1, y1, z) -> list:
    return [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]


def _wall_ring(a, b, z0, z1) -> list:
    """A vertical quad from plan point ``a`` to ``b`` between ``z0`` and ``z1``."""
    return [(a[0], a[1], z0), (b[0], b[1], z0), (b[0], b[1], z1), (a[0], a[1], z1)]


#: The house [ft]: two storeys 10 ft apart, rooms 9 ft high (interior), walls 0.5 ft thick drawn
#: on their centre lines by the surfaces and the AnalyticalShell. Room -> (storey, interior
#: x0, y0, x1, y1 [ft], its window on the south (y0) wall: x from, x to, sill, head [ft]).
HOUSE_FT = {"1 Living": (0, 0.25, 0.25, 19.75, 14.75, (4.0, 10.0, 3.0, 7.0)),
            "2 Kitchen": (0, 20.25, 0.25, 31.75, 14.75, (23.0, 27.0, 3.5, 7.0)),
            "3 Bedroom": (1, 0.25, 0.25, 15.75, 14.75, (5.0, 9.0, 3.0, 7.0)),
            "4 Bedroom": (1, 16.25, 0.25, 31.75, 14.75, (22.0, 26.0, 3.0, 7.0))}
HOUSE_LEVEL_FT, HOUSE_ROOM_FT, HOUSE_HALF_WALL_FT = 10.0, 9.0, 0.25


def old_revit_house() -> str:
    """The gbXML of a two-storey house as Revit 2009 wrote it (``HOUSE_FT``): no version attribute,
    lengthUnit Feet, no BuildingStorey; each Space's ShellGeometry (unit="Feet") holds its room's
    ClosedShell and an AnalyticalShell (the space's surfaces on the walls' centre lines, from its
    level to the next, each window a ShellOpening); the surfaces on the centre lines with their
    Openings. Each room's Area is its interior footprint [ft²]."""
    spaces, surfs = [], []
    for k, (name, (storey, x0, y0, x1, y1, (wa, wb, sill, head))) in enumerate(HOUSE_FT.items()):
        sid, z = f"sp-{k + 1}", storey * HOUSE_LEVEL_FT
        closed = "".join(poly_loop(r) for r in box_shell(x0, x1, y0, y1, z, z + HOUSE_ROOM_FT))
        e = HOUSE_HALF_WALL_FT
        ax0, ay0, ax1, ay1 = x0 - e, y0 - e, x1 + e, y1 + e
        corners = [(ax0, ay0), (ax1, ay0), (ax1, ay1), (ax0, ay1)]
        window = _wall_ring((wa, ay0), (wb, ay0), z + sill, z + head)
        shell_surfaces = [("Floor", _rect(ax0, ay0, ax1, ay1, z)[::-1], ""),
                          ("Ceiling", _rect(ax0, ay0, ax1, ay1, z + HOUSE_LEVEL_FT), "")]
        for i in range(4):
            op = (f'<ShellOpening openingType="OperableWindow">{poly_loop(window)}</ShellOpening>' if i == 0 else "")
            shell_surfaces.append(("Wall", _wall_ring(corners[i], corners[(i + 1) % 4], z, z + HOUSE_LEVEL_FT), op))
        analytical = "".join(f'<ShellSurface surfaceType="{t}">{poly_loop(r)}{op}</ShellSurface>' for t, r, op in shell_surfaces)
        area = (x1 - x0) * (y1 - y0)
        spaces.append(f'<Space id="{sid}" zoneIdRef="zone-Default"><Name>{name}</Name><Area>{area!r}</Area>'
                      f'<ShellGeometry id="sg-{sid}" unit="Feet"><ClosedShell>{closed}</ClosedShell>'
                      f"<AnalyticalShell>{analytical}</AnalyticalShell></ShellGeometry></Space>")
        surfs.append(surface(f"su-{sid}-s", "ExteriorWall", _wall_ring(corners[0], corners[1], z, z + HOUSE_LEVEL_FT), (sid,),
                             [(f"su-{sid}-s-op-1", "OperableWindow", window, f"window {name}")]))
        for i in (1, 2, 3):
            surfs.append(surface(f"su-{sid}-{i}", "ExteriorWall", _wall_ring(corners[i], corners[(i + 1) % 4], z,
                                                                              z + HOUSE_LEVEL_FT), (sid,)))
        surfs.append(surface(f"su-{sid}-f", "SlabOnGrade" if storey == 0 else "InteriorFloor", _rect(ax0, ay0, ax1, ay1, z),
                             (sid,)))
        if storey == 1:
            surfs.append(surface(f"su-{sid}-r", "Roof", _rect(ax0, ay0, ax1, ay1, z + HOUSE_LEVEL_FT), (sid,)))
    return ('<?xml version="1.0"?>\n<gbXML temperatureUnit="F" lengthUnit="Feet" areaUnit="SquareFeet" '
            'volumeUnit="CubicFeet" useSIUnitsForResults="false" xmlns="http://www.gbxml.org/schema">'
            '<Campus id="cmps-1"><Location><Name>Boston, MA</Name><Latitude>42.213</Latitude><Longitude>-71.033'
            f'</Longitude></Location><Building id="bldg-1" buildingType="SingleFamily">{"".join(spaces)}</Building>'
            f'{"".join(surfs)}</Campus><Zone id="zone-Default"><Name>Default</Name></Zone></gbXML>\n')


# --- a space whose ShellGeometry is not closed, as Revit 2025 writes some ---------------------------

#: The L-shaped living room [m]: its floor outline (interior, counterclockwise), 15.6 m², 2.45 m to 5.47 m;
#: the window in the south wall (y = -5.44, the wall's face 0.46 m south of the floor's outline).
L_FLOOR = [(0.35, -4.985), (5.476, -4.985), (5.476, -2.263), (2.16, -2.263), (2.16, -1.355), (0.35, -1.355)]
L_Z = (2.45, 5.47)
L_WINDOW = [(1.5, -5.442, 3.25), (4.5, -5.442, 3.25), (4.5, -5.442, 5.25), (1.5, -5.442, 5.25)]


def l_floor_area() -> float:
    import shapely

    return shapely.Polygon(L_FLOOR).area


def open_shell_room() -> str:
    """A gbXML (metres, version 7.03, Revit 2025) with one L-shaped Space whose ShellGeometry is not
    closed: its floor and its ceiling (the ceiling only over the floor's southern part, a roof slope
    being left out) and four pieces of its walls, drawn on the walls' faces and stopping short; its
    Area the floor's. The exterior walls around it as Surfaces, the window an Opening of the south wall."""
    z0, z1 = L_Z
    floor = [(x, y, z0) for x, y in L_FLOOR[::-1]]  # facing down
    ceiling = [(0.36, -4.93, z1), (5.52, -4.93, z1), (5.52, -2.8, z1), (0.36, -2.8, z1)]
    walls = [[(0.867, -5.442, z0), (5.987, -5.442, z0), (5.987, -5.442, z1), (0.867, -5.442, z1)],
             [(5.987, -5.442, z0), (5.987, -1.847, z0), (5.987, -1.847, z1), (5.987, -5.442, z1)],
             [(2.752, -1.847, z0), (2.752, -1.847, z1), (5.987, -1.847, z1), (5.987, -1.847, z0)],
             [(0.0, -0.737, z0), (1.642, -0.737, z0), (1.642, -0.737, z1), (0.0, -0.737, z1)]]
    loops = "".join(poly_loop(r) for r in [floor, ceiling, *walls])
    sp = (f'<Space id="aim1947" buildingStoreyIdRef="st1" zoneIdRef="z1"><Name>24 Soggiorno</Name>'
          f'<Area>{l_floor_area()!r}</Area><ShellGeometry id="sh"><ClosedShell>{loops}</ClosedShell></ShellGeometry></Space>')
    x0, y0, x1, y1 = 0.0, -5.442, 5.987, -0.9
    surfs = [surface("s-south", "ExteriorWall", [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)], ("aim1947",),
                     [("o-1", "OperableWindow", L_WINDOW, "S-24-E-W-53-W-1")]),
             surface("s-east", "ExteriorWall", [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)], ("aim1947",)),
             surface("s-north", "ExteriorWall", [(x1, y1, z0), (x0, y1, z0), (x0, y1, z1), (x1, y1, z1)], ("aim1947",)),
             surface("s-west", "ExteriorWall", [(x0, y1, z0), (x0, y0, z0), (x0, y0, z1), (x0, y1, z1)], ("aim1947",)),
             surface("s-floor", "InteriorFloor", [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)], ("aim1947",)),
             surface("s-roof", "Roof", [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)], ("aim1947",))]
    return document([sp], surfs, version="7.03", lat=41.9, lon=12.5)
