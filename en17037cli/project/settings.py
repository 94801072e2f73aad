"""Typed, frozen settings built once from the resolved project document.

This module and :mod:`en17037cli.project.load` are the only places that know the project file's
keys; scene building, engines and reports receive these objects. Units are in the field names.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from en17037cli.project.glare_settings import GlareSettings
from en17037cli.standard import Thresholds


@dataclass(frozen=True)
class LayerRule:
    """One rule of a file's ``layers:`` list: faces whose part matches get ``layer``.

    match : glob tested on every name and attribute value of a part (object, group, material,
        file stem; IFC class, Name, GlobalId, type, storey; CityJSON type, id, surface), or None
    keys : part attribute -> glob, each of which must match (``class``, ``surface``, ``attr.roofType``...)
    """

    match: str | None
    layer: str
    obstructs_sun: bool = True
    keys: tuple[tuple[str, str], ...] = ()
    reflectance: float | None = None  # visible, 0..1 (daylight, clause 5.1); None: the layer's default
    transmittance: float | None = None  # visible, normal-hemispherical, 0..1, for glazing; None: the default

    def describe(self) -> str:
        """The rule as the project file writes it, for messages."""
        parts = ([f"match: '{self.match}'"] if self.match is not None else []) + [f"{k}: '{v}'" for k, v in self.keys]
        return ", ".join(parts)


#: Rule keys that match one part attribute each (see :data:`~en17037cli.io.mesh.PART_KEYS`).
RULE_KEYS = ("class", "name", "id", "type", "storey", "surface", "parent")


@dataclass(frozen=True)
class Transform:
    """Rotation about the vertical axis [deg, counterclockwise seen from above], then translation [m]."""

    rotate_deg: float = 0.0
    translate_m: tuple[float, float, float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class ModelFile:
    """One entry of ``model.files``.

    path : the file, resolved; display : the path as the project file writes it
    layer : one layer for the whole file, or None when ``rules`` decide
    units, up_axis : this file's own, or None (the format's, else the model's)
    transform : where the file's geometry goes, or None
    crs : the file's CRS where the file does not say (``EPSG:nnnn``), or None
    lod, exclude, exclude_overlapping, context_radius_m : for city models (see the project schema)
    """

    path: Path
    display: str
    layer: str | None
    obstructs_sun: bool
    rules: tuple[LayerRule, ...]
    units: str | None
    up_axis: str | None
    transform: Transform | None = None
    crs: str | None = None
    lod: str = "highest"
    exclude: tuple[str, ...] = ()
    exclude_overlapping: bool = True
    context_radius_m: float = 1000.0

    @property
    def all_ignored(self) -> bool:
        """Every face of the file goes to ``ignore`` (its layer, or rules that all say ``ignore`` ending
        with a catch-all): the file need not be read."""
        catch_all = any(r.match == "*" and not r.keys for r in self.rules)
        return self.layer == "ignore" or (catch_all and all(r.layer == "ignore" for r in self.rules))


@dataclass(frozen=True)
class ModelSettings:
    units: str
    up_axis: str
    true_north_deg: float | None  # None: from the IFC model's TrueNorth, else 0
    files: tuple[ModelFile, ...]


@dataclass(frozen=True)
class Location:
    latitude: float | None  # [deg], north positive; None: from the IFC model's IfcSite
    longitude: float | None  # [deg], east positive; None: from the IFC model's IfcSite
    timezone: str  # IANA name
    elevation_m: float = 0.0


@dataclass(frozen=True)
class Requirements:
    """Levels a room must reach per check, and how rooms are combined for sunlight."""

    view: str
    sunlight: str
    sunlight_rooms: str = "all"
    daylight: str = "none"
    glare: str = "none"


@dataclass(frozen=True)
class RoomSpec:
    """One entry of ``rooms`` as the project file gives it.

    floor_z : [m], in the scene frame; ceiling_z : [m] or None (derived from the model)
    ifc_spaces : a glob on IfcSpace names: the entry stands for one room per matched space (the
        scene makes their specs; ``name`` and ``floor_z`` are then None)
    gbxml_spaces : the same on the Spaces of a gbXML model
    auto : the entry stands for one room per region the walls enclose at ``floor_z`` (or at every
        storey, ``auto_all_storeys``) with a window; inside : (2,) [m] a point in the room, or None
    floor : (k, 2) [m] polygon in the scene frame, or None (derived from the model)
    windows : globs on window names, or None: every window that bounds the room
    window_margin_m : [m], how far beyond the floor's outline a window of the room may lie (the wall)
    view_points : (n, 3) [m] explicit viewpoints (scene frame), or None (a grid)
    sun_points : (k, 3) [m] explicit points P, one per window, or None (the A.3 rule)
    """

    name: str
    index: int
    floor_z: float
    floor: np.ndarray | None
    windows: tuple[str, ...] | None
    ceiling_z: float | None
    window_margin_m: float
    view_points: np.ndarray | None
    sun_points: np.ndarray | None
    requirements: Requirements
    ifc_spaces: str | None = None
    gbxml_spaces: str | None = None
    auto: bool = False  # one room per region the walls enclose with a window (scene/section.py)
    auto_all_storeys: bool = False  # auto without floor_z: at every storey of the model
    inside: np.ndarray | None = None  # (2,) [m] a point in the room: picks the region around it
    own_requirements: tuple[str, ...] = ()  # the checks whose level the entry's own 'requirements' gives
    #: the thresholds of the room where its kinds ask others than the project's (project/kinds.py), else None
    thresholds: Thresholds | None = None


@dataclass(frozen=True)
class ViewSettings:
    """``view:`` section (clause 5.2). See the project schema for each key's meaning."""

    eye_heights_m: tuple[float, ...]
    grid_spacing_m: float
    wall_margin_m: float
    layer_threshold_sr: float
    area_fraction: float
    angular_resolution_deg: float
    frame_depth_m: float
    refine_levels: int
    solid_angle_rel_tolerance: float
    solid_angle_abs_tolerance_sr: float
    horizontal_resolution_deg: float
    angle_tolerance_deg: float
    distance_method: str
    distance_statistic: str
    grid_offset: float = 0.0
    sight_angle_method: str = "plan"  # plan | fan
    mullions_block: bool = True  # members inside an opening cut the horizontal sight angle
    #: share of the horizon in front of a room's windows the model's landscape must cover to judge the layers
    surroundings_min_share: float = 0.25
    #: how far the solid angles are refined: ``decided`` (until every level is decided and every
    #: interval within ``tolerance``) or ``exact`` (until the error estimate meets the solid-angle
    #: tolerances): :mod:`en17037cli.criteria.view.decide`
    refine: str = "decided"
    #: ``decided``: the largest half-width of a layer's solid-angle interval, as a fraction of the
    #: windows' solid angle at the point [-]
    tolerance: float = 0.05


