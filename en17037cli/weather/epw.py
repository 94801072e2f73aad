"""A small reader of EnergyPlus weather files (EPW): the site and the hourly light the daylight
criterion needs, vectorised over the year's rows.

EPW is plain CSV: 8 header lines (the first, ``LOCATION``, gives the site; the last, ``DATA
PERIODS``, the records per hour and the day of the week the data start on) and one row per hour
with 35 fields (EnergyPlus Auxiliary Programs, "Weather Converter Program", EPW data dictionary).
Only the fields used here are read: date and hour, global, direct normal and diffuse horizontal
irradiance [Wh/m²] and the global, direct normal and diffuse horizontal illuminance [lx] (missing
values: 9999 / 999999). pvlib's ``read_epw`` does the same with pandas; a reader of some 80 lines
spares the daylight extra two heavy dependencies (pandas, pvlib) for six columns.
"""
from __future__ import annotations

import csv
import datetime
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.standard import DAYLIGHT_HOURS

#: Columns of an EPW data row that are read (0-based), by name.
COLUMNS = {"year": 0, "month": 1, "day": 2, "hour": 3, "ghi_wh_m2": 13, "dni_wh_m2": 14, "dhi_wh_m2": 15,
           "global_lx": 16, "direct_normal_lx": 17, "diffuse_lx": 18}
#: EPW's "missing" markers for the irradiance (9999) and illuminance (999999) fields.
MISSING = 9999.0
#: Days of the week as EPW's DATA PERIODS line names them, Monday first (Python's ``weekday()``).
WEEKDAYS = ("Monday", "Tuesday", "Wednesday", "Thursday", "Friday", "Saturday", "Sunday")


@dataclass(frozen=True)
class Weather:
    """One EPW file: the site and one value per hour of the file (8760 rows, 8784 in a leap year).

    latitude, longitude [deg] (north, east positive); tz_hours : offset of standard time from UTC [h];
    elevation_m [m]; month, day, hour : (n,) int (hour 1..24 ends the hour); the rest (n,) float,
    irradiance [W/m²] (hourly sums [Wh/m²]) and illuminance [lx], NaN where the file says missing;
    start_weekday : the day of the week the data start on as DATA PERIODS gives it (0 Monday .. 6
    Sunday); weekday_note : why that day does not fit the data (see :func:`weekday_note`), or None
    """

    path: Path
    place: str
    latitude: float
    longitude: float
    tz_hours: float
    elevation_m: float
    month: np.ndarray
    day: np.ndarray
    hour: np.ndarray
    ghi_wh_m2: np.ndarray
    dni_wh_m2: np.ndarray
    dhi_wh_m2: np.ndarray
    global_lx: np.ndarray
    direct_normal_lx: np.ndarray
    diffuse_lx: np.ndarray
    start_weekday: int = 6
    weekday_note: str | None = None

    def daylight_hours(self) -> np.ndarray:
        """Indices of the daylight hours of EN 17037 (clause 5.1, Annex A): the half of the year's
        hours (:data:`~en17037cli.standard.DAYLIGHT_HOURS` of 8760) with the highest diffuse
        horizontal illuminance, in time order (ties: the earlier hour first)."""
        n = round(DAYLIGHT_HOURS * len(self.hour) / 8760)
        order = np.argsort(-np.nan_to_num(self.diffuse_lx, nan=-1.0), kind="stable")
        return np.sort(order[:n])

    def median_diffuse_lx(self) -> float:
        """E_v,d,med: the median diffuse horizontal illuminance over :meth:`daylight_hours` [lx]."""
        return float(np.median(self.diffuse_lx[self.daylight_hours()]))


