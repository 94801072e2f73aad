"""The usage hours of the annual method and the moments of the point-in-time checks.

An EPW row is one hour of local *standard* time (hour k ends at k:00); its sky is taken at the
hour's middle (:func:`~en17037cli.weather.epw.wea_text`). The usage time is local *clock* time
(08:00 to 18:00 in summer is 07:00 to 17:00 standard time where clocks go forward): a row is a
usage hour when its start, moved to clock time by the site's time zone (``zoneinfo``), lies in
[start, end) on a usage day of ``glare.year`` (the EPW's own year column is not read: a typical
year mixes years). Holidays are not left out (the standard names none).
"""
from __future__ import annotations

import datetime as dt
import zoneinfo
from dataclasses import dataclass

import numpy as np

#: Seconds of an hour.
HOUR_S = 3600.0


@dataclass(frozen=True)
class UsageHours:
    """The usage hours of one weather file and year.

    rows : (h,) int, the EPW rows (0-based) of the usage hours, in time order
    unix_mid : (h,) float [s], each hour's middle (where its sky and sun are taken), UTC
    local_start : (h,) datetime64[m], each hour's start on the local clock (for the reports)
    """

    rows: np.ndarray
    unix_mid: np.ndarray
    local_start: np.ndarray

    def __len__(self) -> int:
        return len(self.rows)


def row_starts(month, day, year: int) -> tuple[np.ndarray, np.ndarray]:
    """Each EPW row's date at 00:00 as seconds since 1970 (of the local standard day), for the rows
    whose date exists in ``year`` (Feb 29 of a leap-year file in a common year does not):
    (row indices, seconds)."""
    month, day = np.asarray(month, int), np.asarray(day, int)
    first = (np.datetime64(f"{year:04d}-01", "M") + (month - 1)).astype("datetime64[D]")
    date = first + (day - 1)
    keep = (date.astype("datetime64[M]") == first.astype("datetime64[M]")) & (day >= 1)
    return np.flatnonzero(keep), date[keep].astype("datetime64[s]").astype(float)


def usage_hours(month, day, hour, tz_hours: float, timezone: str, year: int, start_h: float, end_h: float,
                days: tuple[int, ...]) -> UsageHours:
    """The usage hours of a weather file's rows (see the module docstring).

    Parameters
    ----------
    month, day, hour : (n,) int, the EPW's date and hour (1..24, ending the hour) per row
    tz_hours : the file's standard time offset from UTC [h]
    timezone : IANA name of the site's time zone (its clock, with summer time)
    year : the calendar year of the weekdays
    start_h, end_h : usage time of day on the local clock [h from midnight]
    days : weekday numbers of the usage days (Monday 0)
    """
    rows, day0 = row_starts(month, day, year)
    h = np.asarray(hour, dtype=float)[rows]
    start_unix = day0 + (h - 1.0 - tz_hours) * HOUR_S  # the row's start, UTC
    tz = zoneinfo.ZoneInfo(timezone)
    # the clock's offset from UTC at each start: one lookup per day of the year (365 calls), shared by its hours
    unique_days, inverse = np.unique(day0, return_inverse=True)
    epoch = dt.datetime(1970, 1, 1, 12)  # noon of each day on the local clock
    offsets = np.array([tz.utcoffset(epoch + dt.timedelta(seconds=float(d))).total_seconds() for d in unique_days])
    local = start_unix + offsets[inverse]
    local_day = np.floor(local / 86400.0)
    clock_h = (local - local_day * 86400.0) / HOUR_S
    weekday = ((local_day.astype(np.int64) + 3) % 7)  # 1970-01-01 was a Thursday (3)
    use = np.isin(weekday, days) & (clock_h >= start_h - 1e-9) & (clock_h < end_h - 1e-9)
    sel = np.flatnonzero(use)
    return UsageHours(rows=rows[sel], unix_mid=start_unix[sel] + 0.5 * HOUR_S,
                      local_start=(local[sel] / 60.0).round().astype("datetime64[m]"))


def count_usage_hours(year: int, start_h: float, end_h: float, days: tuple[int, ...]) -> int:
    """Hours of whole clock hours from ``start_h`` to ``end_h`` on the usage days of ``year``: what
    :func:`usage_hours` gives on a full year's file without summer time (a check of it)."""
    d0 = np.datetime64(f"{year}-01-01")
    n = int((np.datetime64(f"{year + 1}-01-01") - d0).astype(int))
    weekday = (np.arange(n) + (d0.astype(int) + 3)) % 7
    return int(np.isin(weekday, days).sum()) * int(round(end_h - start_h))


def parse_moment(text: str, timezone: str) -> tuple[float, dt.datetime]:
    """A point-in-time check's moment (local clock time, ``2026-12-21T12:00``) as UTC seconds and the
    local datetime (aware)."""
    local = dt.datetime.fromisoformat(text).replace(tzinfo=zoneinfo.ZoneInfo(timezone))
    return local.timestamp(), local


def standard_time(local: dt.datetime) -> tuple[int, int, float]:
    """(month, day, decimal hour) of an aware local datetime in the zone's standard time (summer
    time taken off), as gensky and gendaylit read them."""
    dst = local.dst() or dt.timedelta(0)
    st = (local - dst).replace(tzinfo=None)
    return st.month, st.day, st.hour + st.minute / 60.0 + st.second / 3600.0


def standard_offset_h(timezone: str, year: int) -> float:
    """The zone's standard-time offset from UTC in ``year`` [h] (its offset on 1 January less summer time)."""
    tz = zoneinfo.ZoneInfo(timezone)
    jan = dt.datetime(year, 1, 15, 12)
    return ((tz.utcoffset(jan) or dt.timedelta(0)) - (tz.dst(jan) or dt.timedelta(0))).total_seconds() / HOUR_S
