"""EN 17037 clause 5.2, View out: horizontal sight angle, outside distance and view layers.

* viewpoints: :mod:`.viewpoints`; the windows as sampled: :mod:`.frames`, :mod:`.gnomonic`
* solid angles of the layers: :mod:`.solid_angle`; sight angle: :mod:`.sight_angle`;
  outside distance: :mod:`.distance`; where a ray goes: :mod:`.rays`
* per point and per room: :mod:`.assess` into :mod:`.results`; report section: :mod:`.report`
"""
from __future__ import annotations

from en17037cli.criteria.base import Context, Criterion
from en17037cli.criteria.view.assess import assess_room
from en17037cli.criteria.view.pictures import room_plan
from en17037cli.criteria.view.rays import ViewRays
from en17037cli.criteria.view.report import view_section
from en17037cli.criteria.view.results import ViewResult
from en17037cli.criteria.view.surroundings import no_landscape, sparse_surroundings
from en17037cli.criteria.view.viewpoints import viewpoints
from en17037cli.project.settings import Project, ViewSettings
from en17037cli.scene.model import Scene, room_window_group

__all__ = ["ViewCriterion", "layers_unjudged", "no_landscape", "sparse_surroundings"]


def layers_unjudged(scene: Scene, room, settings: ViewSettings) -> str | None:
    """Why the view layers of ``room`` cannot be judged, or None: the model has no landscape at all
    (:func:`~.surroundings.no_landscape`), or none in front of the room's windows
    (:func:`~.surroundings.sparse_surroundings`)."""
    return no_landscape(scene) or sparse_surroundings(scene, room, settings.surroundings_min_share)


def layers_aside(result: ViewResult) -> str:
    """The room's levels of sight angle and outside distance (the lowest over eye heights), for a
    view whose layers cannot be judged."""
    from en17037cli.standard import LEVELS

    out = []
    for crit, label in (("horizontal_sight_angle", "horizontal sight angle"), ("outside_distance", "outside distance")):
        levels = [e.level_by_criterion[crit] for e in result.eye_heights if crit in e.level_by_criterion]
        out.append(f"{label} {LEVELS[min(levels)] if levels else 'none'}")
    return ", ".join(out)


class ViewCriterion(Criterion):
    name = "view"
    title = "view out (5.2)"

    def settings(self, project: Project) -> ViewSettings | None:
        return project.view

    def _settings(self, ctx: Context) -> ViewSettings:
        if ctx.project.view is None:
            raise ValueError("the view criterion runs only on projects with a view section")
        return ctx.project.view

    def ray_groups(self, scene):
        return [room_window_group(r) for r in scene.rooms] + ["opaque"]

    def plan(self, ctx: Context, room):
        plans = ctx.cache.setdefault("view_plans", {})
        if room.name not in plans:
            plans[room.name] = viewpoints(ctx.scene, room, self._settings(ctx))
        return plans[room.name]

    def check_inputs(self, ctx: Context) -> dict[str, str]:
        return self.unplannable(ctx)

    def size(self, plan) -> int:
        groups, _ = plan
        return sum(len(p) for _, p in groups)

    def assess(self, ctx: Context, room, plan, progress=None) -> ViewResult:
        if "view_rays" not in ctx.cache:
            ctx.cache["view_rays"] = ViewRays(ctx.engine, ctx.scene)
        reuse = ctx.cache.get("view_reuse", {}).get(room.name)  # set by the sensitivity study only
        why = layers_unjudged(ctx.scene, room, self._settings(ctx))
        layers = why is None or ctx.cache.get("view_all_layers", False)  # the studies keep them
        result = assess_room(ctx.cache["view_rays"], ctx.scene, room, self._settings(ctx), ctx.project.thresholds, plan, progress,
                             reuse, layers)
        if why is not None:
            result.layers_unassessable = f"{why}; without the layers: {layers_aside(result)}"
        return result

    def unassessable(self, result: ViewResult) -> str | None:
        return result.layers_unassessable

    def illustrate(self, ctx: Context, room, result: ViewResult):
        """The room in plan for the maps (:mod:`.pictures`); the values are in ``result``."""
        return room_plan(ctx.scene, room, self._settings(ctx))

    def level(self, result: ViewResult) -> int:
        return result.level

    def report(self, ctx: Context, room, result: ViewResult) -> dict:
        return view_section(ctx.scene, result, self.required(room), self._settings(ctx), ctx.project.thresholds)
