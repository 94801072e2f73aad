"""The report's pictures, checked on their pixels: projections, colours, orientation, reproducibility.

The PNG files are decoded with matplotlib (no extra image library). Cells of plan maps and the
fisheye's class raster are drawn without anti-aliasing, so their pixels carry the exact colours
of the module's tables; lines are anti-aliased, so they are found by a colour tolerance.
"""
from __future__ import annotations

import datetime as dt
import io
import math
import struct

import numpy as np
import pytest

from en17037cli.report import pictures as P
from en17037cli.report.numbers import fmt_hm
from en17037cli.report.pictures.canvas import _scale_bar_m
from en17037cli.report.pictures.colours import _layer_level, _rgb
from en17037cli.report.pictures.plan import _rot

pytest.importorskip("matplotlib")

THRESH_ANGLE = {"minimum": 14.0, "medium": 28.0, "high": 54.0}  # EN 17037 Table A.5 [deg]
THRESH_DISTANCE = {"minimum": 6.0, "medium": 20.0, "high": 50.0}  # Table A.5 [m]
THRESH_HOURS = {"minimum": 1.5, "medium": 3.0, "high": 4.0}  # Table A.6 [h]


def decode(png: bytes) -> np.ndarray:
    """(h, w, 3) uint8 pixels of a PNG."""
    import matplotlib.image

    return np.round(matplotlib.image.imread(io.BytesIO(png))[..., :3] * 255).astype(np.uint8)


def rgb8(hex_colour: str) -> np.ndarray:
    return np.round(_rgb([hex_colour])[0] * 255).astype(np.uint8)


def png_chunks(png: bytes) -> list[tuple[bytes, bytes]]:
    """(type, data) of each chunk of a PNG file."""
    out, i = [], 8
    while i < len(png):
        (n,) = struct.unpack(">I", png[i:i + 4])
        out.append((png[i + 4:i + 8], png[i + 8:i + 8 + n]))
        i += 12 + n
    return out


def rotate(p, angle_deg, about=(0.0, 0.0), shift=(0.0, 0.0)):
    """Points (k, 2) rotated counter-clockwise about ``about`` and then shifted [m]."""
    return (np.asarray(p, dtype=float) - about) @ _rot(angle_deg).T + np.asarray(about) + np.asarray(shift)


# ------------------------------------------------------------------------------------------------
# A 6 m x 4 m room with its window on the long wall at y = 4 and a 0.5 m viewpoint grid
# ------------------------------------------------------------------------------------------------

FLOOR = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 4.0], [0.0, 4.0]])
UTILISED = np.array([[0.5, 0.5], [5.5, 0.5], [5.5, 3.5], [0.5, 3.5]])
WINDOWS = [np.array([[1.5, 4.0], [4.5, 4.0]])]
_gx, _gy = np.meshgrid(np.arange(0.75, 5.26, 0.5), np.arange(0.75, 3.26, 0.5))
POINTS = np.column_stack([_gx.ravel(), _gy.ravel()])  # 10 x 6 cells inside the utilised area


def room_kwargs(**kw):
    base = {"floor": FLOOR, "utilised": UTILISED, "windows": WINDOWS, "true_north_deg": 15.0, "spacing_m": 0.5}
    return base | kw


def plan_region(img: np.ndarray) -> np.ndarray:
    """The part of a plan map that holds the plan (left of the colour bar and legends)."""
    x0, _, w, _ = P.PLAN_BOX_PX
    return img[:, : x0 + w]


def count_colour(img: np.ndarray, hex_colour: str) -> int:
    return int(np.all(img == rgb8(hex_colour), axis=-1).sum())


# ------------------------------------------------------------------------------------------------
# fmt_duration
# ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("hours, text", [
    (5.8594, "5 h 52 min"),  # 351.56 min
    (0.3, "18 min"),
    (1.5, "1 h 30 min"),
    (0.0, "0 min"),
    (4.0, "4 h"),
    (59.99 / 60, "1 h"),  # 59.99 min rounds to the hour
    (0.5 / 60, "1 min"),  # half a minute rounds up (not to even)
    (0.49 / 60, "0 min"),
    (float("nan"), "n/a"),
])
def test_fmt_duration(hours, text):
    assert P.fmt_duration(hours) == text


# ------------------------------------------------------------------------------------------------
# Reproducibility
# ------------------------------------------------------------------------------------------------

def _fisheye_args(view_azimuth_deg=180.0, n=128, paths=None):
    return (window_raster(n, view_azimuth_deg),), {"sun_paths": sun_paths_52n() if paths is None else paths,
                                                   "min_altitude_deg": 11.0, "view_azimuth_deg": view_azimuth_deg, "title": "W1"}


