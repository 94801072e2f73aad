"""The ``screen:`` section of a project: which buildings, how the probes are placed, how finely
each figure is integrated; and the run's other settings the screen takes from the project."""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from en17037cli import standard
from en17037cli.errors import InputError
from en17037cli.io import is_context
from en17037cli.project.settings import Project, SunSettings, ViewSettings, sun_settings, view_settings

#: The view's settings at the probes beside ``view_resolution_deg`` (the project's view: section or a
#: room's defaults otherwise): refinement of cells with two layers in them and its tolerances; no
#: frame (the half-space has none). The outside distance is the rooms' horizontal one
#: (:mod:`~en17037cli.district.figures`), the solid angles' own distance is not traced.
PROBE_VIEW = {"refine_levels": 3, "solid_angle_rel_tolerance": 0.02, "solid_angle_abs_tolerance_sr": 0.002,
              "distance_method": "horizontal", "frame_depth_m": 0.0}
#: The vertical sky component's refinement beside ``sky_resolution_deg``: levels, and the bound a
#: probe stops at, max(relative x VSC, absolute) [-] (5e-4: 0.05 % of the unobstructed horizontal
#: illuminance, 0.13 % of an unobstructed facade's 39.6 %).
SKY_REFINE_LEVELS, SKY_REL_TOLERANCE, SKY_ABS_TOLERANCE = 6, 0.005, 5e-4


@dataclass(frozen=True)
class ScreenSettings:
    """What ``screen:`` says (see the project schema for each key), with the sun and view settings.

    buildings : ``"*"``, a tuple of ids, or a polygon (k, 2) [m, the model's CRS]
    """

    buildings: object
    storey_height_m: float
    spacing_m: float
    sill_height_m: float
    window_width_m: float
    window_height_m: float
    shared_wall_tolerance_m: float
    sky_resolution_deg: float
    view: ViewSettings
    sun: SunSettings
    buildings_per_task: int

    @property
    def p_above_floor_m(self) -> float:
        """Height of P above the storey's floor [m]: max(1.2 m, sill + 0.3 m) (EN 17037 Annex A.3)."""
        return max(standard.SUN_POINT_MIN_ABOVE_FLOOR_M, self.sill_height_m + standard.SUN_POINT_MIN_ABOVE_SILL_M)


def screen_settings(project: Project) -> ScreenSettings:
    """The :class:`ScreenSettings` of a loaded project; one-line :class:`InputError` where the project
    cannot be screened (no ``screen:`` section, no location, a first file that is no city model, a
    virtual window whose P lies above its head)."""
    where = project.path.name
    config = project.config
    s = config.get("screen")
    if s is None:
        raise InputError(f"{where}: screen: missing; 'en17037 screen' needs a screen: section (screen: {{buildings: \"*\"}} "
                         "screens every building of model.files[0]); docs/district.md")
    if project.location is None:
        raise InputError(f"{where}: location: missing; the screen needs at least location.timezone (latitude and longitude "
                         "come from the city model's CRS where not given)")
    first = project.model.files[0]
    if not is_context(first.path):
        raise InputError(f"{where}: model.files[0]: {first.display} is not a city model; the screen probes the buildings of "
                         "a CityJSON or CityGML file given first (the other files are context)")
    b = s["buildings"]
    buildings = b if b == "*" else (tuple(b) if isinstance(b, list) else np.asarray(b["polygon"], dtype=float))
    w = s["window"]
    out = ScreenSettings(buildings=buildings, storey_height_m=float(s["storey_height_m"]), spacing_m=float(s["spacing_m"]),
                         sill_height_m=float(s["sill_height_m"]), window_width_m=float(w["width_m"]),
                         window_height_m=float(w["height_m"]), shared_wall_tolerance_m=float(s["shared_wall_tolerance_m"]),
                         sky_resolution_deg=float(s["sky_resolution_deg"]),
                         view=probe_view(config, float(s["view_resolution_deg"])), sun=probe_sun(config),
                         buildings_per_task=int(s["buildings_per_task"]))
    head = out.sill_height_m + out.window_height_m
    if out.p_above_floor_m > head + 1e-9:
        raise InputError(f"{where}: screen.window.height_m: P at max(floor + 1.2 m, sill + 0.3 m) = {out.p_above_floor_m:g} m "
                         f"lies above the window's head ({head:g} m above the floor); give a taller window or a higher sill")
    if head > out.storey_height_m + 1e-9:
        raise InputError(f"{where}: screen.window.height_m: the window's head ({head:g} m above the floor) lies above the "
                         f"storey ({out.storey_height_m:g} m); give a lower window or sill, or a taller storey_height_m")
    return out


def probe_view(config: dict, resolution_deg: float) -> ViewSettings:
    """The view's settings at the probes: the project's ``view:`` section (a room's defaults where
    it has none) with :data:`PROBE_VIEW` and the probes' resolution."""
    from en17037cli.project.schema import fill_defaults
    from en17037cli.schemas import load_schema

    schema = load_schema("project")
    base = fill_defaults(dict(config.get("view") or {}), schema["properties"]["view"], schema)
    return replace(view_settings(base), angular_resolution_deg=resolution_deg, **PROBE_VIEW)


def probe_sun(config: dict) -> SunSettings:
    """The project's ``sunlight:`` section (the defaults where it has none), over its period; a given
    date only (no worst or best day) is assessed over that day alone."""
    from en17037cli.project.schema import fill_defaults
    from en17037cli.schemas import load_schema

    schema = load_schema("project")
    sun = sun_settings(fill_defaults(dict(config.get("sunlight") or {}), schema["properties"]["sunlight"], schema))
    if sun.date not in ("worst", "best"):
        sun = replace(sun, period_start=sun.date, period_end=sun.date)
    return sun
