"""Convergence study: error against run time for ladders of the engines' resolution knobs.

``en17037 study convergence project.yaml --out DIR`` runs the project's engines once per rung of
each ladder (one knob varied, the others at the project's values), times each run, and measures
each reported quantity's error against a reference run at a finer setting than any rung, and how many values
differ from the reference by more than both runs' error estimates together. It
writes ``DIR/convergence.csv`` and ``DIR/convergence.png`` (error / target against wall time,
log-log, one line per quantity), prints a table, the observed order of convergence of each
quantity (the slope of log error against log knob, fitted over the rungs whose error is above
round-off), and the cheapest rung whose errors are all within the targets.

The engines are run in-process on one scene and one ray engine (acceleration structures built
once), so the times are those of the view or sunlight stage alone.
"""
from __future__ import annotations

import csv
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

#: Default error targets per kind of quantity (overridable with ``--target kind=value``).
TARGETS = {"angle_deg": 0.01, "solid_angle_sr": 1e-3, "distance_m": 1e-3, "sun_time_s": 2.0, "share_pp": 5.0,
           "daylight_factor_pct": 0.05, "sky_component_pct": 0.02, "share_of_hours": 0.01}

#: Errors below this fraction of the target are round-off: left out of the order fit (so are
#: errors below twice the reference run's own error estimate: they are not measurable).
ROUND_OFF = 1e-6


@dataclass(frozen=True)
class Quantity:
    """A reported quantity: how to read its values and error estimates out of a run."""

    name: str
    kind: str  # key of TARGETS
    check: str  # "view" | "sunlight" | "daylight"


QUANTITIES = {
    "sky": Quantity("sky", "solid_angle_sr", "view"),
    "landscape": Quantity("landscape", "solid_angle_sr", "view"),
    "ground": Quantity("ground", "solid_angle_sr", "view"),
    "sight_angle": Quantity("sight_angle", "angle_deg", "view"),
    "distance": Quantity("distance", "distance_m", "view"),
    "share_medium": Quantity("share_medium", "share_pp", "view"),
    "sun_time": Quantity("sun_time", "sun_time_s", "sunlight"),  # the hours of sun, its error in seconds
    # daylight provision: D per point and its two parts (method 1) or the share of daylight hours per
    # point and target (method 2)
    "daylight_factor": Quantity("daylight_factor", "daylight_factor_pct", "daylight"),
    "sky_component": Quantity("sky_component", "sky_component_pct", "daylight"),
    "reflected": Quantity("reflected", "daylight_factor_pct", "daylight"),
    "share_of_hours": Quantity("share_of_hours", "share_of_hours", "daylight"),
}

#: The daylight ladders' finer references: the sky component's cells half as large and its
#: tolerance a tenth of the last rung's; the reflected part's paths four times as many.
SKY_REFERENCE = {"daylight.sky_component.resolution_deg": 0.5, "daylight.sky_component.rel_tolerance": 0.0005,
                 "daylight.sky_component.abs_tolerance_pct": 0.0005, "daylight.sky_component.refine_levels": 10}
#: Every point traces max_rays paths (no stopping early), so that the rungs are what they say.
PATHS_EXTRA = {"daylight.radiance.rel_tolerance": 0, "daylight.radiance.abs_tolerance_pct": 0,
               "daylight.radiance.stop_clear_of_thresholds": False}
PATHS_REFERENCE = {"daylight.radiance.max_rays": 16384, **PATHS_EXTRA}


@dataclass(frozen=True)
class Ladder:
    """One knob, its rungs from coarse to fine, the reference run's overrides, the quantities it moves."""

    knob: str
    values: tuple
    reference: dict
    quantities: tuple
    per_point: bool = True  # the rungs share viewpoints (False for the grid spacing)
    extra: dict = field(default_factory=dict)  # overrides applied to every rung
    levels: bool = False  # the knob counts halvings: the step size is 2^-value


#: The view's solid angles refined to the last digit (the resolution ladders measure the exact mode).
EXACT = {"view.refine": "exact"}

