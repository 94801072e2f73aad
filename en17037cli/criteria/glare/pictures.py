"""Which pictures of clause 5.4 a room gets (drawn by :mod:`en17037cli.report.pictures.glare`): the
map of its critical positions, the DGP of every usage hour at its worst view, and the fisheye of
each point-in-time check."""
from __future__ import annotations

import numpy as np


def glare_jobs(result, i: int, slug: str, figures_dir: str) -> list[tuple]:
    """The glare pictures of room ``i`` as :class:`~en17037cli.report.figures.Job` fields."""
    r = result.rooms[i]
    res, plan = r.assessed("glare"), r.illustrations.get("glare")
    if res is None:
        return []
    s = result.project.glare
    name = r.room.name
    out = []
    views = [v.view for v in res.views] or _moment_views(res)
    if plan is not None and views:
        levels = [v.level for v in res.views] if res.views else [0] * len(views)
        eyes = result.scene.to_world(np.array([v.eye for v in views]))[:, :2]
        dirs = np.array([v.direction[:2] for v in views])
        labels = [str(k + 1) for k in range(len(views))]
        title = f"{name}: critical positions for glare, each view coloured by its level"
        out.append((f"{figures_dir}/{slug}-glare-positions.png", name, "glare", title, "positions_map",
                    (plan.floor, plan.windows, eyes, dirs, levels, labels), {"true_north_deg": plan.true_north_deg, "title": title},
                    True))
    if res.views and res.worst is not None:
        w = res.views[res.worst]
        title = (f"{name}: DGP of every usage hour at view {res.worst + 1} ({w.view.label}), "
                 f"{'with the shading where deployed' if s.shading else 'no shading'}")
        out.append((f"{figures_dir}/{slug}-glare-hours.png", name, "glare", title, "dgp_carpet", (res.usage_local, w.dgp),
                    {"limits": s.limits(), "title": title}, True))
    for k, m in enumerate(res.moments):
        if m.picture is None:
            continue
        idx = next((j for j, v in enumerate(views) if v is m.view), 0)
        title = f"{name}: {m.time}, view {idx + 1} ({m.view.label}): DGP {m.dgp:.2f}, E_v {m.ev_lx:.0f} lx"
        out.append((f"{figures_dir}/{slug}-glare-moment-{k + 1}.png", name, "glare", title, "luminance_fisheye", (m.picture,),
                    {"title": title}, False))
    return out


def _moment_views(res) -> list:
    """The views of the point-in-time checks, once each, in order (a room without the annual method)."""
    seen: list = []
    for m in res.moments:
        if not any(v is m.view for v in seen):
            seen.append(m.view)
    return seen
