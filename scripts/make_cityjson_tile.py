"""Write a synthetic CityJSON 2.0 tile of N LoD2 buildings for benchmarking the CityJSON reader.

The tile is laid out like a 3D BAG tile (https://3dbag.nl): each ``Building`` carries the
attributes and a LoD 0 footprint (MultiSurface); its one ``BuildingPart`` child carries a LoD
1.2 block (Solid) and a LoD 2.2 model (Solid) with semantic surfaces (GroundSurface,
WallSurface, RoofSurface). Buildings stand on a jittered 25 m grid around (85000, 446000) in
EPSG:7415 (Delft, Dutch national grid + NAP heights), turned at random: 55 % gabled boxes (two
pentagonal gable walls), 40 % flat-roofed L shapes (concave hexagons) and 5 % flat-roofed
courtyard blocks (ground and roof with a hole). Vertices are integers with scale 0.001 (mm).
The same seed gives the same file byte for byte.

Usage::

    python scripts/make_cityjson_tile.py                      # out/cityjson-tile-10000.city.json
    python scripts/make_cityjson_tile.py -n 2000 -o tile.city.json --measure

``--measure`` then reads the tile with :func:`en17037cli.io.cityjson.read_cityjson` and prints
the load time (best of ``--repeat`` runs), the process's peak resident memory over those reads
and the peak of the Python heap during one more read (tracemalloc, numpy arrays included). Generated tiles
are not committed (``out/`` is ignored by git).
"""
from __future__ import annotations

import argparse
import json
import math
import resource
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

ORIGIN = (85000.0, 446000.0)
SCALE = 0.001
SEMANTICS = [{"type": "GroundSurface"}, {"type": "WallSurface"}, {"type": "RoofSurface"}]
G, W, R = 0, 1, 2


def gabled(w: float, d: float, h: float, ridge: float):
    """Box w x d [m], eaves at h, ridge along x at height ridge; local vertices (10, 3) and surfaces."""
    v = [(0, 0, 0), (w, 0, 0), (w, d, 0), (0, d, 0), (0, 0, h), (w, 0, h), (w, d, h), (0, d, h),
         (0, d / 2, ridge), (w, d / 2, ridge)]
    surfaces = [([[0, 3, 2, 1]], G), ([[0, 1, 5, 4]], W), ([[1, 2, 6, 9, 5]], W), ([[2, 3, 7, 6]], W), ([[3, 0, 4, 8, 7]], W),
                ([[4, 5, 9, 8]], R), ([[6, 7, 8, 9]], R)]
    return np.array(v, dtype=float), surfaces, [[0, 1, 2, 3]]


def l_shape(w: float, d: float, w1: float, d1: float, h: float):
    """Flat-roofed L: footprint (0,0) (w,0) (w,d1) (w1,d1) (w1,d) (0,d), height h."""
    ring = [(0, 0), (w, 0), (w, d1), (w1, d1), (w1, d), (0, d)]
    v = [(x, y, 0) for x, y in ring] + [(x, y, h) for x, y in ring]
    walls = [([[i, (i + 1) % 6, 6 + (i + 1) % 6, 6 + i]], W) for i in range(6)]
    surfaces = [([[5, 4, 3, 2, 1, 0]], G), *walls, ([[6, 7, 8, 9, 10, 11]], R)]
    return np.array(v, dtype=float), surfaces, [[0, 1, 2, 3, 4, 5]]


def courtyard(w: float, d: float, t: float, h: float):
    """Flat-roofed block w x d around a courtyard (wings t deep): ground and roof have a hole."""
    outer = [(0, 0), (w, 0), (w, d), (0, d)]
    inner = [(t, t), (w - t, t), (w - t, d - t), (t, d - t)]
    v = [(x, y, 0) for x, y in outer + inner] + [(x, y, h) for x, y in outer + inner]
    walls = [([[i, (i + 1) % 4, 8 + (i + 1) % 4, 8 + i]], W) for i in range(4)]
    walls += [([[4 + (i + 1) % 4, 4 + i, 12 + i, 12 + (i + 1) % 4]], W) for i in range(4)]
    surfaces = [([[3, 2, 1, 0], [4, 5, 6, 7]], G), *walls, ([[8, 9, 10, 11], [15, 14, 13, 12]], R)]
    return np.array(v, dtype=float), surfaces, [[0, 1, 2, 3], [7, 6, 5, 4]]


def block(footprint: np.ndarray, z0: float, h: float):
    """LoD 1.2 Solid of a footprint prism: vertices (2k, 3) local and its surfaces."""
    k = len(footprint)
    v = np.concatenate([np.c_[footprint, np.full(k, z0)], np.c_[footprint, np.full(k, z0 + h)]])
    surfaces = [([list(range(k))[::-1]], G), ([list(range(k, 2 * k))], R)]
    surfaces += [([[i, (i + 1) % k, k + (i + 1) % k, k + i]], W) for i in range(k)]
    return v, surfaces


