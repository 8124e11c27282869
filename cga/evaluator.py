"""Derive the shape tree: apply a grammar's rules to the lot until only terminals remain.

The evaluator works on :mod:`cga.ast` nodes (never on parse trees) and knows nothing of
geometry: operations do the geometry, looked up by name in a per-evaluator copy of the
:class:`~cga.registry.OperationRegistry` (a user may register operations of their own).

Derivation (docs/language.md):

* The start symbol is ``Lot`` if a rule for it exists, else the first rule's predecessor.
  The root shape is the lot: a :class:`~cga.shape.Mass` of height 0.
* Variables are evaluated once, in order (a variable may use earlier ones); ``[a;b]``
  draws from the stream ``(seed, "variables", name)``.
* A shape whose symbol has a rule is rewritten: a stochastic choice draws from the
  shape's own stream, a ``case`` takes the first true guard, and each ``op(args)
  Successors`` step of the chosen sequence is applied to the shape. A symbol without a
  rule is terminal; terminals are collected in depth-first order.
* Each shape's stream is :func:`~cga.randomness.shape_rng` ``(seed, path)``. A path is
  the chain of successor names from the root; a rule application that yields several
  children names them ``Symbol[i]`` (``i`` counts the application's children from 0).
  Paths depend only on the rules above a shape, so editing one rule re-rolls only the
  shapes under it.
* Arguments are bound to the operation's declared parameters (:mod:`cga.binding`);
  ``length``/``area`` arguments are converted from grammar units to metres. Split
  parts become ``args["parts"] = [(mode, size, successor_index)]`` (sizes of absolute
  and floating parts in metres, relative parts as ratios) and ``args["repeat"]``.
* Errors a user can cause are :class:`~cga.errors.DerivationError` with the span of the
  offending text; a :class:`~cga.errors.SourceError` raised inside an operation without
  a span gets the call's span. Other exceptions from operations are bugs and propagate.
"""

from __future__ import annotations

import math
import time
from collections import defaultdict
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from shapely.geometry import Polygon

from . import ast
from .binding import bind_arguments
from .errors import (BudgetError, CGAError, DerivationError, NoSolutionError, ResourceAccessError,
                     ResourceNotFoundError, SourceError, Span, UsageError)
from .expressions import UNKNOWN, Namespace, Value, describe, evaluate, shape_attributes
from .lot import DEFAULT_LOT, lot_from_call, rectangle
from .model import Diagnostic
from .overrides import check_override_names, override_value
from .randomness import shape_rng, variable_rng
from .resources import resolve_resource
from .sandbox import Sandbox
from .shape import Mass, Shape
from cga.registry import OperationRegistry, UnknownOperation
from cga.operation import PARALLEL_SPINES_USED, Child, Operation, OperationContext

if TYPE_CHECKING:  # pragma: no cover
    from cga.operations.furniture.library import ModelLibrary

__all__ = [
    "DEFAULT_MAX_DEPTH",
    "MAX_DEPTH_LIMIT",
    "MAX_SHAPES",
    "DerivedShape",
    "Derivation",
    "Evaluator",
    "derive",
    "start_symbol",
    "index_rules",
    "evaluate_units",
    "evaluate_variables",
    "choose_sequence",
    "check_percentages",
    "successor_symbols",
    "check_successors",
    "check_max_depth",
]

DEFAULT_MAX_DEPTH = 64
"""Deepest shape path a derivation may reach before it is reported as runaway recursion."""

MAX_DEPTH_LIMIT = 1_000
"""Largest depth limit that may be asked for (``--max-depth``). Every shape stores its
path from the root, so memory grows with the square of the depth; 100,000 took 7.5 GB."""

MAX_SHAPES = 20_000
"""Most shapes one derivation may make (docs/limits.md). Buildings make hundreds; each
shape costs meshing and export time, and nested repeats of tiny sizes would make
millions. Splits refuse before cutting when they would pass it."""


@dataclass
class DerivedShape:
    """A node of the derived shape tree: the shape, the rule applied to it (None for a
    terminal) and the shapes that rule produced."""

    shape: Shape
    rule: ast.Rule | None = None
    children: list["DerivedShape"] = field(default_factory=list)

    def walk(self) -> Iterator["DerivedShape"]:
        """This node and all nodes below it, depth first."""
        stack = [self]
        while stack:
            node = stack.pop()
            yield node
            stack.extend(reversed(node.children))


