"""Model readers, registered by file name ending; each returns a :class:`~en17037cli.io.mesh.Mesh`.

A reader is ``read(path: Path, options: ReadOptions) -> Mesh``. It parses one format and
describes what it finds (parts with attributes, the site, spaces); it applies no layer rules,
no units of the project and no transform (the scene does). Bad files raise
:class:`~en17037cli.errors.InputError` with one line naming the file and what to do.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from en17037cli.errors import InputError
from en17037cli.io.mesh import Mesh, Part, Site, Space  # noqa: F401 - the package's public types


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


def is_context(path: Path) -> bool:
    """Whether ``path`` is read as a city model (context), by its file name."""
    return reader_for(Path(path)) in CONTEXT_READERS


def reader_for(path: Path) -> Reader:
    """The reader registered for ``path``'s longest matching ending."""
    _load_builtin_readers()
    name = path.name.lower()
    for ending in sorted(READERS, key=len, reverse=True):
        if name.endswith(ending):
            return READERS[ending]
    raise InputError(f"{path}: unsupported model format '{path.suffix}'; use one of {', '.join(sorted(READERS))}")


def read_model(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read a model file with the reader registered for its name."""
    return reader_for(Path(path))(Path(path), options or ReadOptions())


def _load_builtin_readers() -> None:
    """Import the reader modules (they register themselves); heavy libraries load only when used."""
    from en17037cli.io import citygml, cityjson, dxf, gbxml, ifc, obj, ply, stl, trimesh_formats  # noqa: F401
