"""report.json's writer gives the standard library's text, character for character."""
from __future__ import annotations

import json

import pytest
from golden.scenes import BOXES, SAMPLES, pinned
from hypothesis import given, settings
from hypothesis import strategies as st

from en17037cli.report.json_text import dumps_indented


def reference(doc) -> str:
    return json.dumps(doc, indent=2, ensure_ascii=False, allow_nan=False)


@pytest.mark.parametrize("name", [*SAMPLES, *BOXES])
def test_golden_reports_written_alike(name):
    doc = json.loads(pinned(name)["report.json"])
    assert dumps_indented(doc) == reference(doc)


_leaf = (st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False, allow_infinity=False)
         | st.text(max_size=8))
_doc = st.recursive(_leaf, lambda inner: st.lists(inner, max_size=5) | st.tuples(inner, inner)
                    | st.dictionaries(st.text(max_size=5) | st.integers() | st.floats(allow_nan=False, allow_infinity=False)
                                      | st.booleans() | st.none(), inner, max_size=5)
                    | st.lists(st.floats(allow_nan=False, allow_infinity=False), max_size=6)
                    | st.lists(st.integers(), max_size=6) | st.lists(st.text(max_size=4), max_size=6), max_leaves=30)


@settings(max_examples=300, deadline=None)
@given(_doc)
def test_generated_documents_written_alike(doc):
    """Any document of JSON's types (floats, ints, strings with control characters and quotes,
    keys of every kind JSON allows, empty containers, tuples) gives the same text."""
    assert dumps_indented(doc) == reference(doc)


@pytest.mark.parametrize("bad", [float("nan"), [1.0, float("inf")], {"a": [float("-inf")]}, {float("nan"): 1}])
def test_nan_and_infinity_refused(bad):
    with pytest.raises(ValueError, match="Out of range float"):
        dumps_indented(bad)
    with pytest.raises(ValueError, match="Out of range float"):
        reference(bad)


@pytest.mark.parametrize("bad", [{"a": {1, 2}}, [object()], {(1, 2): 3}])
def test_unknown_types_refused(bad):
    with pytest.raises(TypeError):
        dumps_indented(bad)
    with pytest.raises(TypeError):
        reference(bad)
