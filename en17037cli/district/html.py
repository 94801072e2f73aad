"""``report.html``: the screened tile on one map, each probe a dot coloured by the level it reaches
(sunlight, view layers, outside distance) or by its vertical sky component, chosen with the
buttons above it; the walls drawn in plan; the buildings' table; what was done and left out.

One self-contained page (an inline SVG, a few lines of CSS and of JavaScript, no network): the
dots carry one class per figure (``s2`` sunlight level 2...), the buttons set the map's class, the
style sheet colours the dots of that class. Without JavaScript the map shows sunlight. Names and
ids from the model are escaped (``html.escape``).
"""
from __future__ import annotations

import html
import math

import numpy as np

from en17037cli import standard
from en17037cli.district.results import ProbeTable
from en17037cli.report.pictures.colours import LEVEL_COLOURS

#: Map width [px]
WIDTH = 960
#: Bins of the vertical sky component [%] for the map (27 % is BRE's guide value; 39.6 % unobstructed)
VSC_BINS = (5.0, 10.0, 15.0, 20.0, 27.0, 35.0)
VSC_COLOURS = ("#440154", "#443983", "#31688e", "#21918c", "#35b779", "#90d743", "#fde725")
MODES = (("s", "sunlight (5.3)"), ("l", "view layers (5.2)"), ("d", "outside distance (5.2)"), ("v", "vertical sky component"))


def _style() -> str:
    rules = []
    for mode in ("s", "l", "d"):
        rules += [f"svg.m{mode} .{mode}{i}{{fill:{c}}}" for i, c in enumerate(LEVEL_COLOURS)]
    rules += [f"svg.mv .v{i}{{fill:{c}}}" for i, c in enumerate(VSC_COLOURS)]
    return ("body{font-family:system-ui,sans-serif;margin:1.5em;max-width:1100px;color:#222}"
            "table{border-collapse:collapse;font-size:12px}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
            "td:first-child,th:first-child{text-align:left}svg{background:#fafafa;border:1px solid #ddd;max-width:100%;height:auto}"
            "circle{stroke:none}.walls{stroke:#777;stroke-width:0.8;fill:none}.key span{display:inline-block;width:12px;"
            "height:12px;margin:0 4px 0 12px;vertical-align:middle}button{margin-right:6px}" + "".join(rules))


def _legend(mode: str) -> str:
    if mode == "v":
        edges = ("0",) + tuple(f"{b:g}" for b in VSC_BINS)
        labels = [f"{a}-{b} %" for a, b in zip(edges, edges[1:])] + [f"&ge; {VSC_BINS[-1]:g} %"]
        return "".join(f"<span style='background:{c}'></span>{t}" for c, t in zip(VSC_COLOURS, labels))
    return "".join(f"<span style='background:{c}'></span>{n}" for c, n in zip(LEVEL_COLOURS, standard.LEVELS))


def map_svg(table: ProbeTable, buildings: list) -> str:
    """The map: walls in plan (each polygon's extent along its facade) and one dot per probe, the
    higher storeys' first (a plan shows the lowest of a stack)."""
    segs = []
    for b in buildings:  # the walls of every screened building, in plan
        for w in b.walls:
            for poly in w.polygons:
                r = np.asarray(poly[0])[:, :2]
                d = r - r.mean(axis=0)
                _, _, vt = np.linalg.svd(d, full_matrices=False)
                s = d @ vt[0]
                segs.append((r[np.argmin(s)], r[np.argmax(s)]))
    pts = [np.asarray(table.probes.point[:, :2])] + [np.array(s) for s in segs]
    allxy = np.concatenate([p.reshape(-1, 2) for p in pts if len(p)]) if segs or len(table) else np.zeros((1, 2))
    lo, hi = allxy.min(axis=0) - 5.0, allxy.max(axis=0) + 5.0
    scale = WIDTH / max(hi[0] - lo[0], 1e-9)
    height = max(int(math.ceil((hi[1] - lo[1]) * scale)), 1)
    px = lambda xy: ((xy[..., 0] - lo[0]) * scale, (hi[1] - xy[..., 1]) * scale)  # noqa: E731
    path = []
    for a, b in segs:  # one path of all the walls
        (ax, ay), (bx, by) = px(a), px(b)
        path.append(f"M{ax:.1f} {ay:.1f}L{bx:.1f} {by:.1f}")
    x, y = px(table.probes.point[:, :2])
    vbin = np.searchsorted(np.asarray(VSC_BINS), table.vsc_pct, side="right")
    r = max(1.2, min(3.0, 0.8 * scale))
    order = np.argsort(-table.probes.storey, kind="stable")  # storeys above each other: the lowest drawn last, on top
    dots = [f"<circle cx='{x[i]:.1f}' cy='{y[i]:.1f}' r='{r:.1f}' class='s{table.sun_level[i]} l{table.layers_level[i]} "
            f"d{table.distance_level[i]} v{vbin[i]}'/>" for i in order]
    return (f"<svg id='map' class='ms' xmlns='http://www.w3.org/2000/svg' viewBox='0 0 {WIDTH} {height}' width='{WIDTH}' "
            f"height='{height}'><path class='walls' d='{''.join(path)}'/>{''.join(dots)}</svg>")


