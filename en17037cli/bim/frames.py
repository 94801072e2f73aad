"""The model files behind a report, as BIM tools see them: each IFC file opened once, and points and
directions of the scene's world frame taken back into that file's own coordinates.

The scene's world frame is the file's placement coordinates in metres (ifcopenshell's world
coordinates), then the file's IfcMapConversion as the IFC reader applies it (:func:`file_placement`), then
the project's ``model.files[].units`` / ``up_axis`` (:func:`~en17037cli.scene.load.to_metres_z_up`)
and ``transform`` (:func:`~en17037cli.scene.load.transformed`), in that order. A BCF viewpoint is in
the IFC's own coordinates, in metres (BCF 2.1, "Components": "meters for length"): each of those
steps is undone, last first. Other formats stay in the scene's world frame (metres, z up).
"""
from __future__ import annotations

import datetime as dt

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.ifc_georef import map_conversion
from en17037cli.project.settings import ModelFile
from en17037cli.scene.load import UNIT_SCALE_M


def _unrotate(xyz: np.ndarray, deg: float) -> np.ndarray:
    """Points or directions (n, 3) turned by -``deg`` about +z (the inverse of a counterclockwise turn)."""
    a = np.radians(-deg)
    c, s = np.cos(a), np.sin(a)
    return np.column_stack([c * xyz[:, 0] - s * xyz[:, 1], s * xyz[:, 0] + c * xyz[:, 1], xyz[:, 2]])


def file_placement(f):
    """How the IFC reader places the file's own coordinates [m] in the scene's world frame before the
    project's settings (its IfcMapConversion): a function (n, 3) -> (n, 3), or None where it leaves
    them as they are. The one place that knows how the reader reads the map conversion."""
    m = map_conversion(f)
    return None if m is None else m.apply


def affine_inverse(forward, points: np.ndarray, directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points and unit directions (n, 3) taken back through an affine map ``forward`` (v -> v A^T + t,
    found from the images of the origin and the unit vectors): p -> (p - t) A^-T, d -> d A^-T, unit."""
    t = forward(np.zeros((1, 3)))[0]
    a = (forward(np.eye(3)) - t).T  # column j: the image of the unit vector j
    inv = np.linalg.inv(a)
    back = directions @ inv.T
    return (points - t) @ inv.T, back / np.linalg.norm(back, axis=1, keepdims=True)


class ModelFiles:
    """The project's model files by how the project writes them, the IFC ones opened on demand.

    project : the run's settings
    """

    def __init__(self, project) -> None:
        self.project = project
        self.specs: dict[str, ModelFile] = {f.display: f for f in project.model.files}
        self._open: dict[str, object] = {}

    def ifc(self, file: str):
        """The ifcopenshell file of ``file`` (as the project writes it), opened once; None where it is
        not an IFC file of the project."""
        spec = self.specs.get(file)
        if spec is None or spec.path.suffix.lower() != ".ifc":
            return None
        if file not in self._open:
            from en17037cli.io.ifc_step import open_ifc

            self._open[file] = open_ifc(spec.path)[0]
        return self._open[file]

    def forget(self, file: str) -> None:
        """Drop the opened copy of ``file`` (after changing it): the next :meth:`ifc` opens it again."""
        self._open.pop(file, None)

    def to_file(self, file: str | None, points: np.ndarray, directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Points (n, 3) [m] and unit directions (n, 3) of the scene's world frame in ``file``'s own
        coordinates [m] (see the module docstring); unchanged for a file that is not IFC."""
        points = np.atleast_2d(np.asarray(points, float))
        directions = np.atleast_2d(np.asarray(directions, float))
        f = self.ifc(file) if file else None
        if f is None:
            return points, directions
        spec = self.specs[file]  # type: ignore[index]
        if spec.transform is not None:
            points = _unrotate(points - np.asarray(spec.transform.translate_m, float), spec.transform.rotate_deg)
            directions = _unrotate(directions, spec.transform.rotate_deg)
        scale = UNIT_SCALE_M[spec.units or "m"]  # the IFC reader gives metres unless the project says otherwise
        if (spec.up_axis or "z") == "y":  # the inverse of (x, y, z) -> (x, -z, y)
            points, directions = (np.column_stack([v[:, 0], v[:, 2], -v[:, 1]]) for v in (points, directions))
        points = points / scale
        forward = file_placement(f)
        if forward is not None:
            points, directions = affine_inverse(forward, points, directions)
        return points, directions

    def ifc_date(self, file: str) -> str | None:
        """The IFC header's FILE_NAME time stamp as an xs:dateTime (``2016-11-29T10:26:56``), or None."""
        f = self.ifc(file)
        try:
            stamp = str(f.header.file_name.time_stamp).strip()
            return dt.datetime.fromisoformat(stamp.replace("Z", "+00:00")).isoformat()
        except (AttributeError, ValueError, TypeError, RuntimeError):
            return None

    def ifc_project(self, file: str) -> str | None:
        """The GlobalId of the file's IfcProject, or None."""
        f = self.ifc(file)
        projects = f.by_type("IfcProject") if f is not None else []
        return projects[0].GlobalId if projects else None


def require_ifc(project, flag: str) -> list[str]:
    """The IFC files of the project (as it writes them); an :class:`InputError` naming ``flag`` where it has none."""
    files = [f.display for f in project.model.files if f.path.suffix.lower() == ".ifc"]
    if not files:
        raise InputError(f"{flag}: the project has no IFC model file (model.files); results go back into an IFC only")
    return files
