"""CityGML documents written by the tests: from CityJSON objects, and small hand-made ones."""
from __future__ import annotations

from pathlib import Path

import numpy as np

NS2 = {
    "": "http://www.opengis.net/citygml/2.0", "bldg": "http://www.opengis.net/citygml/building/2.0",
    "gml": "http://www.opengis.net/gml", "xlink": "http://www.w3.org/1999/xlink",
    "gen": "http://www.opengis.net/citygml/generics/2.0", "veg": "http://www.opengis.net/citygml/vegetation/2.0",
    "dem": "http://www.opengis.net/citygml/relief/2.0", "app": "http://www.opengis.net/citygml/appearance/2.0",
}
NS3 = {
    "": "http://www.opengis.net/citygml/3.0", "core": "http://www.opengis.net/citygml/3.0",
    "bldg": "http://www.opengis.net/citygml/building/3.0", "con": "http://www.opengis.net/citygml/construction/3.0",
    "gml": "http://www.opengis.net/gml/3.2", "xlink": "http://www.w3.org/1999/xlink",
}


def city_model(members: list[str], ns: dict = NS2, srs: str | None = None, envelope: tuple | None = None) -> str:
    decl = " ".join(f'xmlns{":" + k if k else ""}="{v}"' for k, v in ns.items())
    env = ""
    if envelope is not None:
        lo, hi = envelope
        env = (f'<gml:boundedBy><gml:Envelope srsName="{srs}" srsDimension="3"><gml:lowerCorner>{lo}</gml:lowerCorner>'
               f'<gml:upperCorner>{hi}</gml:upperCorner></gml:Envelope></gml:boundedBy>')
    body = "".join(f"<cityObjectMember>{m}</cityObjectMember>" for m in members)
    return f'<?xml version="1.0" encoding="UTF-8"?>\n<CityModel {decl}>{env}{body}</CityModel>\n'


def pos_list(ring, close: bool = True) -> str:
    pts = list(ring) + ([ring[0]] if close else [])
    return " ".join(f"{float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in pts)


def polygon(rings, gid: str | None = None, close: bool = True) -> str:
    """A gml:Polygon: the first ring its exterior, the others holes."""
    ident = f' gml:id="{gid}"' if gid else ""
    out = f"<gml:Polygon{ident}><gml:exterior><gml:LinearRing><gml:posList>{pos_list(rings[0], close)}</gml:posList>" \
          "</gml:LinearRing></gml:exterior>"
    for hole in rings[1:]:
        out += f"<gml:interior><gml:LinearRing><gml:posList>{pos_list(hole, close)}</gml:posList></gml:LinearRing></gml:interior>"
    return out + "</gml:Polygon>"


def multi_surface(polys, srs: str | None = None, ids=None) -> str:
    s = f' srsName="{srs}"' if srs else ""
    members = "".join(f"<gml:surfaceMember>{polygon(p, None if ids is None else ids[k])}</gml:surfaceMember>"
                      for k, p in enumerate(polys))
    return f"<gml:MultiSurface{s}>{members}</gml:MultiSurface>"


def building(gid: str, surfaces: dict, lod: int = 2, srs: str | None = None, extra: str = "", cls: str = "bldg:Building") -> str:
    """A building with thematic surfaces {surface type: [polygon rings...]} at ``lod``; polygons with no type (key
    None) go into a lod<N>MultiSurface of the building itself."""
    out = f'<{cls} gml:id="{gid}">{extra}'
    for stype, polys in surfaces.items():
        if stype is None:
            out += f"<bldg:lod{lod}MultiSurface>{multi_surface(polys, srs)}</bldg:lod{lod}MultiSurface>"
        else:
            out += (f"<bldg:boundedBy><bldg:{stype}><bldg:lod{lod}MultiSurface>{multi_surface(polys, srs)}"
                    f"</bldg:lod{lod}MultiSurface></bldg:{stype}></bldg:boundedBy>")
    return out + f"</{cls}>"


def box_polys(x0, x1, y0, y1, z0, h) -> dict:
    """Outward-facing faces of an axis-aligned box [m]: GroundSurface, RoofSurface, WallSurface."""
    c = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)]
    t = [(x, y, z0 + h) for x, y, _ in c]
    walls = [[c[i], c[(i + 1) % 4], t[(i + 1) % 4], t[i]] for i in range(4)]
    return {"GroundSurface": [[c[::-1]]], "RoofSurface": [[t]], "WallSurface": [[w] for w in walls]}


def from_cityjson(doc: dict, srs: str) -> str:
    """CityGML 2.0 with the same polygons as a CityJSON document of MultiSurface / Solid buildings, each semantic
    surface as a thematic surface of the building (faces without one in a lod<N>MultiSurface), in file order."""
    tr = doc.get("transform")
    v = np.array(doc["vertices"], dtype=np.float64)
    if tr:
        v = v * np.array(tr["scale"]) + np.array(tr["translate"])
    members = []
    for oid, o in doc["CityObjects"].items():
        out = f'<bldg:Building gml:id="{oid}">'
        for g in o["geometry"]:
            lod = int(float(g["lod"]))
            surfaces = g["boundaries"] if g["type"] in ("MultiSurface", "CompositeSurface") else [s for sh in g["boundaries"] for s in sh]
            sem = g.get("semantics")
            values = sem["values"] if sem else [None] * len(surfaces)
            if sem and g["type"] not in ("MultiSurface", "CompositeSurface"):
                values = [x for sh in values for x in sh]
            for surf, val in zip(surfaces, values):
                rings = [[tuple(v[i]) for i in ring] for ring in surf]
                stype = None if val is None else sem["surfaces"][val]["type"]
                ms = multi_surface([rings], srs)
                if stype is None:
                    out += f"<bldg:lod{lod}MultiSurface>{ms}</bldg:lod{lod}MultiSurface>"
                else:
                    out += f"<bldg:boundedBy><bldg:{stype}><bldg:lod{lod}MultiSurface>{ms}</bldg:lod{lod}MultiSurface></bldg:{stype}></bldg:boundedBy>"
        members.append(out + "</bldg:Building>")
    return city_model(members)


def write(tmp_path: Path, text: str, name: str = "city.gml") -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p
