"""How reports name statuses, and which criterion sections of report.json hold results."""
from __future__ import annotations

#: report.json status -> how people read it
STATUS_LABEL = {"pass": "PASS", "fail": "FAIL", "not_assessed": "NOT ASSESSED", "not_assessable": "NOT ASSESSABLE"}


def assessed(section: dict | None) -> dict | None:
    """A room's criterion section when it holds results (the criterion assessed the room), else None."""
    return section if section and section["status"] in ("pass", "fail") else None


def unassessed(section: dict | None) -> dict | None:
    """A room's criterion section when the criterion did not assess a room that requires it, else None."""
    return section if section and section["status"] not in ("pass", "fail") else None


#: Words of the warnings that report a repair of the geometry as read (dropped or partly
#: triangulated faces, a file read with repairs): facts for the technical section, not the summary.
REPAIR_WORDS = ("could not be fully triangulated", "faces dropped", "vertices dropped", "needed repairs to be read",
                "degenerate, NaN or infinite", "the file holds")


def is_repair(warning: str) -> bool:
    """Whether a warning reports a repair of the geometry as read (:data:`REPAIR_WORDS`)."""
    return any(w in warning for w in REPAIR_WORDS)


#: Characters that mean something to Markdown anywhere in a line (CommonMark and GitHub's:
#: emphasis, code, links and images, tables, HTML, entities, strikethrough, mathematics), escaped
#: with a backslash in text from a model; and those that do at the start of a block (headings,
#: quotes, lists, setext underlines).
_MD_SPECIAL = frozenset("\\`*_[]<|&$~")
_MD_LEADING = frozenset("#>+-=")


def md(text) -> str:
    """``text`` as literal Markdown: names and sentences that carry names from a model (any Unicode,
    ``$``, ``\\``, ``_``, ``*``, ``|``, ``<``...) read back as written, never as markup (issue 43).
    CommonMark lets any ASCII punctuation be escaped with a backslash; line breaks become spaces so
    that a name cannot end a table row or a list item."""
    s = " ".join(str(text).splitlines()) if text is not None else ""
    out = []
    for i, c in enumerate(s):
        # an underscore inside a word (file_name.obj) is no emphasis in CommonMark: left as written
        inside = c == "_" and 0 < i < len(s) - 1 and s[i - 1].isalnum() and s[i + 1].isalnum()
        # a block's first character opens a heading, list, quote or rule only before a space or its
        # like ("- x", "# x", "> x", "---"), never in "-34.7" or a lone "-"
        lead = i == 0 and c in _MD_LEADING and (c == ">" or s[1:2] == " " or s[:3] == c * 3)
        out.append("\\" + c if (c in _MD_SPECIAL and not inside) or lead else c)
    return "".join(out)
