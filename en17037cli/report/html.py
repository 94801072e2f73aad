"""``report.html``: the client report. One self-contained file: the pictures inline as SVG (vector, their
text as text), the style inline, no script and no request to anything outside it.

On a phone (390 px) tables scroll inside their box and pictures scale to the width; printed (A4)
the verdict, the warnings and the first room share the first page, each further room starts a
page, a room's words and tables come first and its pictures after them, in pairs, at their own size (3.45 in: text at least 8 pt, two side by side), the view
maps other than each eye height's level and what limits it stay on screen, and the per-point
values stay in the CSV files, so a room takes about three pages.

Built from the report document and the pictures (:mod:`.figures`); it traces nothing and holds no
time stamp, so the same inputs give the same bytes.
"""
from __future__ import annotations

import base64
import re
from html import escape

from en17037cli.report.glare_text import glare_paragraph, moments_table, positions_table, reference_table, together_text
from en17037cli.report.labels import STATUS_LABEL, assessed, is_repair
from en17037cli.report.markdown import (
    daylight_paragraph,
    daylight_table,
    dwellings_markdown,
    parameter_lines,
    share_table,
    solid_angle_words,
    verdict_rows,
    window_rows,
)
from en17037cli.report.numbers import fmt_bound, fmt_duration
from en17037cli.report.validation import kind_text
from en17037cli.report.verdicts import limit_text

_CSS = """
:root { --pass: #1a7f37; --fail: #b42318; --na: #6e6e6e; --line: #d0d7de; }
body { font-family: "DejaVu Sans", "Helvetica Neue", Arial, sans-serif; font-size: 10.5pt; color: #1f2328;
       max-width: 62rem; margin: 1.5rem auto; padding: 0 1rem; line-height: 1.4; overflow-wrap: anywhere; }
h1 { font-size: 1.6rem; margin-bottom: 0.2rem; } h2 { font-size: 1.25rem; border-bottom: 1px solid var(--line); }
h3 { font-size: 1.05rem; margin-bottom: 0.3rem; }
.scroll { overflow-x: auto; max-width: 100%; }
table { border-collapse: collapse; margin: 0.4rem 0 0.8rem; overflow-wrap: normal; }
th, td { border: 1px solid var(--line); padding: 0.2rem 0.5rem; text-align: left; vertical-align: top; }
th { background: #f6f8fa; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
.verdict { font-size: 1.3rem; font-weight: bold; padding: 0.3rem 0.8rem; display: inline-block; border-radius: 4px; color: white; }
.PASS { background: var(--pass); } .FAIL { background: var(--fail); }
.NOT-ASSESSED, .NOT-ASSESSABLE { background: var(--na); }
span.status { font-weight: bold; padding: 0 0.35rem; border-radius: 3px; color: white; white-space: nowrap; }
.figures { display: flex; flex-wrap: wrap; gap: 0.6rem; }
figure { margin: 0; flex: 0 1 calc(50% - 0.3rem); max-width: 100%; break-inside: avoid; page-break-inside: avoid; }
figure svg { display: block; width: 100%; height: auto; border: 1px solid var(--line); }
figcaption { font-size: 0.85rem; color: #57606a; }
.small { font-size: 0.85rem; color: #57606a; }
tr { break-inside: avoid; page-break-inside: avoid; }
@media (max-width: 40rem) { figure { flex-basis: 100%; } body { padding: 0 0.5rem; }
  td.long { min-width: 15rem; } }
@page { size: A4; margin: 14mm 15mm; }
@media print {
  body { max-width: none; margin: 0; padding: 0; font-size: 8.5pt; line-height: 1.3; }
  table { margin: 0.2rem 0 0.4rem; } th, td { padding: 0.1rem 0.35rem; } p { margin: 0.3rem 0; }
  h1 { font-size: 15pt; } h2 { font-size: 12pt; break-after: avoid; } h3 { font-size: 10pt; break-after: avoid; }
  section.room + section.room { break-before: page; page-break-before: always; }
  .scroll { overflow: visible; }
  section.room { display: flex; flex-wrap: wrap; column-gap: 0.1in; align-items: flex-start; }
  section.room > * { flex: 0 0 100%; order: 1; } section.room > .figures { display: contents; }
  section.room figure { order: 2; flex: 0 0 3.45in; margin-bottom: 0.08in; }
  section.technical { font-size: 8pt; }
  figure.screen { display: none; }
  a { color: inherit; text-decoration: none; } }
"""


def _status(label: str) -> str:
    return f'<span class="status {label.replace(" ", "-")}">{escape(label)}</span>'


#: A cell of more characters than this keeps a readable width on a phone (its table scrolls instead).
LONG_CELL = 40


