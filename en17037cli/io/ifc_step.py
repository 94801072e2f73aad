"""The STEP (ISO 10303-21) text of an IFC file before ifcopenshell reads it: what authoring tools
get wrong in it, repaired where the intent is plain, and a check that every instance was read.

References: ISO 10303-21:2016 clause 12.2.2 (an attribute written ``*`` is a derived attribute
redeclared by a subtype; an unset optional attribute is ``$``).
"""
from __future__ import annotations

import re
from pathlib import Path

from en17037cli.errors import InputError

#: One instance on one line: ``#12= IFCWINDOW(...);`` (id, entity, arguments).
_INSTANCE = re.compile(rb"(?m)^[ \t]*(#\d+[ \t]*=[ \t]*)([A-Za-z0-9_]+)[ \t]*\((.*)\)[ \t]*;[ \t]*\r?$")
#: A ``*`` standing alone as an argument.
_STAR = re.compile(rb"[(,][ \t]*\*[ \t]*[,)]")
#: Tokens of a STEP argument list: strings (with '' escapes), brackets, commas, anything else.
_TOKEN = re.compile(rb"'(?:[^']|'')*'|[(),]|[^'(),]+")


def top_level_arguments(args: bytes) -> list[bytes]:
    """The arguments of one instance (the text between its outer brackets), split at top-level commas."""
    out, depth, cur = [], 0, []
    for tok in _TOKEN.findall(args):
        if tok == b"(":
            depth += 1
        elif tok == b")":
            depth -= 1
        elif tok == b"," and depth == 0:
            out.append(b"".join(cur))
            cur = []
            continue
        cur.append(tok)
    out.append(b"".join(cur))
    return out


def repair_derived_markers(data: bytes, schema_name: str) -> tuple[bytes, int, set[str]]:
    """``data`` with each ``*`` written for an attribute that the schema does not derive replaced by
    ``$`` (unset), the number replaced, and the entities that had them.

    Some exporters (Renga Architecture 2.x) write ``*`` for unset optional attributes (Name,
    Description, ObjectType of every element). ifcopenshell then cannot read those attributes and
    its geometry iterator silently leaves the element out: a house's windows and walls vanish.
    Only single-line instances with such a token are touched; valid ``*`` (the derived attributes
    of IfcGeometricRepresentationSubContext, say) stay.
    """
    if not _STAR.search(data):
        return data, 0, set()
    import ifcopenshell.ifcopenshell_wrapper as wrapper

    schema = wrapper.schema_by_name(schema_name)
    derived: dict[bytes, list[bool] | None] = {}
    count = 0
    entities: set[str] = set()

    def fix(m: re.Match) -> bytes:
        nonlocal count
        body = m.group(3)
        if not _STAR.search(b"(" + body + b")"):
            return m.group(0)
        ent = m.group(2).upper()
        if ent not in derived:
            try:
                derived[ent] = list(schema.declaration_by_name(ent.decode("ascii")).derived())
            except Exception:  # an entity the schema does not know: ifcopenshell will say so
                derived[ent] = None
        flags = derived[ent]
        if flags is None:
            return m.group(0)
        args = top_level_arguments(body)
        changed = [b"$" if a.strip() == b"*" and k < len(flags) and not flags[k] else a for k, a in enumerate(args)]
        n = sum(a is not b for a, b in zip(args, changed))
        if not n:
            return m.group(0)
        count += n
        entities.add(m.group(2).decode("ascii"))
        return m.group(1) + m.group(2) + b"(" + b",".join(changed) + b");"

    return _INSTANCE.sub(fix, data), count, entities


def check_all_read(path: Path, data: bytes, f) -> None:
    """InputError naming the line where ifcopenshell stopped, when it read fewer instances than the
    file defines: on a broken STEP line it may stop without an error, and a model read in part
    would give a wrong answer, not a failed one."""
    read = len(f.entity_names())
    if read >= data.count(b"\n#"):  # cheap: no more instance lines than instances read
        return
    defined = [(int(m.group(1)), m.start()) for m in re.finditer(rb"(?m)^[ \t]*#(\d+)[ \t]*=", data)]
    if read >= len(defined):
        return
    names = set(f.entity_names())
    k = next(i for i, (sid, _) in enumerate(defined) if sid not in names)
    sid, offset = defined[k]  # the first instance missing: reading stopped on its line
    line = data.count(b"\n", 0, offset) + 1
    raise InputError(f"{path}: broken IFC (STEP) data at line {line} (#{sid}): only {read} of {len(defined)} instances "
                     "could be read; re-export the model or repair that line")