LADDERS = (
    Ladder("view.angular_resolution_deg", (4.0, 2.0, 1.0, 0.5),
           {"view.angular_resolution_deg": 0.25, "view.refine_levels": 4, "view.solid_angle_rel_tolerance": 0,
            "view.solid_angle_abs_tolerance_sr": 0, **EXACT}, ("sky", "landscape", "ground"), extra=EXACT),
    Ladder("view.refine_levels", (0, 1, 2, 3, 4),
           {"view.angular_resolution_deg": 0.25, "view.refine_levels": 4, "view.solid_angle_rel_tolerance": 0,
            "view.solid_angle_abs_tolerance_sr": 0, **EXACT}, ("sky", "landscape", "ground"), levels=True, extra=EXACT),
    # the view by decision (issue 44): its interval's half-width against the exact mode at the project's resolution
    Ladder("view.tolerance", (0.2, 0.1, 0.05, 0.02, 0.01), EXACT, ("sky", "landscape", "ground"),
           extra={"view.refine": "decided"}),
    Ladder("view.horizontal_resolution_deg", (2.0, 1.0, 0.5, 0.2, 0.1), {"view.horizontal_resolution_deg": 0.02},
           ("sight_angle", "distance")),
    # the fan's bisection (view.sight_angle_method: fan; in plan the tolerance only brackets far interior
    # faces). Reference 1e-5 deg: finer brackets are below the float32 resolution of a ray direction (about 3e-6 deg)
    Ladder("view.angle_tolerance_deg", (0.1, 0.01, 1e-3, 1e-4),
           {"view.angle_tolerance_deg": 1e-5, "view.sight_angle_method": "fan"}, ("sight_angle",),
           extra={"view.sight_angle_method": "fan"}),
    Ladder("view.grid_spacing_m", (2.0, 1.0, 0.5), {"view.grid_spacing_m": 0.25}, ("share_medium",), per_point=False),
    # the sampled method's timestep against the exact method (edge crossings) at a finer tolerance
    Ladder("sunlight.timestep_min", (60.0, 15.0, 5.0, 2.0, 1.0), {"sunlight.method": "exact", "sunlight.tolerance_s": 0.001},
           ("sun_time",), extra={"sunlight.tolerance_s": 0.01, "sunlight.method": "sampled"}),
    Ladder("sunlight.tolerance_s", (60.0, 10.0, 1.0, 0.1), {"sunlight.tolerance_s": 0.001}, ("sun_time",)),
    # daylight provision: the sky component's base cell (exact up to its bound), and the light paths of
    # the reflected part per point (Monte Carlo: the reference carries its own error estimate, which
    # the error of a rung cannot go below); method 2 traces max_rays / replicates per replicate
    Ladder("daylight.sky_component.rel_tolerance", (0.05, 0.02, 0.005), SKY_REFERENCE, ("sky_component", "daylight_factor")),
    Ladder("daylight.radiance.max_rays", (256, 1024, 4096), PATHS_REFERENCE, ("reflected", "daylight_factor", "share_of_hours"),
           extra=PATHS_EXTRA),
)


def fmt_value(v) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


#: The unit of each kind of error, for tables.
UNITS = {"angle_deg": "deg", "solid_angle_sr": "sr", "distance_m": "m", "sun_time_s": "s", "share_pp": "pp",
         "daylight_factor_pct": "% D", "sky_component_pct": "% D", "share_of_hours": ""}


def rung_settings(lad: Ladder, value) -> str:
    """The settings a rung runs with, as ``--set`` arguments would give them: the knob and the
    ladder's ``extra`` overrides (the timestep ladder runs the sampled method)."""
    return ", ".join(f"{k}={fmt_value(v)}" for k, v in {lad.knob: value, **lad.extra}.items())


class Runner:
    """Runs the view or sunlight criterion of one project at given overrides, on one shared scene."""

    def __init__(self, project_path: Path, overrides=(), max_points: int | None = None):
        from en17037cli.project import load_project
        from en17037cli.raytrace import RayEngine
        from en17037cli.scene import build_scene

        self.path, self.base = Path(project_path), list(overrides)
        self.project = load_project(self.path, self.base)
        self.scene = build_scene(self.project)
        self.engine = RayEngine(self.scene.vertices, self.scene.triangles, self.scene.ray_groups())
        self.max_points = max_points

    def close(self):
        self.engine.close()

    def run(self, check: str, overrides: dict, per_point: bool) -> tuple[dict, float, int]:
        """(values per quantity, wall time [s], rays) of one run."""
        from en17037cli.criteria import CRITERIA, Context
        from en17037cli.project import load_project

        project = load_project(self.path, self.base + [f"{k}={v}" for k, v in overrides.items()])
        ctx = Context(project, self.scene, self.engine)
        ctx.cache["view_all_layers"] = True  # a ladder of the layers' solid angles, landscape or not
        criterion = CRITERIA[check]
        self.engine.rays_traced = 0
        plans = {}
        for r in self.scene.rooms:
            plan = criterion.plan(ctx, r)
            if check == "view" and per_point and self.max_points:
                groups, notes = plan
                plan = ([(h, p[np.unique(np.linspace(0, len(p) - 1, min(self.max_points, len(p))).astype(int))])
                         for h, p in groups], notes)
            plans[r.name] = plan
        t = time.perf_counter()
        res = [criterion.assess(ctx, r, plans[r.name]) for r in self.scene.rooms]  # one pass per room
        wall = time.perf_counter() - t
        if check == "view":
            return _view_values(res, project.view.refine == "decided"), wall, self.engine.rays_traced
        if check == "daylight":
            return _daylight_values(res), wall, 0
        return {"sun_time": (np.concatenate([x.hours for x in res]) * 3600.0,
                          np.concatenate([x.error_h for x in res]) * 3600.0)}, wall, self.engine.rays_traced


