"""Atomic file output, so an interrupted or failed build never leaves half-written files.

Two helpers (docs/outputs.md: "files are written atomically"):

* :func:`atomic_write` writes one file: the bytes go to a temporary file in the same
  folder, are flushed to disk, and the temporary file is renamed over the target with
  :func:`os.replace` (atomic on POSIX and Windows when both are on one file system).
* :func:`atomic_output_dir` stages a whole build: exporters write into a locked
  staging folder inside the target; only when every exporter has succeeded are the
  files moved into the target, each with :func:`os.replace`. If anything fails, the
  staging folder is removed and the target is left exactly as it was.

The target folder itself is never deleted or swapped wholesale (``--out .`` must not
wipe a user's working directory), and a build replaces or removes only files that it
or an earlier build of the same name wrote (:mod:`cga.output_record`).
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import shutil
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING

from .errors import ExportError

if TYPE_CHECKING:  # pragma: no cover
    from .output_record import OutputFormats

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]

__all__ = ["atomic_write", "atomic_output_dir", "remove_stale_staging", "lock_exclusive",
           "lock_shared",
           "OutputConflictError", "STAGING_PREFIX"]

STAGING_PREFIX = ".cga-staging-"
"""Names of staging folders inside an output folder (``.cga-staging-<pid>-<random>``)."""

_staging_folder: contextvars.ContextVar[Path | None] = contextvars.ContextVar(
    "cga_staging_folder", default=None)
"""The staging folder of the innermost :func:`atomic_output_dir`, if any. Files written
inside it skip their own fsync: the folder is flushed once before it is committed (a
URDF export writes hundreds of files, and one fsync each dominated its cost)."""


def _default_file_mode() -> int:
    """Permissions an ordinary ``open(path, "w")`` would give: 0o666 minus the umask."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def atomic_write(path: str | os.PathLike[str], data: bytes | str) -> Path:
    """Write ``data`` to ``path`` atomically (temporary file + rename).

    Parameters
    ----------
    path:
        Target file. Missing parent folders are created.
    data:
        File contents; ``str`` is encoded as UTF-8 (newlines written as given).

    Returns
    -------
    Path
        The target path.

    Notes
    -----
    Readers see either the old file or the complete new one, never a prefix. The
    temporary file lives in the target's folder so the final rename stays on one file
    system; it is removed if writing fails.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    payload = data.encode("utf-8") if isinstance(data, str) else bytes(data)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    tmp = Path(tmp_name)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(payload)
            handle.flush()
            staging = _staging_folder.get()
            if staging is None or not target.resolve().is_relative_to(staging):
                os.fsync(handle.fileno())
        os.chmod(tmp, _default_file_mode())
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return target


def _flush(files: list[Path]) -> None:
    """Make staged files durable before they are moved into place: one ``sync`` where
    the platform has it, else an fsync per file."""
    if hasattr(os, "sync"):
        os.sync()
        return
    for path in files:
        with open(path, "rb+") as handle:
            os.fsync(handle.fileno())


def lock_exclusive(fd: int) -> bool:
    """Take an exclusive advisory lock on an open file or folder without waiting.

    The kernel drops the lock when the process dies, however it dies (SIGKILL too), so
    a lock that can be taken marks a staging folder nobody is using any more."""
    if fcntl is None:  # no advisory locks (Windows): never treat a folder as stale
        return True
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True


def lock_shared(fd: int) -> bool:
    """Take a shared advisory lock on an open file without waiting: any number of
    holders, but none while someone holds it exclusively (:func:`lock_exclusive`)."""
    if fcntl is None:
        return True
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True


def remove_stale_staging(folder: Path) -> list[Path]:
    """Remove staging folders in ``folder`` left by builds that were killed.

    A live build holds a lock on its staging folder (:func:`_staging_dir`); a folder
    whose lock can be taken belongs to a dead process. Returns the folders removed.
    """
    if fcntl is None:
        return []
    removed = []
    for candidate in sorted(folder.glob(f"{STAGING_PREFIX}*")):
        if candidate.is_symlink() or not candidate.is_dir():
            continue
        try:
            fd = os.open(candidate, os.O_RDONLY | os.O_DIRECTORY)
        except OSError:
            continue
        try:
            if lock_exclusive(fd):
                shutil.rmtree(candidate, ignore_errors=True)
                removed.append(candidate)
        finally:
            os.close(fd)
    return removed


@contextlib.contextmanager
def _staging_dir(final: Path) -> Iterator[Path]:
    """A fresh staging folder inside ``final``, locked for as long as it is in use and
    removed afterwards (also on KeyboardInterrupt and :class:`~cga.interrupts.Terminated`)."""
    for _attempt in range(3):
        staging = Path(tempfile.mkdtemp(prefix=f"{STAGING_PREFIX}{os.getpid()}-", dir=final))
        fd = os.open(staging, os.O_RDONLY | os.O_DIRECTORY)
        # another build's stale-staging sweep may have removed it before the lock was taken
        if lock_exclusive(fd) and os.fstat(fd).st_nlink > 0:
            break
        os.close(fd)
    else:
        raise OSError(f"cannot create a staging folder in {final}")
    try:
        yield staging
    finally:
        shutil.rmtree(staging, ignore_errors=True)
        os.close(fd)


class OutputConflictError(ExportError):
    """The build would replace a file it did not write (or that changed since)."""


@contextlib.contextmanager
def atomic_output_dir(target: str | os.PathLike[str], *, owner: str | None = None,
                      protect: Iterable[str | os.PathLike[str]] = (),
                      formats: "OutputFormats | None" = None) -> Iterator[Path]:
    """Stage output files in a folder inside ``target``; move them in on success.

    Parameters
    ----------
    target:
        The folder that receives the files (created if missing).
    owner:
        The build name. With it, the folder keeps a record of the files this build name
        wrote (:class:`~cga.output_record.OutputRecord`): a file that exists but is not
        recorded (or changed since) is never replaced, the build fails with
        :class:`OutputConflictError` before anything moves; recorded files this build
        does not write again are removed. Without it files are only added or replaced.
    protect:
        Inputs (the grammar, a lot file) that must never be replaced or removed.
    formats:
        With ``owner``: the formats this build writes, and the file → format map the
        caller fills inside the ``with`` block. Recorded files are then removed only
        when one of the requested formats wrote them; the others stay.

    Yields
    ------
    Path
        The staging folder; write the outputs there (under the same relative names they
        should have in ``target``).

    Notes
    -----
    Staging inside ``target`` keeps every rename on one file system and needs no write
    permission on ``target``'s parent (issue 19, defect 6). On an exception inside the
    ``with`` block (Ctrl-C and SIGTERM/SIGHUP under :func:`cga.interrupts.handle_termination`
    included) the staging folder is removed and ``target`` is untouched; the commit
    itself runs with those signals deferred. Staging left by a killed build (SIGKILL) is
    removed by the next build into the same folder (:func:`remove_stale_staging`).
    """
    from . import interrupts

    final = Path(target)
    final.mkdir(parents=True, exist_ok=True)
    remove_stale_staging(final)
    protected = [Path(p) for p in protect]
    with _staging_dir(final) as staging:
        token = _staging_folder.set(staging.resolve())
        try:
            yield staging
        finally:
            _staging_folder.reset(token)
        staged = sorted(p for p in staging.rglob("*") if p.is_file())
        _flush(staged)
        with interrupts.deferred():
            _commit(final, staging, staged, owner, protected, formats)


def _commit(final: Path, staging: Path, staged: list[Path], owner: str | None,
            protect: list[Path], formats: "OutputFormats | None" = None) -> None:
    """Move staged files into ``final``; with an owner, replace and remove only its files."""
    from .output_record import OutputRecord

    relatives = [source.relative_to(staging).as_posix() for source in staged]
    record = None
    if owner is not None:
        record = OutputRecord.load(final, owner)
        conflicts = [name for name in relatives
                     if os.path.lexists(final / name) and not record.owns(name, protect)]
        if conflicts:
            raise OutputConflictError(_conflict_message(final, owner, conflicts))
        # list the new files before they move in: a build stopped while moving still
        # owns what it moved (staged files are older than the record)
        record.save(record.files | set(relatives), staging,
                    {**record.formats, **(formats.files if formats else {})})
    for name, source in zip(relatives, staged):
        destination = final / name
        destination.parent.mkdir(parents=True, exist_ok=True)
        os.replace(source, destination)
    if record is not None:
        kept = record.remove_unless(relatives, protect,
                                    formats.requested if formats else None)
        record.save(set(relatives) | kept, staging, record.formats)


def _conflict_message(final: Path, owner: str, conflicts: list[str]) -> str:
    one = len(conflicts) == 1
    shown = ", ".join(str(final / name) for name in conflicts[:3])
    more = f" and {len(conflicts) - 3} more" if len(conflicts) > 3 else ""
    return (f"cannot write into {final}: {shown}{more} already exist{'s' * one} and no "
            f"earlier build of '{owner}' wrote {'it' if one else 'them'} (or "
            f"{'it was' if one else 'they were'} changed since); a build replaces only its "
            f"own files: move {'it' if one else 'them'} away or choose another --out")