def _table(rows: list[list[str]], numeric: tuple[int, ...] = (), raw: tuple[int, ...] = ()) -> str:
    """An HTML table in a box that scrolls sideways on a narrow screen, the first row as header;
    cells escaped unless their column is in ``raw``."""
    head = "".join(f"<th>{escape(str(c))}</th>" for c in rows[0])
    body = []
    for r in rows[1:]:
        cells = []
        for j, c in enumerate(r):
            text = str(c) if j in raw else escape(str(c))
            cls = "num" if j in numeric else "long" if len(str(c)) > LONG_CELL else ""
            cells.append(f'<td class="{cls}">{text}</td>' if cls else f"<td>{text}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f'<div class="scroll"><table><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table></div>'


def inline_svg(svg: bytes, prefix: str) -> str:
    """An SVG document as an element of the page: no XML prolog, sized by the page's CSS (its
    viewBox keeps the proportions), every id prefixed so that the figures' ids cannot collide."""
    text = svg.decode("utf-8")
    text = text[text.index("<svg"):]
    head, rest = text.split(">", 1)
    head = re.sub(r'\s(width|height)="[^"]*"', "", head)
    rest = re.sub(r'\bid="', f'id="{prefix}-', rest)
    rest = re.sub(r"url\(#", f"url(#{prefix}-", rest)
    rest = re.sub(r'href="#', f'href="#{prefix}-', rest)
    return f'{head} role="img">{rest}'


def _figures(pics, n0: int) -> str:
    """Figures in a wrapping row: vector pictures (inline SVG, text as text) with their captions;
    those not meant for paper are left out of the print (class ``screen``)."""
    out = []
    for k, f in enumerate(pics):
        cls = "" if f.print_ else "screen"
        body = inline_svg(f.svg, f"f{n0 + k}") if f.svg else f'<img alt="{escape(f.caption)}" src="data:image/png;base64,' \
            f'{base64.b64encode(f.png).decode("ascii")}">'
        out.append(f'<figure{f" class={chr(34)}{cls}{chr(34)}" if cls else ""}>{body}<figcaption>{escape(f.caption)}'
                   "</figcaption></figure>")
    return f'<div class="figures">{"".join(out)}</div>' if out else ""


def _room(room: dict, figures, n0: int) -> list[str]:
    H = [f'<section class="room"><h2>Room {escape(room["name"])}</h2>', f"<p>Kind: {escape(kind_text(room['kind']))}.</p>"]
    if room.get("problem"):
        H.append(f"<p>Not assessable: {escape(room['problem'])}</p>")
    H.append(_table(window_rows(room)))
    pics = [f for f in figures if f.room == room["name"]]
    n = n0
    d = assessed(room.get("daylight"))
    if d:
        text = daylight_paragraph(d).split("; ", 1)[1].replace("`", "")
        H += [f"<h3>Daylight provision: {escape(d['level'])} {_status(STATUS_LABEL[d['status']])}</h3>",
              f"<p>Required: {escape(d['required'])}. {escape(text)}</p>", _table(daylight_table(d))]
        mine = [f for f in pics if f.section == "daylight"]
        H.append(_figures(mine, n))
        n += len(mine)
    v = assessed(room["view"])
    if v:
        ee = v["error_estimates"]
        H += [f"<h3>View out: {escape(v['level'])} {_status(STATUS_LABEL[v['status']])}</h3>",
              f"<p>Required: {escape(v['required'])}. What limits it: {escape(limit_text('view', v))}.</p>",
              f'<p class="small">Error estimates: {escape(solid_angle_words(ee))}, sight angle '
              f'{fmt_bound(ee["max_horizontal_sight_angle_error_deg"])}°, outside distance {fmt_bound(ee["max_outside_distance_error_m"])} m. '
              "Points ringed on the maps lie within their error estimate of a threshold. The printed report shows each eye "
              "height's level map and the map of what limits it; every point's values are in view_points.csv.</p>"]
        for e in v["eye_heights"]:
            H += [f"<h3>Eye height {e['eye_height_m']} m: {len(e['points'])} points, level {escape(e['level'])}</h3>",
                  _table(share_table(e), numeric=(1, 2, 3))]
            mine = [f for f in pics if f.section == "view" and f"-view-{e['eye_height_m']:g}m-" in f.name]
            H.append(_figures(mine, n))
            n += len(mine)
    s = assessed(room["sunlight"])
    if s:
        hrs = [d["hours_h"] for d in s["days"]]
        H += [f"<h3>Exposure to sunlight: {escape(s['level'])} {_status(STATUS_LABEL[s['status']])}</h3>",
              f"<p>Required: {escape(s['required'])}. {escape(limit_text('sunlight', s)).capitalize()} "
              f"(± {fmt_duration(s['error_estimates']['hours_error_h'])}). Over the period: {fmt_duration(min(hrs))} to "
              f"{fmt_duration(max(hrs))} a day (every day in sunlight_days.csv).</p>"]
        mine = [f for f in pics if f.section == "sunlight"]
        H.append(_figures(mine, n))
        n += len(mine)
    g = room.get("glare")
    if g and "method" in g:
        text = glare_paragraph(g).split("; ", 1)[-1].replace("`", "")
        text = text[:1].upper() + text[1:]
        H += [f"<h3>Protection from glare: {escape(g['level'] or '-')} {_status(STATUS_LABEL[g['status']])}</h3>",
              f"<p>Required: {escape(g['required'])}. {escape(text)}</p>"]
        tables = ([positions_table(g)] if g["positions"] else []) + [t for t in (reference_table(g), moments_table(g)) if len(t) > 1]
        H += [_table(t) for t in tables]
        both = together_text(room)
        if both:
            H.append(f"<p><b>{escape(both)}</b></p>")
        mine = [f for f in pics if f.section == "glare"]
        H.append(_figures(mine, n))
        n += len(mine)
    H.append("</section>")
    return H


def _model_files(report: dict) -> str:
    """The model files and their SHA-256, as a table (what was checked, exactly)."""
    files = report["inputs"].get("model_files", {})
    if not files:
        return ""
    rows = [["model file", "SHA-256"]] + [[name, h.removeprefix("sha256:")[:16] + "…"] for name, h in files.items()]
    return _table(rows)


_CLAUSES = {"daylight": "5.1 (daylight provision)", "view": "5.2 (view out)", "sunlight": "5.3 (exposure to sunlight)",
            "glare": "5.4 (protection from glare)"}


def _clauses(report: dict) -> str:
    """``clauses 5.2 (view out) and 5.3 (exposure to sunlight)``: the clauses this report checks."""
    names = [v for k, v in _CLAUSES.items() if any(room.get(k) for room in report["rooms"])] or list(_CLAUSES.values())
    return ("clause " if len(names) == 1 else "clauses ") + (names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1])


