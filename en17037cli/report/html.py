"""``report.html``: the client report. One self-contained file: the pictures embedded as data URIs,
the style inline, no script and no request to anything outside it; printable to PDF from a
browser (each room starts a page, no picture or table row is split).

Built from the report document and the pictures (:mod:`.figures`); it traces nothing and holds no
time stamp, so the same inputs give the same bytes.
"""
from __future__ import annotations

import base64
from html import escape

from en17037cli.report.labels import STATUS_LABEL, assessed
from en17037cli.report.markdown import (
    daylight_paragraph,
    daylight_table,
    dwellings_markdown,
    parameter_lines,
    share_table,
    verdict_rows,
    window_rows,
)
from en17037cli.report.numbers import fmt_bound, fmt_duration
from en17037cli.report.verdicts import limit_text

#: Per-point rows shown per room and eye height in the appendix; the rest are in view_points.csv.
APPENDIX_ROWS = 50

_CSS = """
:root { --pass: #1a7f37; --fail: #b42318; --na: #6e6e6e; --line: #d0d7de; }
body { font-family: "DejaVu Sans", "Helvetica Neue", Arial, sans-serif; font-size: 10.5pt; color: #1f2328;
       max-width: 60rem; margin: 1.5rem auto; padding: 0 1rem; line-height: 1.4; }
h1 { font-size: 1.6rem; margin-bottom: 0.2rem; } h2 { font-size: 1.25rem; border-bottom: 1px solid var(--line); }
h3 { font-size: 1.05rem; margin-bottom: 0.3rem; }
table { border-collapse: collapse; margin: 0.4rem 0 0.8rem; }
th, td { border: 1px solid var(--line); padding: 0.2rem 0.5rem; text-align: left; vertical-align: top; }
th { background: #f6f8fa; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
.verdict { font-size: 1.3rem; font-weight: bold; padding: 0.3rem 0.8rem; display: inline-block; border-radius: 4px; color: white; }
.PASS { background: var(--pass); } .FAIL { background: var(--fail); }
.NOT-ASSESSED, .NOT-ASSESSABLE { background: var(--na); }
span.status { font-weight: bold; padding: 0 0.35rem; border-radius: 3px; color: white; white-space: nowrap; }
figure { display: inline-block; vertical-align: top; margin: 0.3rem; width: calc(50% - 0.8rem);
         break-inside: avoid; page-break-inside: avoid; }
figure.wide { width: calc(100% - 0.8rem); max-width: 42rem; }
figure img { width: 100%; height: auto; border: 1px solid var(--line); }
figcaption { font-size: 0.85rem; color: #57606a; }
.small { font-size: 0.85rem; color: #57606a; }
tr { break-inside: avoid; page-break-inside: avoid; }
@media print { body { max-width: none; margin: 0; } section.room { break-before: page; page-break-before: always; }
  a { color: inherit; text-decoration: none; } }
"""


def _status(label: str) -> str:
    return f'<span class="status {label.replace(" ", "-")}">{escape(label)}</span>'


