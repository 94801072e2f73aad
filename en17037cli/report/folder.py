"""The report folder: only ever replace what this tool wrote there for the same project, and make a
new set of reports appear at once.

A small manifest (:data:`MANIFEST`) beside the reports names the project file they belong to and
the files written. Before a run, :func:`check_folder` refuses a folder holding report files that
the manifest does not claim for this project (another project's, or a user's own ``report.json``);
other files in the folder are never touched. :func:`commit` writes the new set into a temporary
folder in the same parent, then moves it in with SIGINT and SIGTERM held back, so a signal never
leaves half a set; temporaries are removed on any exit.
"""
from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import signal
import tempfile
from pathlib import Path

from en17037cli.errors import InputError

#: The manifest's file name, in the report folder.
MANIFEST = ".en17037-manifest.json"
#: Temporary folders of unfinished writes start with this.
TMP_PREFIX = ".en17037-tmp-"


def default_folder(project_file: Path) -> Path:
    """``en17037-report/<project file stem>/`` beside the project file: one folder per project file."""
    return project_file.parent / "en17037-report" / project_file.stem


def read_manifest(folder: Path) -> dict | None:
    """The manifest of a report folder, or None where there is none (or it is not ours)."""
    try:
        doc = json.loads((folder / MANIFEST).read_text("utf-8"))
    except (OSError, ValueError):
        return None
    return doc if isinstance(doc, dict) and doc.get("tool") == "en17037cli" else None


def _problem(exc: OSError) -> str:
    return os.strerror(exc.errno) if exc.errno else str(exc)


def check_folder(folder: Path, project_file: Path, names) -> None:
    """Raise :class:`InputError` unless the reports ``names`` can be written into ``folder``.

    The folder (or its nearest existing parent) must be a writable folder, and every report file
    already there must be one this tool wrote for ``project_file``.
    """
    folder = Path(folder)
    where = f"--out {folder}"
    probe = folder
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if probe.exists() and not probe.is_dir():
        raise InputError(f"{where}: {probe} is a file, not a folder; choose another report folder")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise InputError(f"{where}: {probe} is not writable; choose another report folder")
    if not folder.is_dir():
        return
    manifest = read_manifest(folder)
    ours = set(manifest["files"]) if manifest and manifest.get("project") == str(project_file.resolve()) else set()
    foreign = sorted(n for n in names if (folder / n).exists() and n not in ours)
    if foreign:
        owner = f"project {manifest['project']}" if manifest else "someone else (no en17037 manifest)"
        raise InputError(f"{where}: {foreign[0]} there was written by {owner}, not for {project_file.name}; "
                         "choose another report folder or remove it")


@contextlib.contextmanager
def signals_held():
    """Hold SIGINT, SIGTERM and SIGHUP back (delivered on exit) while the block runs in the main thread."""
    sigs = {signal.SIGINT, signal.SIGTERM, signal.SIGHUP}
    try:
        old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
    except (ValueError, OSError):  # not the main thread: nothing to hold
        yield
        return
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def commit(folder: Path, project_file: Path, contents: dict[str, bytes]) -> list[Path]:
    """Write ``contents`` (file name -> bytes) as the report set of ``project_file`` in ``folder``.

    The files are written and flushed into a temporary folder beside ``folder``; the set then
    replaces the earlier one (the files the old manifest names) with signals held back. A new
    folder appears by one rename. Raises :class:`InputError` where the folder cannot be written.
    """
    folder = Path(folder)
    manifest = {"tool": "en17037cli", "project": str(project_file.resolve()), "files": sorted(contents)}
    data = dict(contents) | {MANIFEST: (json.dumps(manifest, indent=2) + "\n").encode("utf-8")}
    try:
        folder.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=TMP_PREFIX, dir=folder.parent))
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)  # a new report folder gets the user's usual mode, not mkdtemp's 0700
    except OSError as exc:
        raise InputError(f"--out {folder}: cannot write there ({_problem(exc)}); choose another report folder") from None
    try:
        for name, blob in data.items():
            (tmp / name).parent.mkdir(parents=True, exist_ok=True)  # figures/
            with open(tmp / name, "wb") as fh:
                fh.write(blob)
                fh.flush()
                os.fsync(fh.fileno())
        with signals_held():
            if not folder.exists():
                os.rename(tmp, folder)
            else:
                old = read_manifest(folder)
                for name in sorted(set(old["files"]) - set(contents)) if old else ():
                    with contextlib.suppress(FileNotFoundError):
                        (folder / name).unlink()  # a report of ours the new set does not have
                    with contextlib.suppress(OSError):
                        if (folder / name).parent != folder:
                            (folder / name).parent.rmdir()  # its sub-folder, once empty
                for name in data:
                    (folder / name).parent.mkdir(parents=True, exist_ok=True)
                    os.replace(tmp / name, folder / name)
    except OSError as exc:
        if exc.errno in (errno.ENOSPC, errno.EACCES, errno.EROFS, errno.EPERM, errno.ENOTDIR, errno.EEXIST):
            raise InputError(f"--out {folder}: cannot write the reports ({_problem(exc)}); choose another report folder") from None
        raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return [folder / n for n in contents]


def check_file(path: Path, flag: str) -> None:
    """Raise :class:`InputError` unless a single output file (``--junit FILE``) can be written at ``path``."""
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{flag} {path}: is a folder; give a file name, e.g. {path / 'junit.xml'}")
    probe = path.parent
    while not probe.exists() and probe.parent != probe:
        probe = probe.parent
    if not probe.is_dir():
        raise InputError(f"{flag} {path}: {probe} is a file, not a folder; choose another file name")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise InputError(f"{flag} {path}: {probe} is not writable; choose another file name")


def write_file(path: Path, data: bytes, flag: str) -> None:
    """Write one output file whole: into a temporary file beside it, then moved over it at once."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=TMP_PREFIX, dir=path.parent)
    except OSError as exc:
        raise InputError(f"{flag} {path}: cannot write there ({_problem(exc)}); choose another file name") from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)  # mkstemp's 0600 would make the file private
        os.replace(tmp, path)
    except OSError as exc:
        raise InputError(f"{flag} {path}: cannot write it ({_problem(exc)}); choose another file name") from None
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
