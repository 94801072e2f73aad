"""Check real IFC exports as a user would, and print the table of docs/bim.md and the README.

Each file gets the project of the README's "From BIM" section (every IfcSpace a room, view and
sunlight with their defaults, minimum levels required), run with ``en17037 check`` in a
subprocess; the table lists the file, the tool that wrote it, its schema, its spaces, the rooms
assessed (a criterion with a level), the spaces with windows left out, the windows in rooms of the
windows found, the exit code and the wall time.

A file whose IfcSite gives no latitude gets ``--latitude``/``--longitude``; the time zone is the
fixed offset of the site's longitude (``Etc/GMT-1`` at 13 deg E): the hours are the same in any
zone, the days start at local midnight.

Usage: python scripts/bim_corpus.py [FILE_OR_FOLDER ...] [--out DIR] [--set KEY=VALUE ...] [--markdown FILE]
Default: the IFC files of ../shared/data/real-models/ (``make bim-corpus``).
"""
from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
DEFAULT = ROOT.parent / "shared" / "data" / "real-models"


def authoring_tool(path: Path) -> tuple[str, str]:
    """(tool, schema): the file's first IfcApplication (name and version), else the STEP header's
    originating system."""
    from en17037cli.io.ifc_step import top_level_arguments

    data = path.read_bytes()
    head = data[:20_000].decode("latin-1")
    schema = (re.search(r"FILE_SCHEMA\s*\(\s*\(\s*'([^']+)'", head) or [None, "?"])[1]
    app = re.search(rb"IFCAPPLICATION\s*\([^,]*,\s*'([^']*)'\s*,\s*'([^']*)'", data, re.I)
    if app:
        name, version = app[2].decode("latin-1").strip(), app[1].decode("latin-1").strip()
        return (name if version in name else f"{name} {version}").strip(), schema
    header = re.search(r"FILE_NAME\s*\((.*?)\)\s*;", head, re.S)
    fields = top_level_arguments(header[1].encode("latin-1")) if header else []
    system = fields[5].decode("latin-1").strip().strip("'") if len(fields) > 5 else ""
    return system or "?", schema


def site_longitude(path: Path) -> float | None:
    """The IfcSite's RefLongitude [deg], or None (ifcopenshell, which the ifc extra brings)."""
    import ifcopenshell

    from en17037cli.io.ifc_site import compound_degrees

    try:
        sites = ifcopenshell.open(str(path)).by_type("IfcSite")
    except Exception:  # a file ifcopenshell cannot open: the check itself says why (exit 2)
        return None
    return compound_degrees(sites[0].RefLongitude) if sites else None


def project_for(ifc: Path, out: Path, latitude: float, longitude: float) -> Path:
    """The README's project for ``ifc`` in ``out``; location from the IfcSite where it has one."""
    lon = site_longitude(ifc)
    location: dict = {}
    if lon is None:
        location = {"latitude": latitude, "longitude": longitude}
        lon = longitude
    offset = int(round(lon / 15.0))
    location["timezone"] = "UTC" if offset == 0 else f"Etc/GMT{-offset:+d}"  # Etc zones count west positive
    doc = {"version": 1, "name": ifc.stem, "model": {"files": [{"path": str(ifc.resolve())}]}, "location": location,
           "rooms": [{"ifc_spaces": "*"}], "view": {}, "sunlight": {"date": "worst"},
           "requirements": {"view": "minimum", "sunlight": "minimum"}}
    p = out / f"{ifc.stem}.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True), encoding="utf-8")
    return p


def run_one(ifc: Path, out: Path, overrides: list[str], latitude: float, longitude: float) -> dict:
    """Check one file; its row of the table."""
    tool, schema = authoring_tool(ifc)
    project = project_for(ifc, out, latitude, longitude)
    folder = out / ifc.stem
    cmd = [sys.executable, "-m", "en17037cli", "check", str(project), "--out", str(folder), "-q", "--no-plots"]
    for o in overrides:
        cmd += ["--set", o]
    t = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    row = {"file": ifc.name, "tool": tool, "schema": schema, "exit": proc.returncode, "time_s": time.perf_counter() - t,
           "message": (proc.stderr.strip().splitlines() or [""])[-1] if proc.returncode >= 2 else ""}
    report = folder / "report.json"
    if proc.returncode < 2 and report.is_file():
        r = json.loads(report.read_text(encoding="utf-8"))
        left = r.get("spaces_left_out", [])
        rooms = r["rooms"]
        row.update(spaces=len(rooms) + len(left), rooms=len(rooms),
                   assessed=sum(1 for room in rooms if any((room[c] or {}).get("status") in ("pass", "fail")
                                                           for c in ("view", "sunlight"))),
                   windowed_left_out=sum(1 for s in left if s["windows"]),
                   windows=sum(len(room["windows"]) for room in rooms))
    return row


def markdown(rows: list[dict]) -> str:
    """The table: file, tool, schema, spaces, rooms assessed, windows in rooms, exit code, time."""
    lines = ["| file | tool | schema | spaces | rooms (assessed) | spaces with windows not assessed | windows in rooms | exit | time [s] |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "rooms" in r:
            lines.append(f"| {r['file']} | {r['tool']} | {r['schema']} | {r['spaces']} | {r['rooms']} ({r['assessed']}) | "
                         f"{r['windowed_left_out']} | {r['windows']} | {r['exit']} | {r['time_s']:.1f} |")
        else:
            lines.append(f"| {r['file']} | {r['tool']} | {r['schema']} | - | - | - | - | {r['exit']} | {r['time_s']:.1f} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("paths", nargs="*", type=Path, default=[DEFAULT], help="IFC files or folders [default: %(default)s]")
    ap.add_argument("--out", type=Path, default=ROOT / "out" / "bim-corpus", help="projects and report folders")
    ap.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                    help="passed to en17037 check --set (repeatable), e.g. view.grid_spacing_m=1")
    ap.add_argument("--latitude", type=float, default=52.0, help="for files whose IfcSite says nothing [deg]")
    ap.add_argument("--longitude", type=float, default=13.0, help="for files whose IfcSite says nothing [deg]")
    ap.add_argument("--markdown", type=Path, default=None, help="also write the table to this file")
    a = ap.parse_args(argv)
    files = sorted({f for p in a.paths for f in ([p] if p.is_file() else sorted(p.glob("*.ifc")))})
    if not files:
        print(f"no IFC file in {', '.join(map(str, a.paths))}", file=sys.stderr)
        return 2
    a.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for f in files:  # one check after the other: each uses every core
        rows.append(run_one(f, a.out, a.overrides, a.latitude, a.longitude))
        r = rows[-1]
        print(f"{f.name}: exit {r['exit']} in {r['time_s']:.1f} s" + (f" ({r['message']})" if r["message"] else ""), file=sys.stderr)
    table = markdown(rows)
    print(table, end="")
    if a.markdown:
        a.markdown.write_text(table, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
