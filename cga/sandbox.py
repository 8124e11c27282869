"""Where a build may read files from: the grammar's folder tree, shipped data, allowed folders.

Grammars are shared and downloaded; a path in one (``type_rooms("../../etc/passwd")``)
must not make a build read, or print, an arbitrary file of the machine that runs it
(docs/limits.md). Every file a grammar leads a build to — rule tables, furniture
models, the lot — must lie, after following symbolic links, inside one of:

* the grammar's folder and everything below it;
* the data shipped with cga (``cga.rules``, ``cga.furniture_models``);
* a folder the user allows explicitly: ``--allow-path DIR`` on the command line
  (repeatable) or ``allow_paths=[...]`` in :func:`cga.build`.

A lot file is named by the user on the command line, not by the grammar, so the working
directory's tree is allowed for it too (:meth:`Sandbox.with_working_directory`).

Anything else is refused with :class:`~cga.errors.ResourceAccessError`, which names the
path and the option that would allow it. Containment is decided on real paths
(:func:`os.path.realpath`), so ``..`` components and symbolic links that leave the tree
are caught alike; ``realpath`` does not raise on a symbolic-link loop (the looping path
is then simply not a file).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from .errors import PATH_LIMIT, ResourceAccessError, UsageError, excerpt
from .paths import is_below, real_path
from .resources import is_folder, shipped_dir

__all__ = ["ALLOW_OPTION", "Sandbox", "real_path"]

_ALLOWED = "allowed with --allow-path"

ALLOW_OPTION = "--allow-path DIR (Python: allow_paths=[DIR])"
"""How a refused file is allowed, as error messages say it."""


@dataclass(frozen=True)
class Sandbox:
    """The folders (real paths, each with a label for messages) a build may read below."""

    roots: tuple[tuple[Path, str], ...]

    @classmethod
    def for_grammar(cls, grammar_dir: str | Path | None,
                    allow_paths: Iterable[str | Path] = ()) -> "Sandbox":
        """The sandbox of a grammar in ``grammar_dir`` (None: the working directory),
        plus the shipped data and ``allow_paths``.

        Raises
        ------
        UsageError
            An allowed path is not an existing folder.
        """
        roots: list[tuple[Path, str]] = [
            (real_path(grammar_dir if grammar_dir is not None else Path.cwd()),
             "the grammar's folder")]
        for package, label in (("cga.rules", "shipped rule tables"),
                               ("cga.furniture_models", "shipped models")):
            folder = shipped_dir(package)
            if folder is not None:
                roots.append((real_path(folder), label))
        for allowed in allow_paths:
            if not is_folder(allowed):
                raise UsageError(f"--allow-path {excerpt(str(allowed), PATH_LIMIT)}: not an "
                                 f"existing folder")
            roots.append((real_path(allowed), _ALLOWED))
        return cls(tuple(roots))

    @property
    def folders(self) -> tuple[Path, ...]:
        """The allowed folders, in order."""
        return tuple(root for root, _ in self.roots)

    def with_working_directory(self) -> "Sandbox":
        """This sandbox plus the working directory's tree, for files the user names on
        the command line (``--lot``) rather than the grammar."""
        return Sandbox((*self.roots, (real_path(Path.cwd()), "the working directory")))

    @property
    def allowed(self) -> tuple[Path, ...]:
        """The folders the user allowed (``--allow-path``), in order."""
        return tuple(root for root, label in self.roots if label == _ALLOWED)

    def contains(self, path: str | Path) -> bool:
        """Whether ``path`` (after resolving links) lies inside an allowed folder."""
        try:
            real = real_path(path)
        except ValueError:  # a NUL byte: no file of the OS has that name
            return False
        return any(is_below(real, root) for root in self.folders)

    def check(self, path: str | Path, what: str, written: str | None = None) -> Path:
        """``path`` if it lies inside an allowed folder.

        Raises
        ------
        ResourceAccessError
            It does not; the message names ``written`` (or ``path``), the allowed
            folders and :data:`ALLOW_OPTION`.
        """
        if self.contains(path):
            return Path(path)
        raise self.refusal(what, written if written is not None else str(path), path)

    def refusal(self, what: str, written: str, path: str | Path | None = None
                ) -> ResourceAccessError:
        """The error for a ``what`` named ``written`` that lies outside every allowed folder."""
        where = "" if path is None or str(path) == written else f" ({excerpt(str(path), PATH_LIMIT)})"
        places = "; ".join(f"{root} ({label})" for root, label in self.roots)
        return ResourceAccessError(
            f"{what} {excerpt(written, PATH_LIMIT)}{where} is outside the folders a build may read "
            f"({places}); allow its folder with {ALLOW_OPTION}", path=written)
