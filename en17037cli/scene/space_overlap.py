"""Spaces drawn over one another: why a space the windows did not go to has none.

Exports hold spaces that overlap: Revit writes the same room two or three times (a room and its
area, an old copy left on the level), each an IfcSpace of the same name with nearly the same
footprint. A window opens into the first of them its rays enter (:mod:`en17037cli.scene.spaces`);
the others are left without a window, and "no window opens into it" is not why. A space that
shares most of its volume with a space that has windows is named as such:
"overlaps 'Hall (15)' by 97 %: its windows went to that one".

The shared volume of two spaces is that of their prisms: the footprints' (with holes) common area
times the overlap of their heights (floor_z to top_z), over the space's own prism volume.
"""
from __future__ import annotations

import numpy as np

from en17037cli.io.mesh import Space

#: A space sharing at least this share of its volume with another overlaps it [-].
OVERLAP_SHARE = 0.5


def _prism(space: Space):
    """(footprint polygon, floor_z, top_z) [m] of a space with a usable footprint, else None."""
    import shapely

    if space.problem or len(space.footprint) < 3 or space.top_z <= space.floor_z:
        return None
    poly = shapely.make_valid(shapely.Polygon(np.asarray(space.footprint)[:, :2], [np.asarray(h)[:, :2] for h in space.holes]))
    return (poly, space.floor_z, space.top_z) if poly.area > 0 else None


def shared_share(a: Space, b: Space) -> float:
    """Share [-] of ``a``'s prism volume that lies in ``b``'s prism (0 where either has none)."""
    fa, fb = np.asarray(a.footprint)[:, :2], np.asarray(b.footprint)[:, :2]
    if len(fa) == 0 or len(fb) == 0 or np.any(fa.max(axis=0) < fb.min(axis=0)) or np.any(fb.max(axis=0) < fa.min(axis=0)):
        return 0.0  # plans apart: no polygon made
    pa, pb = _prism(a), _prism(b)
    if pa is None or pb is None:
        return 0.0
    dz = min(pa[2], pb[2]) - max(pa[1], pb[1])
    if dz <= 0:
        return 0.0
    return float(pa[0].intersection(pb[0]).area * dz / (pa[0].area * (pa[2] - pa[1])))


def overlap_reason(spaces: list[Space], names: list[str], i: int, with_windows) -> str | None:
    """Why space ``i`` has no window when it overlaps a space that has them: "overlaps 'X' by 97 %:
    its windows went to that one", naming the space it shares most of its volume with (at least
    :data:`OVERLAP_SHARE`); None where it overlaps none. ``with_windows``: indices of the spaces
    that windows open into; ``names``: each space's name as reports give it."""
    best = max(((shared_share(spaces[i], spaces[j]), j) for j in with_windows if j != i), default=(0.0, -1))
    if best[0] < OVERLAP_SHARE:
        return None
    return f"overlaps '{names[best[1]]}' by {best[0]:.0%}: its windows went to that one"
