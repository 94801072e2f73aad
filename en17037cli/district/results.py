"""The screen's results: every probe's figures with their errors and levels, and each building's
summary (shares of its facade by level, medians), from the tasks' arrays.

Levels are the standard's (:mod:`en17037cli.standard`, with the project's ``thresholds``):
sunlight by Table A.6 on the assessed day (a given date, or each probe's worst or best day of the
period); the view's outside distance and layers by Table A.5 (a layer counts where its solid angle
exceeds ``view.layer_threshold_sr``). The vertical sky component has no level in EN 17037: it is a
figure (39.6 % unobstructed). A building's shares weigh each probe by the facade it stands for.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from en17037cli import standard
from en17037cli.criteria.view.distance import weighted_statistic
from en17037cli.district.probes import Probes

LAYER_NAMES = ("sky", "landscape", "ground")


@dataclass
class ProbeTable:
    """Every probe of the run, one row each (arrays of equal length); see :func:`probe_table`."""

    probes: Probes
    building_id: list
    surface: list
    day: np.ndarray
    hours_h: np.ndarray
    hours_err_h: np.ndarray
    sun_level: np.ndarray
    vsc_pct: np.ndarray
    vsc_err_pct: np.ndarray
    distance_m: np.ndarray
    distance_err_m: np.ndarray
    distance_level: np.ndarray
    visible: dict
    layers_err_sr: np.ndarray
    layers_level: np.ndarray

    def __len__(self) -> int:
        return len(self.hours_h)

    def layers_label(self, i: int) -> str:
        """'sky+landscape+ground', the layers seen from probe ``i`` ('' for none)."""
        return "+".join(k for k in LAYER_NAMES if self.visible[k][i])


def assessed_days(hours: np.ndarray, date: str) -> np.ndarray:
    """(p,) index of each probe's assessed day in ``hours`` (p, d) [h]: its fewest hours (``worst``,
    the first such day), most (``best``), or the one day of a given date."""
    if hours.shape[1] == 0:
        return np.zeros(len(hours), np.int64)
    if date == "worst":
        return np.argmin(hours, axis=1)
    if date == "best":
        return np.argmax(hours, axis=1)
    return np.zeros(len(hours), np.int64)


def probe_table(parts: list, buildings: list, settings, thresholds) -> ProbeTable:
    """The run's probe table from the tasks' :class:`~en17037cli.district.compute.Screened`, in task order."""
    probes = Probes(*(np.concatenate([getattr(q.probes, f) for q in parts])
                      for f in ("building", "wall", "poly", "storey", "point", "normal", "area_m2")))
    cat = lambda name: np.concatenate([getattr(q, name) for q in parts])  # noqa: E731
    hours, err = cat("hours"), cat("hours_err")
    day = assessed_days(hours, settings.sun.date)
    rows = np.arange(len(day))
    h = hours[rows, day] if len(day) else np.zeros(0)
    he = err[rows, day] if len(day) else np.zeros(0)
    sr = {k: np.concatenate([q.sr[k] for q in parts]) for k in LAYER_NAMES}
    err_sr = {k: np.concatenate([q.err_sr[k] for q in parts]) for k in LAYER_NAMES}
    visible = {k: standard.layer_visible(sr[k], settings.view.layer_threshold_sr) for k in LAYER_NAMES}
    dist = cat("distance_m")
    return ProbeTable(
        probes=probes, building_id=[buildings[b].id for b in probes.building],
        surface=[buildings[b].walls[w].key for b, w in zip(probes.building, probes.wall)], day=day, hours_h=h, hours_err_h=he,
        sun_level=standard.level_from_value(h, thresholds.sunlight_hours), vsc_pct=100.0 * cat("vsc"),
        vsc_err_pct=100.0 * cat("vsc_bound"), distance_m=dist, distance_err_m=cat("distance_gap_m"),
        distance_level=standard.level_from_value(np.where(np.isnan(dist), -np.inf, dist), thresholds.outside_distance_m),
        visible=visible, layers_err_sr=np.max([err_sr[k] for k in LAYER_NAMES], axis=0) if len(dist) else np.zeros(0),
        layers_level=standard.level_from_layers(visible["sky"], visible["landscape"], visible["ground"]))


@dataclass
class BuildingSummary:
    """One building's row: its probes, facade and shares by level, medians (see :func:`summaries`)."""

    id: str
    probes: int
    shared_probes: int
    facade_m2: float
    sunlight_share: dict
    layers_share: dict
    distance_share: dict
    sky_component_median_pct: float
    outside_distance_median_m: float
    sunlight_hours_median_h: float
    problem: str


def _median(values: np.ndarray, weights: np.ndarray) -> float:
    """Weighted lower median (the view engine's :func:`~en17037cli.criteria.view.distance.weighted_statistic`), NaN for none."""
    if len(values) == 0:
        return float("nan")
    return float(weighted_statistic(values[None, :], weights[None, :], "median")[0][0])


def _shares(levels: np.ndarray, area: np.ndarray) -> dict:
    """Share of the area at each level name [-]."""
    total = area.sum()
    return {name: (float(area[levels == i].sum() / total) if total > 0 else 0.0) for i, name in enumerate(standard.LEVELS)}


def summaries(table: ProbeTable, buildings: list, shared: dict, problems: dict) -> list[BuildingSummary]:
    """One :class:`BuildingSummary` per screened building, in the run's order."""
    out = []
    order = np.argsort(table.probes.building, kind="stable")
    starts = np.searchsorted(table.probes.building[order], np.arange(len(buildings) + 1))
    for bi, b in enumerate(buildings):  # one row per building
        sel = order[starts[bi]:starts[bi + 1]]
        a = table.probes.area_m2[sel]
        out.append(BuildingSummary(
            id=b.id, probes=len(sel), shared_probes=int(shared.get(bi, 0)), facade_m2=float(a.sum()),
            sunlight_share=_shares(table.sun_level[sel], a), layers_share=_shares(table.layers_level[sel], a),
            distance_share=_shares(table.distance_level[sel], a), sky_component_median_pct=_median(table.vsc_pct[sel], a),
            outside_distance_median_m=_median(table.distance_m[sel], a), sunlight_hours_median_h=_median(table.hours_h[sel], a),
            problem=problems.get(bi, b.problem or "")))
    return out


def status(rows: list[BuildingSummary], required: str) -> tuple[str, list[str]]:
    """``pass`` where every screened building has some facade (a probe) reaching the sunlight level
    ``required`` (a dwelling there could meet clause 5.3), else ``fail``; and the ids of those that
    have none (buildings left out do not count)."""
    need = standard.level_index(required)
    failing = [r.id for r in rows if not r.problem and (r.probes == 0 or sum(
        v for name, v in r.sunlight_share.items() if standard.level_index(name) >= need) <= 0.0)]
    return ("fail" if failing else "pass"), failing