@dataclass(frozen=True)
class SunSettings:
    """``sunlight:`` section (clause 5.3). ``date`` is MM-DD, ``worst`` or ``best``."""

    year: int
    period_start: str  # MM-DD
    period_end: str  # MM-DD
    date: str
    timestep_min: float
    tolerance_s: float
    min_altitude_deg: float
    refraction: bool
    pressure_mbar: float
    temperature_c: float
    max_reveal_depth_m: float
    method: str = "exact"  # exact | sampled
    #: where P lies behind a member of the window's frame: pane_centres | nearest_glass | as_drawn
    #: (:mod:`en17037cli.criteria.sunlight.member_at_p`)
    point_p_behind_member: str = "pane_centres"


@dataclass(frozen=True)
class RadianceParams:
    """How Radiance computes the reflected components (``daylight.radiance``, see
    :mod:`en17037cli.criteria.daylight.gather`): the gather's ``rays`` per point in a first round,
    ``max_rays`` at most, until the 99 % interval is within max(``rel_tolerance`` x R,
    ``abs_tolerance_pct`` [% D]); Radiance's ambient parameters at each hit (see ``rtrace(1)``):
    bounce limit ``ab``, hemisphere samples ``ad``, super-samples ``as``, the Russian-roulette
    weight ``lw``; ``window_rays``: directions per window a path's bounce sends through the glazing;
    ``replicates`` independent sets of ``climate_rays`` paths per point give method 2's daylight
    coefficients, their spread the error of the shares of hours; ``stop_clear_of_thresholds``: a
    point also stops once its D is farther than its error from every threshold."""

    ab: int = 100
    ad: int = 1
    as_: int = 0
    lw: float = 0.05
    replicates: int = 4
    rays: int = 256
    max_rays: int = 4096
    rel_tolerance: float = 0.05
    abs_tolerance_pct: float = 0.01
    window_rays: int = 1
    climate_rays: int = 1024
    stop_clear_of_thresholds: bool = True


