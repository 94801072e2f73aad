"""Mutation tests (issue 39): the window and space matching (``scene/spaces.py``), the hosts
(``scene/hosts.py``) and the IFC glazing (``io/ifc_glazing.py``) on hand-built geometry.
"""
from __future__ import annotations

from en17037cli.scene import spaces


def test_how_far_reads_by_hand():
    assert spaces._how_far(-0.5) == "inside the space, 0.50 m from its boundary"
    assert spaces._how_far(0.0) == "on the space's boundary"
    assert spaces._how_far(0.204) == "0.20 m from the space"