#: Schemas ifcopenshell does not read whose entities IFC2X3 kept nearly unchanged (IFC2x Edition 2
#: and IFC2x of 2000-2003: Autodesk Architectural Desktop, ArchiCAD 8 to 10, Allplan 2004 exports).
OLDER_SCHEMAS = (b"IFC2X_FINAL", b"IFC2X2_FINAL", b"IFC2X2", b"IFC2X")
_FILE_SCHEMA = re.compile(rb"FILE_SCHEMA\s*\(\s*\(\s*'([A-Za-z0-9_]+)'\s*\)\s*\)")


def as_ifc2x3(data: bytes) -> tuple[bytes, str | None]:
    """``data`` with an older schema named in its header (:data:`OLDER_SCHEMAS`) renamed IFC2X3, and
    the old name; ``data`` and None for any other file. IFC2X3 (2006) is IFC2x2 with additions: the
    classes this tool reads (products, their placements and shape representations, openings,
    fillings, spaces) have the same attributes, so the text reads as it stands."""
    m = _FILE_SCHEMA.search(data, 0, 20_000)
    if m is None or m.group(1).upper() not in OLDER_SCHEMAS:
        return data, None
    return data[:m.start(1)] + b"IFC2X3" + data[m.end(1):], m.group(1).decode("ascii")


def open_ifc(path: Path) -> tuple[object, list[str]]:
    """The ifcopenshell file of ``path`` and notes on what was repaired before reading it."""
    try:
        import ifcopenshell  # noqa: F401  (the extra is named before anything is read)
    except ImportError:
        raise InputError(f"{path}: reading IFC needs ifcopenshell: pip install 'en17037cli[ifc]'") from None
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read model file: {exc.strerror}") from None
    if not data[:64].lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"ISO-10303-21"):
        raise InputError(f"{path}: not an IFC file (no ISO-10303-21 header); export the model as IFC (STEP)")
    notes = []
    data, older = as_ifc2x3(data)
    if older:
        notes.append(f"{path.name}: schema {older} (before IFC2X3), read as IFC2X3, which kept its classes: check "
                     "validate's spaces and windows; ask for an IFC2X3 or IFC4 export if some are missing")
    try:
        f = read_ifc_file(path, data, changed=bool(older))
    except Exception as exc:  # ifcopenshell raises its own error types for broken STEP
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise InputError(f"{path}: cannot read the IFC file ({msg}); ask for an IFC2X3 or IFC4 export of the model") from None
    if f.schema not in ("IFC2X3", "IFC4", "IFC4X3", "IFC4X3_ADD2"):
        raise InputError(f"{path}: IFC schema {f.schema} is not read; ask for an IFC2X3, IFC4 or IFC4X3 export of the model")
    check_all_read(path, data, f)
    fixed, count, entities = repair_derived_markers(data, getattr(f, "schema_identifier", f.schema))  # IFC4X3_ADD2, not IFC4X3
    if count:
        f = read_ifc_file(path, fixed, changed=True)
        names = ", ".join(sorted(entities)[:4]) + (" ..." if len(entities) > 4 else "")
        notes.append(f"{path.name}: {count} attribute(s) written '*' (derived) where the schema stores a value read as "
                     f"unset ('$'), in {names}: not valid STEP (ISO 10303-21 12.2.2); without this ifcopenshell leaves "
                     "those elements out")
    return f, notes


def read_ifc_file(path: Path, data: bytes, changed: bool):
    """ifcopenshell's file of ``path``, or of ``data`` where the text was changed before reading
    (ifcopenshell reads files: the changed text goes through a temporary one)."""
    import ifcopenshell

    if not changed:
        return ifcopenshell.open(str(path))
    import tempfile

    with tempfile.TemporaryDirectory(prefix="en17037-ifc-") as tmp:
        p = Path(tmp) / "repaired.ifc"
        p.write_bytes(data)
        return ifcopenshell.open(str(p))
