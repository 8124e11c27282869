"""``add_furniture(rules.csv, wallWidth>windowWidth>windowHigh, doorWidth, doorHeight,
steeringIterations, clearanceTries)``: furnish every typed room of a floor.

The thin grammar-facing wrapper of :mod:`cga.operations.furniture.solver` (docs/furniture.md,
thesis §5.3.4): it reads the rule table, looks up each item's model (loaded once per
build through the shared model library), converts the table's distances to metres
(from grammar units unless the table says ``# units: m``) and returns the floor with its furniture and the solver's messages.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from cga.errors import DerivationError, ResourceNotFoundError, RuleTableError
from cga.model import Diagnostic, FloorPlan
from cga.shape import Shape
from cga.table_units import unit_note

from cga.operation import CheckContext, Child, Operation, OperationContext, Param, is_number
from .furniture.library import ModelLibrary, grammar_library
from .furniture.passage import PASSAGE_WIDTH
from .furniture.rules import FurnitureRule, FurnitureRules, load_furniture_rules

if TYPE_CHECKING:
    import numpy as np

# The solver (layout, clearances, passage, steering) is imported by ``furnish``, not
# here: ``cga check`` loads this module for its parameters, value and file checks only.

__all__ = ["AddFurniture", "LIBRARY_CACHE_KEY", "MAX_STEERING_ITERATIONS", "furnish"]

LIBRARY_CACHE_KEY = "model_library"
"""Key of the build's :class:`~cga.operations.furniture.library.ModelLibrary` in
:attr:`OperationContext.cache`."""


MAX_STEERING_ITERATIONS = 10_000
"""Most rounds of separation steering a grammar may ask for. Steering stops early once
the items stop moving (usually within a few hundred rounds), but a layout that keeps
oscillating would run every round, for every room and attempt."""


class AddFurniture(Operation):
    """Typed floor → the same floor with furniture in every typed room.

    Parameters (grammar)
    --------------------
    rules:
        The furniture rule table (CSV, see :mod:`cga.operations.furniture.rules`),
        found next to the grammar first, then among the shipped ``rules/``.
    openings, doorWidth, doorHeight:
        ``wallWidth>windowWidth>windowHigh`` and the door size, accepted so the thesis'
        grammars run unchanged. They are not used: the floor plan already knows its
        walls, windows and doors (``make_floor``/``type_rooms``), and the door leaves and
        window panes are sized to the openings themselves.
    steeringIterations:
        Rounds of separation steering of the random start positions (at most
        :data:`MAX_STEERING_ITERATIONS`).
    clearanceTries:
        Attempts per room: while items are left out, the room is solved again from new
        random starts, keeping the layout that places the most items (stopping early
        after :data:`~cga.operations.furniture.solver.PATIENCE` attempts in a row that
        place no more).
    passage_width (keyword):
        Width of the passage every solid item must leave between the doors of its room,
        in grammar units; default 0.6 m (a robot of 0.5 m diameter plus a margin), 0
        switches the rule off. An item that would cut a door off, or wall off more than
        15 % of the floor a robot can reach, stands elsewhere or is left out
        (:mod:`cga.operations.furniture.passage`).
    disorder (keyword):
        Noise in [0, 1] (default 0: tidy) turning and shifting the movable items
        (the chairs, or the rows marked ``isMovable``; a row's own ``disorder`` wins)
        off their tidy pose, each disturbed pose checked like any other
        (:mod:`cga.operations.furniture.disorder`; the TFG's chair noise, 0.4 in its
        robot runs).

    Every item that cannot be placed is left out with a warning naming the item, the
    room and the reason; the warnings travel on the floor plan's ``diagnostics``.
    """

    name = "add_furniture"
    params = (
        Param("rules", "path", doc="furniture rule table (CSV)"),
        Param("openings", "tuple", default=None, items=("length", "length", "length"),
              doc="wallWidth>windowWidth>windowHigh (thesis compatibility; unused)"),
        Param("doorWidth", "length", default=None, doc="door width (thesis compatibility; unused)"),
        Param("doorHeight", "length", default=None,
              doc="door height (thesis compatibility; unused)"),
        Param("steeringIterations", "count", default=10,
              doc="rounds of separation steering of the start positions"),
        Param("clearanceTries", "count", default=20,
              doc="solves per room from new random starts while items are left out"),
        Param("passage_width", "length", default=PASSAGE_WIDTH, keyword_only=True,
              doc="free passage kept between each room's doors (default 0.6 m; 0: none)"),
        Param("disorder", "number", default=0.0, keyword_only=True,
              doc="noise in [0, 1] on the poses of movable items such as chairs (0: tidy)"),
    )
    doc = ("add_furniture(rules.csv, wallWidth>windowWidth>windowHigh, doorWidth, doorHeight, "
           "steeringIterations, clearanceTries): furnish every typed room of the floor")

    def check_values(self, args: dict[str, Any], units: float) -> None:
        passage, steering = args["passage_width"], args["steeringIterations"]
        if is_number(passage) and not passage >= 0:
            raise DerivationError(f"passage_width must not be negative, got {passage / units:g}",
                                  hint="use 0 to switch the passage rule off")
        disorder = args["disorder"]
        if is_number(disorder) and not 0 <= disorder <= 1:
            raise DerivationError(f"disorder must be in [0, 1], got {disorder:g}",
                                  hint="0 keeps every item tidy, 1 is the most disorder")
        if is_number(steering) and steering > MAX_STEERING_ITERATIONS:
            raise DerivationError(
                f"steeringIterations must be at most {MAX_STEERING_ITERATIONS:,}, got "
                f"{steering:,}",
                hint="steering settles within a few hundred rounds; 10 is the usual value")

    def check_files(self, args: dict[str, Any], ctx: CheckContext) -> None:
        """The table loads and every model it names is found and loads."""
        if not isinstance(args["rules"], str):
            return
        rules = _rules(ctx, Path(ctx.resolve(args["rules"], "rules")))
        library = _library(ctx)
        for rule in rules:
            _model(rule, library.check, rules.file)

    def apply(self, shape: Shape, args: dict[str, Any], ctx: OperationContext) -> list[Child]:
        plan = shape.plan
        if plan is None:
            raise DerivationError(
                "add_furniture needs a floor with typed rooms, but this shape has no floor plan",
                ctx.span, hint="apply make_floor(...) and type_rooms(...) before add_furniture")
        if not any(room.type for room in plan.rooms):
            raise DerivationError(
                "add_furniture needs typed rooms, but no room of this floor has a type",
                ctx.span, hint="apply type_rooms(...) before add_furniture")
        self.check_values(args, ctx.units)
        path = Path(ctx.resolve(args["rules"], "rules"))
        furnished = furnish(plan, _rules(ctx, path), _library(ctx), ctx.rng, ctx.units,
                            args["steeringIterations"], args["clearanceTries"],
                            args["passage_width"], args["disorder"])
        return [Child(successor=0, geometry=shape.geometry, scope=shape.scope, plan=furnished)]


def furnish(plan: FloorPlan, rules: FurnitureRules, library: ModelLibrary,
            rng: np.random.Generator, units: float, steering_iterations: int,
            clearance_tries: int, passage_width: float, disorder: float = 0.0) -> FloorPlan:
    """``plan`` with furniture from a parsed table (every model must be in ``library``);
    the operation and :func:`cga.authoring.furnish_floor` both call this."""
    from .furniture.solver import furnish_plan

    models = _models(rules, library)
    furniture, diagnostics = furnish_plan(plan, rules.scaled(units), models, rng,
                                          steering_iterations=steering_iterations,
                                          attempts=clearance_tries,
                                          passage_width=passage_width, disorder=disorder)
    for item in furniture:
        if item.is_detail:
            library.get(item.model)
    return plan.with_changes(furniture=furniture, diagnostics=plan.diagnostics + diagnostics)


def _rules(ctx: OperationContext | CheckContext, path: Path) -> FurnitureRules:
    """The parsed table, read once per build."""
    key = f"furniture_rules:{path.resolve()}"
    rules = ctx.cache.get(key)
    if rules is None:
        rules = ctx.cache[key] = load_furniture_rules(path)
        note = unit_note(rules.file, rules.unit, ctx.units, "distances and clearances")
        if isinstance(ctx, OperationContext) and note is not None:
            ctx.report(Diagnostic("info", "add_furniture", note))
    return rules


def _library(ctx: OperationContext | CheckContext) -> ModelLibrary:
    """The build's model library (``ctx.library``); a hand-made context without one gets
    the grammar's folder and its ``models/``, then each allowed folder (``--allow-path``)
    and its ``models/``, then the shipped models, read only inside ``ctx.sandbox``,
    created on first use and shared through ``ctx.cache``."""
    if ctx.library is not None:
        return ctx.library
    library = ctx.cache.get(LIBRARY_CACHE_KEY)
    if library is None:
        library = ctx.cache[LIBRARY_CACHE_KEY] = grammar_library(ctx.base_dir, ctx.sandbox)
    return library


def _model(rule: FurnitureRule, lookup: Callable[[str], Any], file: str) -> Any:
    """``lookup(rule.name)`` (the library's ``get`` or ``check``), a missing model
    reported at the rule's row."""
    try:
        return lookup(rule.name)
    except ResourceNotFoundError as error:
        looked = ", ".join(error.searched)
        raise RuleTableError(f"no model for '{rule.name}' (looked for "
                             f"{' or '.join(repr(n) for n in rule.model_candidates())}.obj "
                             f"in {looked})", file=file, row=rule.row, column="Name") from None


def _models(rules: FurnitureRules, library: ModelLibrary
            ) -> dict[str, tuple[str, tuple[float, float, float]]]:
    """Rule name → (model name, size in metres); every model must exist."""
    models = {}
    for rule in rules:
        model = _model(rule, library.get, rules.file)
        if not rule.is_detail:
            models[rule.name] = (model.name, model.size)
    return models
