"""Check real exports as a user would, and print the table of docs/bim.md and the README.

Every file of the folder gets a row. An IFC gets the project of the README's "From BIM" section
(every IfcSpace a room, view and sunlight with their defaults, minimum levels required; a file
with no space ``auto: true``), a gbXML the same with ``gbxml_spaces: "*"``; a CityGML or CityJSON city model, which has no rooms, is the context of the box
room of en17037cli.samples set down at the tile's centre on its lowest ground (the buildings it
overlaps left out, as the project key ``exclude_overlapping`` does): what a user does with a city
model. Each is run with ``en17037 check`` in a subprocess; the table lists the file, the tool that
wrote it, its format, its spaces, the rooms assessed (a criterion with a level), the spaces with
windows left out, the windows in rooms, the exit code and the wall time.

A file that says nothing of its latitude gets ``--latitude``/``--longitude``; the time zone is the
fixed offset of the site's longitude (``Etc/GMT-1`` at 13 deg E): the hours are the same in any
zone, the days start at local midnight.

Usage: python scripts/bim_corpus.py [FILE_OR_FOLDER ...] [--out DIR] [--set KEY=VALUE ...] [--markdown FILE]
Default: every IFC, gbXML, CityGML and CityJSON file of ../shared/data/real-models/ (``make bim-corpus``).
"""
from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
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
    """The IfcSite's RefLongitude [deg], or None where it has none or is the null site (0, 0)
    (ifcopenshell, which the ifc extra brings)."""
    import ifcopenshell

    from en17037cli.io.ifc_site import compound_degrees

    try:
        sites = ifcopenshell.open(str(path)).by_type("IfcSite")
    except Exception:  # a file ifcopenshell cannot open: the check itself says why (exit 2)
        return None
    if not sites:
        return None
    from en17037cli.scene.site import is_null_site

    lat, lon = compound_degrees(sites[0].RefLatitude), compound_degrees(sites[0].RefLongitude)
    return None if is_null_site(lat, lon) else lon  # the null site says nothing: the check asks for a location


def text_of(path: Path, limit: int | None = None) -> str:
    """The file's text (or its first ``limit`` bytes'), UTF-16 where it opens with a byte-order mark
    (Revit writes some gbXML so), else UTF-8."""
    data = path.open("rb").read(limit) if limit else path.read_bytes()
    return data.decode("utf-16" if data[:2] in (b"\xff\xfe", b"\xfe\xff") else "utf-8", "replace")


def kind_of(path: Path) -> str | None:
    """'ifc', 'gbxml' or 'citygml' by the file's root, or None for anything else (a README)."""
    suffix = path.suffix.lower()
    if suffix == ".ifc":
        return "ifc"
    if suffix == ".json":  # the "type" key may come last
        try:
            return "cityjson" if json.loads(path.read_text(encoding="utf-8")).get("type") == "CityJSON" else None
        except (ValueError, AttributeError):
            return None
    if suffix not in (".xml", ".gbxml", ".gml", ".citygml"):
        return None
    head = text_of(path, 8000)
    root = re.search(r"<(?!\?|!)([\w.-]+:)?([\w.-]+)", head)
    return {"gbXML": "gbxml", "CityModel": "citygml"}.get(root[2] if root else "")


def gbxml_tool(path: Path) -> tuple[str, str, float | None]:
    """(tool, format, longitude [deg] or None) of a gbXML file: DocumentHistory's ProgramInfo, the
    root's version, Campus/Location."""
    text = text_of(path)
    product = re.search(r"<ProductName>([^<]*)</ProductName>", text)
    version = re.search(r"<gbXML[^>]*\sversion=\"([^\"]*)\"", text)
    lon = re.search(r"<Longitude>\s*([-+0-9.eE]+)\s*</Longitude>", text)
    return ((product[1].strip() if product else "?"), f"gbXML {version[1] if version else '(no version)'}",
            float(lon[1]) if lon else None)


def timezone_of(lon: float) -> str:
    """The fixed-offset zone of a longitude [deg]."""
    offset = int(round(lon / 15.0))
    return "UTC" if offset == 0 else f"Etc/GMT{-offset:+d}"  # Etc zones count west positive


def project_for(ifc: Path, out: Path, latitude: float, longitude: float, kind: str = "ifc") -> Path:
    """The README's project for ``ifc`` (an IFC or gbXML file) in ``out``; location from the file
    where it says (IfcSite, Campus/Location)."""
    lon = site_longitude(ifc) if kind == "ifc" else gbxml_tool(ifc)[2]
    location: dict = {}
    if lon is None:
        location = {"latitude": latitude, "longitude": longitude}
        lon = longitude
    location["timezone"] = timezone_of(lon)
    spaces = re.search(r"IFCSPACE\s*\(" if kind == "ifc" else r"<(\w+:)?Space[\s>]", text_of(ifc), re.I)
    rooms = [{"ifc_spaces" if kind == "ifc" else "gbxml_spaces": "*"}] if spaces else [{"auto": True}]  # no space: auto rooms
    doc = {"version": 1, "name": ifc.stem, "model": {"files": [{"path": str(ifc.resolve())}]}, "location": location,
           "rooms": rooms, "view": {}, "sunlight": {"date": "worst"},
           "requirements": {"view": "minimum", "sunlight": "minimum"}}
    p = out / f"{ifc.stem}.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True), encoding="utf-8")
    return p