@dataclass(frozen=True)
class SkyComponentSettings:
    """``daylight.sky_component``: how finely the sky component is integrated (see
    :class:`en17037cli.criteria.daylight.sky_component.SkyTolerance`): base cell [deg], splits of a
    mixed cell, and the bound's target, max(``rel_tolerance`` x SC, ``abs_tolerance_pct`` [% D])."""

    resolution_deg: float = 1.0
    refine_levels: int = 8
    rel_tolerance: float = 0.005
    abs_tolerance_pct: float = 0.005


@dataclass(frozen=True)
class DaylightSettings:
    """``daylight:`` section (clause 5.1). See the project schema for each key's meaning.

    weather : the EPW file, resolved, or None; weather_display : as the project file writes it
    reflectance : surface -> visible reflectance (floor, walls, ceiling, landscape, ground)
    """

    method: str  # daylight_factor | climate_based
    median_diffuse_lx: float | None
    weather: Path | None
    weather_display: str | None
    reference_plane_m: float
    grid_spacing_m: float
    wall_margin_m: float
    aggregation: str  # hours_first | points_first
    sky_subdivision: int
    sun_subdivision: int
    glazing_transmittance: float
    reflectance: tuple[tuple[str, float], ...]
    radiance: RadianceParams
    grid_offset: float = 0.0
    sky_component: SkyComponentSettings = SkyComponentSettings()

    def reflectance_of(self, surface: str) -> float:
        return dict(self.reflectance)[surface]


@dataclass(frozen=True)
class DwellingSpec:
    """One dwelling as the project file lists it: globs on room names (``main_rooms``: the rooms that
    may satisfy the sunlight rule; None: every room of the dwelling)."""

    name: str
    rooms: tuple[str, ...]
    main_rooms: tuple[str, ...] | None = None


@dataclass(frozen=True)
class DwellingsSpec:
    """How rooms group into dwellings: listed, one per IFC zone (a glob on zone names), or by the
    named group ``dwelling`` of a regular expression on room names; ``main_rooms`` globs apply to
    every dwelling found by zones or pattern."""

    listed: tuple[DwellingSpec, ...] = ()
    ifc_zones: str | None = None
    by_pattern: str | None = None
    main_rooms: tuple[str, ...] | None = None


@dataclass(frozen=True)
class Project:
    """A validated project: where it is, what to load, what to check and against what.

    config : the resolved document (every default filled in), repeated in the report's inputs
    """

    path: Path
    name: str
    model: ModelSettings
    rooms: tuple[RoomSpec, ...]
    location: Location | None
    view: ViewSettings | None
    sunlight: SunSettings | None
    requirements: Requirements
    thresholds: Thresholds
    config: dict
    daylight: DaylightSettings | None = None
    dwellings: DwellingsSpec | None = None
    glare: GlareSettings | None = None
    practice: str = "en17037"
    practice_set: tuple[tuple[str, object], ...] = ()  # the values the practice set (key path, value)
    kind_rules: tuple = ()  # the room_kinds rules (project/kinds.py KindRule), first match wins
    by_kind: dict = field(default_factory=dict)  # room kind -> what its rooms are asked (project/kinds.py KindValues)
    warnings: tuple[str, ...] = ()  # overrides that change nothing under these settings, with why

    @property
    def directory(self) -> Path:
        return self.path.parent


def _fields(cls, d: dict, **extra):
    return cls(**{k: d[k] for k in cls.__dataclass_fields__ if k in d and k not in extra}, **extra)


def view_settings(d: dict) -> ViewSettings:
    return _fields(ViewSettings, d, eye_heights_m=tuple(float(h) for h in d["eye_heights_m"]))


def sun_settings(d: dict) -> SunSettings:
    return _fields(SunSettings, d, period_start=d["period"]["start"], period_end=d["period"]["end"])


