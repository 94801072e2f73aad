"""The pictures of the client report: pure drawing functions that return PNG bytes (and SVG).

Nothing here traces rays or reads files: the callers pass the values, these modules draw them.

- :mod:`.colours`: the colour tables, how light colours read, continuous colours, layer labels;
  :mod:`.colourmaps`: viridis and cividis as 8-bit tables;
- :mod:`.canvas`: what a picture holds (cells, images, paths, markers, text), written as SVG, and
  :mod:`.raster`: the same drawn as PNG with Pillow and numpy; :mod:`.parts`: the parts several
  pictures draw (legends, colour bars, north arrow, scale bar, arrows);
- :mod:`.plan`: plan maps of a room's viewpoints (:func:`plan_map`, :func:`plan_rotation`);
- :mod:`.fisheye`: the fisheye from point P with the sun's paths and its projection;
- :mod:`.charts`: the hours-of-sunlight chart, and the tornado chart of a sensitivity study (the one
  picture matplotlib draws);
- :mod:`.glare`: clause 5.4's map of positions, hourly DGP carpet and fisheye luminance.

Durations are written by :func:`en17037cli.report.numbers.fmt_duration`, re-exported here.
Pillow and matplotlib are imported inside the functions that draw, so this package imports without them.
"""
from __future__ import annotations

from en17037cli.report.numbers import fmt_duration
from en17037cli.report.pictures.canvas import DPI
from en17037cli.report.pictures.charts import CHART_SIZE_IN, hours_chart, tornado
from en17037cli.report.pictures.colours import (
    ASSESSED_COLOUR,
    BAR_COLOUR,
    BLOCKED,
    CLASS_COLOURS,
    CLASS_GROUND,
    CLASS_LANDSCAPE,
    CLASS_NAMES,
    CLASS_SKY,
    CMAP,
    DISTANCE_VMIN_M,
    GROUND,
    LANDSCAPE,
    LAYER_COLOURS,
    LAYER_ORDER,
    LEVEL_COLOURS,
    LEVEL_NAMES,
    OUTSIDE,
    SKY,
    SUN_PATH_COLOUR,
    WINDOW_COLOUR,
    continuous_colours,
    layer_label,
    lightness,
    relative_luminance,
)
from en17037cli.report.pictures.fisheye import (
    FISHEYE_CENTRE_PX,
    FISHEYE_RADIUS_PX,
    FISHEYE_SIZE_IN,
    fisheye,
    fisheye_directions,
    fisheye_pixel,
    fisheye_pixel_xy,
    fisheye_xy,
)
from en17037cli.report.pictures.glare import dgp_carpet, luminance_fisheye, positions_map
from en17037cli.report.pictures.plan import COLOUR_BAR_PX, PLAN_BOX_PX, PLAN_SIZE_IN, plan_map, plan_rotation

__all__ = [
    # drawing
    "plan_map", "plan_rotation", "fisheye", "fisheye_xy", "fisheye_pixel_xy", "fisheye_directions", "fisheye_pixel",
    "hours_chart", "tornado", "positions_map", "dgp_carpet", "luminance_fisheye",
    # colours and numbers
    "relative_luminance", "lightness", "continuous_colours", "layer_label", "fmt_duration",
    # layout
    "DPI", "PLAN_SIZE_IN", "FISHEYE_SIZE_IN", "CHART_SIZE_IN", "PLAN_BOX_PX", "COLOUR_BAR_PX", "FISHEYE_CENTRE_PX",
    "FISHEYE_RADIUS_PX",
    # colour tables and codes
    "LEVEL_COLOURS", "LEVEL_NAMES", "SKY", "LANDSCAPE", "GROUND", "LAYER_ORDER", "LAYER_COLOURS", "OUTSIDE", "BLOCKED",
    "CLASS_SKY", "CLASS_LANDSCAPE", "CLASS_GROUND", "CLASS_NAMES", "CLASS_COLOURS", "WINDOW_COLOUR", "SUN_PATH_COLOUR",
    "BAR_COLOUR", "ASSESSED_COLOUR", "CMAP", "DISTANCE_VMIN_M",
]
