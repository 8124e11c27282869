"""Joining a building's storeys once they are derived (DESIGN §12).

The grammar derives each storey on its own (``repeated_split("y", ...)`` then
``make_floor`` per storey), so facts that span storeys are settled here, after the
derivation and before the Scene is made:

* the top storey: a storey is the top one when no storey of the next index stands on
  its footprint; it gets ``is_top`` (and so a roof slab);
* the stairs: two consecutive storeys that reserved the same stair core (``make_floor``
  registers one core per building, see :func:`cga.operations.stairs.core_for_storey`)
  are joined by a :class:`~cga.model.Stair` laid out in it, which both plans list in
  ``stairs`` (the upper one cuts its stairwell from it).

Stair ids count from 0 up the building, in floor order.
"""

from __future__ import annotations

from collections.abc import Sequence

from .model import Diagnostic, FloorPlan, Stair
from .shape import Shape

__all__ = ["stack_storeys", "stack_plans"]


def stack_plans(plans: Sequence[FloorPlan]) -> list[FloorPlan]:
    """The plans with ``is_top`` and ``stairs`` set, in the given order.

    Raises
    ------
    DerivationError
        Two storeys share a core but are not as far apart as its stair climbs.
    """
    from cga.operations.stairs import stair_between

    order = sorted(range(len(plans)), key=lambda i: plans[i].index)
    at_index: dict[int, list[int]] = {}
    for i in order:
        at_index.setdefault(plans[i].index, []).append(i)
    stairs: dict[int, list[Stair]] = {i: [] for i in range(len(plans))}
    tops = {i: True for i in range(len(plans))}
    count = 0
    for i in order:
        lower = plans[i]
        for j in at_index.get(lower.index + 1, []):
            upper = plans[j]
            if upper.footprint.intersection(lower.footprint).area > 1e-9:
                tops[i] = False
            if lower.core is not None and lower.core == upper.core:
                stair = stair_between(lower.core, lower, upper, count)
                count += 1
                stairs[i].append(stair)
                stairs[j].append(stair)
    return [p.with_changes(is_top=tops[i], stairs=tuple(stairs[i]),
                           diagnostics=p.diagnostics + _cut_off(p, stairs[i], at_index))
            for i, p in enumerate(plans)]


def _cut_off(plan: FloorPlan, stairs: Sequence[Stair],
             at_index: dict[int, list[int]]) -> tuple[Diagnostic, ...]:
    """A warning when ``plan`` stands on a storey but no stair comes up to it
    (``stair = "none"``, an operation that reserves no core): a robot on the ground
    cannot reach its rooms."""
    if plan.index == 0 or plan.index - 1 not in at_index \
            or any(s.floors[1] == plan.index for s in stairs):
        return ()
    return (Diagnostic("warning", "stairs",
                       f"no stair comes up to floor {plan.index} from floor {plan.index - 1} "
                       f"(make_floor's stair = \"none\", or floors that reserve no stair core): "
                       f"its rooms cannot be reached from the ground floor", floor=plan.index),)


def stack_storeys(terminals: Sequence[Shape]) -> list[Shape]:
    """The terminal shapes with their storeys' plans stacked (:func:`stack_plans`).

    Several ``make_floor`` pieces of one storey (wings) are first joined into one plan
    (:func:`cga.wings.join_wings`), kept on the first piece's shape; the other pieces'
    shapes are dropped, their rooms being in that plan."""
    from .wings import join_wings

    at = [k for k, shape in enumerate(terminals) if shape.plan is not None]
    pieces = [terminals[k].plan for k in at]
    plans = stack_plans(join_wings(pieces))  # type: ignore[arg-type]
    out: list[Shape | None] = list(terminals)
    seen: set[int] = set()
    carriers = []
    for k, piece in zip(at, pieces):
        assert piece is not None
        if piece.index in seen:
            out[k] = None  # a wing whose rooms are in its storey's joined plan
        else:
            seen.add(piece.index)
            carriers.append(k)
    for k, plan in zip(carriers, plans):
        out[k] = terminals[k].derive(plan=plan)
    return [shape for shape in out if shape is not None]
