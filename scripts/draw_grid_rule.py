"""Draw docs/images/grid-rule.png: the viewpoint grid rule (en17037cli.criteria.view.viewpoints) on a
4 x 6 m room drawn on round coordinates, given as a rectangle and derived a micron smaller, and an
L-shaped room. Run: python scripts/draw_grid_rule.py [OUT.png]."""
from __future__ import annotations

import sys
from pathlib import Path

import shapely

from en17037cli.criteria.view.viewpoints import grid_points


def main(out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rooms = [("4 x 6 m room, given", shapely.box(0, 0, 4, 6)),
             ("the same, derived 1 µm smaller", shapely.box(1e-6, 1e-6, 4 - 1e-6, 6 - 1e-6)),
             ("L-shaped room", shapely.Polygon([(0, 0), (6, 0), (6, 3), (3, 3), (3, 6), (0, 6)]))]
    fig, axes = plt.subplots(1, 3, figsize=(9.0, 4.2), dpi=150)
    for ax, (title, floor) in zip(axes, rooms):
        utilised = floor.buffer(-0.5, join_style="mitre")
        pts = grid_points(utilised, 0.5)
        ax.plot(*floor.exterior.xy, color="0.2", lw=1.6, label="floor outline")
        ax.plot(*utilised.exterior.xy, color="0.45", lw=1.0, ls="--", label="utilised area (0.5 m in)")
        ax.scatter(pts[:, 0], pts[:, 1], s=9, color="#2a6f97", zorder=3, label="viewpoints")
        ax.set_title(f"{title}\n{len(pts)} viewpoints", fontsize=9)
        ax.set_aspect("equal")
        ax.set_xticks(range(0, 7))
        ax.set_yticks(range(0, 7))
        ax.tick_params(labelsize=7)
        ax.grid(color="0.9", lw=0.5)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 0.07), ncol=3, fontsize=8, frameon=False)
    fig.text(0.5, 0.015, "0.5 m grid: a side of the utilised area within 1e-4 of its size of a multiple of the spacing gets one\n"
             "line less than that multiple, centred: the outermost lines lie 0.25 m inside it, never on it", ha="center",
             fontsize=8)
    fig.subplots_adjust(left=0.04, right=0.99, top=0.9, bottom=0.2, wspace=0.25)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, metadata={"Software": None})
    plt.close(fig)
    print(out)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / "docs/images/grid-rule.png")
