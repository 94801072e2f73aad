"""Where each georeferenced model file stands: its CRS read at the centre of its faces.

A file is georeferenced when it names a map CRS: an IFC's IfcMapConversion (its target CRS), a
CityGML ``srsName``, a CityJSON ``referenceSystem``, or the file's ``crs`` key in the project
(which wins, as in :func:`en17037cli.scene.load.check_crs`). Its vertices, read to metres, are
then map coordinates; the centre of the building's plan, read in the CRS
(:func:`en17037cli.io.georef.locate`), is where the file says it stands (a city model around the
building, read at the building's own files' centre). A file the project moves (``transform``) is no longer
in its CRS's coordinates and says nothing here. :mod:`en17037cli.scene.site` weighs what these
say against the IfcSite's latitude and longitude and the project's location.
"""
from __future__ import annotations

import numpy as np

from en17037cli.io import is_context
from en17037cli.io.georef import Located, format_latlon, locate


def file_crs(f) -> str | None:
    """The CRS a loaded model file's vertices are in: the CRS its reader projected it to, else the
    file's ``crs`` key, else what the file says; None where nothing says."""
    site = f.mesh.site
    if site is not None and site.reprojected_from:
        return site.crs
    return f.spec.crs or (site.crs if site is not None else None)


def located_files(files) -> list[tuple[str, Located]]:
    """(file, where its CRS puts the building) of each loaded file (:class:`LoadedFile`) in a map
    CRS that PROJ knows, in the order given (the model's own files first). The building is the
    centre of the plan of the model's own files (world frame, the frame a city model shares with
    them); a file with none, or a model file on its own, is read at the centre of its own plan."""
    own = [f.vertices for f in files if not is_context(f.spec.path)]
    anchor = _plan_centre(np.concatenate(own)) if own else None
    out = []
    for f in files:
        crs = file_crs(f)
        if crs is None or f.spec.transform is not None:
            continue
        xy = anchor if anchor is not None and is_context(f.spec.path) else _plan_centre(f.vertices)
        where = None if xy is None else locate(crs, float(xy[0]), float(xy[1]))
        if where is not None:
            out.append((f.spec.display, where))
    return out


def _plan_centre(v: np.ndarray) -> np.ndarray | None:
    """Centre (2,) [m] of the plan's bounding box of the finite vertices (n, 3), or None."""
    v = v[np.all(np.isfinite(v), axis=1)]
    return None if not len(v) else 0.5 * (v[:, :2].min(axis=0) + v[:, :2].max(axis=0))


def outside_warnings(located: list[tuple[str, Located]]) -> list[str]:
    """A warning for each file its CRS puts outside that CRS's area of use: not a location."""
    out = []
    for display, w in located:
        if w.inside:
            continue
        at = f"at {format_latlon(w.latitude, w.longitude)}" if np.isfinite(w.latitude) else "nowhere PROJ can say"
        out.append(f"{display}: its georeference puts the model {at} in {w.crs}, outside {w.area}: not taken as the "
                   "building's location (the model not placed in that CRS, a map conversion read in the wrong unit, or the "
                   "wrong CRS named); check the files' transform and crs keys, or give location.latitude and "
                   "location.longitude")
    return out