def _calls():
    dates = [dt.date(2026, 2, 1) + dt.timedelta(days=i) for i in range(49)]
    hours = 2.0 + 2.0 * np.sin(np.arange(49) / 9.0)
    fa, fk = _fisheye_args()
    return {
        "plan_sight_angle": (P.plan_map, (POINTS, 10 + 8 * POINTS[:, 1]), room_kwargs(kind="sight_angle", thresholds=THRESH_ANGLE,
                                                                                      near=np.arange(60) % 7 == 0, title="R1")),
        "plan_distance": (P.plan_map, (POINTS, np.where(POINTS[:, 0] > 4, np.inf, 3 * POINTS[:, 1])),
                          room_kwargs(kind="distance", thresholds=THRESH_DISTANCE)),
        "plan_level": (P.plan_map, (POINTS, np.arange(60) % 4), room_kwargs(kind="level", thresholds=None)),
        "plan_layers": (P.plan_map, (POINTS, np.arange(60) % 8), room_kwargs(kind="layers", thresholds=None)),
        "fisheye": (P.fisheye, fa, fk),
        "hours_chart": (P.hours_chart, (dates, hours), {"thresholds": THRESH_HOURS, "assessed_index": 20,
                                                        "per_window": {"W1": hours / 2}, "title": "R1"}),
        "tornado": (P.tornado, ([("grid spacing", 1.8, 2.1, 2.0), ("wall margin", 1.2, 2.6, 2.0)],), {"title": "T"}),
        "glare_positions": (P.positions_map, (FLOOR, WINDOWS, np.array([[1.0, 1.0], [3.0, 2.0]]), np.array([[0.0, 1.0], [0.6, 0.8]]),
                                              [0, 3], ["1", "2"]), {"true_north_deg": 15.0}),
        "glare_hours": (P.dgp_carpet, (np.arange("2026-01-05T08:00", "2026-01-20T08:00", 60, dtype="datetime64[m]"),
                                       0.3 + 0.1 * np.sin(np.arange(360) / 9.0)), {"limits": {"minimum": 0.45, "medium": 0.4, "high": 0.35}}),
        "glare_luminance": (P.luminance_fisheye, (np.geomspace(10.0, 1e6, 64 * 64).reshape(64, 64),), {}),
    }


@pytest.mark.parametrize("name", ["plan_sight_angle", "plan_distance", "plan_level", "plan_layers", "fisheye", "hours_chart", "tornado",
                                  "glare_positions", "glare_hours", "glare_luminance"])
def test_same_inputs_give_the_same_bytes(name):
    f, args, kwargs = _calls()[name]
    a, b = f(*args, **kwargs), f(*args, **kwargs)
    assert a[:8] == b"\x89PNG\r\n\x1a\n"
    assert a == b
    kinds = [k for k, _ in png_chunks(a)]
    assert b"tIME" not in kinds  # no timestamp
    assert not any(b"Software" in d for k, d in png_chunks(a) if k in (b"tEXt", b"iTXt", b"zTXt"))  # no version string


def test_sizes_are_fixed():
    sizes = {name: decode(f(*a, **k)).shape[:2] for name, (f, a, k) in _calls().items()}
    assert sizes["plan_level"] == (360, 500)  # one PNG pixel per layout pixel: P.PLAN_SIZE_IN x 100
    assert sizes["fisheye"] == (360, 500)
    assert sizes["hours_chart"] == (320, 500)
    assert sizes["tornado"] == (400, 500)
    assert sizes["glare_positions"] == (360, 500) and sizes["glare_hours"] == (320, 500) and sizes["glare_luminance"] == (360, 420)
    many = [(f"choice {i}", 1.0, 2.0 + i / 20, 1.5) for i in range(14)]
    assert decode(P.tornado(many)).shape[:2] == (520, 500)  # 0.3 in more per row beyond 10


def test_a_users_style_does_not_leak_in():
    import matplotlib

    f, args, kwargs = _calls()["plan_sight_angle"]
    ref = f(*args, **kwargs)
    with matplotlib.rc_context({"font.size": 20, "lines.linewidth": 7, "image.cmap": "jet"}):
        assert f(*args, **kwargs) == ref


# ------------------------------------------------------------------------------------------------
# Fisheye projection
# ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("view", [0.0, 137.0, 180.0, 300.0])
def test_fisheye_xy_landmarks(view):
    xy = lambda a, h: np.array(P.fisheye_xy(a, h, view), dtype=float)
    assert np.allclose(xy(view, 0.0), [0.0, 0.0], atol=1e-12)  # optical axis
    assert np.allclose(xy(view + 90.0, 0.0), [1.0, 0.0], atol=1e-12)  # 90 deg to the right: the rim
    assert np.allclose(xy(view - 90.0, 0.0), [-1.0, 0.0], atol=1e-12)
    assert np.allclose(xy(view + 33.0, 90.0), [0.0, 1.0], atol=1e-12)  # zenith, whatever the azimuth
    assert np.allclose(xy(view, 45.0), [0.0, 0.5], atol=1e-12)  # equidistant: 45 deg off axis at radius 0.5
    assert np.allclose(xy(view - 45.0, 0.0), [-0.5, 0.0], atol=1e-12)
    assert np.hypot(*xy(view + 180.0, 0.0)) == pytest.approx(2.0)  # straight behind: outside the field, not at the centre
    # 45 deg off axis in an oblique plane: cos 45 = cos h cos(dA), radius 0.5 along (sin dA cos h, sin h)
    h = 30.0
    da = math.degrees(math.acos(math.cos(math.radians(45.0)) / math.cos(math.radians(h))))
    x, y = xy(view + da, h)
    assert math.hypot(x, y) == pytest.approx(0.5, abs=1e-12)
    assert math.atan2(y, x) == pytest.approx(math.atan2(math.sin(math.radians(h)),
                                                        math.sin(math.radians(da)) * math.cos(math.radians(h))), abs=1e-12)


