"""Mutation tests (issue 39): the exact plan sight angle (``criteria/view/plan.py``), piece by piece
against hand plans, closed forms and brute force (dense sampling of directions).
"""
from __future__ import annotations
