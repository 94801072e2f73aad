"""Back into the BIM: a run's results in the formats the architect's tools read.

- :mod:`~en17037cli.bim.bcf`: the rooms and criteria that fail or cannot be assessed as BCF 2.1
  topics (``check --bcf``), each with a viewpoint at the point that limits the room;
- :mod:`~en17037cli.bim.ifc_out`: the input IFC with an ``EN17037_Results`` property set on every
  assessed space and window (``check --ifc-out``).

Writers return bytes; the command writes the files. Nothing here traces a ray.
"""
from __future__ import annotations

from pathlib import Path


def output_path(project, key: str, given: Path | None) -> Path | None:
    """Where to write a BIM output: the command line's file (``--bcf``), else the project file's
    ``report.<key>`` (relative to the project file), else None."""
    if given is not None:
        return Path(given)
    value = (project.config.get("report") or {}).get(key)
    return None if value is None else project.directory / value
