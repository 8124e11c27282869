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

# The public Python API. Names are imported on first use, so `import cga` (and the `cga`
# command's startup) does not load shapely, trimesh or pybullet.
_PUBLIC = {
    "build": "cga.pipeline",
    "parse": "cga.parser",
    "parse_file": "cga.parser",
    "derive": "cga.evaluator",
    "Evaluator": "cga.evaluator",
    "check_file": "cga.validate",
    "check_grammar": "cga.validate",
    "parse_lot": "cga.lot",
    "scene_nodes": "cga.meshing",
    "Scene": "cga.scene",
    "SceneNode": "cga.scene",
    "check_physics": "cga.checks",
    "check_navigability": "cga.checks",
    "occupancy_grid": "cga.checks",
    "floor_from_rectangles": "cga.authoring",
    "type_floor": "cga.authoring",
    "run_batch": "cga.batch",
}

__all__ = ["__version__", *_PUBLIC]


def __getattr__(name: str):
    """Import a public name from its module the first time it is used (PEP 562)."""
    if name in _PUBLIC:
        import importlib

        value = getattr(importlib.import_module(_PUBLIC[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'cga' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_PUBLIC))
