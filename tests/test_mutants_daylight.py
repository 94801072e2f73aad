"""Mutation tests (issue 39): the daylight criterion's numeric core (``criteria/daylight/``) against
hand values and closed forms.
"""
from __future__ import annotations

import numpy as np
import pytest

from en17037cli.criteria.daylight import assess, patches


def test_reinhart_layout_by_hand():
    assert patches.reinhart_bins(1) == 146 and patches.reinhart_bins(2) == 578
    assert patches.row_counts(1).tolist() == [30, 30, 24, 24, 18, 12, 6, 1]
    assert patches.row_counts(2).tolist() == [60, 60, 60, 60, 48, 48, 48, 48, 36, 36, 24, 24, 12, 12, 1]
    assert patches.row_width_deg(1) == 12.0 and patches.row_width_deg(2) == 90.0 / 14.5
    for mf in (1, 2):  # the patches tile the upper hemisphere: 2 pi sr
        assert patches.patch_solid_angles(mf).sum() == pytest.approx(2 * np.pi, rel=1e-12)


def test_student_t_by_table():
    assert assess.t975(1) == 12.706 and assess.t975(2) == 4.303 and assess.t975(30) == 2.042
    assert assess.t975(31) == 1.96 and assess.t975(0) == 1.96
