"""Find the files a grammar names: rule tables and furniture models.

A grammar names files as its author's machine saw them; the thesis grammars carry
absolute Windows paths (``"D:\\RoomsProjekt\\...\\TestConfig"``, even without the
``.csv``). :func:`resolve_resource` looks, in order:

1. the path as written, relative to the grammar's folder;
2. the path as written, if it is absolute;
3. the path as written (also with the kind's suffix added) in the grammar's folder and
   inside the shipped data package (``cga.rules`` for rule tables, ``cga.furniture_models`` for
   models), matching case-insensitively when no exact name exists;
4. by name: the trailing components of the path (split on both ``\\`` and ``/``),
   longest first, in the grammar's folder and then in the shipped package, trying the
   kind's file suffix (``.csv`` / ``.obj``) when the name has none, again case-
   insensitively as a fallback (Windows file names ignore case).

Trying the longest tail first keeps two files of the same name apart:
``...\\processor\\placement\\TestConfig.csv`` finds ``placement/TestConfig.csv`` before a
plain ``TestConfig.csv``. If nothing matches, :class:`~cga.errors.ResourceNotFoundError`
lists every place that was looked at.

With a :class:`~cga.sandbox.Sandbox` (as every build passes), a file found in any step
must lie inside the sandbox after following links: a path as written that leaves it
(``/etc/passwd``, ``../../x``, ``..\\..\\x``, a link out of the tree) is refused with
:class:`~cga.errors.ResourceAccessError` unless the same name is found inside, and
by-name lookups also search the folders the user allowed. Names the OS rejects (too
long, NUL bytes, link loops) are simply not found.

Shipped data is found with :func:`importlib.resources.files`, which works both in a
source checkout and after ``pip install``.
"""

from __future__ import annotations

import importlib.resources
import importlib.util
import re
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import TYPE_CHECKING

from .errors import PATH_LIMIT, ResourceNotFoundError, shown
from .provenance import note_input

if TYPE_CHECKING:  # pragma: no cover
    from .sandbox import Sandbox

__all__ = ["ResourceKind", "RESOURCE_KINDS", "is_folder", "is_regular_file", "resolve_resource", "shipped_dir"]


@dataclass(frozen=True)
class ResourceKind:
    """What a kind of resource is called in messages, where it ships and its suffix."""

    description: str
    package: str | None
    suffix: str | None


RESOURCE_KINDS: dict[str, ResourceKind] = {
    "rules": ResourceKind("rule table", "cga.rules", ".csv"),
    "model": ResourceKind("model", "cga.furniture_models", ".obj"),
    "file": ResourceKind("file", None, None),
}
"""Kinds :func:`resolve_resource` understands (``kind`` argument)."""


def shipped_dir(package: str) -> Path | None:
    """The folder of a shipped data package (``"cga.rules"``), or None if it is absent.

    Uses :func:`importlib.resources.files`; a data folder without ``__init__.py`` in a
    checkout is a namespace package, whose ``files()`` is a multiplexed view, so the
    folder is taken from the package's search locations in that case.
    """
    try:
        root = importlib.resources.files(package)
    except ModuleNotFoundError:
        return None
    if isinstance(root, Path):
        return root if root.is_dir() else None
    spec = importlib.util.find_spec(package)
    for location in (spec.submodule_search_locations or []) if spec else []:
        if Path(location).is_dir():
            return Path(location)
    return None


def _components(written: str) -> list[str]:
    """Path components of a name written on any OS (``\\`` and ``/`` both separate);
    ``..`` is dropped, so a lookup by name never climbs out of the folder searched."""
    return [part for part in re.split(r"[\\/]+", written) if part and part not in (".", "..")]


def is_folder(path: str | Path) -> bool:
    """``Path(path).is_dir()``, False for names the OS rejects (too long, NUL, link loops)."""
    try:
        return Path(path).is_dir()
    except (OSError, ValueError):
        return False


def is_regular_file(path: str | Path) -> bool:
    """``Path(path).is_file()``, False for names the OS rejects (too long, NUL, link loops)."""
    try:
        return Path(path).is_file()
    except (OSError, ValueError):
        return False


def _match_in(folder: Path, relative: PurePosixPath) -> Path | None:
    """``folder/relative`` if it is a file; else a case-insensitive match, step by step."""
    exact = folder.joinpath(*relative.parts)
    if is_regular_file(exact):
        return exact
    current = folder
    for i, part in enumerate(relative.parts):
        last = i == len(relative.parts) - 1
        try:
            matches = sorted(child for child in current.iterdir()
                             if child.name.lower() == part.lower()
                             and (is_regular_file(child) if last else child.is_dir()))
        except OSError:
            return None
        if not matches:
            return None
        current = matches[0]
    return current


