"""en17037cli: check EN 17037 View out (clause 5.2) and Exposure to sunlight (clause 5.3).

The Python API, for scripts and notebooks (the CLI is a thin layer over it)::

    import en17037cli
    project = en17037cli.load_project("project.yaml", ["sunlight.date=03-21"])
    result = en17037cli.run(project)             # typed results per room and criterion
    report = en17037cli.write_reports(result, "out/")   # the report.json document, files written
    result.status, report["rooms"][0]["view"]["level"]

In a design loop, a :class:`Session` reads each model file once and returns continuous scores::

    session = en17037cli.Session()
    for width in (1.2, 1.8, 2.4):
        scores = session.scores(en17037cli.load_project("project.yaml", [f"model.files.0.path=w{width}.obj"]))
        scores["office"]["view"]      # 0 .. 3, the level at each threshold, linear in between

Heavy modules load on first call, so ``import en17037cli`` stays cheap.
"""
from __future__ import annotations

from en17037cli.version import __version__

__all__ = ["Session", "__version__", "load_project", "run", "write_reports"]


def load_project(path, overrides=()):
    """Read, validate and resolve a project file into typed settings
    (:class:`~en17037cli.project.settings.Project`); ``overrides`` are ``key.path=value`` strings."""
    from en17037cli.project import load_project as load

    return load(path, list(overrides))


def run(project, only: str | None = None, progress=None, pictures: bool = False):
    """Run the project's checks (:func:`en17037cli.pipeline.run`); return a
    :class:`~en17037cli.pipeline.RunResult`. ``pictures=True`` also traces what the report's
    pictures need (fisheyes), so that :func:`write_reports` draws them."""
    from en17037cli.pipeline import run as run_project

    return run_project(project, only, progress, pictures=pictures)


def write_reports(result, out_dir) -> dict:
    """Build the report document of a :class:`~en17037cli.pipeline.RunResult` and write every report
    file into ``out_dir`` as one set (only replacing reports written there for the same project),
    with the pictures when the run traced them; return the document."""
    from pathlib import Path

    from en17037cli.report.document import build_report
    from en17037cli.report.figures import pictures_available, render_figures
    from en17037cli.report.folder import check_folder
    from en17037cli.report.write import WRITERS
    from en17037cli.report.write import write_reports as write

    check_folder(Path(out_dir), result.project.path, WRITERS)
    figures = render_figures(result) if any(r.illustrations for r in result.rooms) and pictures_available() else []
    report = build_report(result)
    write(report, Path(out_dir), result.project.path, figures)
    return report


class Session:
    """Repeated runs of variants of projects (design optimisation): every model file is read once
    per (path, size, modification time, read options) and reused while the session lives, so a loop
    that changes the building re-reads only the building's files; scenes and the ray engine's
    structures are built per run."""

    def __init__(self):
        self._cache: dict = {}

    def run(self, project, only: str | None = None, pictures: bool = False):
        """:func:`run` with the session's file cache."""
        from en17037cli.scene.load import READ_CACHE

        token = READ_CACHE.set(self._cache)
        try:
            return run(project, only, pictures=pictures)
        finally:
            READ_CACHE.reset(token)

    def scores(self, project, only: str | None = None) -> dict:
        """Continuous scores per room: ``{room: {"view": s, "sunlight": s}}``, each in [0, 3]
        (:mod:`en17037cli.scores`)."""
        from en17037cli.scores import room_scores

        return room_scores(self.run(project, only))
