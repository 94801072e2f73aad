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


def space(sid: str, name: str, shell, storey: str = "st1", **kw) -> str:
    loops = "".join(poly_loop(r, **kw) for r in shell)
    return (f'<Space id="{sid}" buildingStoreyIdRef="{storey}" zoneIdRef="z1"><Area>1</Area>'
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
                   azimuth: float | None = None) -> str:
    """The box room as one gbXML Space: its six surfaces (the facade whole, the glazing an Opening 'glazing' of it),
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
    return document([space("sp1", "box room", box_shell(-hw, hw, 0.0, d, 0.0, h), **kw)], surfs, unit=unit, azimuth=azimuth)


def write(directory: Path, text: str, name: str = "model.xml") -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    p = directory / name
    p.write_text(text, encoding="utf-8")
    return p
