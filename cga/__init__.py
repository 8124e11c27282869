"""cga: a shape-grammar building generator (see README.md and DESIGN §1)."""

from __future__ import annotations

from pathlib import Path as _Path

# Installed, setuptools maps the repository's `operations/`, `rules/` and `models/`
# folders to `cga.operations`, `cga.rules` and `cga.models` (see pyproject.toml). In a
# source checkout those folders sit beside this package; adding the checkout root to the
# package path makes the same import names work there too.
_checkout_root = _Path(__file__).resolve().parent.parent
if (_checkout_root / "operations" / "__init__.py").is_file() and not (
        _Path(__file__).resolve().parent / "operations").exists():
    __path__.append(str(_checkout_root))  # type: ignore[name-defined]

__version__ = "0.1.0"
