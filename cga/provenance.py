"""What a build was made from: the grammar, every file it read, the options, the version.

A dataset is one configuration. ``cga batch`` writes, with every manifest line, the
inputs of that seed's build (:func:`provenance`): the SHA-256 of the grammar, of each
rule table and furniture model the build read (they are noted as they are found, see
:func:`note_input`), the build options and the cga version. Resuming a batch compares
the recorded inputs with the ones on disk now (:class:`RecordedInputs`) and refuses when any
differs, naming what changed; without this, an edited grammar silently mixed old and
new houses in one dataset (issue 18).

Files are named portably, so a manifest written on one machine is checked on another:
``cga.rules/house_rooms.csv`` for shipped data (the package and the name inside it),
the path relative to the grammar's folder for the grammar's own files, an absolute path
for anything else (a folder given with ``--allow-path``).

Digests are the first :data:`DIGEST_HEX` hex digits of the SHA-256 (64 bits: a changed
file is told apart from its earlier version with certainty for any practical purpose,
and a house's line stays short; compare with ``sha256sum FILE | cut -c1-16``).
"""

from __future__ import annotations

import contextlib
import contextvars
import functools
import hashlib
import json
import os
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from .paths import is_below, relative_text

__all__ = ["DIGEST_HEX", "SHIPPED_PACKAGES", "note_input", "recording", "file_digest",
           "input_label", "label_path", "provenance", "RecordedInputs"]

DIGEST_HEX = 16
SHIPPED_PACKAGES = ("cga.rules", "cga.furniture_models")
"""Packages of shipped data; a file inside one is named ``<package>/<name>``."""

_reads: contextvars.ContextVar[list[Path] | None] = contextvars.ContextVar(
    "cga_input_reads", default=None)
_DIGESTS: dict[str, tuple[int, int, str]] = {}
"""Digests computed in this process: real path → (mtime_ns, size, digest)."""


def note_input(path: str | Path) -> None:
    """Note that the current build reads ``path`` (a rule table, a model, a lot file);
    a no-op outside :func:`recording`. Called where a file is found, not where it is
    parsed, so files whose contents a process caches are noted by every build."""
    reads = _reads.get()
    if reads is not None:
        reads.append(Path(path))


@contextlib.contextmanager
def recording() -> Iterator[list[Path]]:
    """Collect the files :func:`note_input` notes inside the block (in this thread)."""
    reads: list[Path] = []
    token = _reads.set(reads)
    try:
        yield reads
    finally:
        _reads.reset(token)


def file_digest(path: str | Path) -> str | None:
    """The file's SHA-256 (first :data:`DIGEST_HEX` hex digits), or None if it cannot be
    read. Cached per process by modification time and size: a batch worker hashes each
    model once, not once per house."""
    real = os.path.realpath(path)
    try:
        stat = os.stat(real)
        cached = _DIGESTS.get(real)
        if cached is not None and cached[:2] == (stat.st_mtime_ns, stat.st_size):
            return cached[2]
        sha = hashlib.sha256()
        with open(real, "rb") as file:
            for block in iter(lambda: file.read(1 << 20), b""):
                sha.update(block)
    except OSError:
        return None
    digest = sha.hexdigest()[:DIGEST_HEX]
    _DIGESTS[real] = (stat.st_mtime_ns, stat.st_size, digest)
    return digest


@functools.cache
def _shipped_folders() -> dict[str, Path]:
    """Shipped package → its real folder; found once per process (the packages do not
    move while it runs, and a batch labels every house's reads against them)."""
    from .resources import shipped_dir

    folders = {}
    for package in SHIPPED_PACKAGES:
        folder = shipped_dir(package)
        if folder is not None:
            folders[package] = Path(os.path.realpath(folder))
    return folders


def input_label(path: str | Path, grammar_dir: Path) -> str:
    """The portable name of a file a build read (see the module notes).

    Worked out on the real paths' text (:mod:`cga.paths`)."""
    real = os.path.realpath(path)
    for package, folder in _shipped_folders().items():
        if is_below(real, folder):
            return f"{package}/{relative_text(real, str(folder))}"
    base = os.path.realpath(grammar_dir)
    if is_below(real, base):
        return relative_text(real, base)
    return real


