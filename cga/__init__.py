"""cga: a shape-grammar building generator (README.md; docs/architecture.md).

The public Python API is the names in :data:`__all__`: the build (:func:`build`), the
language (:func:`parse`, :func:`derive`, :func:`check_grammar`), the data a build hands
on (:class:`Scene`, :class:`SceneNode`, :class:`ItemInfo`, :class:`FloorPlan` and the plan
records, :class:`CheckReport`), the checks, the rule-author API
(:func:`floor_from_rectangles`, :func:`type_floor`, :func:`furnish_floor`) and the errors
(:class:`CGAError` and its subclasses; every user error is one).
"""

from __future__ import annotations

from pathlib import Path as _Path
from typing import TYPE_CHECKING

from . import _checkout

_checkout.install(_Path(__file__).resolve().parent)

__version__ = "0.1.0"

# Names are imported on first use, so `import cga` (and the `cga` command's startup) does
# not load shapely, trimesh or pybullet. Type checkers read the imports below instead.
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
    "ItemInfo": "cga.scene",
    "CheckReport": "cga.report",
    "FloorPlan": "cga.model",
    "FloorSettings": "cga.model",
    "Room": "cga.model",
    "Wall": "cga.model",
    "Door": "cga.model",
    "Window": "cga.model",
    "Opening": "cga.model",
    "FurnitureItem": "cga.model",
    "Diagnostic": "cga.model",
    "OUTSIDE": "cga.model",
    "check_physics": "cga.checks",
    "check_navigability": "cga.checks",
    "occupancy_grid": "cga.checks",
    "floor_from_rectangles": "cga.authoring",
    "type_floor": "cga.authoring",
    "furnish_floor": "cga.authoring",
    "run_batch": "cga.batch",
    "CGAError": "cga.errors",
    "SourceError": "cga.errors",
    "GrammarSyntaxError": "cga.errors",
    "DerivationError": "cga.errors",
    "RuleTableError": "cga.errors",
    "NoSolutionError": "cga.errors",
    "ResourceNotFoundError": "cga.errors",
    "UsageError": "cga.errors",
    "ExportError": "cga.errors",
}

if TYPE_CHECKING:  # pragma: no cover
    from .authoring import floor_from_rectangles, furnish_floor, type_floor
    from .batch import run_batch
    from .checks import check_navigability, check_physics, occupancy_grid
    from .errors import (CGAError, DerivationError, ExportError, GrammarSyntaxError,
                         NoSolutionError, ResourceNotFoundError, RuleTableError, SourceError,
                         UsageError)
    from .evaluator import Evaluator, derive
    from .lot import parse_lot
    from .meshing import scene_nodes
    from .model import (OUTSIDE, Diagnostic, Door, FloorPlan, FloorSettings, FurnitureItem,
                        Opening, Room, Wall, Window)
    from .parser import parse, parse_file
    from .pipeline import build
    from .report import CheckReport
    from .scene import ItemInfo, Scene, SceneNode
    from .validate import check_file, check_grammar

__all__ = ["__version__", *_PUBLIC]


def __getattr__(name: str) -> object:
    """Import a public name from its module the first time it is used (PEP 562)."""
    if name in _PUBLIC:
        import importlib

        value = getattr(importlib.import_module(_PUBLIC[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'cga' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_PUBLIC))
