"""Wavefront OBJ reader: n-gons, concave ones included, ear-clipped in their best-fit plane.

trimesh's OBJ reader fans n-gons, which adds area outside a concave polygon (the seed scene's
buildings would load 19 % too large), so OBJ is read here.

The whole file is read at once and split with numpy (:func:`_read_fast`): statements are found
by the bytes that start each line, the numbers of every ``v`` and ``f`` line are split in one
step and converted by Python's own ``float`` and ``int``. Anything out of the ordinary (a line
the line-by-line reader :func:`_read_lines` would refuse, unusual whitespace, non-ASCII in a
vertex or face line, indentation) goes to that reader, which gives the messages; both give the
same mesh for every file the fast path takes.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangulate_polygons
from en17037cli.io.mesh import Mesh, Part
from en17037cli.io.registry import ReadOptions, register


@register(".obj")
def read_obj(path: Path, options: ReadOptions | None = None) -> Mesh:
    """Read a Wavefront OBJ file: ``v``, ``f`` (any ``v/vt/vn`` form, negative indices),
    ``o``, ``g`` and ``usemtl`` for names. Other statements are ignored."""
    try:
        got = _read_fast(path.read_bytes())  # the bytes are freed as soon as they are decoded
    except OSError as exc:
        raise InputError(f"{path}: cannot read model file: {exc.strerror}") from None
    if got is None:
        return _read_lines(path)
    verts, flat, sizes, face_names, keys, bad_faces = got
    warnings: list = []
    if bad_faces:
        warnings.append(f"{path.name}: {bad_faces} faces with fewer than 3 vertices dropped")
    if len(sizes) == 0:
        raise InputError(f"{path}: no faces found; is this an OBJ model file?")
    tris, tri_names, n_failed = _triangulate_flat(verts, flat, sizes, face_names)
    if n_failed:
        warnings.append(f"{path.name}: {n_failed} polygons could not be fully triangulated (self-intersecting or degenerate); their remaining area was dropped")
    parts = [Part({"object": o, "group": g, "material": m}) for (o, g, m) in keys]
    return Mesh(verts, tris, tri_names, parts, warnings)


#: Bytes that ``str.split`` takes for whitespace and ``bytes.split`` does not, or that end a line
#: for ``str.splitlines`` only: files holding any go to the line-by-line reader.
_ODD_SPACE = (0x0B, 0x0C, 0x1C, 0x1D, 0x1E, 0x1F)


#: Bytes of ``-?digits[.digits]`` numbers and the spaces between them.
_DECIMAL_BYTES = np.zeros(256, dtype=bool)
_DECIMAL_BYTES[list(b"0123456789.- \t")] = True


def _plain_decimals(b: np.ndarray, t0: np.ndarray, t1: np.ndarray) -> bool:
    """Whether every token (bytes ``b``, tokens [t0, t1)) is ``-?digits[.digits]`` with digits on
    at least one side of the point: numbers numpy's text parser reads exactly as ``float`` does."""
    if not _DECIMAL_BYTES[b].all():
        return False
    minus = np.flatnonzero(b == ord("-"))
    if len(np.setdiff1d(minus, t0, assume_unique=True)):  # a minus sign inside a token
        return False
    dots = np.bincount(np.searchsorted(t0, np.flatnonzero(b == ord(".")), side="right") - 1, minlength=len(t0))
    signs = b[t0] == ord("-")
    return bool(dots.max(initial=0) <= 1 and ((t1 - t0) - dots - signs >= 1).all())


