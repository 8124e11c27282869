"""Run make_floor directly on one storey, as the evaluator would, for property tests."""

from __future__ import annotations

from typing import Any

import numpy as np

from cga.model import Diagnostic
from cga.operation import Child, OperationContext
from cga.operations.make_floor import MakeFloor
from cga.shape import Mass, Shape


def run_make_floor(footprint: Any, *, floor: int, seed: int,
                   **args: Any) -> tuple[Child, list[Diagnostic]]:
    """make_floor on storey ``floor`` (3 m high) over ``footprint`` with the operation's
    defaults overridden by ``args``: (the child shape, the diagnostics it reported).
    Raises what make_floor raises."""
    mass = Mass(footprint, 3.0 * floor, 3.0)
    shape = Shape("Floor", ("Lot", "Floor"), mass.scope(), mass, {"floor": floor})
    reports: list[Diagnostic] = []
    ctx = OperationContext(rng=np.random.default_rng(seed), units=1.0,
                           resolve=lambda p, k="rules": p, report=reports.append, span=None,
                           successor_count=1, seed=seed)
    defaults = {p.name: p.default for p in MakeFloor.params if not p.required}
    [child] = MakeFloor().apply(shape, defaults | args, ctx)
    return child, reports