def _table(rows: list[list[str]], numeric: tuple[int, ...] = (), raw: tuple[int, ...] = ()) -> str:
    """An HTML table, the first row as header; cells escaped unless their column is in ``raw``."""
    head = "".join(f"<th>{escape(str(c))}</th>" for c in rows[0])
    body = []
    for r in rows[1:]:
        cells = []
        for j, c in enumerate(r):
            text = str(c) if j in raw else escape(str(c))
            cells.append(f'<td class="num">{text}</td>' if j in numeric else f"<td>{text}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def _figure(f) -> str:
    data = base64.b64encode(f.png).decode("ascii")
    wide = ' class="wide"' if f.section == "sunlight" else ""
    return (f'<figure{wide}><img alt="{escape(f.caption)}" src="data:image/png;base64,{data}">'
            f"<figcaption>{escape(f.caption)}</figcaption></figure>")


def _point_rows(e: dict) -> list[list[str]]:
    rows = [["x m", "y m", "z m", "sight angle °", "distance m", "sky / landscape / ground sr", "level"]]
    for p in e["points"][:APPENDIX_ROWS]:
        d = "unobstructed" if p["outside_distance_unobstructed"] else p["outside_distance_m"]
        sa = p["solid_angle_sr"]
        rows.append([*p["point"], p["horizontal_sight_angle_deg"], d, f"{sa['sky']} / {sa['landscape']} / {sa['ground']}",
                     p["level"] + (" *" if p["near_threshold"] else "")])
    return rows


def _room(room: dict, figures) -> list[str]:
    H = [f'<section class="room"><h2>Room {escape(room["name"])}</h2>']
    if room.get("problem"):
        H.append(f"<p>Not assessable: {escape(room['problem'])}</p>")
    H.append(_table(window_rows(room)))
    pics = [f for f in figures if f.room == room["name"]]
    v = assessed(room["view"])
    if v:
        ee = v["error_estimates"]
        H += [f"<h3>View out: {escape(v['level'])} {_status(STATUS_LABEL[v['status']])}</h3>",
              f"<p>Required: {escape(v['required'])}. What limits it: {escape(limit_text('view', v))}.</p>",
              f'<p class="small">Error estimates: solid angles {fmt_bound(ee["max_solid_angle_error_sr"])} sr, sight angle '
              f'{fmt_bound(ee["max_horizontal_sight_angle_error_deg"])}°, outside distance {fmt_bound(ee["max_outside_distance_error_m"])} m. '
              "Points ringed on the maps lie within their error estimate of a threshold.</p>"]
        for e in v["eye_heights"]:
            H += [f"<h3>Eye height {e['eye_height_m']} m: {len(e['points'])} points, level {escape(e['level'])}</h3>",
                  _table(share_table(e), numeric=(1, 2, 3))]
            H += [_figure(f) for f in pics if f.section == "view" and f"-view-{e['eye_height_m']:g}m-" in f.name]
    s = assessed(room["sunlight"])
    if s:
        hrs = [d["hours"] for d in s["days"]]
        H += [f"<h3>Exposure to sunlight: {escape(s['level'])} {_status(STATUS_LABEL[s['status']])}</h3>",
              f"<p>Required: {escape(s['required'])}. {escape(limit_text('sunlight', s)).capitalize()} "
              f"(± {fmt_duration(s['error_estimates']['hours_error_h'])}). Over the period: {fmt_duration(min(hrs))} to "
              f"{fmt_duration(max(hrs))} a day.</p>"]
        H += [_figure(f) for f in pics if f.section == "sunlight"]
    d = assessed(room.get("daylight"))
    if d:
        text = daylight_paragraph(d).split("; ", 1)[1].replace("`", "")
        H += [f"<h3>Daylight provision: {escape(d['level'])} {_status(STATUS_LABEL[d['status']])}</h3>",
              f"<p>Required: {escape(d['required'])}. {escape(text)}</p>", _table(daylight_table(d))]
        H += [_figure(f) for f in pics if f.section == "daylight"]
    H.append("</section>")
    return H


def report_html(report: dict, figures=()) -> str:
    """The HTML report of a report document and its pictures (see the module docstring)."""
    title = f"EN 17037 check: {report['project']['name']}"
    status = report["status"].upper()
    H = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
         '<meta name="viewport" content="width=device-width, initial-scale=1">',
         # nothing may leave the page: no fetch of any kind, images only from the page itself
         "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; img-src data:; style-src 'unsafe-inline'\">",
         f"<title>{escape(title)}</title><style>{_CSS}</style></head><body>",
         f"<h1>{escape(title)}</h1>",
         f'<p><span class="verdict {status}">{status}</span> '
         f'<span class="small">en17037cli {escape(report["tool"]["version"])}, project file '
         f'<code>{escape(report["project"]["file"])}</code>; EN 17037:2018+A1:2021 clauses 5.1 (daylight provision), 5.2 '
         "(view out) and 5.3 (exposure to sunlight).</span></p>",
         '<h2 id="verdict">Verdict</h2>']
    rows = verdict_rows(report)
    H.append(_table([["room", "check", "reached", "required", "result", "what limits it", "score"]]
                    + [[escape(r["room"]), escape(r["check"]), escape(r["reached"]), escape(r["required"]),
                        _status(r["result"]), escape(r["limits"]), r["score"]] for r in rows], numeric=(6,),
                    raw=(0, 1, 2, 3, 4, 5)))
    H.append('<p class="small">Score: 0 to 3, equal to the level at each threshold and linear in the quantity between '
             "thresholds (beyond the standard: for comparing designs).</p>")
    dw = [line for line in dwellings_markdown(report) if line and not line.startswith("|")]
    H += [f"<p>{escape(line.replace('`', ''))}</p>" for line in dw]
    dwell = [d for d in report["dwellings"] if d["sunlight"]["status"] is not None]
    if len(report["dwellings"]) > 1 and dwell:
        H.append(_table([["dwelling", "rooms", "sunlight met by", "hours", "required", "result"]] + [
            [escape(d["name"]), escape(", ".join(d["rooms"])),
             escape(d["sunlight"]["room"] if d["sunlight"]["status"] == "pass"
                    else f"best: {d['sunlight']['room']}, {fmt_duration(d['sunlight']['shortfall_h'])} short"),
             fmt_duration(d["sunlight"]["hours"]), escape(d["sunlight"]["required"]), _status(STATUS_LABEL[d["sunlight"]["status"]])]
            for d in dwell], raw=(0, 1, 2, 3, 4, 5)))
    for room in report["rooms"]:
        H += _room(room, figures)
    H += ['<section><h2 id="parameters">Parameters the standard leaves open</h2><ul>']
    H += [f"<li>{escape(line)}</li>" for line in parameter_lines(report)] + ["</ul>"]
    if report["warnings"] or report["notes"]:
        H += ["<h2>Warnings and notes</h2><ul>"] + [f"<li>{escape(n)}</li>" for n in report["warnings"] + report["notes"]]
        H.append("</ul>")
    H.append("</section>")
    appendix = [(room, e) for room in report["rooms"] if assessed(room["view"]) for e in room["view"]["eye_heights"]]
    if appendix:
        H.append('<section class="room"><h2 id="appendix">Appendix: viewpoints</h2>')
        for room, e in appendix:
            n = len(e["points"])
            more = f" (the first {APPENDIX_ROWS} of {n}; every point in <code>view_points.csv</code>)" if n > APPENDIX_ROWS else ""
            H += [f"<h3>{escape(room['name'])}, eye height {e['eye_height_m']} m{more}</h3>",
                  _table(_point_rows(e), numeric=(0, 1, 2, 3, 4))]
        H.append('<p class="small">* within the error estimate of a threshold: the level could flip.</p></section>')
    H.append("</body></html>")
    return "\n".join(H) + "\n"