@dataclass
class Derivation:
    """The result of :meth:`Evaluator.derive`.

    ``terminals`` are the leaves in depth-first order; ``timings`` sums the seconds spent
    in each operation (by operation name); ``variables`` are the evaluated variables;
    ``units`` is metres per grammar unit; ``lot`` the starting footprint (metres).
    """

    root: DerivedShape
    terminals: list[Shape]
    variables: dict[str, Value]
    units: float
    lot: Polygon
    diagnostics: list[Diagnostic] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)


def start_symbol(grammar: ast.Grammar) -> str:
    """``Lot`` if a rule for it exists, else the first rule's predecessor.

    Raises
    ------
    DerivationError
        The grammar has no rules.
    """
    names = [rule.predecessor.name for rule in grammar.rules]
    if not names:
        raise DerivationError("the grammar has no rules", Span(grammar.file, 1, 1),
                              hint="add a Rules: section, e.g. Lot --> extrude(6) Building")
    return "Lot" if "Lot" in names else names[0]


def evaluate_units(grammar: ast.Grammar) -> float:
    """The grammar's ``units`` (metres per grammar unit), 1 if not declared.

    Raises
    ------
    DerivationError
        ``units`` is not a positive number.
    """
    if grammar.units is None:
        return 1.0
    value = evaluate(grammar.units, Namespace(variables={}))
    if isinstance(value, bool) or not isinstance(value, float) or not value > 0:
        raise DerivationError(f"units must be a positive number (metres per grammar unit), "
                              f"got {describe(value)}", grammar.units.span)
    return value


def evaluate_variables(grammar: ast.Grammar, seed: int | None,
                       overrides: Mapping[str, str] | None = None) -> dict[str, Value]:
    """Evaluate the Variables section in order.

    ``seed=None`` evaluates statically (for ``cga check``): ranges become UNKNOWN.
    ``overrides`` (``--set NAME=VALUE``, :mod:`cga.overrides`) replace a variable's value
    by text of the same kind; later variables see the new value.

    Raises
    ------
    DerivationError
        A variable uses an undefined or later variable, a shape attribute, or a value
        of the wrong kind.
    """
    values: dict[str, Value] = {}
    pending = {a.name: a.span for a in grammar.variables}
    for assignment in grammar.variables:
        pending.pop(assignment.name, None)
        rng = None if seed is None else variable_rng(seed, assignment.name)
        ns = Namespace(variables=values, attributes=None, rng=rng, later=pending)
        value = evaluate(assignment.value, ns)
        if overrides and assignment.name in overrides:
            value = override_value(assignment.name, overrides[assignment.name], value)
        values[assignment.name] = value
    return values


def index_rules(grammar: ast.Grammar) -> dict[str, ast.Rule]:
    """Rules by predecessor name.

    Raises
    ------
    DerivationError
        Two rules share a predecessor.
    """
    rules: dict[str, ast.Rule] = {}
    for rule in grammar.rules:
        name = rule.predecessor.name
        if name in rules:
            raise DerivationError(f"a second rule for {name} (the first is at line "
                                  f"{rules[name].span.line})", rule.predecessor.span,
                                  hint="merge them into one rule with `|` alternatives")
        rules[name] = rule
    return rules


