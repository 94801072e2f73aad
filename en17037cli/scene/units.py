"""Units sanity: a model whose windows (or building) are implausible in the unit the project gives
it was exported in another unit. A model in millimetres declared as metres has 1,400 m windows;
one in metres declared as millimetres, 1.4 mm windows. Both are input errors that name the unit
the model looks like and the key to set, before anything else is said about the model."""
from __future__ import annotations

import numpy as np

from en17037cli.errors import InputError

#: The units a project may give [m per unit] (the project schema's model.units).
UNIT_M = {"m": 1.0, "cm": 0.01, "mm": 0.001, "ft": 0.3048, "in": 0.0254}
#: Window heights (the median over a file's window objects) a building can have [m] ...
WINDOW_PLAUSIBLE_M = (0.005, 12.0)  # a 1 cm peephole is odd, not a unit; 1.4 mm is
#: ... and the range a re-read unit must bring them into, the most likely nearest :data:`WINDOW_TYPICAL_M`.
WINDOW_LIKELY_M, WINDOW_TYPICAL_M = (0.3, 4.0), 1.4
#: The size of the building checked (its interior and window faces, their largest extent) [m]:
#: plausible, and likely for a re-read unit.
BUILDING_PLAUSIBLE_M, BUILDING_LIKELY_M, BUILDING_TYPICAL_M = (1.0, 3000.0), (3.0, 500.0), 20.0


def _likely_unit(size_m: float, declared: str, likely: tuple[float, float], typical: float) -> tuple[str, float] | None:
    """The unit (other than ``declared``) that brings ``size_m`` (read in ``declared``) into ``likely``,
    nearest ``typical`` in ratio; None when none does."""
    best = None
    for unit, m in UNIT_M.items():
        size = size_m / UNIT_M[declared] * m
        if unit != declared and likely[0] <= size <= likely[1]:
            score = abs(np.log(size / typical))
            if best is None or score < best[0]:
                best = (score, unit, size)
    return None if best is None else (best[1], best[2])


def check_units(vertices_m: np.ndarray, triangles: np.ndarray, face_part: np.ndarray, part_layer: np.ndarray,
                window_layer: int, building_layers: tuple[int, ...], declared: str, key: str, where: str) -> None:
    """Raise an :class:`InputError` when a file read in ``declared`` units is implausible.

    Parameters
    ----------
    vertices_m : (n, 3) float [m], the file's vertices scaled by ``declared``, z up
    triangles : (m, 3) int; face_part : (m,) int, each face's part; part_layer : (parts,) int
    key : the project key that gives the unit (``model.units`` or ``model.files[i].units``)

    The windows decide where the file has some (the median height of its window parts; a curtain
    wall does not move a median), else the size of its building faces; a file with neither (a
    context tile) is not judged.
    """
    layer = part_layer[face_part] if len(face_part) else np.zeros(0, int)
    win = layer == window_layer
    if win.any():
        z = vertices_m[triangles[win]][..., 2]
        parts = face_part[win]
        order = np.argsort(parts, kind="stable")
        starts = np.r_[0, np.flatnonzero(np.diff(parts[order])) + 1]
        hi = np.maximum.reduceat(z.max(axis=1)[order], starts)
        lo = np.minimum.reduceat(z.min(axis=1)[order], starts)
        size, what, bounds, likely, typical = float(np.median(hi - lo)), "its windows are", WINDOW_PLAUSIBLE_M, \
            WINDOW_LIKELY_M, WINDOW_TYPICAL_M
        if size <= 0:
            return  # flat glazing only (roof lights): the building's size decides below
    else:
        size = 0.0
    if not win.any() or size <= 0:
        body = np.isin(layer, building_layers)
        if not body.any():
            return
        v = vertices_m[np.unique(triangles[body])]
        size, what, bounds, likely, typical = float((v.max(axis=0) - v.min(axis=0)).max()), "its building is", \
            BUILDING_PLAUSIBLE_M, BUILDING_LIKELY_M, BUILDING_TYPICAL_M
    if bounds[0] <= size <= bounds[1]:
        return
    guess = _likely_unit(size, declared, likely, typical)
    looks = (f"; it looks like {guess[0]} ({size / UNIT_M[declared] * UNIT_M[guess[0]]:.2f} m): set {key}: {guess[0]} "
             "(the unit the file was exported in)") if guess else f"; set {key} to the unit the file was exported in"
    raise InputError(f"{where}: {what} {size:,.4g} m {'tall' if 'windows' in what else 'across'} read in {declared} "
                     f"({key}), not a building's size{looks}")
