"""The city model written back with the screen's results: each probed wall surface gets its figures
as attributes, each screened building its summary.

**Attributes.** A wall surface: ``en17037_probes``, ``en17037_sunlight_hours_median_h`` and its
``en17037_sunlight_level``, ``en17037_sky_component_median_pct``, ``en17037_outside_distance_median_m``
(left out where the view is open to the horizon: ``en17037_outside_distance_open`` true) and
``en17037_view_layers_level`` (of its median probe); medians over its probes weighted by the facade
each stands for. A building: ``en17037_probes``, ``en17037_facade_m2``,
``en17037_sunlight_share_<level>`` (its facade's share at each level), ``en17037_sunlight_hours_median_h``,
``en17037_sky_component_median_pct`` and, where it was left out, ``en17037_left_out`` (why).

**CityJSON** (plain JSON: the file is read as the reader reads it and written back whole, its
other members untouched): a wall surface's attributes go on a semantic surface object of its own
(CityJSON 2.0 §3.3: a copy of the one it shared, with the attributes; its ``values`` entry points
to it), a building's into its ``attributes``. A CityJSONSeq is written back line by line.
cjio reads the result (the tests re-read it with cjio, the reference implementation).

**CityGML** (streamed with lxml: each member parsed, changed, written out and dropped): generic
attributes (1.0, 2.0: ``gen:stringAttribute`` / ``gen:doubleAttribute`` / ``gen:intAttribute``
with ``gen:value``; 3.0: ``genericAttribute`` holding ``gen:StringAttribute``...) on the
``WallSurface`` and the ``Building``, after the object's leading GML and core properties (where
the schemas put them). Walls that are polygons of a block without thematic surfaces have no
element of their own: their building's attributes say what they got.
"""
from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np

from en17037cli import standard
from en17037cli.district.results import BuildingSummary, ProbeTable, _median
from en17037cli.district.walls import at

PREFIX = "en17037_"


def wall_attributes(table: ProbeTable, thresholds) -> dict:
    """(building index, wall index) -> attributes of the wall surface (module docstring);
    ``thresholds`` the project's (:class:`~en17037cli.standard.Thresholds`)."""
    p = table.probes
    key = p.building * 100_000 + p.wall
    out = {}
    for k in np.unique(key):  # one entry per probed wall
        sel = np.flatnonzero(key == k)
        a = p.area_m2[sel]
        hours = _median(table.hours_h[sel], a)
        dist = _median(table.distance_m[sel], a)
        layers = _median(table.layers_level[sel].astype(float), a)
        attrs = {"probes": len(sel), "sunlight_hours_median_h": round(hours, 4),
                 "sunlight_level": standard.LEVELS[int(standard.level_from_value([hours], thresholds.sunlight_hours)[0])],
                 "sky_component_median_pct": round(_median(table.vsc_pct[sel], a), 3)}
        if np.isfinite(dist):
            attrs["outside_distance_median_m"] = round(dist, 3)
        else:
            attrs["outside_distance_open"] = True
        attrs["view_layers_level"] = standard.LEVELS[int(layers)]
        out[(int(p.building[sel[0]]), int(p.wall[sel[0]]))] = {PREFIX + n: v for n, v in attrs.items()}
    return out


def building_attributes(rows: list[BuildingSummary]) -> dict:
    """building index -> attributes of the building (module docstring)."""
    out = {}
    for i, r in enumerate(rows):  # one entry per building
        attrs: dict = {"probes": r.probes, "facade_m2": round(r.facade_m2, 2)}
        attrs |= {f"sunlight_share_{k}": round(v, 4) for k, v in r.sunlight_share.items()}
        for name, v, digits in (("sunlight_hours_median_h", r.sunlight_hours_median_h, 4),
                                ("sky_component_median_pct", r.sky_component_median_pct, 3)):
            if np.isfinite(v):
                attrs[name] = round(v, digits)
        if r.problem:
            attrs["left_out"] = r.problem
        out[i] = {PREFIX + n: v for n, v in attrs.items()}
    return out


def written_name(path: Path) -> str:
    """The written-back file's name: ``<name>.screened`` before the city model's ending."""
    name = path.name
    for end in (".city.jsonl", ".city.json"):
        if name.lower().endswith(end):
            return name[: -len(end)] + ".screened" + name[-len(end):]
    return path.stem + ".screened" + path.suffix