@pytest.mark.parametrize("view, tn", [(180.0, 0.0), (35.0, 0.0), (250.0, -20.0), (0.0, 123.0)])
def test_fisheye_directions_invert_fisheye_xy(view, tn):
    from en17037cli.criteria.sunlight.solar_position import direction_vectors

    n = 64
    dirs, inside = P.fisheye_directions(n, view, tn)
    assert dirs.shape == (n, n, 3) and inside.shape == (n, n)
    assert np.allclose(np.linalg.norm(dirs, axis=-1), 1.0, atol=1e-12)
    # back to azimuth (clockwise from true north) and altitude by the project's convention
    az = np.degrees(np.arctan2(dirs[..., 0], dirs[..., 1])) - tn
    alt = np.degrees(np.arcsin(np.clip(dirs[..., 2], -1, 1)))
    assert np.allclose(direction_vectors(alt[inside], az[inside], tn), dirs[inside], atol=1e-12)
    x, y = P.fisheye_xy(az, alt, view)
    px, py = P.fisheye_pixel_xy(n)
    # the round trip is exact to rounding; the brief's bound is 1/n (one pixel)
    err = np.hypot(x - px, y - py)[inside]
    assert err.max() < 1e-9 < 1.0 / n
    assert inside.sum() == pytest.approx(math.pi / 4 * n * n, rel=0.02)
    # row 0 is the top: the first row looks up, the last down; column 0 to the left
    assert dirs[0, n // 2, 2] > 0.99 and dirs[-1, n // 2, 2] < -0.99
    left = P.fisheye_xy(az[n // 2, 0], alt[n // 2, 0], view)[0]
    assert left < -0.95


def test_fisheye_pixel_is_the_drawn_circle():
    c, r = P.FISHEYE_CENTRE_PX, P.FISHEYE_RADIUS_PX
    row, col = P.fisheye_pixel(np.array([0.0, 1.0, -1.0]), np.array([0.0, 0.0, 1.0]))
    assert (row[0], col[0]) == (c[1], c[0])
    assert (row[1], col[1]) == (c[1], c[0] + r)
    assert (row[2], col[2]) == (c[1] - r, c[0] - r)


# ------------------------------------------------------------------------------------------------
# Fisheye picture
# ------------------------------------------------------------------------------------------------

#: The box room's window seen from P: the glazing plane 2 m ahead, the opening 2 m wide and from
#: 0.4 m below to 1.1 m above the eye [m]; through it sky above 4 deg, landscape within +-4 deg, ground
#: below (a flat world beyond a distant horizon band); elsewhere the room (blocked).
WINDOW_AHEAD_M, WINDOW_HALF_W_M, WINDOW_BOTTOM_M, WINDOW_TOP_M = 2.0, 1.0, -0.4, 1.1
LANDSCAPE_BAND_DEG = 4.0


def window_raster(n: int, view_azimuth_deg: float, true_north_deg: float = 0.0) -> np.ndarray:
    """The class raster a caller would trace for the box room's window (see above)."""
    dirs, inside = P.fisheye_directions(n, view_azimuth_deg, true_north_deg)
    az = np.degrees(np.arctan2(dirs[..., 0], dirs[..., 1])) - true_north_deg
    h = np.radians(np.degrees(np.arcsin(np.clip(dirs[..., 2], -1, 1))))
    d = np.radians(az - view_azimuth_deg)
    fwd, right, up = np.cos(h) * np.cos(d), np.cos(h) * np.sin(d), np.sin(h)
    with np.errstate(divide="ignore", invalid="ignore"):
        u, v = WINDOW_AHEAD_M * right / fwd, WINDOW_AHEAD_M * up / fwd
    through = (fwd > 0) & (np.abs(u) <= WINDOW_HALF_W_M) & (v >= WINDOW_BOTTOM_M) & (v <= WINDOW_TOP_M)
    alt = np.degrees(h)
    img = np.full((n, n), P.BLOCKED, dtype=np.int8)
    img[through & (alt > LANDSCAPE_BAND_DEG)] = P.CLASS_SKY
    img[through & (np.abs(alt) <= LANDSCAPE_BAND_DEG)] = P.CLASS_LANDSCAPE
    img[through & (alt < -LANDSCAPE_BAND_DEG)] = P.CLASS_GROUND
    img[~inside] = P.OUTSIDE
    return img


def sun_path(lat_deg: float, decl_deg: float, label: str, visible=None) -> dict:
    """A day's sun path by declination and hour angle (every 2 min), with hour marks 7:00-17:00 solar time.

    The paths only need the right shape here (where the sun is in the sky), not SPA's precision.
    """
    hour_angle = np.radians(np.arange(-180.0, 180.0, 0.5))
    phi, d = math.radians(lat_deg), math.radians(decl_deg)

    def pos(H):
        alt = np.degrees(np.arcsin(np.sin(phi) * np.sin(d) + np.cos(phi) * np.cos(d) * np.cos(H)))
        az = np.degrees(np.arctan2(np.sin(H), np.cos(H) * np.sin(phi) - np.tan(d) * np.cos(phi))) + 180.0
        return az, alt

    az, alt = pos(hour_angle)
    marks = [(*(float(v) for v in pos(np.radians(15.0 * (hh - 12)))), f"{hh}:00") for hh in range(7, 18)]
    vis = np.ones_like(alt, dtype=bool) if visible is None else visible(az, alt)
    return {"label": label, "azimuth_deg": az, "altitude_deg": alt, "visible": vis, "hour_marks": marks}


def declination_deg(day_of_year: int) -> float:
    """Cooper (1969): 23.45 sin(360 (284 + n) / 365) [deg]."""
    return 23.45 * math.sin(math.radians(360.0 * (284 + day_of_year) / 365.0))


def sun_paths_52n(visible=None) -> list[dict]:
    """1 February, 1 March and 21 March at 52 deg N (the period of EN 17037 clause 5.3)."""
    return [sun_path(52.0, declination_deg(doy), label, visible) for doy, label in ((32, "1 Feb"), (60, "1 Mar"), (80, "21 Mar"))]


def path_pixels(img: np.ndarray, within: float = 1.0) -> int:
    """Pixels of the sun-path colour (anti-aliased cores: each channel within 40 of it) inside
    ``within`` times the circle's radius."""
    core = np.all(np.abs(img.astype(int) - rgb8(P.SUN_PATH_COLOUR).astype(int)) <= 40, axis=-1)
    rows, cols = np.indices(img.shape[:2])
    c = P.FISHEYE_CENTRE_PX
    r = np.hypot(cols + 0.5 - c[0], rows + 0.5 - c[1]) / P.FISHEYE_RADIUS_PX
    return int((core & (r <= within)).sum())


def test_path_colour_differs_from_every_class_colour():
    for colour in P.CLASS_COLOURS.values():
        assert np.abs(rgb8(colour).astype(int) - rgb8(P.SUN_PATH_COLOUR).astype(int)).max() > 40


def test_fisheye_draws_the_class_raster_in_place():
    view = 200.0
    png = P.fisheye(window_raster(256, view), sun_paths=[], min_altitude_deg=11.0, view_azimuth_deg=view)
    img = decode(png)
    # straight ahead, halfway between the 11 deg curve (drawn over the raster) and the opening's top: sky
    top_alt = math.degrees(math.atan2(WINDOW_TOP_M, WINDOW_AHEAD_M))
    r, c = P.fisheye_pixel(*P.fisheye_xy(view, 0.5 * (11.0 + top_alt), view))
    assert tuple(img[r, c]) == tuple(rgb8(P.CLASS_COLOURS[P.CLASS_SKY]))
    # the ground seen through the bottom of the opening, 10 deg down
    r, c = P.fisheye_pixel(*P.fisheye_xy(view, -10.0, view))
    assert tuple(img[r, c]) == tuple(rgb8(P.CLASS_COLOURS[P.CLASS_GROUND]))
    # far from the window: the room, 80 deg down and 60 deg up to the side
    for a, h in ((view, -80.0), (view - 70.0, 60.0)):
        r, c = P.fisheye_pixel(*P.fisheye_xy(a, h, view))
        assert tuple(img[r, c]) == tuple(rgb8(P.CLASS_COLOURS[P.BLOCKED]))
    # outside the circle the background, even where a raster says otherwise
    png = P.fisheye(np.full((64, 64), P.CLASS_SKY, dtype=np.int8), sun_paths=[], min_altitude_deg=11.0, view_azimuth_deg=view)
    r, c = P.fisheye_pixel(0.9, -0.9)
    assert tuple(decode(png)[r, c]) == (255, 255, 255)


def test_no_sun_path_in_a_north_facing_view_at_52n():
    """From 1 February to 21 March at 52 N the sun stays in the southern half of the sky, behind a
    north-facing window's 180 deg field. On 21 March it rises about half a degree north of east
    at an altitude below half a degree, so its path may touch the rim: pixels within 3 % of the
    radius from the rim are not counted."""
    paths = sun_paths_52n()
    north = decode(P.fisheye(window_raster(128, 0.0), sun_paths=paths, min_altitude_deg=11.0, view_azimuth_deg=0.0))
    assert path_pixels(north, within=0.97) == 0
    south = decode(P.fisheye(window_raster(128, 180.0), sun_paths=paths, min_altitude_deg=11.0, view_azimuth_deg=180.0))
    assert path_pixels(south, within=0.97) > 300  # the same paths do show in a south-facing view


def test_seen_path_parts_are_thicker_than_hidden_ones():
    seen = sun_paths_52n(lambda az, alt: np.ones_like(alt, dtype=bool))
    hidden = sun_paths_52n(lambda az, alt: np.zeros_like(alt, dtype=bool))
    kw = {"min_altitude_deg": 11.0, "view_azimuth_deg": 180.0}
    n_seen = path_pixels(decode(P.fisheye(window_raster(128, 180.0), sun_paths=seen, **kw)))
    n_hidden = path_pixels(decode(P.fisheye(window_raster(128, 180.0), sun_paths=hidden, **kw)))
    assert n_seen > 2 * n_hidden > 0  # 2.2 pt solid against 0.9 pt dashed


# ------------------------------------------------------------------------------------------------
# Colours that read in grey
# ------------------------------------------------------------------------------------------------

def test_luminance_reference_values():
    assert P.relative_luminance(["#000000", "#ffffff", "#00ff00", "#ff0000", "#0000ff"]) == pytest.approx(
        [0.0, 1.0, 0.7152, 0.2126, 0.0722], abs=1e-12)  # Rec. 709 coefficients
    assert P.lightness(["#777777"]) == pytest.approx([50.0], abs=0.1)  # sRGB 119 is mid-grey L* 50


def _assert_steps(colours, min_step_lstar, what):
    y = P.relative_luminance(colours)
    lstar = P.lightness(colours)
    assert np.all(np.diff(y) > 0), f"{what}: luminance not increasing: {y}"
    assert np.diff(lstar).min() >= min_step_lstar, f"{what}: L* steps {np.diff(lstar)}"


def test_level_colours_step_up_in_grey():
    # none darkest ... high lightest; 4 levels over viridis' L* 15..91 give steps of about 25
    _assert_steps(P.LEVEL_COLOURS, 20.0, "levels")


def test_layer_colours_step_up_in_grey_in_the_order_of_their_levels():
    # 8 combinations over the same range: steps of about 10.5 L*, 8 keeps them apart in print
    _assert_steps(P.LAYER_COLOURS, 8.0, "layers")
    levels = [P.LEVEL_NAMES.index(_layer_level(c)) for c in P.LAYER_ORDER]
    assert levels == sorted(levels)
    assert sorted(P.LAYER_ORDER) == list(range(8))


def test_fisheye_classes_step_up_in_grey():
    order = [P.CLASS_COLOURS[k] for k in (P.BLOCKED, P.CLASS_GROUND, P.CLASS_LANDSCAPE, P.CLASS_SKY)]
    _assert_steps(order, 10.0, "fisheye classes")


@pytest.mark.parametrize("kind, thresholds, low", [("sight_angle", THRESH_ANGLE, 0.0), ("distance", THRESH_DISTANCE, 1.0)])
def test_continuous_maps_step_up_at_the_thresholds(kind, thresholds, low):
    import matplotlib

    cmap = matplotlib.colormaps[P.CMAP[kind]]
    assert np.all(np.diff(P.relative_luminance(cmap(np.linspace(0, 1, 256)))) > 0)  # monotone everywhere
    values = np.array([low, thresholds["minimum"], thresholds["medium"], thresholds["high"]])
    rgba = P.continuous_colours(kind, values, thresholds)
    # the default scales (sight angle 0..1.25 high, distance 1..2 high on a log axis) put the
    # thresholds at least 15 L* apart; 10 leaves room for a map whose values widen the scale
    _assert_steps(rgba, 10.0, kind)
    # +inf (unobstructed) is the top colour, NaN is not coloured
    top = P.continuous_colours("distance", [np.inf, 1e6], THRESH_DISTANCE, all_values=[1.0, 50.0])
    assert np.array_equal(top[0], top[1])
    assert np.isnan(P.continuous_colours(kind, [np.nan], thresholds)).all()


# ------------------------------------------------------------------------------------------------
# Plan maps
# ------------------------------------------------------------------------------------------------

def test_plan_rotation_of_a_rotated_room():
    about = np.array([3.0, 2.0])
    floor = rotate(FLOOR, 30.0, about)
    top_wall = rotate([[1.5, 4.0], [4.5, 4.0]], 30.0, about)
    bottom_wall = rotate([[1.5, 0.0], [4.5, 0.0]], 30.0, about)
    right_wall = rotate([[6.0, 1.0], [6.0, 3.0]], 30.0, about)
    left_wall = rotate([[0.0, 1.0], [0.0, 3.0]], 30.0, about)
    assert P.plan_rotation(floor, [top_wall]) == pytest.approx(-30.0, abs=1e-9)
    assert P.plan_rotation(floor, [bottom_wall]) == pytest.approx(150.0, abs=1e-9)
    assert P.plan_rotation(floor, [right_wall]) == pytest.approx(60.0, abs=1e-9)  # window wall on top beats long side horizontal
    assert P.plan_rotation(floor, [left_wall]) == pytest.approx(-120.0, abs=1e-9)
    assert P.plan_rotation(floor, [top_wall, bottom_wall, top_wall]) == pytest.approx(-30.0, abs=1e-9)  # the windows' mean
    # no window, or windows balanced about the centre: the long side horizontal
    for wins in ([], [top_wall, bottom_wall]):
        assert math.fmod(P.plan_rotation(floor, wins) + 30.0 + 360.0, 180.0) == pytest.approx(0.0, abs=1e-9)


def test_plan_is_drawn_in_the_rooms_own_orientation():
    """The same room turned by 30 deg and moved in the model, its north turned with it, gives the
    same picture, byte for byte: the plan depends on the room, not on the model's axes."""
    about, shift = np.array([3.0, 2.0]), np.array([10.0, -5.0])
    values = np.arange(60) % 4
    assert P.plan_rotation(FLOOR, WINDOWS) == 0.0
    ref = P.plan_map(POINTS, values, kind="level", thresholds=None, **room_kwargs())
    turned = P.plan_map(rotate(POINTS, 30.0, about, shift), values, kind="level", thresholds=None,
                        **room_kwargs(floor=rotate(FLOOR, 30.0, about, shift), utilised=rotate(UTILISED, 30.0, about, shift),
                                      windows=[rotate(w, 30.0, about, shift) for w in WINDOWS], true_north_deg=15.0 - 30.0))
    assert turned == ref
    # north matters: the same room with north elsewhere is another picture
    assert P.plan_map(POINTS, values, kind="level", thresholds=None, **room_kwargs(true_north_deg=45.0)) != ref
    # the window is at the top, the long side horizontal
    img = plan_region(decode(ref))
    window_rows = np.flatnonzero(np.all(img == rgb8(P.WINDOW_COLOUR), axis=-1).any(axis=1))
    cells = np.zeros(img.shape[:2], bool)
    for c in P.LEVEL_COLOURS:
        cells |= np.all(img == rgb8(c), axis=-1)
    rows, cols = np.nonzero(cells)
    assert window_rows.max() < rows.min()
    assert (cols.max() - cols.min()) / (rows.max() - rows.min()) == pytest.approx(5.0 / 3.0, rel=0.03)  # 10 x 6 cells


def test_plan_level_cells_have_the_level_colours_in_proportion():
    # columns of the grid by x: 3 columns of level 0, 2 of level 1, 3 of level 2, 2 of level 3
    col = np.round((POINTS[:, 0] - 0.75) / 0.5).astype(int)
    level = np.select([col < 3, col < 5, col < 8], [0, 1, 2], 3)
    img = plan_region(decode(P.plan_map(POINTS, level, kind="level", thresholds=None, **room_kwargs())))
    counts = np.array([count_colour(img, c) for c in P.LEVEL_COLOURS], dtype=float)
    cells = np.bincount(level, minlength=4).astype(float)
    # exact colours (cells are not anti-aliased); the outline, windows and rings cover a few per cent
    assert np.allclose(counts / counts.sum(), cells / cells.sum(), atol=0.03)


def test_plan_layer_cells_take_their_combinations_colour():
    img = plan_region(decode(P.plan_map(POINTS, np.full(60, P.LANDSCAPE), kind="layers", thresholds=None, **room_kwargs())))
    own = P.LAYER_COLOURS[P.LAYER_ORDER.index(P.LANDSCAPE)]
    assert count_colour(img, own) > 0.9 * 60 * (0.5 * P.PLAN_BOX_PX[2] / 6.0) ** 2 * 0.9  # 60 cells of about 18 px square
    assert all(count_colour(img, c) == 0 for c in P.LAYER_COLOURS if c != own)


def test_plan_continuous_cells_match_continuous_colours():
    values = np.full(60, THRESH_ANGLE["medium"])
    values[0] = 60.0  # sets the top of the scale with 1.25 x 54 = 67.5
    img = plan_region(decode(P.plan_map(POINTS, values, kind="sight_angle", thresholds=THRESH_ANGLE, **room_kwargs())))
    rgba = P.continuous_colours("sight_angle", [THRESH_ANGLE["medium"]], THRESH_ANGLE, all_values=values)[0]
    colour = np.round(rgba[:3] * 255).astype(np.uint8)
    side = 0.5 * P.PLAN_BOX_PX[2] / 6.0 - 3  # a cell's side [px] less its anti-aliased rim
    assert int(np.all(img == colour, axis=-1).sum()) > 50 * side * side


def test_plan_marks_points_near_a_threshold():
    kw = room_kwargs(kind="sight_angle", thresholds=THRESH_ANGLE)
    values = 10 + 8 * POINTS[:, 1]
    plain = P.plan_map(POINTS, values, **kw)
    assert P.plan_map(POINTS, values, near=np.zeros(60, bool), **kw) == plain
    marked = decode(P.plan_map(POINTS, values, near=np.abs(values - 28.0) < 2.5, **kw))
    assert np.any(marked != decode(plain))


def test_plan_map_rejects_bad_input():
    with pytest.raises(ValueError, match="kind must be one of"):
        P.plan_map(POINTS, np.zeros(60), kind="daylight", thresholds=None, **room_kwargs())
    with pytest.raises(ValueError, match=r"values must have shape \(60,\)"):
        P.plan_map(POINTS, np.zeros(59), kind="level", thresholds=None, **room_kwargs())
    with pytest.raises(ValueError, match="needs thresholds"):
        P.plan_map(POINTS, np.zeros(60), kind="distance", thresholds=None, **room_kwargs())


def test_plan_map_without_spacing_utilised_or_windows():
    # the cell side from the nearest neighbours (0.5 m), no utilised outline, no window, NaN cells
    values = np.where(np.arange(60) % 9 == 0, np.nan, 3.0)
    png = P.plan_map(POINTS, values, kind="level", thresholds=None, floor=FLOOR, utilised=None, windows=[], true_north_deg=0.0)
    img = plan_region(decode(png))
    assert count_colour(img, P.LEVEL_COLOURS[3]) > 0.8 * 53 * (0.5 * P.PLAN_BOX_PX[2] / 6.0) ** 2


def test_scale_bar_lengths():
    assert [_scale_bar_m(w) for w in (3.0, 6.0, 10.0, 20.0, 40.0, 100.0)] == [0.5, 1.0, 2.0, 5.0, 10.0, 20.0]


# ------------------------------------------------------------------------------------------------
# Charts
# ------------------------------------------------------------------------------------------------

def test_hours_chart_highlights_the_assessed_day():
    dates = [dt.date(2026, 2, 1) + dt.timedelta(days=i) for i in range(49)]
    hours = np.full(49, 3.5)
    img = decode(P.hours_chart(dates, hours, thresholds=THRESH_HOURS, assessed_index=10))
    assert count_colour(img, P.ASSESSED_COLOUR) > 20
    bars = count_colour(img, P.BAR_COLOUR)
    none = decode(P.hours_chart(dates, hours, thresholds=THRESH_HOURS, assessed_index=-1))
    assert count_colour(none, P.ASSESSED_COLOUR) == 0
    assert count_colour(none, P.BAR_COLOUR) > bars
    with pytest.raises(ValueError, match=r"hours must have shape \(49,\)"):
        P.hours_chart(dates, hours[:-1], thresholds=THRESH_HOURS, assessed_index=0)


def test_hour_ticks():
    assert [fmt_hm(v) for v in (0.0, 1.5, 3.0, 4.25, 5.8594)] == ["0:00", "1:30", "3:00", "4:15", "5:52"]


def test_module_imports_without_matplotlib():
    import subprocess
    import sys

    code = ("import sys; sys.modules['matplotlib'] = None\n"  # any matplotlib import now fails
            "from en17037cli.report import pictures\n"
            "print(pictures.fmt_duration(1.5), pictures.lightness(pictures.LEVEL_COLOURS).round().tolist())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "1 h 30 min [15.0, 42.0, 67.0, 91.0]"


def test_package_does_not_import_matplotlib():
    import subprocess
    import sys

    code = ("import sys\n"
            "import en17037cli.report.pictures\n"
            "import en17037cli.report.pictures.canvas, en17037cli.report.pictures.charts, en17037cli.report.pictures.colours\n"
            "import en17037cli.report.pictures.fisheye, en17037cli.report.pictures.plan\n"
            "print(sorted(m for m in sys.modules if m == 'matplotlib' or m.startswith('matplotlib.')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_package_exports_every_public_name_of_the_former_plots_module():
    from en17037cli.report import numbers

    expected = {
        "plan_map", "plan_rotation", "fisheye", "fisheye_xy", "fisheye_pixel_xy", "fisheye_directions", "fisheye_pixel",
        "hours_chart", "tornado", "positions_map", "dgp_carpet", "luminance_fisheye", "relative_luminance", "lightness", "continuous_colours", "layer_label", "fmt_duration",
        "DPI", "PLAN_SIZE_IN", "FISHEYE_SIZE_IN", "CHART_SIZE_IN", "PLAN_BOX_PX", "COLOUR_BAR_PX", "FISHEYE_CENTRE_PX",
        "FISHEYE_RADIUS_PX", "LEVEL_COLOURS", "LEVEL_NAMES", "SKY", "LANDSCAPE", "GROUND", "LAYER_ORDER", "LAYER_COLOURS",
        "OUTSIDE", "BLOCKED", "CLASS_SKY", "CLASS_LANDSCAPE", "CLASS_GROUND", "CLASS_NAMES", "CLASS_COLOURS", "WINDOW_COLOUR",
        "SUN_PATH_COLOUR", "BAR_COLOUR", "ASSESSED_COLOUR", "CMAP", "DISTANCE_VMIN_M",
    }
    assert len(P.__all__) == len(expected) and set(P.__all__) == expected
    assert all(hasattr(P, name) for name in expected)
    assert P.fmt_duration is numbers.fmt_duration


@pytest.mark.parametrize("n", [0, 1])
def test_plan_map_of_no_or_one_viewpoint(n):
    png = P.plan_map(POINTS[:n], np.full(n, 30.0), kind="sight_angle", thresholds=THRESH_ANGLE, floor=FLOOR, utilised=UTILISED,
                     windows=WINDOWS, true_north_deg=0.0)
    assert decode(png).shape == (360, 500, 3)


def test_painters_deal_jobs_to_several_workers_and_keep_their_order(tmp_path):
    """Many pictures fork extra drawing processes; every figure comes back in the jobs' order and
    byte-identical to drawing it here (what a building's report relies on)."""
    from en17037cli.pipeline import run
    from en17037cli.project import load_project
    from en17037cli.report.figures import JOBS_PER_EXTRA_WORKER, Painters, draw, figure_jobs
    from en17037cli.samples import BoxRoom, box_room_project

    path = box_room_project(tmp_path / "p", BoxRoom(), sunlight={"date": "worst"}, view={"grid_spacing_m": 1.0})
    jobs = figure_jobs(run(load_project(path, []), pictures=True))
    assert len(jobs) >= 3
    many = (jobs * (2 * JOBS_PER_EXTRA_WORKER // len(jobs) + 1))[: 2 * JOBS_PER_EXTRA_WORKER + 1]
    here = [draw(j) for j in many]
    pool = Painters(3)
    try:
        got = pool.draw(many)
        assert len(pool._workers) == 3  # 1 + (33 // 16) = 3 workers, capped at 3
    finally:
        pool.close()
    assert [f.name for f in got] == [j.name for j in many]
    assert all(a == b for a, b in zip(got, here, strict=True))


def test_an_error_bound_rounded_to_zero_is_not_printed_as_zero():
    """The plan sight angle's bound (about 1e-11 deg) rounds to 0 at the JSON's 6 decimals: the
    reports print it as under half the last decimal, not as 'no error'."""
    from en17037cli.report.numbers import fmt_bound

    assert fmt_bound(0.0) == "< 5e-07"
    assert fmt_bound(0.005467) == "≤ 0.005467"
    assert fmt_bound(0.0, nd=4) == "< 5e-05"
    assert fmt_bound(None) == "n/a"


def _svg_texts(svg) -> list[tuple[str, float, float, str]]:
    """(text, x, y, anchor) of every <text> of an SVG picture (fonts kept as text), x and y in points
    of the printed picture (its width in pt over its viewBox's width)."""
    import re

    s = svg.decode() if isinstance(svg, bytes) else svg
    head = re.search(r"<svg[^>]*>", s)[0]
    k = float(re.search(r'width="([\d.]+)pt"', head)[1]) / float(re.search(r'viewBox="[-\d.]+ [-\d.]+ ([\d.]+)', head)[1])
    out = []
    for m in re.finditer(r'<text style="([^"]*)" (?:x="([-\d.]+)" y="([-\d.]+)"|transform="translate\(([-\d.]+) ([-\d.]+)\)")'
                         r'[^>]*>([^<]*)</text>', s):  # one line at x, y; a line of several at translate(x y)
        anchor = re.search(r"text-anchor: (\w+)", m[1])
        x, y = (m[2], m[3]) if m[2] is not None else (m[4], m[5])
        out.append((m[6], k * float(x), k * float(y), anchor[1] if anchor else "start"))
    return out


def test_fisheye_path_labels_at_the_rim_stay_in_the_picture_and_apart():
    """A window facing west sees the February and March paths top out at the left rim (south): their
    labels were centred there, half over the picture's edge, one on the other (SampleHouse4's
    living room). Labelled inwards, the second under the first."""
    path = lambda label, top: {"label": label, "azimuth_deg": np.linspace(182, 240, 30), "altitude_deg": np.linspace(top, 2, 30),
                               "visible": np.ones(30, bool), "hour_marks": []}
    svg = P.fisheye(np.full((64, 64), P.CLASS_SKY, dtype=np.int8), sun_paths=[path("21 Mar (last day)", 35),
                    path("1 Feb (first day, assessed)", 30)], min_altitude_deg=11.0, view_azimuth_deg=270.0, fmt="svg")
    labels = {t: (x, y, a) for t, x, y, a in _svg_texts(svg) if "Mar" in t or "Feb" in t}
    assert len(labels) == 2
    for x, _, anchor in labels.values():
        assert anchor == "start" and x >= 0  # drawn rightwards from inside the picture
    (_, y1, _), (_, y2, _) = labels.values()
    assert abs(y1 - y2) >= 8  # one 8 pt line apart at least


def test_hours_chart_names_at_most_three_windows_shortened_in_the_middle():
    from en17037cli.report.pictures.charts import MAX_NAME_CHARS, _short

    dates = [dt.date(2026, 2, 1) + dt.timedelta(days=i) for i in range(10)]
    long = {f"M_Fixed:4835mm x 2420mm:{k}": np.full(10, 1.0 + i) for i, k in enumerate((146016, 171975))}
    texts = [t for t, *_ in _svg_texts(P.hours_chart(dates, np.full(10, 3.0), thresholds={"minimum": 1.5, "medium": 3, "high": 4},
                                                     assessed_index=0, per_window=long, fmt="svg"))]
    assert [t for t in texts if t.startswith("window ")] == [f"window {_short(n)}" for n in long]
    assert all(len(_short(n)) == MAX_NAME_CHARS and _short(n).endswith(n[-8:]) for n in long)  # the id kept
    many = {f"w{k}": np.full(10, 1.0) for k in range(4)}
    texts = [t for t, *_ in _svg_texts(P.hours_chart(dates, np.full(10, 3.0), thresholds={"minimum": 1.5, "medium": 3, "high": 4},
                                                     assessed_index=0, per_window=many, fmt="svg"))]
    assert not [t for t in texts if t.startswith("window ")]  # four windows: the table names them, not a legend


def test_hours_chart_assessed_label_stays_left_of_the_threshold_labels():
    """FZK-Haus's office, assessed 16 Feb (16th of 49 days): 'assessed 16 Feb: 2 h 42 min' on one
    line ran into 'medium 3:00' right of the axes. On two lines, each ends before the threshold
    labels begin (width bound: 0.62 em a character, DejaVu Sans's widest digits and letters)."""
    dates = [dt.date(2026, 2, 1) + dt.timedelta(days=i) for i in range(49)]
    hours = np.linspace(2.9, 3.9, 49)
    hours[15] = 2.7
    texts = _svg_texts(P.hours_chart(dates, hours, thresholds={"minimum": 1.5, "medium": 3, "high": 4}, assessed_index=15,
                                     fmt="svg"))
    medium_x = next(x for t, x, _, _ in texts if t.startswith("medium"))
    lines = [(t, x) for t, x, _, a in texts if t.startswith("assessed") or t == "2 h 42 min"]
    assert [t for t, _ in lines] == ["assessed 16 Feb:", "2 h 42 min"], texts
    assert all(x + 0.62 * 8 * len(t) < medium_x for t, x in lines)