def _daylight_values(results: list) -> dict:
    """(values, error estimates) of D [%] and of the shares of hours [-] (every point and target),
    concatenated over rooms; empty for the method a project does not use."""
    cat = lambda xs: np.concatenate(xs) if xs else np.zeros(0)  # noqa: E731
    def two(value, error):
        return (cat([getattr(r, value) for r in results if getattr(r, value) is not None]),
                cat([getattr(r, error) for r in results if getattr(r, error) is not None]))

    sh = [v for r in results if r.share_of_hours for v in r.share_of_hours.values()]
    se = [v for r in results if r.share_of_hours_err for v in r.share_of_hours_err.values()]
    return {"daylight_factor": two("daylight_factor_pct", "daylight_factor_err_pct"),
            "sky_component": two("sky_component_pct", "sky_component_bound_pct"),
            "reflected": two("reflected_pct", "reflected_err_pct"), "share_of_hours": (cat(sh), cat(se))}


def _view_values(results: list, intervals: bool = False) -> dict:
    """(values, error estimates) per view quantity, concatenated over rooms and eye heights;
    ``intervals``: a solid angle's error is the farther end of its interval (``view.refine:
    decided``), not the exact mode's estimate."""
    vals: dict = {k: ([], []) for k in ("sky", "landscape", "ground", "sight_angle", "distance", "share_medium")}
    for res in results:
        for e in res.eye_heights:
            v = e.values
            if v is None:
                continue
            for k in ("sky", "landscape", "ground"):
                vals[k][0].append(v.solid.sr[k])
                s = v.solid
                vals[k][1].append(np.maximum(s.sr[k] - s.lo_sr[k], s.hi_sr[k] - s.sr[k])
                                  if intervals and s.lo_sr is not None else s.err_sr[k])
            vals["sight_angle"][0].append(v.sight.angle_deg)
            vals["sight_angle"][1].append(v.sight.angle_err_deg)
            vals["distance"][0].append(v.distance_m)
            vals["distance"][1].append(v.distance_gap_m)
            vals["share_medium"][0].append([100.0 * e.share_by_level["view"]["medium"]])
            vals["share_medium"][1].append([np.nan])
    return {k: (np.concatenate(a) if a else np.zeros(0), np.concatenate(b) if b else np.zeros(0)) for k, (a, b) in vals.items()}


def max_error(values: np.ndarray, reference: np.ndarray) -> float:
    """Largest absolute difference; equal infinities (unobstructed distances) differ by 0."""
    v, r = np.asarray(values, float), np.asarray(reference, float)
    if v.shape != r.shape or v.size == 0:
        return math.nan
    same = (v == r) | (np.isnan(v) & np.isnan(r))
    with np.errstate(invalid="ignore"):
        d = np.where(same, 0.0, np.abs(v - r))
    return float(np.nanmax(np.where(np.isnan(d), np.inf, d)))


def count_over_estimate(values, estimates, reference, reference_estimates) -> int:
    """Values whose difference from the reference exceeds both runs' error estimates together.

    -1 where the quantity has no estimate (room shares). Equal infinities differ by 0.
    """
    v, e, r, re = (np.asarray(a, float) for a in (values, estimates, reference, reference_estimates))
    if v.shape != r.shape or not np.any(np.isfinite(e)):
        return -1
    with np.errstate(invalid="ignore"):
        d = np.where((v == r) | (np.isnan(v) & np.isnan(r)), 0.0, np.abs(v - r))
        bound = np.where(np.isfinite(e), e, 0.0) + np.where(np.isfinite(re), re, 0.0)
        return int(np.count_nonzero(~(d <= bound + 1e-12)))


def observed_order(knob_values, errors, floor: float) -> float:
    """Least-squares slope of log(error) against log(knob) over the errors above ``floor``.

    An error that falls as h^p gives p (Roache 1998, 'Verification and Validation in Computational
    Science and Engineering', ch. 5). NaN with fewer than two usable rungs.
    """
    h, e = np.asarray(knob_values, float), np.asarray(errors, float)
    ok = np.isfinite(e) & (e > floor) & (h > 0)
    if ok.sum() < 2 or np.ptp(np.log(h[ok])) == 0:
        return math.nan
    return float(np.polyfit(np.log(h[ok]), np.log(e[ok]), 1)[0])


