"""Write a synthetic CityGML 2.0 tile of N buildings for benchmarking the CityGML reader.

Laid out like a German state's LoD2 tile: each ``bldg:Building`` has a ``gml:id``, a few
attributes (``bldg:function``, ``bldg:roofType``, ``bldg:measuredHeight``, a
``gen:stringAttribute``), a LoD 1 block (``lod1Solid``, polygons written out) and LoD 2 thematic
surfaces (GroundSurface, four WallSurfaces of which two are pentagonal gables, two RoofSurfaces,
each a ``lod2MultiSurface`` with ``srsName="EPSG:25833"``). Buildings stand on a jittered 25 m grid
around (389500, 5819500) (Berlin, ETRS89 / UTM 33N), turned at random, 8 to 14 m by 10 to 18 m,
6 to 24 m to the eaves. Coordinates have 3 decimals (mm). The same seed gives the same file byte
for byte; the file is written as it is made (memory stays small).

Usage::

    python scripts/make_citygml_tile.py -n 12000 -o out/citygml-tile.gml   # about 60 MB
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

ORIGIN = (389500.0, 5819500.0)
SRS = "EPSG:25833"
HEAD = ('<?xml version="1.0" encoding="UTF-8"?>\n<CityModel xmlns="http://www.opengis.net/citygml/2.0" '
        'xmlns:bldg="http://www.opengis.net/citygml/building/2.0" xmlns:gml="http://www.opengis.net/gml" '
        'xmlns:gen="http://www.opengis.net/citygml/generics/2.0" xmlns:xlink="http://www.w3.org/1999/xlink">\n')


def _pos(ring) -> str:
    return " ".join(f"{x:.3f} {y:.3f} {z:.3f}" for x, y, z in list(ring) + [ring[0]])


def _poly(ring, gid: str) -> str:
    return (f'<gml:surfaceMember><gml:Polygon gml:id="{gid}"><gml:exterior><gml:LinearRing><gml:posList srsDimension="3">'
            f"{_pos(ring)}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></gml:surfaceMember>")


def building(k: int, rng: np.random.Generator, side: int) -> str:
    """One gabled building as a ``cityObjectMember``."""
    gx, gy = k % side, k // side
    cx = ORIGIN[0] + (gx - side / 2) * 25.0 + rng.uniform(-3, 3)
    cy = ORIGIN[1] + (gy - side / 2) * 25.0 + rng.uniform(-3, 3)
    w, d = rng.uniform(8, 14), rng.uniform(10, 18)
    h, ridge, z0 = rng.uniform(6, 24), rng.uniform(2, 6), 34.0 + rng.uniform(-1, 1)
    a = rng.uniform(0, math.pi)
    ca, sa = math.cos(a), math.sin(a)
    place = lambda x, y, z: (cx + ca * x - sa * y, cy + sa * x + ca * y, z)  # noqa: E731
    c = [(-w / 2, -d / 2), (w / 2, -d / 2), (w / 2, d / 2), (-w / 2, d / 2)]
    g = [place(x, y, z0) for x, y in c]
    e = [place(x, y, z0 + h) for x, y in c]
    r0, r1 = place(0, -d / 2, z0 + h + ridge), place(0, d / 2, z0 + h + ridge)
    bid = f"DEBE_{k:08d}"
    ground = [g[3], g[2], g[1], g[0]]
    walls = [[g[0], g[1], e[1], r0, e[0]], [g[1], g[2], e[2], e[1]], [g[2], g[3], e[3], r1, e[2]], [g[3], g[0], e[0], e[3]]]
    roofs = [[e[1], e[2], r1, r0], [e[3], e[0], r0, r1]]
    flat = [(x, y, z0 + h) for x, y, _ in g]
    lod1 = [ground, flat] + [[g[i], g[(i + 1) % 4], flat[(i + 1) % 4], flat[i]] for i in range(4)]
    out = [f'<cityObjectMember><bldg:Building gml:id="{bid}"><gml:name>{bid}</gml:name>',
           '<gen:stringAttribute name="Gemeindeschluessel"><gen:value>11000000</gen:value></gen:stringAttribute>',
           "<bldg:function>31001_1000</bldg:function><bldg:roofType>3100</bldg:roofType>",
           f'<bldg:measuredHeight uom="urn:adv:uom:m">{h + ridge:.3f}</bldg:measuredHeight>',
           f'<bldg:lod1Solid><gml:Solid srsName="{SRS}" srsDimension="3"><gml:exterior><gml:CompositeSurface>',
           *(_poly(r, f"{bid}_l1_{i}") for i, r in enumerate(lod1)),
           "</gml:CompositeSurface></gml:exterior></gml:Solid></bldg:lod1Solid>"]
    n = 0
    for kind, polys in (("GroundSurface", [ground]), ("WallSurface", walls), ("RoofSurface", roofs)):
        for p in polys:
            out.append(f'<bldg:boundedBy><bldg:{kind} gml:id="{bid}_{kind}_{n}"><bldg:lod2MultiSurface>'
                       f'<gml:MultiSurface srsName="{SRS}" srsDimension="3">{_poly(p, f"{bid}_p{n}")}</gml:MultiSurface>'
                       f"</bldg:lod2MultiSurface></bldg:{kind}></bldg:boundedBy>")
            n += 1
    out.append("</bldg:Building></cityObjectMember>\n")
    return "".join(out)


def write_tile(path: Path, n: int, seed: int = 17037) -> int:
    """Write ``n`` buildings to ``path``; its size [bytes]."""
    rng = np.random.default_rng(seed)
    side = math.ceil(math.sqrt(n))
    half = side * 12.5 + 20
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", encoding="utf-8") as fh:
        fh.write(HEAD)
        fh.write(f'<gml:boundedBy><gml:Envelope srsName="{SRS}" srsDimension="3"><gml:lowerCorner>{ORIGIN[0] - half:.3f} '
                 f"{ORIGIN[1] - half:.3f} 30</gml:lowerCorner><gml:upperCorner>{ORIGIN[0] + half:.3f} {ORIGIN[1] + half:.3f} 70"
                 "</gml:upperCorner></gml:Envelope></gml:boundedBy>\n")
        for k in range(n):
            fh.write(building(k, rng, side))
        fh.write("</CityModel>\n")
    return path.stat().st_size


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=12000, help="buildings (default 12000: about 60 MB)")
    ap.add_argument("-o", "--out", default="out/citygml-tile.gml")
    args = ap.parse_args(argv)
    size = write_tile(Path(args.out), args.n)
    print(f"wrote {args.out}: {args.n} buildings, {size / 1e6:.1f} MB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
