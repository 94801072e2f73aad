"""Geometry on numpy arrays: triangles and polygons (:mod:`.triangles`), planar containment and
clipping (:mod:`.planar`), exact solid angles (:mod:`.solid_angle`)."""
from en17037cli.geometry.planar import (
                                        area2,
                                        boxes_vs_convex,
                                        clip_halfplane,
                                        convex_halfplanes,
                                        cut_triangles,
                                        in_triangle,
                                        points_in_convex,
                                        points_in_triangles,
                                        turn,
)
from en17037cli.geometry.solid_angle import (
                                        clipped_solid_angle,
                                        corner_solid_angle,
                                        offset_rectangle_solid_angle,
                                        rectangle_solid_angle,
                                        triangle_solid_angle,
)
from en17037cli.geometry.triangles import check_shape, triangle_normals, triangulate_polygon, triangulate_polygons, window_axes

__all__ = ["area2", "boxes_vs_convex", "convex_halfplanes", "points_in_convex", "clip_halfplane", "cut_triangles", "in_triangle", "points_in_triangles", "clipped_solid_angle", "corner_solid_angle",
           "offset_rectangle_solid_angle", "rectangle_solid_angle", "triangle_solid_angle", "check_shape",
           "triangle_normals", "triangulate_polygon", "triangulate_polygons", "turn", "window_axes"]