def _read_fast(data: bytes):
    """The OBJ file ``data`` split with numpy: vertices (n, 3) float64, face vertex indices
    (flat, 0-based), vertices per face, part of each face, part keys (object, group, material)
    in order of first use, faces dropped for fewer than 3 vertices; None for a file the
    line-by-line reader must read (see the module's docstring)."""
    buf = data.decode("utf-8-sig", errors="replace").encode("utf-8")  # as the text-mode reader decodes it
    del data
    if b"\r" in buf:  # universal newlines
        buf = buf.replace(b"\r\n", b"\n").replace(b"\r", b"\n")
    if not buf.endswith(b"\n"):
        buf += b"\n"
    arr = np.frombuffer(buf, dtype=np.uint8)
    if any(bytes([c]) in buf for c in _ODD_SPACE):
        return None
    nl = np.flatnonzero(arr == 10)
    starts = np.r_[0, nl[:-1] + 1]
    last = len(arr) - 1

    def at(k):  # byte k of each line (the final newline past the end of the buffer)
        return arr[np.minimum(starts + k, last)]

    def is_space(c):
        return (c == 32) | (c == 9)

    def ends(c):  # whitespace or the end of the line
        return is_space(c) | (c == 10)

    c0, c1 = at(0), at(1)
    if (c0 >= 128).any() or (c0 == 0).any():  # a line opening with non-ASCII whitespace, or a NUL
        return None
    indented = is_space(c0)
    if indented.any():  # an indented statement; blank lines of spaces are fine
        for i in np.flatnonzero(indented):
            if buf[starts[i]:nl[i]].strip():
                return None
    letter = (c0 == ord("v")) | (c0 == ord("f")) | (c0 == ord("o")) | (c0 == ord("g"))
    if (letter & (c1 >= 128)).any():  # a tag followed by non-ASCII whitespace, perhaps
        return None
    is_v = (c0 == ord("v")) & ends(c1)
    is_f = (c0 == ord("f")) & ends(c1)
    is_name = ((c0 == ord("o")) | (c0 == ord("g"))) & ends(c1)
    usemtl = np.ones(len(starts), dtype=bool)
    for k, ch in enumerate(b"usemtl"):
        usemtl &= at(k) == ch
    if (usemtl & (at(6) >= 128)).any():
        return None
    is_name |= usemtl & ends(at(6))
    # the numbers of v and f lines: the bytes after the one-letter tag up to the newline
    line_len = nl - starts + 1

    def tokens(mask):
        """(bytes of the lines in ``mask`` after their tag, tokens per line, longest token), or None if not plain ASCII."""
        sel = np.repeat(mask, line_len)
        sel[starts[mask]] = False  # the tag
        b = arr[sel]
        b[b == 10] = 32  # each line's newline: a space between its last token and the next line's first
        if (b >= 128).any():
            return None
        sp = is_space(b)
        t0 = np.flatnonzero(~sp & np.r_[True, sp[:-1]])  # token starts and ends
        t1 = np.flatnonzero(~sp & np.r_[sp[1:], True]) + 1
        seg = line_len[mask] - 1
        line = np.searchsorted(np.cumsum(seg) - seg, t0, side="right") - 1  # of each token
        count = np.bincount(line, minlength=len(seg))
        return b.tobytes(), count, int((t1 - t0).max(initial=0)), _plain_decimals(b, t0, t1)

    vt, ft = tokens(is_v), tokens(is_f)
    if vt is None or ft is None:
        return None
    vbytes, vcount, _, plain = vt
    if len(vcount) and vcount.min() < 3:
        return None
    verts = None
    if (vcount == 3).all() and plain:  # what float() reads, in C
        verts = np.fromstring(vbytes, dtype=np.float64, sep=" ")
        verts = verts.reshape(-1, 3) if len(verts) == 3 * len(vcount) else None
    try:
        if verts is not None:
            pass
        elif (vcount == 3).all():
            verts = np.array(list(map(float, vbytes.split())), dtype=np.float64).reshape(-1, 3)
        else:  # x y z of lines with more numbers (w, colours)
            vtok = vbytes.split()
            first = np.repeat(np.cumsum(vcount) - vcount, 3) + np.tile(np.arange(3), len(vcount))
            verts = np.array(list(map(float, [vtok[i] for i in first])), dtype=np.float64).reshape(-1, 3)
    except ValueError:
        return None
    # faces: each token's vertex index is what comes before its first '/'
    fbytes, fcount, longest, _ = ft
    if b"/" in fbytes:
        import re

        fbytes = re.sub(rb"/[^ \t]*", b"", fbytes)
        longest = 99  # not known any more
    try:
        if longest < 18 and not fbytes.translate(None, b"0123456789 \t"):
            idx = np.fromstring(fbytes, dtype=np.int64, sep=" ")  # digits only: what int() reads, in C
        else:
            idx = np.array(list(map(int, fbytes.split())), dtype=np.int64)
    except (ValueError, OverflowError):
        return None
    if len(idx) != fcount.sum():  # a token opening with '/' has no vertex index
        return None
    # vertices defined before each face line (negative indices count back from there)
    nv_before = np.cumsum(is_v)[is_f]
    nvf = np.repeat(nv_before, fcount)
    idx = np.where(idx > 0, idx - 1, nvf + idx)
    face_of = np.repeat(np.arange(len(fcount)), fcount)
    bad_index = (idx < 0) | (idx >= nvf)
    short = fcount < 3
    if (bad_index & ~short[face_of]).any():
        return None  # the line-by-line reader names the line
    keep = ~short
    flat, sizes = idx[keep[face_of]], fcount[keep]
    # parts: the (object, group, material) in force at each kept face, numbered by first use
    name_lines = np.flatnonzero(is_name)
    state_keys = [("", "", "")]
    o = g = m = ""
    for i in name_lines:  # one step per o / g / usemtl statement
        words = buf[starts[i]:nl[i]].decode("utf-8").split()
        value = " ".join(words[1:])
        if words[0] == "o":
            o = value
        elif words[0] == "g":
            g = value
        else:
            m = value
        state_keys.append((o, g, m))
    state = np.searchsorted(name_lines, np.flatnonzero(is_f)[keep])  # statements before each kept face
    # a new part starts at a face after a statement; the same key again is the same part
    used, first_use = np.unique(state, return_index=True)
    names: dict = {}
    part_of_state = np.zeros(len(state_keys), dtype=np.int64)
    for st in used[np.argsort(first_use)]:
        part_of_state[st] = names.setdefault(state_keys[st], len(names))
    return verts, flat, sizes, part_of_state[state], list(names), int(np.count_nonzero(short))


