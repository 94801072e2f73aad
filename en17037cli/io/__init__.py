"""Model readers, registered by file name ending; each returns a :class:`~en17037cli.io.mesh.Mesh`.

A reader is ``read(path: Path, options: ReadOptions) -> Mesh``. It parses one format and
describes what it finds (parts with attributes, the site, spaces); it applies no layer rules,
no units of the project and no transform (the scene does). Bad files raise
:class:`~en17037cli.errors.InputError` with one line naming the file and what to do. Readers
register themselves in :mod:`~en17037cli.io.registry` (which imports none of them); this module
imports them when a file is read.
"""
from __future__ import annotations

from pathlib import Path

from en17037cli.errors import InputError
from en17037cli.io.mesh import Mesh, Part, Site, Space  # noqa: F401 - the package's public types
from en17037cli.io.registry import CONTEXT_READERS, READERS, Reader, ReadOptions, register  # noqa: F401 - public


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