def check_percentages(choice: ast.Stochastic, ns: Namespace) -> list[tuple[float, ast.Branch]]:
    """The stochastic branches with their percentages, checked.

    Returns
    -------
    list
        ``(percent, branch)`` pairs in order; ``else`` gets the remainder to 100. Empty
        when a percentage is :data:`~cga.expressions.UNKNOWN` (static checks only).

    Raises
    ------
    DerivationError
        A percentage is not a number in [0, 100], they sum past 100, or they fall short
        of 100 without an ``else`` branch.
    """
    weighted: list[tuple[float, ast.Branch]] = []
    total = 0.0
    else_branch: ast.Branch | None = None
    for branch in choice.branches:
        if branch.guard is None:
            else_branch = branch
            continue
        value = evaluate(branch.guard, ns)
        if value is UNKNOWN:  # static check of a percentage that depends on the shape
            return []
        if isinstance(value, bool) or not isinstance(value, float) or not 0 <= value <= 100:
            raise DerivationError(f"a stochastic branch needs a percentage between 0 and 100, "
                                  f"got {describe(value)}", branch.guard.span)
        weighted.append((value, branch))
        total += value
    if total > 100 + 1e-9:
        raise DerivationError(f"the percentages add up to {total:g}%, more than 100%", choice.span,
                              hint="lower them so they add up to at most 100%")
    if else_branch is not None:
        weighted.append((max(0.0, 100.0 - total), else_branch))
    elif total < 100 - 1e-9:
        raise DerivationError(f"the percentages add up to {total:g}%, not 100%, and there is "
                              f"no else branch", choice.span,
                              hint="add `| else : ...` or make them add up to 100%")
    return weighted


def choose_sequence(body: ast.Body, ns: Namespace, rng: np.random.Generator,
                    symbol: str) -> ast.Sequence:
    """Resolve choices in ``body`` down to the sequence of steps to apply.

    A stochastic choice draws one uniform number from ``rng``; a ``case`` takes the first
    branch whose guard is true.

    Raises
    ------
    DerivationError
        Bad percentages, or no ``case`` is true and there is no ``else``.
    """
    while not isinstance(body, ast.Sequence):
        if isinstance(body, ast.Stochastic):
            draw = rng.uniform(0.0, 100.0)
            cumulative = 0.0
            weighted = check_percentages(body, ns)
            chosen = weighted[-1][1]
            for percent, branch in weighted:
                cumulative += percent
                if draw < cumulative:
                    chosen = branch
                    break
            body = chosen.body
        else:
            for branch in body.branches:
                if branch.guard is None or evaluate(branch.guard, ns):
                    body = branch.body
                    break
            else:
                values = ", ".join(f"{name} = {describe(value)}" for name, value in
                                   (ns.attributes or {}).items() if not name.startswith("scope.t"))
                raise DerivationError(f"no case of rule {symbol} is true for this shape "
                                      f"({values})", body.span,
                                      hint="add `| else : ...` as the last branch")
    return body


def successor_symbols(step: ast.Step) -> tuple[ast.Symbol, ...]:
    """The successors of a step: the split parts' symbols if it has parts."""
    if step.parts:
        return tuple(part.successor for part in step.parts)
    return step.successors


def _area(shape: Shape) -> float:
    geometry = shape.geometry
    if isinstance(geometry, Mass):
        return float(geometry.footprint.area)
    pts = np.asarray(geometry.vertices, dtype=float)
    return float(np.linalg.norm(np.cross(pts, np.roll(pts, -1, axis=0)).sum(axis=0)) / 2)


def _base_name(element: str) -> str:
    return element.split("[", 1)[0]


def _cycle(path: tuple[str, ...]) -> str:
    """``X → Y → X …`` from the tail of a path that recursed too deeply."""
    names = [_base_name(e) for e in path]
    last = names[-1]
    earlier = [i for i, name in enumerate(names[:-1]) if name == last]
    start = earlier[-1] if earlier else max(0, len(names) - 4)
    return " → ".join(names[start:]) + " …"


@dataclass
class _Run:
    """The state of one derivation, shared by all rule applications."""

    variables: Mapping[str, Value]
    diagnostics: list[Diagnostic] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=lambda: defaultdict(float))
    cache: dict[str, Any] = field(default_factory=dict)
    shapes: int = 1
    parallel_spines: bool = True


def check_max_depth(max_depth: int) -> None:
    """Refuse a depth limit outside ``1..MAX_DEPTH_LIMIT``.

    Raises
    ------
    UsageError
        Naming the option and the allowed range.
    """
    if isinstance(max_depth, bool) or not isinstance(max_depth, int) \
            or not 1 <= max_depth <= MAX_DEPTH_LIMIT:
        raise UsageError(f"--max-depth must be a whole number from 1 to {MAX_DEPTH_LIMIT:,}, "
                         f"got {max_depth!r}")


