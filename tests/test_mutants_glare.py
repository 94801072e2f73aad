"""Mutation tests (issue 39): the glare criterion's numeric core (``criteria/glare/``: dgp, usage,
positions, annual, assess) against hand values and closed forms.
"""
from __future__ import annotations

import numpy as np
import pytest

from en17037cli.criteria.glare import positions


@pytest.mark.parametrize("d, north, bearing", [
    ((1.0, 0.0, 0.0), 0.0, 90.0), ((1.0, 0.0, 0.0), 30.0, 60.0), ((0.0, -1.0, 0.0), 0.0, 180.0),
    ((-1.0, 0.0, 0.0), 0.0, 270.0), ((0.0, 1.0, 0.0), 10.0, 350.0)])
def test_bearing_and_direction_by_hand(d, north, bearing):
    assert positions.bearing_deg(d, north) == pytest.approx(bearing, abs=1e-12)
    assert np.allclose(positions.direction_of(bearing, north), d, atol=1e-12)
