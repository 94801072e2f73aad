"""Small CityJSON 2.0 city models for the screen's tests: box buildings and a building round a
courtyard, as closed Solids with semantic surfaces (one WallSurface object per wall), in
EPSG:7415 near Delft, and the project that screens them."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import yaml

#: Where the models stand [m, EPSG:7415]; coordinates below are relative to it
PLACE = (85000.0, 446000.0, 0.0)
LAT, LON, TZ = 52.0, 4.36, "Europe/Amsterdam"


def _newell(pts) -> np.ndarray:
    p = np.asarray(pts, float)
    p = p - p.mean(axis=0)
    n = np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)
    return n / np.linalg.norm(n)


class City:
    """Vertices and objects of a CityJSON file being built; coordinates relative to :data:`PLACE` [m]."""

    def __init__(self):
        self.vertices: list = []
        self.objects: dict = {}

    def _v(self, p) -> int:
        self.vertices.append([round(c * 1000) for c in p])
        return len(self.vertices) - 1

    def solid(self, oid: str, faces: list, kinds: list, check_inside=None, cls: str = "Building") -> City:
        """One Solid of faces (each [outer ring, holes...] of points) with their semantic types; with
        ``check_inside`` a point inside, every face's normal is checked to point away from it."""
        bounds, surfaces, values = [], [], []
        for face, kind in zip(faces, kinds):
            if check_inside is not None and kind == "WallSurface":
                c = np.mean(face[0], axis=0)
                assert _newell(face[0]) @ (c - np.asarray(check_inside)) > 0, (oid, face)
            bounds.append([[self._v(p) for p in ring] for ring in face])
            surfaces.append({"type": kind})
            values.append(len(surfaces) - 1)
        self.objects[oid] = {"type": cls, "geometry": [{"type": "Solid", "lod": "2.2", "boundaries": [bounds],
                                                        "semantics": {"surfaces": surfaces, "values": [values]}}]}
        return self

    def box(self, oid: str, x0, x1, y0, y1, h, z0=0.0, roof=True) -> City:
        """An axis-aligned box building (``roof=False``: its roof left out, an open solid)."""
        c = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        lo = [(x, y, z0) for x, y in c]
        hi = [(x, y, z0 + h) for x, y in c]
        faces = [[[lo[0], lo[3], lo[2], lo[1]]], [[hi[0], hi[1], hi[2], hi[3]]]]
        kinds = ["GroundSurface", "RoofSurface"]
        for a in range(4):
            b = (a + 1) % 4
            faces.append([[lo[a], lo[b], hi[b], hi[a]]])
            kinds.append("WallSurface")
        if not roof:
            faces, kinds = faces[:1] + faces[2:], kinds[:1] + kinds[2:]
        return self.solid(oid, faces, kinds, check_inside=((x0 + x1) / 2, (y0 + y1) / 2, z0 + h / 2))

    def courtyard(self, oid: str, outer: tuple, inner: tuple, h: float) -> City:
        """A building round a courtyard: footprint the square ring between ``outer`` and ``inner``
        (x0, x1, y0, y1 each), height h."""
        def ring(box, z):
            x0, x1, y0, y1 = box
            return [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]

        ol, oh, il, ih = ring(outer, 0.0), ring(outer, h), ring(inner, 0.0), ring(inner, h)
        faces = [[[ol[0], ol[3], ol[2], ol[1]], il], [oh, [ih[0], ih[3], ih[2], ih[1]]]]
        kinds = ["GroundSurface", "RoofSurface"]
        for a in range(4):
            b = (a + 1) % 4
            faces.append([[ol[a], ol[b], oh[b], oh[a]]])
            faces.append([[il[b], il[a], ih[a], ih[b]]])  # the courtyard's walls face into it
            kinds += ["WallSurface", "WallSurface"]
        return self.solid(oid, faces, kinds)

    def write(self, path: Path, crs: str | None = "https://www.opengis.net/def/crs/EPSG/0/7415") -> Path:
        doc = {"type": "CityJSON", "version": "2.0", "transform": {"scale": [0.001] * 3, "translate": list(PLACE)},
               "metadata": {"referenceSystem": crs} if crs else {}, "CityObjects": self.objects, "vertices": self.vertices}
        path.write_text(json.dumps(doc))
        return path


def screen_project(folder: Path, city: Path, buildings="*", sun_date="03-21", location=None, **screen) -> Path:
    """A project screening ``city`` (sunlight on ``sun_date`` alone, true north +Y)."""
    doc = {"version": 1, "name": "screen test", "model": {"true_north_deg": 0.0, "files": [{"path": str(city)}]},
           "location": location or {"latitude": LAT, "longitude": LON, "timezone": TZ},
           "screen": {"buildings": buildings, **screen},
           "sunlight": {"date": sun_date, "period": {"start": sun_date, "end": sun_date}}}
    p = folder / "project.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p