class Evaluator:
    """Derives a grammar's shape tree.

    Parameters
    ----------
    grammar:
        The parsed grammar.
    seed:
        Build seed (non-negative); with the same seed a derivation is identical.
    units:
        Metres per grammar unit; overrides the grammar's ``units`` when given.
    operations:
        Operation table; copied, so registering on it later does not affect this
        evaluator. Default: :class:`~cga.registry.OperationRegistry` ().
    max_depth:
        Longest shape path allowed before the derivation fails as runaway recursion.
    base_dir:
        Folder that relative file arguments are resolved against (default: the
        grammar file's folder).
    strict:
        Passed to operations (``OperationContext.strict``): fail instead of repairing.
    library:
        The furniture model library operations use (``OperationContext.library``);
        default: the grammar's folder and its ``models/``, then the shipped models.
    sandbox:
        The folders rule tables and models may be read from (:mod:`cga.sandbox`);
        default: ``base_dir`` and the shipped data.
    overrides:
        ``--set`` values of grammar variables (name → text, :mod:`cga.overrides`).

    Raises
    ------
    UsageError
        An override names no variable of the grammar.
    """

    def __init__(self, grammar: ast.Grammar, *, seed: int = 0, units: float | None = None,
                 operations: OperationRegistry | None = None,
                 max_depth: int = DEFAULT_MAX_DEPTH, base_dir: str | Path | None = None,
                 strict: bool = False, library: ModelLibrary | None = None,
                 sandbox: Sandbox | None = None, overrides: Mapping[str, str] | None = None):
        if seed < 0:
            raise ValueError(f"seed must be non-negative, got {seed}")
        check_max_depth(max_depth)
        self.grammar = grammar
        self.seed = int(seed)
        self.units = evaluate_units(grammar) if units is None else float(units)
        if not self.units > 0:
            raise ValueError(f"units must be positive, got {units}")
        self.operations = (operations or OperationRegistry()).copy()
        self.max_depth = max_depth
        self.base_dir = Path(base_dir) if base_dir is not None else Path(grammar.file).parent
        self.strict = strict
        self.sandbox = sandbox if sandbox is not None else Sandbox.for_grammar(self.base_dir)
        self.rules = index_rules(grammar)
        self.overrides = dict(overrides or {})
        check_override_names(grammar, self.overrides)
        if library is None:
            # imported here: `cga check` uses this module and needs no model files
            from cga.operations.furniture.library import grammar_library

            library = grammar_library(self.base_dir, self.sandbox)
        self.library = library

    # -- public -----------------------------------------------------------------------

    def derive(self, lot: Polygon | None = None) -> Derivation:
        """Derive the shape tree from ``lot`` (metres), the grammar's ``Lot:`` or the default.

        A floor too deep for one corridor is laid on parallel spines (``make_floor``'s
        ``max_room_depth``), whose middle band has no outer wall: a table whose rooms
        need windows may then type no layout of it. Such a derivation is made once more
        with every floor on one spine, as before the spines, with a warning (not with
        ``strict``); if that fails too, the first error is raised.

        Raises
        ------
        DerivationError
            Any rule that cannot be applied (see the module docstring).
        CGAError
            Errors raised by operations (rule tables, infeasible typing, ...).
        """
        variables = evaluate_variables(self.grammar, self.seed, self.overrides)
        footprint = lot if lot is not None else self._grammar_lot(variables)
        run = _Run(variables=variables)
        try:
            return self._derive(footprint, run)
        except NoSolutionError as error:
            if self.strict or not run.cache.get(PARALLEL_SPINES_USED):
                raise
            first = error
        retry = _Run(variables=variables, parallel_spines=False)
        try:
            derivation = self._derive(footprint, retry)
        except CGAError:
            raise first from None
        why = str(first).splitlines()[0]
        derivation.diagnostics.insert(0, Diagnostic("warning", "make_floor", (
            f"no layout on parallel spines could be typed ({why}), so every floor was laid "
            "on one spine, its rooms deeper than max_room_depth")))
        for name, seconds in run.timings.items():
            derivation.timings[name] = derivation.timings.get(name, 0.0) + seconds
        return derivation

    def _derive(self, footprint: Polygon, run: _Run) -> Derivation:
        """:meth:`derive` in one pass, with ``run``'s state (its ``parallel_spines`` goes to
        the operations)."""
        symbol = start_symbol(self.grammar)
        mass = Mass(footprint=footprint, base=0.0, height=0.0)
        root = DerivedShape(Shape(symbol=symbol, path=(symbol,), scope=mass.scope(), geometry=mass))
        terminals: list[Shape] = []
        stack = [root]
        try:
            while stack:
                node = stack.pop()
                rule = self.rules.get(node.shape.symbol)
                if rule is None:
                    terminals.append(node.shape)
                    continue
                node.rule = rule
                node.children = self._apply_rule(node.shape, rule, run)
                stack.extend(reversed(node.children))
        except CGAError as error:  # keep what the derivation said before it failed
            error.diagnostics = (*run.diagnostics, *error.diagnostics)
            raise
        return Derivation(root=root, terminals=terminals, variables=dict(run.variables),
                          units=self.units, lot=footprint, diagnostics=run.diagnostics,
                          timings=dict(run.timings))

    # -- derivation steps ------------------------------------------------------------

    def _grammar_lot(self, variables: Mapping[str, Value]) -> Polygon:
        call = self.grammar.lot
        if call is None:
            return rectangle(*DEFAULT_LOT)
        ns = Namespace(variables=variables)
        values = [evaluate(arg, ns) for arg in call.args]
        return lot_from_call(call.name, values, call.span, self.units)

    def _namespace(self, shape: Shape, variables: Mapping[str, Value],
                   rng: np.random.Generator) -> Namespace:
        attributes = shape_attributes(shape.scope.size, shape.scope.origin, _area(shape),
                                      shape.attrs, self.units)
        return Namespace(variables=variables, attributes=attributes, rng=rng)

    def _apply_rule(self, shape: Shape, rule: ast.Rule, run: _Run) -> list[DerivedShape]:
        if len(shape.path) > self.max_depth:
            raise DerivationError(
                f"recursion deeper than {self.max_depth} at rule {rule.predecessor.name} "
                f"({_cycle(shape.path)})", rule.predecessor.span,
                hint="guard the recursion with a case that stops it (e.g. `case scope.sy > 1 "
                     ": ... | else : ...`) or raise the depth limit")
        rng = shape_rng(self.seed, shape.path)
        ns = self._namespace(shape, run.variables, rng)
        sequence = choose_sequence(rule.body, ns, rng, rule.predecessor.name)
        produced: list[tuple[ast.Symbol, Child]] = []
        for step in sequence.steps:
            produced.extend(self._apply_step(shape, step, rule, ns, rng, run))
        several = len(produced) > 1
        children = []
        for i, (symbol, child) in enumerate(produced):
            element = f"{symbol.name}[{i}]" if several else symbol.name
            children.append(DerivedShape(Shape(
                symbol=symbol.name, path=shape.path + (element,), scope=child.scope,
                geometry=child.geometry, attrs={**shape.attrs, **child.attrs},
                plan=child.plan)))
        return children

    def _apply_step(self, shape: Shape, step: ast.Step, rule: ast.Rule, ns: Namespace,
                    rng: np.random.Generator, run: _Run) -> list[tuple[ast.Symbol, Child]]:
        successors = successor_symbols(step)
        if step.op is None:
            return [(symbol, Child(successor=i, geometry=shape.geometry, scope=shape.scope,
                                   plan=shape.plan)) for i, symbol in enumerate(successors)]
        call = step.op
        operation = self._operation(call)
        check_successors(operation, step, rule)
        values = [evaluate(arg.value, ns) for arg in call.args]
        args = bind_arguments(operation, call, values, units=self.units)
        if operation.takes_split_parts:
            args["parts"] = self._split_parts(step, ns)
            args["repeat"] = step.repeat
        ctx = OperationContext(
            rng=rng, units=self.units, resolve=self._resolver(call),
            report=run.diagnostics.append, span=call.span, successor_count=len(successors),
            cache=run.cache, seed=self.seed, strict=self.strict, base_dir=self.base_dir,
            library=self.library, sandbox=self.sandbox, shapes_left=MAX_SHAPES - run.shapes,
            parallel_spines=run.parallel_spines)
        started = time.perf_counter()
        try:
            children = operation.apply(shape, args, ctx)
        except SourceError as error:
            if error.span is None:
                error.span = call.span
            raise
        finally:
            run.timings[operation.name] += time.perf_counter() - started
        run.shapes += len(children)
        if run.shapes > MAX_SHAPES:
            raise BudgetError(f"the derivation made more than {MAX_SHAPES:,} shapes "
                              f"(docs/limits.md)", call.span,
                              hint="use larger split sizes or fewer repeats")
        for child in children:
            if not 0 <= child.successor < len(successors):
                raise IndexError(f"operation {operation.name} produced a child for successor "
                                 f"{child.successor}, but the step has {len(successors)}")
        return [(successors[child.successor], child) for child in children]

    def _resolver(self, call: ast.OpCall) -> Callable[..., Path]:
        """``ctx.resolve`` for one call: a missing file is reported at the argument that
        names it (or the call)."""
        def resolve(path: str | Path, kind: str = "rules") -> Path:
            try:
                return resolve_resource(path, kind, base_dir=self.base_dir,
                                        sandbox=self.sandbox)
            except (ResourceNotFoundError, ResourceAccessError) as error:
                span = next((a.span for a in call.args if isinstance(a.value, ast.String)
                             and a.value.value == str(path)), None)
                raise DerivationError(str(error), span or call.span) from None
        return resolve

    def _operation(self, call: ast.OpCall) -> Operation:
        try:
            return self.operations[call.name]
        except UnknownOperation as error:
            hint = (f"did you mean '{error.suggestions[0]}'?" if error.suggestions else
                    "operations: " + ", ".join(sorted(self.operations)))
            raise DerivationError(f"unknown operation '{call.name}'", call.span,
                                  hint=hint) from None

    def _split_parts(self, step: ast.Step, ns: Namespace
                     ) -> list[tuple[ast.SplitMode, float, int]]:
        parts = []
        for index, part in enumerate(step.parts):
            value = evaluate(part.size, ns)
            if isinstance(value, bool) or not isinstance(value, float):
                raise DerivationError(f"a split size must be a number, got {describe(value)}",
                                      part.size.span)
            if not 0 <= value < math.inf:
                raise DerivationError(f"a split size must be a finite number ≥ 0, got "
                                      f"{describe(value)}", part.size.span)
            size = value if part.mode == "relative" else value * self.units
            parts.append((part.mode, size, index))
        return parts