def make_tile(n: int, seed: int) -> dict:
    """The CityJSON 2.0 tile of ``n`` buildings (a dict ready for json.dump)."""
    rng = np.random.default_rng(seed)
    cols = math.ceil(math.sqrt(n))
    spacing = 25.0
    translate = np.array([ORIGIN[0] - cols * spacing / 2, ORIGIN[1] - cols * spacing / 2, -5.0])
    vertices: list = []
    objects: dict = {}
    for i in range(n):
        row, col = divmod(i, cols)
        centre = translate[:2] + (np.array([col, row]) + 0.5) * spacing + rng.uniform(-2.0, 2.0, 2)
        z0 = float(rng.uniform(-1.0, 2.0))
        kind = rng.random()
        w, d = rng.uniform(8.0, 16.0), rng.uniform(7.0, 12.0)
        if kind < 0.55:
            h = rng.uniform(4.0, 9.0)
            local, surfaces, foot = gabled(w, d, h, h + rng.uniform(2.0, 5.0))
            lod1_h, roof = h + 1.5, "slanted"
        elif kind < 0.95:
            h = rng.uniform(6.0, 18.0)
            local, surfaces, foot = l_shape(w, d, w * rng.uniform(0.35, 0.65), d * rng.uniform(0.35, 0.65), h)
            lod1_h, roof = h, "horizontal"
        else:
            w, d, h = w + 6.0, d + 8.0, rng.uniform(9.0, 20.0)
            local, surfaces, foot = courtyard(w, d, rng.uniform(3.0, 4.5), h)
            lod1_h, roof = h, "horizontal"
        theta = rng.uniform(0.0, math.pi)
        rot = np.array([[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]])
        xy = (local[:, :2] - [w / 2, d / 2]) @ rot.T + centre
        world = np.c_[xy, local[:, 2] + z0]
        base = len(vertices)
        ids = [int(x) for x in foot[0]]
        lod1_v, lod1_s = block(world[ids, :2], z0, lod1_h)
        ints = np.rint((np.concatenate([world, lod1_v]) - translate) / SCALE).astype(np.int64)
        vertices.extend(ints.tolist())
        b1 = base + len(world)
        lod0 = [[[base + j for j in ring] for ring in foot]]
        lod1 = [[[[b1 + j for j in ring] for ring in s] for s, _ in lod1_s]]
        lod2 = [[[[base + j for j in ring] for ring in s] for s, _ in surfaces]]
        bid = f"NL.IMBAG.Pand.0503100000{i:06d}"
        objects[bid] = {
            "type": "Building",
            "attributes": {"identificatie": bid, "status": "Pand in gebruik",
                           "oorspronkelijkbouwjaar": int(rng.integers(1700, 2024)), "b3_dak_type": roof,
                           "b3_h_maaiveld": round(z0, 2), "b3_h_dak_max": round(float(world[:, 2].max()), 2),
                           "b3_val3dity_lod22": []},
            "geometry": [{"type": "MultiSurface", "lod": "0", "boundaries": lod0}],
            "children": [f"{bid}-0"],
        }
        objects[f"{bid}-0"] = {
            "type": "BuildingPart",
            "parents": [bid],
            "geometry": [
                {"type": "Solid", "lod": "1.2", "boundaries": lod1,
                 "semantics": {"surfaces": SEMANTICS, "values": [[sem for _, sem in lod1_s]]}},
                {"type": "Solid", "lod": "2.2", "boundaries": lod2,
                 "semantics": {"surfaces": SEMANTICS, "values": [[sem for _, sem in surfaces]]}},
            ],
        }
    return {
        "type": "CityJSON",
        "version": "2.0",
        "transform": {"scale": [SCALE, SCALE, SCALE], "translate": [round(float(t), 3) for t in translate]},
        "metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/7415",
                     "title": f"synthetic tile, {n} buildings, seed {seed}"},
        "CityObjects": objects,
        "vertices": vertices,
    }


def measure(path: Path, repeat: int) -> None:
    """Print load time (best of ``repeat``), peak RSS and tracemalloc peak of read_cityjson on ``path``."""
    from en17037cli.io.cityjson import read_cityjson

    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # KiB on Linux
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        mesh = read_cityjson(path)
        times.append(time.perf_counter() - t0)
        del mesh
    rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    tracemalloc.start()
    mesh = read_cityjson(path)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    print(f"read_cityjson: {len(mesh.parts)} parts, {len(mesh.triangles)} triangles, {len(mesh.vertices)} vertices")
    print(f"load time: best {min(times):.2f} s of {repeat} (all: {', '.join(f'{t:.2f}' for t in times)})")
    print(f"peak memory: process RSS {rss1:.0f} MiB ({rss0:.0f} MiB before reading); "
          f"Python heap peak during one read {peak / 2**20:.0f} MiB (tracemalloc, numpy included)")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-n", "--buildings", type=int, default=10_000, help="number of buildings (default 10000)")
    ap.add_argument("-o", "--out", type=Path, help="output file (default out/cityjson-tile-N.city.json)")
    ap.add_argument("--seed", type=int, default=17037)
    ap.add_argument("--measure", action="store_true", help="read the tile back and print load time and peak memory")
    ap.add_argument("--repeat", type=int, default=3, help="timed reads with --measure (default 3)")
    args = ap.parse_args(argv)
    out = args.out or Path("out") / f"cityjson-tile-{args.buildings}.city.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    tile = make_tile(args.buildings, args.seed)
    with out.open("w", encoding="utf-8") as fh:
        json.dump(tile, fh, separators=(",", ":"))
    print(f"{out}: {args.buildings} buildings, {len(tile['vertices'])} vertices, {out.stat().st_size / 2**20:.1f} MiB")
    del tile
    if args.measure:
        measure(out, args.repeat)
    return 0


if __name__ == "__main__":
    sys.exit(main())
