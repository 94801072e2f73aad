"""CI formats: JUnit XML (``--junit FILE``) and GitHub Actions annotations, from run records.

JUnit: one ``testsuite`` per run, one ``testcase`` per room and criterion (see
:mod:`en17037cli.report.summary`): a ``failure`` where its verdict is FAIL, an ``error`` where it is
NOT ASSESSABLE or NOT ASSESSED, nothing where it passes; a run that did not finish (bad input,
internal error) is one testcase with an ``error``. With a baseline, a testcase that got worse is a
``failure`` (type REGRESSION) and one that does not pass but did not get worse is ``skipped`` (a
known shortfall). So a testcase fails or errs exactly when it makes the exit code 1. The document validates against the Apache Ant JUnit schema that CI
systems read (``tests/data/JUnit.xsd``, windyroad/JUnit-Schema): every required attribute, and
``properties``, ``system-out`` and ``system-err`` in every suite.

GitHub annotations (``::error file=...,title=...::message``) name the same failures; the CLI prints
them on stdout when ``GITHUB_ACTIONS=true``.
"""
from __future__ import annotations

import datetime as dt
import os
import re
import time
import xml.etree.ElementTree as ET
from pathlib import Path

from en17037cli.report.labels import STATUS_LABEL
from en17037cli.report.numbers import fmt_duration
from en17037cli.report.summary import RunRecord

#: Characters XML 1.0 does not allow (control characters in names from a model), dropped.
_NOT_XML = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")
#: How testcases name the criteria.
CRITERION_TITLE = {"view": "view out (5.2)", "sunlight": "exposure to sunlight (5.3)", "daylight": "daylight provision (5.1)",
                   "glare": "protection from glare (5.4)"}
#: Host name written into every suite: one fixed name, so that the file does not depend on the
#: machine (the schema asks for 'localhost' where the host cannot be named; a batch on a cluster
#: runs on many).
HOSTNAME = "localhost"


def timestamp(now: float | None = None) -> str:
    """UTC time of the report, ``YYYY-MM-DDTHH:MM:SS`` (the schema's pattern, no time zone):
    ``SOURCE_DATE_EPOCH`` where set (reproducible output), else ``now`` or the current time."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH", "").strip()
    t = float(epoch) if epoch.isdigit() else (time.time() if now is None else now)
    return dt.datetime.fromtimestamp(t, dt.UTC).strftime("%Y-%m-%dT%H:%M:%S")


def _describe(row: dict) -> str:
    """What a row's verdict means, in one line."""
    crit = CRITERION_TITLE[row["criterion"]]
    if row["status"] in ("pass", "fail"):
        what = f"{crit}: level {row['level']} reached, {row['required']} required"
        if row["criterion"] == "sunlight":
            what += f" ({fmt_duration(row['hours_h'])} on {row['assessed_date']}"
            what += f"; dwelling '{row['dwelling']}' fails the sunlight rule)" if row["dwelling"] and row["verdict"] != "pass" else ")"
        return what
    return f"{crit}: {STATUS_LABEL[row['status']]}: {row['message']}"


def _outcome(rec: RunRecord, row: dict) -> tuple[str, str, str] | None:
    """(element, type, message) of a testcase: ``failure``, ``error`` or ``skipped``; None when it passes.

    Without a baseline the verdict decides; with one, a regression fails (whatever the verdict)
    and any other shortfall is skipped as known.
    """
    verdict = row["verdict"]
    if rec.regressions is not None:
        change = rec.regressions.get((row["room"], row["criterion"]))
        if change is not None:
            return "failure", "REGRESSION", f"worse than the baseline ({change}): {_describe(row)}"
        return None if verdict == "pass" else ("skipped", "", f"as in the baseline: {_describe(row)}")
    if verdict == "pass":
        return None
    return ("failure" if verdict == "fail" else "error"), STATUS_LABEL[verdict], _describe(row)