def sensitivity_html(doc: dict, charts: list[tuple[str, bytes]], project_name: str) -> str:
    """``sensitivity.html`` of ``en17037 study sensitivity``: the verdicts' robustness table and a
    tornado chart of the scores per room; self-contained like report.html."""
    title = f"EN 17037 sensitivity: {project_name}"
    H = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
         "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; img-src data:; style-src 'unsafe-inline'\">",
         f"<title>{escape(title)}</title><style>{_CSS}</style></head><body>", f"<h1>{escape(title)}</h1>",
         "<p>Each choice the standard leaves open is set, one at a time, to each value of its range; the level and the "
         "score (0 to 3, beyond the standard) are judged again. <b>robust pass</b>: every value passes; <b>robust fail</b>: "
         "none does; <b>depends on</b>: the choices that flip the verdict.</p>"]
    H.append(_table([["room", "check", "required", "level", "score", "lowest", "highest", "moved by", "verdict"]] + [
        [r["room"], r["check"], r["required"], r["level"], f"{r['score']:.2f}", r["lowest"], r["highest"],
         ", ".join(r["moved_by"]) or "-", r["verdict"]] for r in doc["rooms"]], numeric=(4,)))
    for caption, png in charts:
        data = base64.b64encode(png).decode("ascii")
        H.append(f'<figure class="wide"><img alt="{escape(caption)}" src="data:image/png;base64,{data}">'
                 f"<figcaption>{escape(caption)}</figcaption></figure>")
    H.append("<h2>Ranges</h2><ul>" + "".join(f"<li>{escape(k)}: {escape(', '.join(v))}</li>" for k, v in doc["ranges"].items())
             + "</ul>")
    c = doc.get("cost")
    if c:
        H.append(f'<p class="small">Cost: {c["total_s"]} s, {c["ratio"]} x the check with the project\'s own settings.</p>')
    H.append("</body></html>")
    return "\n".join(H) + "\n"