def _name_variants(parts: list[str], suffix: str | None) -> list[PurePosixPath]:
    """Tails of ``parts`` longest first, each also with ``suffix`` if its name has none."""
    variants: list[PurePosixPath] = []
    for start in range(len(parts)):
        tail = PurePosixPath(*parts[start:])
        variants.append(tail)
        if suffix and not tail.suffix:
            variants.append(tail.with_name(tail.name + suffix))
    return variants


def resolve_resource(path: str | Path, kind: str = "rules", *,
                     base_dir: str | Path | None = None,
                     sandbox: "Sandbox | None" = None) -> Path:
    """Find the file a grammar argument names.

    Parameters
    ----------
    path:
        The path as written in the grammar (any OS's separators), or a Path.
    kind:
        ``"rules"`` (rule tables, shipped in ``cga.rules``), ``"model"`` (furniture
        models, shipped in ``cga.furniture_models``) or ``"file"`` (no shipped fallback).
    base_dir:
        The grammar's folder; relative paths are looked up there first. None means
        the current working directory.
    sandbox:
        The folders the file must lie in (see the module docstring); None reads any
        file (for Python callers naming their own files).

    Returns
    -------
    Path
        An existing file.

    Raises
    ------
    ResourceNotFoundError
        Nothing matched; the message lists every place looked at.
    ResourceAccessError
        The path as written, or every file found, lies outside ``sandbox``.
    ValueError
        ``kind`` is not one of :data:`RESOURCE_KINDS` (a programming error).
    """
    found = _find_resource(path, kind, base_dir=base_dir, sandbox=sandbox)
    note_input(found)  # a batch records what each house was made from
    return found


def _find_resource(path: str | Path, kind: str = "rules", *,
                   base_dir: str | Path | None = None,
                   sandbox: "Sandbox | None" = None) -> Path:
    """:func:`resolve_resource` without noting the file as read."""
    try:
        spec = RESOURCE_KINDS[kind]
    except KeyError:
        raise ValueError(f"unknown resource kind {kind!r}; expected one of "
                         f"{', '.join(RESOURCE_KINDS)}") from None
    written = str(path)
    written_shown = shown(written, PATH_LIMIT)
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    shipped = shipped_dir(spec.package) if spec.package else None
    searched: list[str] = []
    refused: Path | None = None

    def accept(candidate: Path) -> bool:
        nonlocal refused
        if sandbox is None or sandbox.contains(candidate):
            return True
        refused = refused or candidate
        return False

    # "..\\..\\x" climbs out on Windows; judge the path with either separator
    as_written = Path(written.replace("\\", "/"))
    if not as_written.is_absolute():
        candidate = base / written
        searched.append(f"{base / written_shown} (as written, next to the grammar)")
        if is_regular_file(candidate) and accept(candidate):
            return candidate
        as_written = base / as_written
    else:
        searched.append(f"{written_shown} (as written)")
        if is_regular_file(as_written) and accept(as_written):
            return as_written
    # a name with a NUL byte names no file at all: "not found", not "outside"
    escapes = sandbox is not None and "\x00" not in written and not sandbox.contains(as_written)

    parts = _components(written)
    variants = _name_variants(parts, spec.suffix)
    whole = [v for v in variants if len(v.parts) == len(parts)]
    tails = [v for v in variants if len(v.parts) < len(parts)]
    folders = [(base, "the grammar's folder")]
    if shipped is not None:
        folders.append((shipped, f"shipped {spec.description}s"))
    if sandbox is not None:
        folders.extend((folder, "allowed folder") for folder in sandbox.allowed)
    names = ", ".join(shown(str(v), PATH_LIMIT) for v in variants if len(v.parts) == 1)
    how = (f"as written, then by name: {names} (longest trailing path first)"
           if len(parts) > 1 else f"by name: {names}")
    searched.extend(f"{folder} ({label}): {how}" for folder, label in folders)
    for group in (whole, tails):
        for folder, _ in folders:
            for variant in group:
                found = _match_in(folder, variant)
                if found is not None and accept(found):
                    return found
    if sandbox is not None and (escapes or refused is not None):
        raise sandbox.refusal(spec.description, written, refused)
    if spec.package is not None and shipped is None:
        searched.append(f"package {spec.package} (not installed)")
    raise ResourceNotFoundError(spec.description, written_shown, searched)
