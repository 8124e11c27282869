"""Atomic file output, so an interrupted or failed build never leaves half-written files.

Two helpers (DESIGN §10, "files are written atomically"):

* :func:`atomic_write` writes one file: the bytes go to a temporary file in the same
  folder, are flushed to disk, and the temporary file is renamed over the target with
  :func:`os.replace` (atomic on POSIX and Windows when both are on one file system).
* :func:`atomic_output_dir` stages a whole build: exporters write into a temporary
  folder beside the target; only when every exporter has succeeded are the files moved
  into the target, each with :func:`os.replace`. If anything fails, the staging folder
  is removed and the target is left exactly as it was.

The target folder itself is never deleted or swapped wholesale (``--out .`` must not
wipe a user's working directory); files from an earlier build that this build did not
write can be removed by naming a glob pattern (``replace_matching``).
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_write", "atomic_output_dir"]

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


@contextlib.contextmanager
def atomic_output_dir(target: str | os.PathLike[str], *,
                      replace_matching: str | None = None) -> Iterator[Path]:
    """Stage output files in a temporary folder and move them into ``target`` on success.

    Parameters
    ----------
    target:
        The folder that receives the files (created if missing).
    replace_matching:
        Optional file-name glob (e.g. ``"house.*"``). After the new files are in place,
        files matching it that this build did not write are deleted from ``target`` and
        from every subfolder this build wrote into (``urdf/``, ``meshes/``), so a
        rebuild with fewer floors or items leaves no stale ``house.floor3.svg`` behind.
        Other folders are never touched. Nothing is deleted if the build fails.

    Yields
    ------
    Path
        The staging folder; write the outputs there (under the same relative names they
        should have in ``target``).

    Notes
    -----
    On an exception inside the ``with`` block the staging folder is removed and the
    exception propagates; ``target`` is untouched. On success each staged file is
    moved with :func:`os.replace`, so every file in ``target`` is always complete.
    """
    final = Path(target)
    final.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{final.name}.", suffix=".staging", dir=final.parent))
    token = _staging_folder.set(staging.resolve())
    try:
        yield staging
        _staging_folder.reset(token)
        token = None
        staged = sorted(p for p in staging.rglob("*") if p.is_file())
        _flush(staged)
        final.mkdir(parents=True, exist_ok=True)
        written: set[Path] = set()
        for source in staged:
            relative = source.relative_to(staging)
            destination = final / relative
            destination.parent.mkdir(parents=True, exist_ok=True)
            os.replace(source, destination)
            written.add(relative)
        if replace_matching is not None:
            folders = {final} | {final / relative.parent for relative in written}
            for folder in sorted(folders):
                for stale in sorted(folder.glob(replace_matching)):
                    if stale.is_file() and stale.relative_to(final) not in written:
                        stale.unlink()
    finally:
        if token is not None:
            _staging_folder.reset(token)
        shutil.rmtree(staging, ignore_errors=True)