def _pct(v: float) -> str:
    return "" if not math.isfinite(v) else f"{100 * v:.0f}"


def _num(v: float, fmt: str) -> str:
    return "" if math.isnan(v) else ("&infin;" if math.isinf(v) else format(v, fmt))


def report_html(title: str, info: dict, table: ProbeTable, buildings: list, rows: list, warnings: list) -> str:
    """The page (module docstring); ``info``: what ``summary.json`` holds."""
    e = html.escape
    buttons = "".join(f"<button onclick=\"show('{m}')\">{e(t)}</button>" for m, t in MODES)
    legends = "".join(f"<p class='key' id='key{m}' style='display:{'block' if m == 's' else 'none'}'>{e(t)}:{_legend(m)}</p>"
                      for m, t in MODES)
    head = ("<tr><th>building</th><th>probes</th><th>facade m&sup2;</th>"
            + "".join(f"<th>sun {e(lv)} %</th>" for lv in standard.LEVELS)
            + "<th>sun median h</th><th>VSC median %</th><th>outside distance median m</th><th>left out</th></tr>")
    body = "".join(
        f"<tr><td>{e(r.id)}</td><td>{r.probes}</td><td>{r.facade_m2:.0f}</td>"
        + "".join(f"<td>{_pct(r.sunlight_share[lv]) if r.probes else ''}</td>" for lv in standard.LEVELS)
        + f"<td>{_num(r.sunlight_hours_median_h, '.2f')}</td><td>{_num(r.sky_component_median_pct, '.1f')}</td>"
        f"<td>{_num(r.outside_distance_median_m, '.1f')}</td><td>{e(r.problem)}</td></tr>" for r in rows)
    facts = "".join(f"<li>{e(str(k))}: {e(str(v))}</li>" for k, v in info["facts"].items())
    warn = "".join(f"<li>{e(w)}</li>" for w in warnings) or "<li>none</li>"
    script = ("<script>function show(m){document.getElementById('map').setAttribute('class','m'+m);"
              "for(const k of ['s','l','d','v'])document.getElementById('key'+k).style.display=k==m?'block':'none';}</script>")
    return (f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><meta name='viewport' content='width=device-width'>"
            f"<title>{e(title)}: facade screen</title><style>{_style()}</style></head><body>"
            f"<h1>{e(title)}: facade screen (EN 17037)</h1><p>{e(info['headline'])}</p><ul>{facts}</ul>"
            f"<h2>Map</h2><p>{buttons}</p>{legends}{map_svg(table, buildings)}"
            "<p>Each dot is a probe: the point P of a virtual window flush with the facade, one per storey along each wall "
            "(docs/district.md); where storeys stand above each other the lowest is drawn on top. Walls shared with a "
            "neighbour have none.</p>"
            f"<h2>Buildings</h2><table>{head}{body}</table><h2>Warnings</h2><ul>{warn}</ul>{script}</body></html>\n")