def _read_lines(path: Path) -> Mesh:
    """Read a Wavefront OBJ file line by line (the reference for :func:`_read_fast`, and its messages)."""
    vertices: list = []
    faces: list = []
    face_names: list = []
    names: dict = {}
    obj, group, mtl = "", "", ""
    current = None
    warnings: list = []
    bad_faces = 0
    try:
        fh = path.open("r", encoding="utf-8-sig", errors="replace")  # -sig: a byte-order mark is not part of line 1
    except OSError as exc:
        raise InputError(f"{path}: cannot read model file: {exc.strerror}") from None
    with fh:
        for lineno, line in enumerate(fh, 1):
            if not line or line[0] == "#":
                continue
            parts = line.split()
            if not parts:
                continue
            tag = parts[0]
            if tag == "v":
                try:
                    vertices.append((float(parts[1]), float(parts[2]), float(parts[3])))
                except (ValueError, IndexError):
                    raise InputError(f"{path}:{lineno}: corrupt OBJ vertex line {line.strip()[:60]!r}; re-export the model") from None
            elif tag == "f":
                nv = len(vertices)
                try:
                    idx = [int(p.split("/", 1)[0]) for p in parts[1:]]
                except ValueError:
                    raise InputError(f"{path}:{lineno}: corrupt OBJ face line {line.strip()[:60]!r}; re-export the model") from None
                idx = [i - 1 if i > 0 else nv + i for i in idx]
                if len(idx) < 3 or min(idx) < 0 or max(idx) >= nv:
                    if len(idx) >= 3:
                        raise InputError(f"{path}:{lineno}: face refers to a vertex that does not exist; re-export the model")
                    bad_faces += 1
                    continue
                if current is None:
                    key = (obj, group, mtl)
                    current = names.setdefault(key, len(names))
                faces.append(idx)
                face_names.append(current)
            elif tag == "o":
                obj = " ".join(parts[1:])
                current = None
            elif tag == "g":
                group = " ".join(parts[1:])
                current = None
            elif tag == "usemtl":
                mtl = " ".join(parts[1:])
                current = None
    if bad_faces:
        warnings.append(f"{path.name}: {bad_faces} faces with fewer than 3 vertices dropped")
    if not faces:
        raise InputError(f"{path}: no faces found; is this an OBJ model file?")
    verts = np.array(vertices, dtype=np.float64).reshape(-1, 3)
    sizes = np.fromiter((len(f) for f in faces), dtype=np.int64, count=len(faces))
    flat = np.fromiter((i for f in faces for i in f), dtype=np.int64, count=int(sizes.sum()))
    tris, tri_names, n_failed = _triangulate_flat(verts, flat, sizes, np.asarray(face_names, dtype=np.int64))
    if n_failed:
        warnings.append(f"{path.name}: {n_failed} polygons could not be fully triangulated (self-intersecting or degenerate); their remaining area was dropped")
    parts = [Part({"object": o, "group": g, "material": m}) for (o, g, m) in names]  # dicts keep insertion order
    return Mesh(verts, tris, tri_names, parts, warnings)


def _triangulate_flat(verts: np.ndarray, flat: np.ndarray, sizes: np.ndarray, names: np.ndarray):
    """Triangles of all faces (vertex indices ``flat``, ``sizes`` per face, part ``names`` per face):
    triangles as they are, in file order, then quads and n-gons ear-clipped, grouped by vertex count."""
    offsets = np.cumsum(sizes) - sizes
    out_tris = []
    out_names = []
    tri_mask = sizes == 3
    if tri_mask.any():
        out_tris.append(flat[offsets[tri_mask, None] + np.arange(3)].astype(int))
        out_names.append(names[tri_mask].astype(int))
    n_failed = 0
    for k in np.unique(sizes[~tri_mask]):  # polygons grouped by vertex count
        rows = np.flatnonzero(sizes == k)
        idx = flat[offsets[rows, None] + np.arange(k)].astype(int)
        for r, ix, local in zip(rows, idx, triangulate_polygons(verts[idx])):  # one step per polygon (earcut's API)
            if len(local) < k - 2:
                n_failed += 1
            if len(local):
                out_tris.append(ix[local])
                out_names.append(np.full(len(local), names[r]))
    if not out_tris:
        return np.zeros((0, 3), dtype=int), np.zeros(0, dtype=int), n_failed
    return np.concatenate(out_tris), np.concatenate(out_names), n_failed
