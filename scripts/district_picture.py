"""A picture of a screened tile for docs/district.md: the walls in plan and every probe of
``en17037 screen``'s probes.csv, coloured by its sunlight level (left) and its vertical sky
component (right), as PNG.

Run: python scripts/district_picture.py CITY_MODEL SCREEN_FOLDER OUT.png [--box x0 y0 x1 y1]
(the screen's city model, the folder it wrote, the picture; ``--box`` crops to part of the tile).
"""
from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np


def main(argv=None) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    from matplotlib.colors import BoundaryNorm, ListedColormap

    from en17037cli.district.city import read_buildings
    from en17037cli.district.html import VSC_BINS, VSC_COLOURS
    from en17037cli.report.pictures.colours import LEVEL_COLOURS
    from en17037cli.standard import LEVELS

    ap = argparse.ArgumentParser()
    ap.add_argument("city")
    ap.add_argument("folder")
    ap.add_argument("out")
    ap.add_argument("--box", nargs=4, type=float, default=None)
    a = ap.parse_args(argv)
    rows = sorted(csv.DictReader((Path(a.folder) / "probes.csv").open()), key=lambda r: -int(r["storey"]))  # lowest on top
    xy = np.array([[float(r["x"]), float(r["y"])] for r in rows])
    sun = np.array([LEVELS.index(r["sunlight_level"]) for r in rows])
    vsc = np.array([float(r["sky_component_pct"]) for r in rows])
    segs = []
    for b in read_buildings(Path(a.city))[0]:
        for w in b.walls:
            for poly in w.polygons:
                r = np.asarray(poly[0])[:, :2]
                d = r - r.mean(axis=0)
                s = d @ np.linalg.svd(d, full_matrices=False)[2][0]
                segs.append([r[np.argmin(s)], r[np.argmax(s)]])
    box = a.box or (*xy.min(axis=0) - 5, *xy.max(axis=0) + 5)
    fig, axes = plt.subplots(1, 2, figsize=(12, 6.2), dpi=110, constrained_layout=True)
    for ax, values, cmap, norm, title, ticks, labels in (
            (axes[0], sun, ListedColormap(LEVEL_COLOURS), BoundaryNorm(np.arange(5) - 0.5, 4), "sunlight (5.3), 21 March",
             range(4), LEVELS),
            (axes[1], vsc, ListedColormap(VSC_COLOURS), BoundaryNorm([0, *VSC_BINS, 40], len(VSC_COLOURS)),
             "vertical sky component [%]", None, None)):
        ax.add_collection(LineCollection(segs, colors="0.55", linewidths=0.5))
        sc = ax.scatter(xy[:, 0], xy[:, 1], c=values, cmap=cmap, norm=norm, s=3 if a.box is None else 9, linewidths=0)
        ax.set_xlim(box[0], box[2])
        ax.set_ylim(box[1], box[3])
        ax.set_aspect("equal")
        ax.set_title(title)
        ax.tick_params(labelsize=7)
        cb = fig.colorbar(sc, ax=ax, shrink=0.7, ticks=ticks)
        if labels is not None:
            cb.ax.set_yticklabels(labels)
    fig.savefig(a.out, metadata={"Software": None})
    print(a.out)


if __name__ == "__main__":
    main()
