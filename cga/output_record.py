"""Which files in an output folder a build wrote, so a rebuild replaces only those.

A build may share its folder with anything: ``cga build house.grammar --out .`` writes
beside the grammar itself and the user's ``house.notes.txt``. Matching files by name
(``house.*``) once deleted both (issue 19, defect 1). Instead every build name keeps a
record, ``.cga-<name>.files.json`` in the output folder, of the files it wrote and a
SHA-256 of each as written. A later build of the same name

* replaces a file only if the record lists it and its content is still what the build
  wrote (a file the user made or edited is never overwritten: the build is refused and
  names it);
* removes the recorded files it does not write again (a rebuild with fewer floors
  leaves no stale ``house.floor3.svg``), again only while they are unchanged;
* never touches a file outside the folder, a folder, or a protected input (the grammar,
  the lot file), whatever the record says.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

__all__ = ["OutputRecord", "file_digest", "record_path"]

_FORMAT = "cga.outputs"


def record_path(folder: Path, owner: str) -> Path:
    """Where the record of build name ``owner`` lives in ``folder``."""
    return folder / f".cga-{owner}.files.json"


def file_digest(path: Path) -> str:
    """SHA-256 of a file's bytes, hex."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _safe_relative(text: str) -> PurePosixPath | None:
    """A record entry as a relative path that stays inside the folder, else None."""
    path = PurePosixPath(text)
    if not text or path.is_absolute() or ".." in path.parts or "\\" in text or "\x00" in text:
        return None
    return path


@dataclass
class OutputRecord:
    """The files (relative POSIX paths → SHA-256) a build name wrote into ``folder``."""

    folder: Path
    owner: str
    files: dict[str, str] = field(default_factory=dict)

    @classmethod
    def load(cls, folder: Path, owner: str) -> "OutputRecord":
        """Read the record; a missing or unreadable one owns nothing."""
        path = record_path(folder, owner)
        files: dict[str, str] = {}
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            data = None
        if isinstance(data, dict) and isinstance(data.get("files"), dict):
            files = {name: digest for name, digest in data["files"].items()
                     if isinstance(digest, str) and _safe_relative(name) is not None}
        return cls(Path(folder), owner, files)

    def save(self, files: Mapping[str, str]) -> None:
        """Replace the record (atomically) with ``files``."""
        from .fsutil import atomic_write

        self.files = dict(files)
        document = {"format": _FORMAT, "version": 1, "name": self.owner,
                    "files": dict(sorted(self.files.items()))}
        atomic_write(record_path(self.folder, self.owner), json.dumps(document, indent=1) + "\n")

    def owns(self, relative: str, protect: Iterable[Path] = ()) -> bool:
        """Whether the file at ``relative`` may be replaced or removed: recorded, a plain
        file inside the folder, unchanged since it was written and not a protected input."""
        entry = _safe_relative(relative)
        if entry is None or relative not in self.files:
            return False
        path = self.folder / entry
        try:
            inside = path.parent.resolve().is_relative_to(self.folder.resolve())
            if not inside or not path.is_file() or path.is_symlink():
                return False
            if any(_same_file(path, other) for other in protect):
                return False
            return file_digest(path) == self.files[relative]
        except OSError:
            return False

    def remove_unless(self, keep: Iterable[str], protect: Iterable[Path] = ()) -> None:
        """Delete the recorded files not in ``keep`` that this record still owns (a file
        changed since it was written stays); folders this empties are removed too."""
        protect = list(protect)
        for relative in sorted(set(self.files) - set(keep)):
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