def read_epw(path: Path, where: str = "daylight.weather") -> Weather:
    """Read an EPW file; an :class:`InputError` naming the file, line and field for a bad one."""
    try:
        text = Path(path).read_text(encoding="utf-8-sig", errors="replace")
    except OSError as exc:
        raise InputError(f"{where}: cannot read {path}: {exc.strerror}") from None
    lines = text.splitlines()
    if len(lines) < 9 or not lines[0].upper().startswith("LOCATION"):
        raise InputError(f"{where}: {path} is not an EPW weather file (its first line is not LOCATION,...); give an "
                         "EnergyPlus .epw file of the site")
    loc = next(csv.reader([lines[0]]))
    try:
        lat, lon, tz, elev = (float(loc[k]) for k in (6, 7, 8, 9))
    except (IndexError, ValueError):
        raise InputError(f"{where}: {path}:1: LOCATION needs latitude, longitude, time zone and elevation in fields 7 to 10") from None
    per_hour, weekday = data_period(lines[7], f"{where}: {path}:8")
    rows = [r for r in lines[8:] if r.strip()]
    if per_hour != 1:
        raise InputError(f"{where}: {path}:8: DATA PERIODS gives {per_hour} records per hour; give an hourly EPW file (1 record "
                         "per hour, 8760 rows)")
    if len(rows) not in (8760, 8784):
        raise InputError(f"{where}: {path}: {len(rows)} hourly rows; an EPW file has 8760 (8784 in a leap year)")
    cols = sorted(COLUMNS.values())
    try:
        data = np.loadtxt(io.StringIO("\n".join(rows)), delimiter=",", usecols=cols, dtype=float, ndmin=2)
    except ValueError as exc:
        raise InputError(f"{where}: {path}: a data row is not numbers where EPW has them ({exc})") from None
    col = {name: data[:, cols.index(i)] for name, i in COLUMNS.items()}
    for name in ("ghi_wh_m2", "dni_wh_m2", "dhi_wh_m2"):
        col[name] = np.where(col[name] >= MISSING, np.nan, col[name])
    for name in ("global_lx", "direct_normal_lx", "diffuse_lx"):
        col[name] = np.where(col[name] >= 999900.0, np.nan, col[name])
    if np.isnan(col["diffuse_lx"]).mean() > 0.01:
        raise InputError(f"{where}: {path}: the diffuse horizontal illuminance (field 19) is missing in "
                         f"{np.isnan(col['diffuse_lx']).sum()} rows; EN 17037 takes E_v,d,med from it: use a file that "
                         "has it (e.g. a TMYx file) or give daylight.median_diffuse_lx")
    return Weather(Path(path), ", ".join(x for x in loc[1:4] if x.strip()), lat, lon, tz, elev,
                   col["month"].astype(int), col["day"].astype(int), col["hour"].astype(int),
                   col["ghi_wh_m2"], col["dni_wh_m2"], col["dhi_wh_m2"], col["global_lx"], col["direct_normal_lx"],
                   col["diffuse_lx"], weekday, weekday_note(weekday, col["year"].astype(int), col["month"].astype(int),
                                                            col["day"].astype(int)))


def data_period(line: str, where: str) -> tuple[int, int]:
    """Records per hour and the start day of the week (0 Monday .. 6 Sunday) of an EPW file's
    ``DATA PERIODS`` line: ``DATA PERIODS,<periods>,<records per hour>,<name>,<start weekday>,<start
    date>,<end date>`` (EnergyPlus Auxiliary Programs, "Weather Converter Program", EPW header);
    an :class:`InputError` naming the line when it does not read."""
    f = [x.strip() for x in next(csv.reader([line]))]
    if not f or f[0].upper() != "DATA PERIODS" or len(f) < 5:
        raise InputError(f"{where}: the 8th header line is not 'DATA PERIODS,<n>,<records per hour>,<name>,<start day>,...'; "
                         "give an EnergyPlus .epw file")
    try:
        per_hour = int(f[2])
    except ValueError:
        raise InputError(f"{where}: DATA PERIODS: records per hour {f[2]!r} is not a whole number") from None
    names = [w.lower() for w in WEEKDAYS]
    if f[4].lower() not in names:
        raise InputError(f"{where}: DATA PERIODS: start day {f[4]!r} is not a day of the week (Sunday, Monday, ...)")
    return per_hour, names.index(f[4].lower())


def weekday_note(weekday: int, year: np.ndarray, month: np.ndarray, day: np.ndarray) -> str | None:
    """Why the header's start day does not fit the data, or None: when every row is of one calendar
    year (measured or synthetic weather, not a typical year stitched from months of different
    years), the first row's date falls on a weekday of its own; a header naming another day is kept
    (EnergyPlus runs the file's schedules from it) and noted. Daylight provision does not depend on
    the day of the week."""
    if not len(year) or np.any(year != year[0]) or year[0] < 1:
        return None
    try:
        actual = datetime.date(int(year[0]), int(month[0]), int(day[0])).weekday()
    except ValueError:
        return None
    if actual == weekday:
        return None
    return (f"the weather file's DATA PERIODS line says its data start on a {WEEKDAYS[weekday]}, but its first row, "
            f"{int(year[0])}-{int(month[0]):02d}-{int(day[0]):02d}, is a {WEEKDAYS[actual]}")


def wea_text(w: Weather) -> str:
    """The weather as Radiance's ``.wea`` (``epw2wea``'s format): site header, then month, day,
    decimal solar-time-free hour (the hour's middle), direct normal and diffuse horizontal
    irradiance [W/m²] per row. Missing irradiance is written 0."""
    head = (f"place {w.place.replace(' ', '_') or 'site'}\nlatitude {w.latitude:.4f}\nlongitude {-w.longitude:.4f}\n"
            f"time_zone {-15.0 * w.tz_hours:.1f}\nsite_elevation {w.elevation_m:.1f}\nweather_data_file_units 1\n")
    rows = np.column_stack([w.month, w.day, w.hour - 0.5, np.nan_to_num(w.dni_wh_m2), np.nan_to_num(w.dhi_wh_m2)])
    buf = io.StringIO()
    np.savetxt(buf, rows, fmt="%d %d %.3f %.1f %.1f")
    return head + buf.getvalue()
