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
  leaves no stale ``house.floor3.svg``), again only while they are unchanged, and only
  among the formats it writes: the record notes which format wrote each file, so
  ``cga.build(..., formats=("glb",))`` after a ``cga build`` that also wrote plans
  replaces the glb and keeps the plans (issue 20); a file of unknown format (a record
  from before formats were noted) counts as any format's;
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

__all__ = ["OutputFormats", "OutputRecord", "record_path"]

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
class OutputFormats:
    """What a build writes, by format: the ``requested`` formats and, filled while the
    exporters run, ``files``: each written file (relative POSIX path) → its format."""

    requested: frozenset[str]
    files: dict[str, str] = field(default_factory=dict)


@dataclass
class OutputRecord:
    """The files (relative POSIX paths) a build name wrote into ``folder``."""

    folder: Path
    owner: str
    files: set[str] = field(default_factory=set)
    written_ns: int = -1
    """Modification time of the record when it was read; files modified later are not
    the build's any more (-1: no record, nothing is owned)."""
    formats: dict[str, str] = field(default_factory=dict)
    """File → the format (exporter) that wrote it, for the files whose format is known."""

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
        kinds = data.get("formats") if isinstance(data, dict) else None
        formats = {name: kind for name, kind in kinds.items()
                   if name in files and isinstance(kind, str)} if isinstance(kinds, dict) else {}
        return cls(Path(folder), owner, files, written_ns, formats)

    def save(self, files: Iterable[str], scratch: Path,
             formats: dict[str, str] | None = None) -> None:
        """Replace the record with ``files`` (``formats``: file → the format that wrote
        it, where known) by one rename of a draft written in ``scratch`` (the build's
        staging folder: a build killed while writing the draft leaves it there, where
        the next build's sweep removes it)."""
        from .fsutil import atomic_write

        self.files = set(files)
        if formats is not None:
            self.formats = {name: kind for name, kind in formats.items() if name in self.files}
        document = {"format": _FORMAT, "version": 2, "name": self.owner,
                    "files": sorted(self.files),
                    "formats": dict(sorted(self.formats.items()))}
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

    def remove_unless(self, keep: Iterable[str], protect: Iterable[Path] = (),
                      formats: Iterable[str] | None = None) -> set[str]:
        """Delete the recorded files not in ``keep`` that this record still owns (a file
        changed since it was written stays) and that one of ``formats`` wrote (None:
        any; a file of unknown format counts as any format's); folders this empties are
        removed too. Returns the recorded files of other formats that were kept."""
        protect = list(protect)
        wanted = None if formats is None else set(formats)
        other = set()
        for relative in sorted(self.files - set(keep)):
            kind = self.formats.get(relative)
            if wanted is not None and kind is not None and kind not in wanted:
                if self.owns(relative, protect):
                    other.add(relative)
                continue
            if self.owns(relative, protect):
                path = self.folder / relative
                path.unlink()
                _remove_empty_parents(path.parent, self.folder)
        return other


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