def write_cityjson(path: Path, buildings: list, walls: dict, blds: dict) -> bytes:
    """The CityJSON (or CityJSONSeq) file ``path`` with the attributes added, as bytes."""
    from en17037cli.io.cityjson.documents import load_documents

    docs = load_documents(path)
    objects = {}
    for _, doc in docs:
        for oid, obj in (doc.get("CityObjects") or {}).items():
            objects.setdefault(oid, obj)
    for bi, attrs in blds.items():
        obj = objects[buildings[bi].id]
        obj["attributes"] = {**(obj.get("attributes") or {}), **attrs}
    for (bi, wi), attrs in walls.items():
        _, oid, gi, pos = buildings[bi].walls[wi].handle
        g = objects[oid]["geometry"][gi]
        sem = g.get("semantics")
        if not isinstance(sem, dict) or sem.get("values") is None:
            continue  # a wall without semantics: its building's attributes say it
        holder = at(sem["values"], pos[:-1]) if len(pos) > 1 else sem["values"]
        old = holder[pos[-1]]
        base = sem["surfaces"][old] if isinstance(old, int) else {"type": "WallSurface"}
        sem["surfaces"].append({**base, **attrs})
        holder[pos[-1]] = len(sem["surfaces"]) - 1
    if len(docs) == 1:
        return (json.dumps(docs[0][1], ensure_ascii=False, separators=(",", ":")) + "\n").encode("utf-8")
    return "".join(json.dumps(d, ensure_ascii=False, separators=(",", ":")) + "\n" for _, d in docs).encode("utf-8")


def _namespaces(core: str) -> tuple[str, str, int]:
    """(generics namespace, the property namespace generic attributes go in, version) of a CityGML core namespace."""
    version = 3 if core.endswith("/3.0") else (1 if core.endswith("/1.0") else 2)
    gen = f"http://www.opengis.net/citygml/generics/{version}.0"
    return gen, core, version


def _add_attributes(el, attrs: dict, core: str) -> None:
    """Append generic attributes to a CityGML object element, after its leading GML/core/gen/app properties."""
    from lxml import etree

    gen, core_ns, version = _namespaces(core)
    leading = ("http://www.opengis.net/gml", core_ns, gen, "http://www.opengis.net/citygml/appearance")
    pos = 0
    for child in el:
        ns = etree.QName(child).namespace if isinstance(child.tag, str) else None
        if ns is None or not any(ns.startswith(x) for x in leading):
            break
        pos += 1
    for k, (name, v) in enumerate(attrs.items()):
        kind = "string" if isinstance(v, bool) else ("int" if isinstance(v, int) else ("double" if isinstance(v, float) else "string"))
        text = ("true" if v else "false") if isinstance(v, bool) else (repr(v) if isinstance(v, float) else str(v))
        if version == 3:
            prop = etree.Element(f"{{{core_ns}}}genericAttribute")
            a = etree.SubElement(prop, f"{{{gen}}}{kind.capitalize()}Attribute", nsmap={"gen": gen})
            etree.SubElement(a, f"{{{gen}}}name").text = name
            etree.SubElement(a, f"{{{gen}}}value").text = text
        else:
            prop = etree.Element(f"{{{gen}}}{kind}Attribute", name=name, nsmap={"gen": gen})
            etree.SubElement(prop, f"{{{gen}}}value").text = text
        el.insert(pos + k, prop)


def write_citygml(path: Path, buildings: list, walls: dict, blds: dict) -> bytes:
    """The CityGML file ``path`` with the attributes added, as bytes (streamed member by member)."""
    from en17037cli.district.walls_gml import MEMBERS
    from en17037cli.io.citygml import _lxml
    from en17037cli.io.citygml.walk import gml_id, local

    etree = _lxml(path)
    by_id = {b.id: bi for bi, b in enumerate(buildings)}
    wall_of = {(bi, b.walls[wi].handle[2]): attrs for (bi, wi), attrs in walls.items()
               for b in [buildings[bi]] if b.walls[wi].handle[0] == "citygml"}
    buf = io.BytesIO()
    with etree.xmlfile(buf, encoding="utf-8") as xf, contextlib.ExitStack() as stack:
        xf.write_declaration()
        depth, core = 0, ""
        for event, el in etree.iterparse(str(path), events=("start", "end"), huge_tree=True):
            if event == "start":
                depth += 1
                if depth == 1:
                    core = etree.QName(el).namespace or ""
                    stack.enter_context(xf.element(el.tag, attrib=dict(el.attrib), nsmap=el.nsmap))
                continue
            depth -= 1
            if depth != 1:
                continue
            if local(el.tag) in MEMBERS:
                for feature in el:
                    if not isinstance(feature.tag, str) or local(feature.tag) != "Building":
                        continue
                    bi = by_id.get(gml_id(feature) or f"Building#{feature.sourceline}")
                    if bi is None:
                        continue
                    for k, w in enumerate([e for e in feature.iter() if local(e.tag) == "WallSurface"]):
                        if (bi, k) in wall_of:
                            _add_attributes(w, wall_of[(bi, k)], core)
                    if bi in blds:
                        _add_attributes(feature, blds[bi], core)
            xf.write(el)
            parent = el.getparent()
            el.clear()
            if parent is not None:
                while el.getprevious() is not None:
                    del parent[0]
    return buf.getvalue() + b"\n"
