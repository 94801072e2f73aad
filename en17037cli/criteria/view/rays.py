"""Where a ray from inside a room goes: blocked, or out through a window onto sky, landscape or ground."""
from __future__ import annotations

import numpy as np

from en17037cli.raytrace import RayEngine
from en17037cli.scene.model import GROUND, LANDSCAPE, Scene

#: Classes of a direction seen from inside a room.
BLOCKED, SKY, LANDSCAPE_HIT, GROUND_HIT = 0, 1, 2, 3


class ViewRays:
    """The view engine's queries on a scene's ray engine.

    ``face_class`` is the class of a ray whose first opaque face beyond the glazing is each face:
    ``interior`` beyond the glazing (outer reveals, frames, the building's own walls) blocks;
    ``landscape`` and ``ground`` are seen.
    """

    def __init__(self, engine: RayEngine, scene: Scene):
        self.engine, self.scene = engine, scene
        self.face_class = np.select([scene.layer == LANDSCAPE, scene.layer == GROUND], [LANDSCAPE_HIT, GROUND_HIT],
                                    BLOCKED).astype(np.int8)
        self._top_z: dict[int, float] = {}

    def _top(self, layer: int) -> float:
        """The highest point of any face of ``layer`` [m], local frame (-inf: none)."""
        if layer not in self._top_z:
            triangles = getattr(self.scene, "triangles", None)
            if triangles is None:  # a scene of layers only (the district's): every direction stays possible
                self._top_z[layer] = np.inf
            else:
                faces = triangles[self.scene.layer == layer]
                self._top_z[layer] = float(self.scene.vertices[faces][..., 2].max()) if len(faces) else -np.inf
        return self._top_z[layer]

    @property
    def ground_top_z(self) -> float:
        """The highest point of any ground face [m], local frame (-inf: none): from above it, ground
        can be seen only below the horizon (a ray that misses everything below it is ground too)."""
        return self._top(GROUND)

    @property
    def landscape_top_z(self) -> float:
        """The highest point of any landscape face [m], local frame (-inf: none): from above it,
        landscape can be seen only below the horizon."""
        return self._top(LANDSCAPE)

    def layer_of(self, face: np.ndarray) -> np.ndarray:
        """Layer code of each face index (-1 where face is -1)."""
        return np.where(face >= 0, self.scene.layer[np.maximum(face, 0)], -1)

    def outside_class(self, face: np.ndarray, directions: np.ndarray) -> np.ndarray:
        """Class of rays whose first opaque face beyond the glazing is ``face`` (-1: none).

        A ray that meets nothing is sky when it points upwards and ground when it leaves the
        model below the horizon.

        Returns
        -------
        (n,) int8, BLOCKED / SKY / LANDSCAPE_HIT / GROUND_HIT
        """
        cls = self.face_class[np.maximum(face, 0)]
        none = face < 0
        cls[none] = np.where(directions[none, 2] < 0, GROUND_HIT, SKY)
        return cls

    def through_windows(self, window_group: str, origins, directions):
        """Where each ray from inside a room goes: through which window and onto which layer.

        A ray *leaves through a window* when it reaches a face of ``window_group`` (the room's
        windows) before any opaque face, and the first opaque face beyond the glazing is not
        ``interior`` (see :meth:`outside_class`). Two queries per ray: the room's windows (a scene
        of a few triangles) and the opaque faces.

        Parameters
        ----------
        window_group : str, :func:`~en17037cli.scene.model.room_window_group` of the room
        origins : (n, 3) float [m]; directions : (n, 3) unit

        Returns
        -------
        cls : (n,) int8, BLOCKED / SKY / LANDSCAPE_HIT / GROUND_HIT
        window_face : (n,) int, the window face crossed (-1 if blocked)
        outside_face : (n,) int, the first opaque face beyond the glazing (-1 if none or blocked)
        outside_distance : (n,) float [m] along the ray to that face (+inf if none)
        glass_distance : (n,) float [m] along the ray to the window face (+inf if blocked)
        """
        n = len(origins)
        cls = np.zeros(n, dtype=np.int8)
        wface = np.full(n, -1, dtype=np.int64)
        oface = np.full(n, -1, dtype=np.int64)
        odist = np.full(n, np.inf)
        gdist = np.full(n, np.inf)
        f_g, t_g = self.engine.first_hit(window_group, origins, directions)
        cand = np.flatnonzero(f_g >= 0)
        if len(cand) == 0:
            return cls, wface, oface, odist, gdist
        f_o, t_o = self.engine.first_hit("opaque", origins[cand], directions[cand])
        ok = t_g[cand] < t_o
        cand, f_o, t_o = cand[ok], f_o[ok], t_o[ok]
        c = self.outside_class(f_o, directions[cand])
        cls[cand] = c
        keep = cand[c != BLOCKED]
        wface[keep] = f_g[keep]
        oface[keep] = f_o[c != BLOCKED]
        odist[keep] = t_o[c != BLOCKED]
        gdist[keep] = t_g[keep]
        return cls, wface, oface, odist, gdist