def city_extent(path: Path, kind: str) -> tuple[str, str, np.ndarray, np.ndarray]:
    """(format, CRS, lowest corner, highest corner [the CRS's units]) of a CityGML tile (its
    top-level gml:Envelope) or a CityJSON file (its vertices and referenceSystem)."""
    from en17037cli.io.citygml.crs import parse_srs_name

    if kind == "cityjson":
        doc = json.loads(path.read_text(encoding="utf-8"))
        v = np.asarray(doc["vertices"], float)
        tr = doc.get("transform")
        if tr:
            v = v * np.asarray(tr["scale"], float) + np.asarray(tr["translate"], float)
        srs = (doc.get("metadata") or {}).get("referenceSystem", "")
        return f"CityJSON {doc.get('version', '?')}", parse_srs_name(srs) or srs, v.min(axis=0), v.max(axis=0)
    head = path.open("rb").read(20000).decode("utf-8", "replace")
    env = re.search(r"<gml:Envelope[^>]*srsName=\"([^\"]+)\"[^>]*>\s*<gml:lowerCorner>([^<]+)</gml:lowerCorner>\s*"
                    r"<gml:upperCorner>([^<]+)</gml:upperCorner>", head)
    version = re.search(r"http://www\.opengis\.net/citygml/(\d\.\d)", head)
    if env is None:
        raise ValueError("no gml:Envelope with a srsName at the top of the file")
    lo, hi = (np.array(c.split(), float) for c in (env[2], env[3]))
    return f"CityGML {version[1] if version else '?'}", parse_srs_name(env[1]) or env[1], lo, hi


def citygml_project(gml: Path, out: Path, kind: str = "citygml") -> tuple[Path, str, str]:
    """The box room set down at the centre of a city model's extent, on its lowest point, in the
    model's CRS, with the city model as context: (project, tool, format)."""
    import pyproj

    from en17037cli.samples import BoxRoom, box_room_project

    fmt, crs, lo, hi = city_extent(gml, kind)
    centre = (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), lo[2])
    lon, lat = pyproj.Transformer.from_crs(crs, "EPSG:4326", always_xy=True).transform(centre[0], centre[1])
    folder = out / gml.stem
    b = BoxRoom(building_height=0)  # no street building: the tile is the surroundings
    p = box_room_project(folder, b, offset=centre, name=gml.stem, location={"latitude": round(lat, 6),
                         "longitude": round(lon, 6), "timezone": timezone_of(lon)}, sunlight={"date": "worst"}, view={})
    doc = yaml.safe_load(p.read_text(encoding="utf-8"))
    doc["model"]["files"][0]["crs"] = crs
    doc["model"]["files"].append({"path": str(gml.resolve())})
    doc["requirements"] = {"view": "minimum", "sunlight": "minimum"}
    p.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True), encoding="utf-8")
    return p, "-", f"{fmt}, {crs} (context of the box room)"


def run_one(ifc: Path, out: Path, overrides: list[str], latitude: float, longitude: float) -> dict:
    """Check one file; its row of the table."""
    kind = kind_of(ifc)
    if kind in ("citygml", "cityjson"):
        project, tool, schema = citygml_project(ifc, out, kind)
    else:
        tool, schema = authoring_tool(ifc) if kind == "ifc" else gbxml_tool(ifc)[:2]
        project = project_for(ifc, out, latitude, longitude, kind or "ifc")
    folder = out / f"{ifc.stem}-report" if kind in ("citygml", "cityjson") else out / ifc.stem
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
        auto = any(r.get("auto") for r in r["inputs"]["config"]["rooms"])  # a file with no space: regions, not spaces
        row.update(spaces="-" if kind in ("citygml", "cityjson") or auto else len(rooms) + len(left), rooms=len(rooms),
                   assessed=sum(1 for room in rooms if any((room[c] or {}).get("status") in ("pass", "fail")
                                                           for c in ("view", "sunlight"))),
                   windowed_left_out=sum(1 for s in left if s["windows"]),
                   windows=sum(len(room["windows"]) for room in rooms))
    return row


def markdown(rows: list[dict]) -> str:
    """The table: file, tool, schema, spaces, rooms assessed, windows in rooms, exit code, time."""
    lines = ["| file | tool | format | spaces | rooms (assessed) | spaces with windows not assessed | windows in rooms | exit | time [s] |",
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
    ap.add_argument("paths", nargs="*", type=Path, default=[DEFAULT],
                    help="IFC, gbXML or CityGML files or folders [default: %(default)s]")
    ap.add_argument("--out", type=Path, default=ROOT / "out" / "bim-corpus", help="projects and report folders")
    ap.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                    help="passed to en17037 check --set (repeatable), e.g. view.grid_spacing_m=1")
    ap.add_argument("--latitude", type=float, default=52.0, help="for files whose IfcSite says nothing [deg]")
    ap.add_argument("--longitude", type=float, default=13.0, help="for files whose IfcSite says nothing [deg]")
    ap.add_argument("--markdown", type=Path, default=None, help="also write the table to this file")
    a = ap.parse_args(argv)
    files = sorted({f for p in a.paths for f in ([p] if p.is_file() else sorted(p.iterdir())) if kind_of(f)})
    if not files:
        print(f"no IFC, gbXML, CityGML or CityJSON file in {', '.join(map(str, a.paths))}", file=sys.stderr)
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