def label_path(label: str, grammar_dir: Path) -> Path:
    """Where the file named ``label`` is on this machine (inverse of :func:`input_label`)."""
    package, _, rest = label.partition("/")
    folder = _shipped_folders().get(package) if rest else None
    if folder is not None:
        return folder / rest
    return Path(label) if os.path.isabs(label) else Path(grammar_dir) / label


def _jsonable(options: Mapping[str, Any]) -> dict[str, Any]:
    """Build options as JSON values, keys sorted (paths become text)."""
    return json.loads(json.dumps(dict(options), sort_keys=True, default=str))


def provenance(grammar: Path, options: Mapping[str, Any], reads: Sequence[Path] = ()
               ) -> dict[str, Any]:
    """The inputs of one build: the grammar's digest, the digest of every file in
    ``reads`` (by label, sorted), the build options and the cga version."""
    from . import __version__

    files = {input_label(path, grammar.parent): file_digest(path)
             for path in dict.fromkeys(reads)}  # a file read twice is one input
    return {"grammar": file_digest(grammar), "files": dict(sorted(files.items())),
            "options": _jsonable(options), "version": __version__}


def _kind(label: str) -> str:
    suffix = Path(label).suffix.lower()
    return {".csv": "rule table", ".obj": "model"}.get(suffix, "file")


def _value(value: Any) -> str:
    return json.dumps(value, sort_keys=True)


class RecordedInputs:
    """The inputs recorded by many manifest lines, summed up field by field: each value
    seen, with where it was first seen (a seed, a manifest). Builds of different seeds
    read different models (a house without a bathroom reads no bathtub), so files are
    compared name by name, never as whole sets."""

    def __init__(self) -> None:
        self.values: dict[str, dict[str, str]] = {}
        """Field (``version``, ``grammar``, ``option NAME``, ``file LABEL``) → value
        (JSON) → where it was first seen."""
        self.unrecorded: str | None = None
        """Where a line without recorded inputs was first seen."""

    def add(self, recorded: Mapping[str, Any], where: str) -> None:
        if not recorded:
            self.unrecorded = self.unrecorded or where
            return
        fields = {"version": recorded.get("version"), "grammar": recorded.get("grammar")}
        fields.update((f"option {k}", v) for k, v in recorded.get("options", {}).items())
        fields.update((f"file {k}", v) for k, v in recorded.get("files", {}).items())
        for name, value in fields.items():
            self.values.setdefault(name, {}).setdefault(_value(value), where)

    @staticmethod
    def _phrase(name: str, grammar_name: str) -> str:
        kind, _, rest = name.partition(" ")
        if kind == "file":
            return f"the {_kind(rest)} {rest}"
        if kind == "option":
            return f"the option {rest}"
        if kind == "grammar":
            return f"the grammar {grammar_name}".rstrip()
        return "the cga version"

    def changes(self, grammar: Path, options: Mapping[str, Any]) -> list[str]:
        """What differs between the recorded inputs and a build of ``grammar`` with
        ``options`` now, one phrase each; the files are hashed again where they are now."""
        from . import __version__

        if not self.values and self.unrecorded is None:
            return []  # nothing built yet
        current = {"version": _value(__version__), "grammar": _value(file_digest(grammar))}
        for key, value in _jsonable(options).items():
            current[f"option {key}"] = _value(value)
        found = []
        if self.unrecorded is not None:
            found.append(f"no record of the inputs of {self.unrecorded} (written by an "
                         f"earlier cga)")
        for name in sorted(set(self.values) | {k for k in current if k.startswith("option ")}):
            if name.startswith("file "):
                now = _value(file_digest(label_path(name[5:], grammar.parent)))
            else:
                now = current.get(name, _value(None))
            before = [v for v in self.values.get(name, {_value(None): ""}) if v != now]
            if before:
                shown = now if now != "null" else "missing"
                found.append(f"{self._phrase(name, grammar.name)} "
                             f"({', '.join(before)} → {shown})".replace('"', ""))
        return found

    def conflicts(self, grammar_name: str = "") -> list[str]:
        """Fields recorded with more than one value, each with where its values were seen."""
        found = []
        if self.unrecorded is not None and self.values:
            found.append(f"no record of the inputs of {self.unrecorded}")
        for name, seen in sorted(self.values.items()):
            if len(seen) > 1:
                where = ", ".join(f"{value} in {place}" for value, place in seen.items())
                found.append(f"{self._phrase(name, grammar_name)} "
                             f"({where})".replace('"', ""))
        return found
