"""Layers of faces: the project's rules matched against each part's names and attributes."""
from __future__ import annotations

import fnmatch

import numpy as np

from en17037cli.errors import InputError
from en17037cli.io.mesh import Mesh, Part
from en17037cli.project.settings import LayerRule, ModelFile
from en17037cli.scene.model import LAYERS


def layer_code(layer: str) -> int:
    """Code of a layer name in :data:`~en17037cli.scene.model.LAYERS`; -1 for ``ignore``."""
    return -1 if layer == "ignore" else LAYERS.index(layer)


def own_names(part: Part) -> list[str]:
    """The part's own names a rule's ``match`` glob is tested on: each attribute value, whole and
    word by word (so ``match: window`` finds the group 'window 3')."""
    out = []
    for value in (v for k, v in part.attrs.items() if k != "file"):
        if value:
            out.append(value)
            out.extend(value.split())
    return out


def by_stem(rules, parts: list[Part], stem: str) -> list[bool]:
    """Per rule, whether its ``match`` glob may place a part by the file's name (``stem``, whole and
    word by word): only where the glob names no object of the file. A rule that names objects of a
    file is about objects there, so the file's name does not decide for the others (``glass*`` in a
    file called ``glasshouse.obj`` is the glass, not every wall); one that names none places the
    whole file (``*window*`` for ``ref_room_window.obj`` whose only object is ``Mesh``)."""
    names = sorted({c for part in parts for c in own_names(part)})
    return [r.match is not None and not fnmatch.filter(names, r.match) for r in rules]


def match_candidates(part: Part, stem: str, with_stem: bool = True) -> list[str]:
    """Every string a rule's ``match`` glob is tested on: the part's :func:`own_names`, and the file
    stem (whole and word by word) where ``with_stem`` (:func:`by_stem`)."""
    out = own_names(part)
    if with_stem and stem:
        out += [stem, *stem.split()]
    return out or [""]


def rule_matches(rule: LayerRule, part: Part, candidates: list[str]) -> bool:
    """Whether every glob of ``rule`` matches: ``match`` one of the part's names, each key its attribute."""
    if rule.match is not None and not any(fnmatch.fnmatchcase(c, rule.match) for c in candidates):
        return False
    return all(key in part.attrs and fnmatch.fnmatchcase(part.attrs[key], glob) for key, glob in rule.keys)


def assign_layers(spec: ModelFile, mesh: Mesh, where: str, stem: str) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Per-part layer code (-1 for ignore) and obstructs_sun flag of one model file, and warnings.

    A file-wide ``layer`` wins; otherwise the first rule whose glob matches one of the part's
    names, or the file's name where the glob names no object of the file (:func:`by_stem`); otherwise the format's default layer of the part (IFC and
    CityJSON class tables). A part that none of these places is an input error naming it. A rule
    that places no part (a typo such as ``Tree*`` for ``tree_1``) is a warning.
    """
    n = len(mesh.parts)
    if spec.layer is not None:
        by_part = np.full(n, layer_code(spec.layer))
        sun = np.full(n, spec.obstructs_sun)
        return by_part, sun, []
    by_part = np.empty(n, dtype=int)
    sun = np.empty(n, dtype=bool)
    used = [False] * len(spec.rules)
    stem_ok = by_stem(spec.rules, mesh.parts, stem)
    for i, part in enumerate(mesh.parts):  # one pass per part (a named object), not per face
        candidates = (match_candidates(part, stem, False), match_candidates(part, stem, True))
        for k, rule in enumerate(spec.rules):
            if rule_matches(rule, part, candidates[stem_ok[k]]):
                by_part[i] = layer_code(rule.layer)
                sun[i] = rule.obstructs_sun
                used[k] = True
                break
        else:
            if part.layer is not None:
                by_part[i] = layer_code(part.layer)
                sun[i] = part.obstructs_sun
                continue
            faces = np.flatnonzero(mesh.part == i)
            first = int(faces[0]) if len(faces) else 0
            label = ", ".join(f"'{v}'" for k, v in part.attrs.items() if k != "file") or "(no name)"
            raise InputError(
                f"{where}.layers: face {first} ({label}) matches no layer rule; "
                "add a rule for it or end the list with {match: \"*\", layer: ...}"
            )
    warnings = [f"{where}.layers[{k}] ({r.describe()}, layer: {r.layer}): matches no object of {spec.display}; "
                "check the name (validate --objects lists them)" for k, (r, u) in enumerate(zip(spec.rules, used))
                if not u and not (r.match == "*" and not r.keys)]
    return by_part, sun, warnings


def assign_optics(spec: ModelFile, mesh: Mesh, stem: str) -> np.ndarray | None:
    """Per-part (reflectance, transmittance) from the first rule that places the part (as
    :func:`assign_layers` picks it), NaN where the rule gives none (the daylight defaults apply);
    None when no rule of the file gives either (the usual case: nothing to carry)."""
    if spec.layer is not None or not any(r.reflectance is not None or r.transmittance is not None for r in spec.rules):
        return None
    out = np.full((len(mesh.parts), 2), np.nan)
    stem_ok = by_stem(spec.rules, mesh.parts, stem)
    for i, part in enumerate(mesh.parts):  # one pass per part, not per face
        candidates = (match_candidates(part, stem, False), match_candidates(part, stem, True))
        rule = next((r for k, r in enumerate(spec.rules) if rule_matches(r, part, candidates[stem_ok[k]])), None)
        if rule is not None:
            out[i] = [np.nan if rule.reflectance is None else rule.reflectance,
                      np.nan if rule.transmittance is None else rule.transmittance]
    return out
