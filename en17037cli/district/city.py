"""The buildings of the screened city model, whatever its format (:mod:`~en17037cli.district.walls`)."""
from __future__ import annotations

from pathlib import Path

from en17037cli.district.walls import CityBuilding, read_buildings_json
from en17037cli.district.walls_gml import read_buildings_gml


def read_buildings(path: Path, lod: str = "highest", exclude=(), crs: str | None = None) -> tuple[list[CityBuilding], str | None]:
    """The buildings of a CityJSON or CityGML file with their walls, in file order, and the file's CRS.

    Parameters
    ----------
    path : the city model (``model.files[0]``); lod : its ``lod`` key; exclude : ids left out (with
        their parts); crs : its ``crs`` key, for a file that names none
    """
    if path.suffix.lower() in (".gml", ".citygml"):
        return read_buildings_gml(path, lod, exclude, crs)
    return read_buildings_json(path, lod, exclude, crs)
