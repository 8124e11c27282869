"""Which files in an output folder a build wrote, so a rebuild replaces only those.

A build may share its folder with anything: ``cga build house.grammar --out .`` writes
beside the grammar itself and the user's ``house.notes.txt``. Matching files by name
(``house.*``) once deleted both (issue 19, defect 1). Instead every build name keeps a
record, ``.cga-<name>.files.json`` in the output folder, of the files it wrote. The
record is written after its files are in place, so a file modified later than the
record (an edit, a user's own file copied over it) is no longer the build's. A later
build of the same name

* replaces a file only if the record lists it and it is unchanged since (a file the
  user made or edited is never overwritten: the build is refused and names it);
* removes the recorded files it does not write again (a rebuild with fewer floors
  leaves no stale ``house.floor3.svg``), again only while they are unchanged;
* never touches a file outside the folder, a folder, or a protected input (the grammar,
  the lot file), whatever the record says.

The record holds names only, no hashes or times, so two builds with the same seed
still give identical folders.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

__all__ = ["OutputRecord", "record_path"]

_FORMAT = "cga.outputs"


def record_path(folder: Path, owner: str) -> Path:
    """Where the record of build name ``owner`` lives in ``folder``."""
    return folder / f".cga-{owner}.files.json"


def _safe_relative(text: str) -> PurePosixPath | None:
    """A record entry as a relative path that stays inside the folder, else None."""
    path = PurePosixPath(text)
    if not text or path.is_absolute() or ".." in path.parts or "\\" in text or "\x00" in text:
        return None
    return path


@dataclass
class OutputRecord:
    """The files (relative POSIX paths) a build name wrote into ``folder``."""

    folder: Path
    owner: str
    files: set[str] = field(default_factory=set)
    written_ns: int = -1
    """Modification time of the record when it was read; files modified later are not
    the build's any more (-1: no record, nothing is owned)."""

    @classmethod
    def load(cls, folder: Path, owner: str) -> "OutputRecord":
        """Read the record; a missing or unreadable one owns nothing."""
        path = record_path(folder, owner)
        try:
            written_ns = path.stat().st_mtime_ns
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return cls(Path(folder), owner)
        names = data.get("files") if isinstance(data, dict) else None
        files = {name for name in names if isinstance(name, str)
                 and _safe_relative(name) is not None} if isinstance(names, list) else set()
        return cls(Path(folder), owner, files, written_ns)

    def save(self, files: Iterable[str], scratch: Path) -> None:
        """Replace the record with ``files`` by one rename of a draft written in
        ``scratch`` (the build's staging folder: a build killed while writing the draft
        leaves it there, where the next build's sweep removes it)."""
        from .fsutil import atomic_write

        self.files = set(files)
        document = {"format": _FORMAT, "version": 1, "name": self.owner,
                    "files": sorted(self.files)}
        draft = atomic_write(scratch / ".cga-record.json",
                             json.dumps(document, indent=1, ensure_ascii=False) + "\n")
        path = record_path(self.folder, self.owner)
        os.replace(draft, path)
        self.written_ns = path.stat().st_mtime_ns

    def owns(self, relative: str, protect: Iterable[Path] = ()) -> bool:
        """Whether the file at ``relative`` may be replaced or removed: recorded, a plain
        file inside the folder, not modified since the record was written and not a
        protected input."""
        entry = _safe_relative(relative)
        if entry is None or relative not in self.files:
            return False
        path = self.folder / entry
        try:
            inside = path.parent.resolve().is_relative_to(self.folder.resolve())
            if not inside or path.is_symlink() or not path.is_file():
                return False
            if any(_same_file(path, other) for other in protect):
                return False
            return path.stat().st_mtime_ns <= self.written_ns
        except OSError:
            return False

    def remove_unless(self, keep: Iterable[str], protect: Iterable[Path] = ()) -> None:
        """Delete the recorded files not in ``keep`` that this record still owns (a file
        changed since it was written stays); folders this empties are removed too."""
        protect = list(protect)
        for relative in sorted(self.files - set(keep)):
            if self.owns(relative, protect):
                path = self.folder / relative
                path.unlink()
                _remove_empty_parents(path.parent, self.folder)


def _same_file(path: Path, other: Path) -> bool:
    try:
        return os.path.samefile(path, other)
    except OSError:
        return False


def _remove_empty_parents(folder: Path, root: Path) -> None:
    while folder != root and folder.is_relative_to(root):
        try:
            folder.rmdir()
        except OSError:
            return
        folder = folder.parent