def daylight_settings(d: dict, directory: Path) -> DaylightSettings:
    rp = d["radiance"]
    w = d.get("weather")
    return DaylightSettings(
        method=d["method"], median_diffuse_lx=None if d.get("median_diffuse_lx") is None else float(d["median_diffuse_lx"]),
        weather=None if w is None else (directory / w).resolve(), weather_display=w,
        reference_plane_m=float(d["reference_plane_m"]), grid_spacing_m=float(d["grid_spacing_m"]),
        wall_margin_m=float(d["wall_margin_m"]), aggregation=d["aggregation"], sky_subdivision=int(d["sky_subdivision"]),
        sun_subdivision=int(d["sun_subdivision"]), glazing_transmittance=float(d["glazing_transmittance"]),
        reflectance=tuple((k, float(v)) for k, v in d["reflectance"].items()),
        radiance=RadianceParams(ab=int(rp["ab"]), ad=int(rp["ad"]), as_=int(rp["as"]), lw=float(rp["lw"]),
                                replicates=int(rp["replicates"]), rays=int(rp["rays"]), max_rays=int(rp["max_rays"]),
                                rel_tolerance=float(rp["rel_tolerance"]), abs_tolerance_pct=float(rp["abs_tolerance_pct"]),
                                window_rays=int(rp["window_rays"]), climate_rays=int(rp["climate_rays"]),
                                stop_clear_of_thresholds=bool(rp["stop_clear_of_thresholds"])),
        grid_offset=float(d.get("grid_offset", 0.0)),
        sky_component=_sky_component_settings(d.get("sky_component", {})))


def _sky_component_settings(d: dict) -> SkyComponentSettings:
    base = SkyComponentSettings()
    return SkyComponentSettings(resolution_deg=float(d.get("resolution_deg", base.resolution_deg)),
                                refine_levels=int(d.get("refine_levels", base.refine_levels)),
                                rel_tolerance=float(d.get("rel_tolerance", base.rel_tolerance)),
                                abs_tolerance_pct=float(d.get("abs_tolerance_pct", base.abs_tolerance_pct)))


def layer_rule(r: dict) -> LayerRule:
    keys = [(k, r[k]) for k in RULE_KEYS if k in r] + [(f"attr.{k}", v) for k, v in r.get("attributes", {}).items()]
    opt = {k: float(r[k]) for k in ("reflectance", "transmittance") if k in r}
    return LayerRule(r.get("match"), r["layer"], bool(r.get("obstructs_sun", True)), tuple(keys), **opt)


def dwellings_spec(d) -> DwellingsSpec | None:
    if d is None:
        return None
    if isinstance(d, list):
        return DwellingsSpec(listed=tuple(DwellingSpec(x["name"], tuple(x["rooms"]),
                                                       tuple(x["main_rooms"]) if "main_rooms" in x else None) for x in d))
    main = tuple(d["main_rooms"]) if "main_rooms" in d else None
    return DwellingsSpec(ifc_zones=d.get("ifc_zones"), by_pattern=d.get("by_pattern"), main_rooms=main)


def transform(t: dict) -> Transform:
    x, y, z = (float(c) for c in t.get("translate_m", (0.0, 0.0, 0.0)))
    return Transform(float(t.get("rotate_deg", 0.0)), (x, y, z))


def model_file(f: dict, directory: Path) -> ModelFile:
    t = f.get("transform")
    return ModelFile(path=(directory / f["path"]).resolve(), display=f["path"], layer=f.get("layer"),
                     obstructs_sun=bool(f.get("obstructs_sun", True)), rules=tuple(layer_rule(r) for r in f.get("layers", ())),
                     units=f.get("units"), up_axis=f.get("up_axis"),
                     transform=None if t is None else transform(t),
                     crs=f.get("crs"), lod=f.get("lod", "highest"), exclude=tuple(f.get("exclude", ())),
                     exclude_overlapping=bool(f.get("exclude_overlapping", True)),
                     context_radius_m=float(f.get("context_radius_m", 1000.0)))


def model_settings(d: dict, directory: Path) -> ModelSettings:
    files = tuple(model_file(f, directory) for f in d["files"])
    north = d.get("true_north_deg")
    return ModelSettings(units=d["units"], up_axis=d["up_axis"], true_north_deg=None if north is None else float(north),
                         files=files)
