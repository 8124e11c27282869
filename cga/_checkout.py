"""Importing ``cga`` from a source checkout, where the library's data and operations
sit beside the package instead of inside it.

Installed, setuptools maps the repository's ``operations/``, ``rules/`` and ``models/``
folders to ``cga.operations``, ``cga.rules`` and ``cga.furniture_models``
(pyproject.toml). In a checkout, :func:`install` adds a finder for exactly those three
names, so they import the same way there; no other folder of the checkout (``build/``,
``tests/``, ``docs/``, ...) becomes importable as ``cga.<name>``. Putting the checkout
root on ``cga.__path__`` instead would make ``import cga.build`` pick up a setuptools
``build/`` folder and rebind :func:`cga.build`.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import sys
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType

__all__ = ["SUBPACKAGES", "install"]

SUBPACKAGES = {"cga.operations": "operations", "cga.rules": "rules",
               "cga.furniture_models": "models"}
"""Package name → folder of the repository it is installed from."""


class _CheckoutFinder:
    """A meta path finder for :data:`SUBPACKAGES` in one checkout."""

    def __init__(self, root: Path):
        self.root = root

    def find_spec(self, fullname: str, path: Sequence[str] | None = None,
                  target: ModuleType | None = None) -> importlib.machinery.ModuleSpec | None:
        folder = SUBPACKAGES.get(fullname)
        if folder is None:
            return None
        location = self.root / folder
        init = location / "__init__.py"
        if init.is_file():
            return importlib.util.spec_from_file_location(
                fullname, init, submodule_search_locations=[str(location)])
        if location.name == fullname.rpartition(".")[2]:
            # a data folder without __init__.py (rules/): a namespace package, made by
            # the standard path finder so importlib.resources can read it
            return importlib.machinery.PathFinder.find_spec(fullname, [str(self.root)])
        return None


def install(package_dir: Path) -> None:
    """Let the checkout's folders import as :data:`SUBPACKAGES` when ``package_dir`` (the
    ``cga`` package folder) sits in a checkout; do nothing when installed."""
    root = package_dir.parent
    if not (root / "operations" / "__init__.py").is_file() or (package_dir / "operations").exists():
        return
    if not any(isinstance(f, _CheckoutFinder) and f.root == root for f in sys.meta_path):
        # first: the folders beside the imported package win over any other mapping
        sys.meta_path.insert(0, _CheckoutFinder(root))