def _classname(rec: RunRecord) -> str:
    """``en17037.`` and the project file's path without its suffix, dotted (``a/b/project.yaml`` ->
    ``en17037.a.b.project``), then the variant: what CI systems group test cases by."""
    parts = [x for x in Path(rec.project).with_suffix("").parts if x not in ("/", ".", "..")]
    return ".".join(["en17037", *parts, *([rec.variant] if rec.variant else [])]).replace(" ", "_")


def _fmt_time(t) -> str:
    return f"{(t or 0.0):.3f}"


def junit_xml(records: list[RunRecord], now: float | None = None) -> str:
    """The JUnit XML document of ``records`` (see the module docstring)."""
    root = ET.Element("testsuites")
    stamp = timestamp(now)
    for i, rec in enumerate(records):
        suite = ET.SubElement(root, "testsuite", {"name": f"en17037 {rec.label}", "package": "en17037", "id": str(i),
                                                  "timestamp": stamp, "hostname": HOSTNAME})
        props = ET.SubElement(suite, "properties")
        for name, value in (("project", rec.project), ("variant", rec.variant), ("report", rec.report_dir),
                            ("status", rec.status or ""), ("exit_code", str(rec.exit_code))):
            ET.SubElement(props, "property", {"name": name, "value": value})
        classname = _classname(rec)
        counts = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
        if rec.exit_code >= 2:
            case = ET.SubElement(suite, "testcase", {"name": "run", "classname": classname, "time": _fmt_time(rec.time_s)})
            kind = "bad input" if rec.exit_code == 2 else "internal error"
            err = ET.SubElement(case, "error", {"type": kind, "message": rec.message.splitlines()[0] if rec.message else kind})
            err.text = rec.message
            counts["tests"], counts["errors"] = 1, 1
        for row in rec.rows:
            case = ET.SubElement(suite, "testcase", {"name": f"{row['room']}: {CRITERION_TITLE[row['criterion']]}",
                                                     "classname": classname, "time": _fmt_time(row["time_s"])})
            counts["tests"] += 1
            out = _outcome(rec, row)
            if out is None:
                continue
            elem, kind, message = out
            attrs = {"message": message} if elem == "skipped" else {"type": kind, "message": message}
            ET.SubElement(case, elem, attrs).text = f"room '{row['room']}' of {rec.label}: {message}"
            counts[{"failure": "failures", "error": "errors", "skipped": "skipped"}[elem]] += 1
        for k, v in counts.items():
            suite.set(k, str(v))
        suite.set("time", _fmt_time(rec.time_s))
        ET.SubElement(suite, "system-out").text = "\n".join(f"warning: {w}" for w in rec.warnings)
        ET.SubElement(suite, "system-err").text = ""
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + _NOT_XML.sub("", ET.tostring(root, encoding="unicode")) + "\n"


def _escape_data(s: str) -> str:
    return s.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _escape_property(s: str) -> str:
    return _escape_data(s).replace(":", "%3A").replace(",", "%2C")


def annotation(level: str, message: str, title: str, file: str | None = None) -> str:
    """One GitHub Actions workflow command, ``::error file=F,title=T::message`` (escaped)."""
    props = ([f"file={_escape_property(file)}"] if file else []) + [f"title={_escape_property(title)}"]
    return f"::{level} {','.join(props)}::{_escape_data(message)}"


def github_annotations(records: list[RunRecord]) -> list[str]:
    """Errors for what fails the runs (the JUnit failures and errors), warnings for shortfalls
    known from a baseline and for the reports' warnings."""
    out = []
    for rec in records:
        if rec.exit_code >= 2:
            kind = "bad input" if rec.exit_code == 2 else "internal error"
            out.append(annotation("error", rec.message, f"EN 17037 {kind}: {rec.label}", rec.project))
            continue
        for row in rec.rows:
            o = _outcome(rec, row)
            if o is None:
                continue
            elem, kind, message = o
            title = f"EN 17037 {kind or STATUS_LABEL[row['verdict']]}: {row['room']}, {CRITERION_TITLE[row['criterion']]}"
            out.append(annotation("warning" if elem == "skipped" else "error", f"{message} ({rec.label})", title, rec.project))
        out += [annotation("warning", w, f"EN 17037 warning: {rec.label}", rec.project) for w in rec.warnings]
    return out