def check_successors(operation: Operation, step: ast.Step, rule: ast.Rule) -> None:
    """Check a step's successors against the operation: split parts and successor count.

    Raises
    ------
    DerivationError
        Sized parts given to an operation that takes plain successors (or the reverse),
        or a successor count outside ``min_successors..max_successors``; at the step.
    """
    span = step.span or rule.span
    if operation.takes_split_parts and not step.parts:
        raise DerivationError(
            f"{operation.name} needs sized parts, e.g. {operation.name}(...)"
            f"{{ 2 : A | ~1 : B }}", span,
            hint="sizes: absolute `2`, floating `~2`, relative `'0.5`; `*` after `}` repeats")
    if step.parts and not operation.takes_split_parts:
        raise DerivationError(f"{operation.name} takes successors {{A, B}}, not sized parts",
                              span, hint=f"signature: {operation.signature()}")
    count = len(successor_symbols(step))
    low, high = operation.min_successors, operation.max_successors
    if count < low or (high is not None and count > high):
        if high is None:
            expected = f"at least {low}"
        elif low == high:
            expected = str(low)
        else:
            expected = f"{low} to {high}"
        raise DerivationError(
            f"{operation.name} takes {expected} successor{'s' * (expected != '1')}, "
            f"got {count} in rule {rule.predecessor.name}", span,
            hint=f"signature: {operation.signature()}")


def derive(grammar: ast.Grammar, lot: Polygon | None = None, *, seed: int = 0,
           **options: Any) -> Derivation:
    """Shortcut for ``Evaluator(grammar, seed=seed, **options).derive(lot)``."""
    return Evaluator(grammar, seed=seed, **options).derive(lot)