def report_html(report: dict, figures=()) -> str:
    """The HTML report of a report document and its pictures (see the module docstring)."""
    title = f"EN 17037 check: {report['project']['name']}"
    status = report["status"].upper()
    attention = [w for w in report["warnings"] if not is_repair(w)]
    repairs = [w for w in report["warnings"] if is_repair(w)]
    H = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
         '<meta name="viewport" content="width=device-width, initial-scale=1">',
         # nothing may leave the page: no fetch of any kind, images only from the page itself
         "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; img-src data:; style-src 'unsafe-inline'\">",
         f"<title>{escape(title)}</title><style>{_CSS}</style></head><body>",
         f"<h1>{escape(title)}</h1>",
         f'<p><span class="verdict {status}">{status}</span> '
         f'<span class="small">en17037cli {escape(report["tool"]["version"])}, project file '
         f'<code>{escape(report["project"]["file"])}</code>; EN 17037:2018+A1:2021 {_clauses(report)}.</span></p>']
    if report["project"].get("description"):
        H.append(f"<p>{escape(report['project']['description'])}</p>")
    H.append('<h2 id="verdict">Verdict</h2>')
    rows = verdict_rows(report)
    H.append(_table([["room", "check", "reached", "required", "result", "what limits it", "score"]]
                    + [[escape(r["room"]), escape(r["check"]), escape(r["reached"]), escape(r["required"]),
                        _status(r["result"]), escape(r["limits"]), r["score"]] for r in rows], numeric=(6,),
                    raw=(0, 1, 2, 3, 4, 5)))
    H.append('<p class="small">Score: 0 to 3, equal to the level at each threshold and linear in the quantity between '
             "thresholds (beyond the standard: for comparing designs).</p>")
    if attention:
        H += ["<p><b>Warnings:</b></p><ul>"] + [f"<li>{escape(w)}</li>" for w in attention] + ["</ul>"]
    dw = [line for line in dwellings_markdown(report) if line and not line.startswith("|")]
    H += [f"<p>{escape(line.replace('`', ''))}</p>" for line in dw]
    dwell = [d for d in report["dwellings"] if d["sunlight"]["status"] is not None]
    if len(report["dwellings"]) > 1 and dwell:
        H.append(_table([["dwelling", "rooms", "sunlight met by", "hours", "required", "result"]] + [
            [escape(d["name"]), escape(", ".join(d["rooms"])),
             escape(d["sunlight"]["room"] if d["sunlight"]["status"] == "pass"
                    else f"best: {d['sunlight']['room']}, {fmt_duration(d['sunlight']['shortfall_h'])} short"),
             fmt_duration(d["sunlight"]["hours_h"]), escape(d["sunlight"]["required"]), _status(STATUS_LABEL[d["sunlight"]["status"]])]
            for d in dwell], raw=(0, 1, 2, 3, 4, 5)))
    n = 0
    for room in report["rooms"]:
        H += _room(room, figures, n)
        n += sum(f.room == room["name"] for f in figures)
    H += ['<section class="technical"><h2 id="technical">Technical notes</h2>', _model_files(report),
          "<h3>Parameters the standard leaves open</h3><ul>"]
    H += [f"<li>{escape(line)}</li>" for line in parameter_lines(report)] + ["</ul>"]
    if repairs or report["notes"]:
        H += ["<h3>The model as read</h3><ul>"] + [f"<li>{escape(w)}</li>" for w in repairs + report["notes"]] + ["</ul>"]
    H.append('<p class="small">Every point and day: view_points.csv, sunlight_days.csv and daylight_points.csv beside this '
             "file" + (", every glare view and hour: glare_points.csv and glare_hours.csv" if any(r.get("glare") for r in report["rooms"])
                       else "") + "; the whole result: report.json.</p></section>")
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
