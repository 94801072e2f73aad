"""What a batch runs: a variants file read into named override sets (:class:`Variant`), and every
project file times every variant planned as a run (:class:`RunSpec`, plain data a worker receives)."""
from __future__ import annotations

import hashlib
import json
import os
import re
import uuid
from dataclasses import dataclass
from pathlib import Path

from en17037cli.budget import MAX_POINTS
from en17037cli.errors import InputError

#: A project with at most this many rooms is one unit of work; a larger one goes out in groups of
#: this many rooms (small enough to spread a building over the workers, large enough that sending
#: a group costs little next to assessing it).
ROOMS_PER_TASK = 8
#: Variants files larger than this are not parsed [bytes].
MAX_VARIANTS_BYTES = 1024 * 1024
#: What a variant may be called: it names a folder.
VARIANT_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")


# --- variants ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class Variant:
    """A named set of ``--set`` overrides (``key.path=value``) applied to a project."""

    name: str
    overrides: tuple[str, ...] = ()


def _override(key, value) -> str:
    """``key=value`` with the value written as YAML flow (JSON is YAML), read back as it was."""
    return f"{key}={json.dumps(value, ensure_ascii=False)}"


def load_variants(path: Path) -> list[Variant]:
    """Read a variants file: a YAML list of ``{name: NAME, set: {key.path: value, ...}}`` (``set``
    may also be a list of ``key.path=value`` strings, or left out for the project as it is).

    Raises :class:`InputError` naming the file, the item and what to do.
    """
    from en17037cli.project.yaml12 import parse_yaml_or_fail

    where = f"--variants {path}"
    try:
        if path.stat().st_size > MAX_VARIANTS_BYTES:
            raise InputError(f"{where}: over {MAX_VARIANTS_BYTES // 1024} kB; a variants file lists override sets, not geometry")
        text = path.read_bytes().decode("utf-8-sig")
    except FileNotFoundError:
        raise InputError(f"{where}: file not found; give a YAML list of variants (name and set)") from None
    except UnicodeDecodeError as exc:
        raise InputError(f"{where}: not UTF-8 text (byte {exc.start}); save it as UTF-8") from None
    except OSError as exc:
        raise InputError(f"{where}: cannot read it ({exc.strerror})") from None
    doc = parse_yaml_or_fail(text, where)
    if not isinstance(doc, list) or not doc:
        raise InputError(f"{where}: expected a YAML list of variants, e.g. '- {{name: wide, set: {{view.grid_spacing_m: 1}}}}'")
    out, seen = [], set()
    for i, item in enumerate(doc):
        at = f"{where}: [{i}]"
        if not isinstance(item, dict) or set(item) - {"name", "set"}:
            raise InputError(f"{at}: expected a mapping with 'name' and 'set' (and nothing else)")
        name = item.get("name")
        if not isinstance(name, str) or not VARIANT_NAME.match(name):
            raise InputError(f"{at}: name {name!r}: give each variant a name of letters, digits, '.', '_' or '-' "
                             "(it names the variant's report folder)")
        if name in seen:
            raise InputError(f"{at}: name '{name}' is used twice; give each variant its own name")
        seen.add(name)
        sets = item.get("set") or {}
        if isinstance(sets, dict):
            overrides = tuple(_override(k, v) for k, v in sets.items())
        elif isinstance(sets, list) and all(isinstance(s, str) and "=" in s for s in sets):
            overrides = tuple(sets)
        else:
            raise InputError(f"{at} '{name}': set: expected a mapping key.path: value, or a list of 'key.path=value'")
        out.append(Variant(name, overrides))
    return out


# --- runs ---------------------------------------------------------------------------------------

@dataclass(frozen=True)
class RunSpec:
    """One run as a worker receives it (plain data).

    project : the project file as given; path : the same, absolute (what the worker opens)
    folder : the run's report folder, relative to the batch's folder
    overrides : the batch's ``--set`` then the variant's
    batch : the batch's id, so that a worker's cached sessions never serve another batch
    """

    index: int
    project: str
    path: str
    variant: str = ""
    overrides: tuple[str, ...] = ()
    folder: str = ""
    only: str | None = None
    max_points: int = MAX_POINTS
    rooms_per_task: int = ROOMS_PER_TASK
    batch: str = ""

    @property
    def key(self) -> str:
        """What a worker's session cache is keyed by: the project and everything that changes it."""
        raw = json.dumps([self.batch, self.path, list(self.overrides), self.only, self.max_points])
        return hashlib.sha256(raw.encode("utf-8")).hexdigest()


def _folders(projects: list[str]) -> list[str]:
    """A report folder name per project file: its stem where the stems differ, else its path from
    the files' common folder: the folder alone where every file has the same name
    (``a/project.yaml``, ``b/project.yaml`` -> ``a``, ``b``), else without the suffix."""
    paths = [Path(p).resolve() for p in projects]
    stems = [p.stem for p in paths]
    if len(set(stems)) == len(stems):
        return stems
    common = Path(os.path.commonpath([p.parent for p in paths]))
    parents = [p.parent.relative_to(common).as_posix() for p in paths]
    if len({p.name for p in paths}) == 1 and "." not in parents:
        return parents
    return [p.relative_to(common).with_suffix("").as_posix() for p in paths]


def plan_runs(projects: list[str], variants: list[Variant] | None = None, overrides: tuple[str, ...] = (),
              only: str | None = None, max_points: int = MAX_POINTS, rooms_per_task: int = ROOMS_PER_TASK) -> list[RunSpec]:
    """Every run of a batch: each project file, times each variant where a variants file is given,
    in that order. Raises :class:`InputError` for a project file given twice."""
    seen: dict[Path, str] = {}
    for p in projects:
        r = Path(p).resolve()
        if r in seen:
            raise InputError(f"{p}: given twice (also as {seen[r]}); give each project file once, use --variants for variants")
        seen[r] = p
    batch = uuid.uuid4().hex
    specs: list[RunSpec] = []
    for project, folder in zip(projects, _folders(projects)):
        for v in variants or [Variant("")]:
            specs.append(RunSpec(index=len(specs), project=str(project), path=str(Path(project).resolve()), variant=v.name,
                                 overrides=tuple(overrides) + v.overrides, folder=f"{folder}/{v.name}" if v.name else folder,
                                 only=only, max_points=max_points, rooms_per_task=rooms_per_task, batch=batch))
    return specs

