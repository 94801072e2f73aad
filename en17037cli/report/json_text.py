"""JSON text of a report: ``json.dumps(doc, indent=2, ensure_ascii=False, allow_nan=False)``, the
same characters, written faster.

With ``indent`` the standard library encodes in Python, one call per value: 2.8 s of the paper
grid's 2,800-point report. Here a list of plain floats, ints or strings (the per-point values,
most of a report) is written with one ``join`` over ``float.__repr__`` (what ``json`` writes for a
float); anything else takes the standard library's path, value by value (tests/report/test_json_text.py
compares the two on the golden reports and on generated documents).
"""
from __future__ import annotations

import math
from json.encoder import encode_basestring

_NAMES = {None: "null", True: "true", False: "false"}


def dumps_indented(doc) -> str:
    """``json.dumps(doc, indent=2, ensure_ascii=False, allow_nan=False)``: the same text.

    Raises ValueError for NaN or infinity and TypeError for a value JSON has no type for, as
    ``json.dumps`` does.
    """
    return _value(doc, 0)


def _float(x: float) -> str:
    if not math.isfinite(x):
        raise ValueError("Out of range float values are not JSON compliant: " + repr(x))
    return float.__repr__(x)


def _value(o, level: int) -> str:
    if isinstance(o, str):
        return encode_basestring(o)
    if o is None or o is True or o is False:
        return _NAMES[o]
    if isinstance(o, int):
        return int.__repr__(o)
    if isinstance(o, float):
        return _float(o)
    if isinstance(o, (list, tuple)):
        return _list(o, level)
    if isinstance(o, dict):
        return _dict(o, level)
    raise TypeError(f"Object of type {o.__class__.__name__} is not JSON serializable")


def _list(o, level: int) -> str:
    if not o:
        return "[]"
    kinds = set(map(type, o))
    if kinds == {float}:
        if not all(map(math.isfinite, o)):
            next(_float(x) for x in o if not math.isfinite(x))  # raises
        items = map(float.__repr__, o)
    elif kinds == {int}:
        items = map(int.__repr__, o)
    elif kinds == {str}:
        items = map(encode_basestring, o)
    else:
        items = (_value(x, level + 1) for x in o)
    inner = "\n" + "  " * (level + 1)
    return "[" + inner + ("," + inner).join(items) + "\n" + "  " * level + "]"


def _key(k) -> str:
    if isinstance(k, str):
        return k
    if isinstance(k, float):
        return _float(k)
    if k is None or k is True or k is False:
        return _NAMES[k]
    if isinstance(k, int):
        return int.__repr__(k)
    raise TypeError(f"keys must be str, int, float, bool or None, not {k.__class__.__name__}")


def _dict(o: dict, level: int) -> str:
    if not o:
        return "{}"
    inner = "\n" + "  " * (level + 1)
    items = (encode_basestring(_key(k)) + ": " + _value(v, level + 1) for k, v in o.items())
    return "{" + inner + ("," + inner).join(items) + "\n" + "  " * level + "}"