def convergence(project_path: Path, out_dir: Path, ladders=LADDERS, targets: dict | None = None, overrides=(),
                max_points: int | None = None, log=print) -> dict:
    """Run the study; write ``convergence.csv`` (and ``convergence.png`` when matplotlib is present).

    Returns
    -------
    dict with ``rows`` (list of dicts, one per rung and quantity), ``orders`` and ``cheapest``
    (per ladder) and ``png`` (path or None).
    """
    targets = {**TARGETS, **(targets or {})}
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    runner = Runner(project_path, overrides, max_points)
    cfg = runner.project.config
    rows, orders, cheapest = [], {}, {}
    try:
        for lad in ladders:
            check = QUANTITIES[lad.quantities[0]].check
            if check not in cfg:
                continue
            ref, _, _ = runner.run(check, {**lad.extra, **lad.reference}, lad.per_point)
            rung_rows = []
            for value in lad.values:  # one run per rung
                vals, wall, rays = runner.run(check, {**lad.extra, lad.knob: value}, lad.per_point)
                for q in lad.quantities:
                    if not vals[q][0].size and not ref[q][0].size:
                        continue  # a quantity the project's method does not give (shares of hours under method 1)
                    kind = QUANTITIES[q].kind
                    err = max_error(vals[q][0], ref[q][0])
                    est = float(np.nanmax(vals[q][1])) if vals[q][1].size and np.any(np.isfinite(vals[q][1])) else math.nan
                    over = count_over_estimate(vals[q][0], vals[q][1], ref[q][0], ref[q][1])
                    rung_rows.append({"ladder": lad.knob, "value": value, "quantity": q, "kind": kind, "error": err,
                                      "estimate": est, "over_estimate": over, "target": targets[kind], "within_target": bool(err <= targets[kind]),
                                      "wall_s": wall, "rays": rays})
                log(f"  {lad.knob} = {fmt_value(value)}: {wall:.3f} s")
            rows += rung_rows
            for q in lad.quantities:
                qr = [r for r in rung_rows if r["quantity"] == q]
                if not qr:
                    continue
                ref_est = ref[q][1][np.isfinite(ref[q][1])]
                floor = max(ROUND_OFF * targets[QUANTITIES[q].kind], 2.0 * float(ref_est.max()) if ref_est.size else 0.0)
                h = [2.0 ** -r["value"] if lad.levels else r["value"] for r in qr]
                orders[(lad.knob, q)] = observed_order(h, [r["error"] for r in qr], floor)
            ok = {}
            for r in rung_rows:
                ok.setdefault(r["value"], []).append(r["within_target"])
            good = [v for v in lad.values if all(ok[v])]
            times = {r["value"]: r["wall_s"] for r in rung_rows}
            cheapest[lad.knob] = min(good, key=lambda v: times[v]) if good else None
    finally:
        runner.close()
    _write_csv(out_dir / "convergence.csv", rows)
    png = _plot(out_dir / "convergence.png", rows)
    return {"rows": rows, "orders": orders, "cheapest": cheapest, "png": png}


def _write_csv(path: Path, rows: list) -> None:
    cols = ["ladder", "value", "quantity", "kind", "error", "estimate", "over_estimate", "target", "within_target", "wall_s",
            "rays"]
    tmp = path.with_suffix(".csv.tmp")
    with tmp.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(cols)
        for r in rows:
            w.writerow([fmt_value(r[c]) if isinstance(r[c], float) else r[c] for c in cols])
    tmp.replace(path)


def _plot(path: Path, rows: list) -> Path | None:
    """Error / target against wall time, log-log, one line per (ladder, quantity); None without matplotlib."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    fig, ax = plt.subplots(figsize=(10, 6))
    colours = plt.get_cmap("tab20").colors
    markers = "osD^v<>ph*"
    lines = {}
    for r in rows:
        lines.setdefault((r["ladder"], r["quantity"]), []).append(r)
    ladders = list(dict.fromkeys(k[0] for k in lines))
    for i, ((ladder, q), rs) in enumerate(lines.items()):
        t = np.array([r["wall_s"] for r in rs])
        e = np.array([r["error"] / r["target"] for r in rs])
        ok = np.isfinite(e) & (e > 0)
        if ok.any():
            ax.loglog(t[ok], e[ok], marker=markers[ladders.index(ladder) % len(markers)], color=colours[i % len(colours)],
                      label=f"{q} ({ladder.split('.', 1)[1]})")
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.set_xlabel("wall time of the engine stage [s]")
    ax.set_ylabel("max error / target")
    ax.set_title("Convergence: error against run time (reference: finer setting than any rung)")
    if ax.get_legend_handles_labels()[0]:  # an exact quantity (error 0) draws no line
        ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    tmp = path.with_name(path.stem + ".tmp.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    tmp.replace(path)
    return path
