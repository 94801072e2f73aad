"""What a criterion of EN 17037 is to the pipeline: a small interface every check implements.

A criterion (view out, exposure to sunlight; daylight provision and glare protection may follow)
says whether a project asks for it, which ray groups it traces against, which input problems it
can find without a ray (``validate`` runs these), how much work a room is (for progress), how to
assess one room into a typed result, and its part of report.json. Adding a criterion touches its
own folder, :mod:`en17037cli.standard` and one line of :data:`en17037cli.criteria.CRITERIA`.
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from en17037cli.errors import NotAssessable
from en17037cli.project.settings import Project
from en17037cli.raytrace import RayEngine
from en17037cli.scene.model import Room, Scene
from en17037cli.standard import Thresholds


def room_thresholds(project: Project, room: Room) -> Thresholds:
    """The thresholds ``room`` is judged by: those its kinds ask (``RoomSpec.thresholds``,
    project/kinds.py: the daylight targets of a practice per room kind), else the project's."""
    return room.spec.thresholds or project.thresholds


@dataclass(frozen=True)
class Unassessed:
    """A criterion's result for a room it did not assess, and why.

    status : ``not_assessed`` (the check did not run: no section in the project, or ``--only``)
        or ``not_assessable`` (the room, or every window of it, cannot be assessed)
    """

    status: str
    reason: str


@dataclass
class Context:
    """What every criterion sees of a run: the project, its scene and the shared ray engine.

    cache : per-criterion state built once per run (e.g. lookups over the scene's faces)
    """

    project: Project
    scene: Scene
    engine: RayEngine
    cache: dict[str, Any] = field(default_factory=dict)


class Criterion(ABC):
    """One criterion of the standard (clause 5.2, 5.3, ...)."""

    #: key of the criterion in report.json and on the command line (``--only``)
    name: str = ""
    #: how reports title it
    title: str = ""

    @abstractmethod
    def settings(self, project: Project):
        """The criterion's settings, or None when the project does not ask for it."""

    @abstractmethod
    def ray_groups(self, scene: Scene) -> list[str]:
        """Names of the engine groups the criterion queries (built once, before any room)."""

    def check_inputs(self, ctx: Context) -> dict[str, str]:
        """Rooms the criterion cannot assess, found without tracing a ray: room name -> reason.

        Raises :class:`~en17037cli.errors.InputError` for contradictions in the project file (say,
        explicit points that do not fit the room). ``validate`` and ``check`` both call it.
        """
        return {}

    @abstractmethod
    def plan(self, ctx: Context, room: Room) -> Any:
        """What the criterion will compute for ``room`` (viewpoints, say); ``size(plan)`` counts it."""

    def unplannable(self, ctx: Context) -> dict[str, str]:
        """The rooms (with no problem of their own) whose :meth:`plan` says they cannot be
        assessed: room name -> reason, for :meth:`check_inputs`."""
        out = {}
        for room in ctx.scene.rooms:
            if room.problem is None:
                try:
                    self.plan(ctx, room)
                except NotAssessable as exc:
                    out[room.name] = str(exc)
        return out

    def size(self, plan) -> int:
        """Units of work of a plan, for a progress bar."""
        return 1

    @abstractmethod
    def assess(self, ctx: Context, room: Room, plan, progress: Callable[[int], None] | None = None):
        """The criterion's typed result for one room."""

    @abstractmethod
    def level(self, result) -> int:
        """Level index (see :data:`~en17037cli.standard.LEVELS`) a result reaches."""

    def unassessable(self, result) -> str | None:
        """Why a result the criterion computed still cannot give the room a level (a part of the
        criterion the model cannot answer), or None: the room is then ``not_assessable``."""
        return None

    def required(self, room: Room) -> str:
        """The level ``room`` must reach for this criterion."""
        return getattr(room.spec.requirements, self.name)

    def notes(self, result) -> list[str]:
        """Notes the result carries for the report."""
        return list(getattr(result, "notes", []))

    @abstractmethod
    def report(self, ctx: Context, room: Room, result) -> dict:
        """The criterion's section of a room in report.json."""

    def illustrate(self, ctx: Context, room: Room, result) -> Any:
        """What the report's pictures need of this result beyond it, traced while the ray engine
        is open (fisheye classes, sun paths), or None. Runs only when pictures are asked for."""
        return None
