"""``en17037 validate --plan DIR``: the plan of each storey as the tool read it, one PNG per floor
level: the walls cut at eye height (the plan the rooms come from), each room's floor region
(filled, labelled with its name and area), its windows (thick, with an arrow out of the room),
the viewpoint grid of the first eye height and each window's point P. A wrong room is caught by
looking. Needs matplotlib (the ``plot`` extra)."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

#: Figure size [in] and resolution [dpi]: a storey fits an A4 page's width.
SIZE_IN, DPI = (8.0, 6.0), 120
#: Fill colours of rooms, in turn (light, distinct in grey).
ROOM_COLOURS = ("#cfe3f5", "#f5e0c3", "#d6efd0", "#eed3ea", "#f3f0c2", "#d9d9f3")


@dataclass
class RoomDrawing:
    """What is drawn of one room, in the model's coordinates [m]: floor outline(s), windows as
    (start, end, outward) in plan, viewpoints (n, 2) and points P (k, 2)."""

    name: str
    floor_z: float
    floor: object  # shapely Polygon, model frame
    windows: list = field(default_factory=list)
    viewpoints: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    points_p: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))


def window_trace(window, origin) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(start, end, outward) of a window in plan [m, model frame]: its glazing's extent along the wall."""
    from en17037cli.geometry import window_axes

    n = np.asarray(window.normal, float)
    pts = window.triangles.reshape(-1, 3)
    if abs(n[2]) >= 0.5:  # roof light: its plan box's diagonal
        lo, hi = pts[:, :2].min(axis=0), pts[:, :2].max(axis=0)
        return lo + origin[:2], hi + origin[:2], np.zeros(2)
    a, _ = window_axes(n)
    s = pts @ a
    c = window.centroid
    ends = [c + (s.min() - c @ a) * a, c + (s.max() - c @ a) * a]
    h = n[:2] / max(np.linalg.norm(n[:2]), 1e-12)
    return ends[0][:2] + origin[:2], ends[1][:2] + origin[:2], h


def draw_storeys(walls_by_level: dict, rooms: list[RoomDrawing], out_dir: Path, title: str) -> list[Path]:
    """One PNG per floor level into ``out_dir`` (``plan-z<level>.png``); returns their paths.

    walls_by_level : floor level [m, model frame] -> shapely geometry of the walls cut at eye height
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import shapely

    out_dir.mkdir(parents=True, exist_ok=True)
    with matplotlib.rc_context({"text.parse_math": False}):  # room names are data, never TeX (issue 43)
        return _draw_storeys(plt, shapely, walls_by_level, rooms, out_dir, title)


def _draw_storeys(plt, shapely, walls_by_level: dict, rooms: list[RoomDrawing], out_dir: Path, title: str) -> list[Path]:
    written = []
    for level in sorted(walls_by_level):
        here = [r for r in rooms if abs(r.floor_z - level) < 1e-6]
        fig, ax = plt.subplots(figsize=SIZE_IN, dpi=DPI)
        for line in shapely.get_parts(walls_by_level[level]):
            xy = np.asarray(line.coords)
            ax.plot(xy[:, 0], xy[:, 1], color="#333333", lw=1.0, solid_capstyle="butt")
        for k, r in enumerate(here):
            for poly in shapely.get_parts(r.floor):
                x, y = poly.exterior.xy
                ax.fill(x, y, color=ROOM_COLOURS[k % len(ROOM_COLOURS)], alpha=0.9, lw=0)
                for hole in poly.interiors:
                    hx, hy = hole.xy
                    ax.fill(hx, hy, color="white", lw=0)
            if len(r.viewpoints):
                ax.plot(r.viewpoints[:, 0], r.viewpoints[:, 1], ".", color="#555555", ms=2.0)
            for a, b, n in r.windows:
                ax.plot([a[0], b[0]], [a[1], b[1]], color="#1f6fb2", lw=3.5, solid_capstyle="butt")
                if np.any(n):
                    m = 0.5 * (a + b)
                    ax.annotate("", xy=m + 0.6 * n, xytext=m, annotation_clip=False, zorder=5,
                                arrowprops={"arrowstyle": "-|>", "color": "#1f6fb2", "lw": 1.2})
            if len(r.points_p):
                ax.plot(r.points_p[:, 0], r.points_p[:, 1], "x", color="#b42318", ms=7, mew=2)
            c = r.floor.representative_point()
            ax.text(c.x, c.y, f"{r.name}\n{r.floor.area:.1f} m²", ha="center", va="center", fontsize=9,
                    bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.8})
        ax.set_aspect("equal")
        ax.set_title(f"{title}: floor z {level:.2f} m, walls cut at eye height", fontsize=10)
        ax.set_xlabel("x [m]", fontsize=9)
        ax.set_ylabel("y [m]", fontsize=9)
        ax.tick_params(labelsize=8)
        handles = [plt.Line2D([], [], color="#333333", lw=1, label="walls at 1.2 m"),
                   plt.Line2D([], [], color="#1f6fb2", lw=3.5, label="window (arrow: out)"),
                   plt.Line2D([], [], ls="", marker=".", color="#555555", label="viewpoints (first eye height)"),
                   plt.Line2D([], [], ls="", marker="x", color="#b42318", mew=2, label="point P")]
        ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
        fig.tight_layout()
        path = out_dir / f"plan-z{level:.2f}.png"
        fig.savefig(path, dpi=DPI, metadata={"Software": None})
        plt.close(fig)
        written.append(path)
    return written
