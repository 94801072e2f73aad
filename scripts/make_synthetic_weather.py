"""Write the samples' synthetic EPW weather file (see en17037cli/samples/weather.py for the models).

Usage: python scripts/make_synthetic_weather.py OUT.epw [--lat 52.0 --lon 4.36 --tz 1 --year 2026]
The rows are of one calendar year (not a leap year); the header's DATA PERIODS line names the day
of the week that year starts on (2026: Thursday). The file is synthetic; give a real EPW of the
site (daylight.weather) for a real assessment.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from en17037cli.samples.weather import synthetic_epw

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("out")
    ap.add_argument("--lat", type=float, default=52.0)
    ap.add_argument("--lon", type=float, default=4.36)
    ap.add_argument("--tz", type=float, default=1.0)
    ap.add_argument("--year", type=int, default=2026)
    a = ap.parse_args()
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    print(synthetic_epw(a.out, lat=a.lat, lon=a.lon, tz=a.tz, year=a.year))
