"""The registry of model readers: what a project may ask of a reader (:class:`ReadOptions`), and
the readers by file name ending (:func:`register`, :data:`READERS`). Each reader module registers
itself here on import; :mod:`en17037cli.io` imports them and picks one for a file.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from en17037cli.io.mesh import Mesh


@dataclass(frozen=True)
class ReadOptions:
    """What a project file may ask of a reader (readers ignore what does not apply to them).

    lod : CityJSON level of detail, "highest" or e.g. "2.2"
    exclude : object ids (CityJSON ids, IFC GlobalIds) to leave out
    near : ((x, y), radius_m) in the file's own coordinates (the target CRS's, where one is given):
        objects entirely farther away may be left out before triangulation, or None
    crs : the file's CRS as the project gives it (its ``crs`` key, ``EPSG:nnnn``), over what the file says
    target_crs : the CRS of the project's other files: a city model in another CRS (CityGML) is
        projected to it, or None
    """

    lod: str = "highest"
    exclude: tuple[str, ...] = ()
    near: tuple[tuple[float, float], float] | None = None
    crs: str | None = None
    target_crs: str | None = None


Reader = Callable[[Path, ReadOptions], Mesh]

#: file name ending (lower case, with the dot) -> reader; longer endings win (".city.json" over ".json")
READERS: dict[str, Reader] = {}
#: readers of city models: the context around a building, read after the building itself (so they
#: can be cut to the building's surroundings) and never the building's own rooms
CONTEXT_READERS: set = set()


def register(*endings: str, context: bool = False):
    """Decorator registering a reader for file names ending in any of ``endings``; ``context`` marks
    a city-model format (see :data:`CONTEXT_READERS`)."""
    def deco(fn: Reader) -> Reader:
        for e in endings:
            READERS[e.lower()] = fn
        if context:
            CONTEXT_READERS.add(fn)
        return fn
    return deco
