"""``cga check``: find a grammar's mistakes without deriving any geometry.

Everything the evaluator would reject that does not depend on a shape is checked here,
for every rule and every branch (a derivation only visits the branches it takes):
unknown operations, argument counts, names and kinds, undefined variables, successor
arity and split parts, stochastic percentages, the ``Lot:`` shape, argument values no
shape could accept (``extrude(-3)``, ``wallWidth = 0``; :meth:`Operation.check_values`),
and the files arguments name: rule tables are read and checked and every model a
furniture table names is loaded (:meth:`Operation.check_files`), inside the same
sandbox as a build (:mod:`cga.sandbox`). Shape attributes (``scope.sx``, ``area``, ...) and ``[a;b]``
draws inside rules are unknown statically; arguments that depend on them skip the kind
check. All problems are reported, not only the first.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any, TypeVar

from . import ast
from .binding import bind_arguments
from .errors import (CGAError, DerivationError, ResourceAccessError, ResourceNotFoundError,
                     SourceError)
from .evaluator import (check_percentages, check_successors, evaluate_units,
                        evaluate_variables, index_rules, start_symbol)
from .expressions import ATTRIBUTES, UNKNOWN, Namespace, Value, evaluate
from .lot import lot_from_call
from .resources import resolve_resource
from .sandbox import Sandbox
from cga.operation import CheckContext
from cga.registry import OperationRegistry, UnknownOperation

__all__ = ["check_grammar", "check_file"]

_T = TypeVar("_T")


class _Checker:
    def __init__(self, grammar: ast.Grammar, base_dir: Path, operations: OperationRegistry,
                 sandbox: Sandbox):
        self.grammar = grammar
        self.base_dir = base_dir
        self.sandbox = sandbox
        self.operations = operations
        self.problems: list[CGAError] = []
        self.cache: dict[str, object] = {}
        self.units = 1.0

    def attempt(self, check: Callable[..., _T], *args: Any) -> _T | None:
        """Run one check; record a user error and carry on."""
        try:
            return check(*args)
        except CGAError as error:
            self.problems.append(error)
            return None

    def run(self) -> list[CGAError]:
        self.attempt(start_symbol, self.grammar)
        self.attempt(index_rules, self.grammar)
        self.units = self.attempt(evaluate_units, self.grammar) or 1.0
        variables = self.attempt(evaluate_variables, self.grammar, None)
        if variables is None:
            variables = {a.name: UNKNOWN for a in self.grammar.variables}
        if self.grammar.lot is not None:
            self.attempt(self.check_lot, variables)
        ns = Namespace(variables=variables, attributes=dict.fromkeys(ATTRIBUTES, UNKNOWN))
        for rule in self.grammar.rules:
            self.check_body(rule, rule.body, ns)
        return self.problems

    def check_lot(self, variables: dict[str, Value]) -> None:
        call = self.grammar.lot
        if call is None:
            return
        values = [evaluate(arg, Namespace(variables=variables)) for arg in call.args]
        if UNKNOWN not in values:
            lot_from_call(call.name, values, call.span, self.units)

    def check_body(self, rule: ast.Rule, body: ast.Body, ns: Namespace) -> None:
        if isinstance(body, ast.Sequence):
            for step in body.steps:
                self.attempt(self.check_step, rule, step, ns)
            return
        if isinstance(body, ast.Stochastic):
            self.attempt(check_percentages, body, ns)
        else:
            for branch in body.branches:
                if branch.guard is not None:
                    self.attempt(evaluate, branch.guard, ns)
        for branch in body.branches:
            self.check_body(rule, branch.body, ns)

    def check_step(self, rule: ast.Rule, step: ast.Step, ns: Namespace) -> None:
        if step.op is None:
            return
        call = step.op
        try:
            operation = self.operations[call.name]
        except UnknownOperation as error:
            hint = (f"did you mean '{error.suggestions[0]}'?" if error.suggestions else
                    "operations: " + ", ".join(sorted(self.operations)))
            raise DerivationError(f"unknown operation '{call.name}'", call.span, hint=hint) from None
        check_successors(operation, step, rule)
        for part in step.parts:
            self.attempt(evaluate, part.size, ns)
        values: list[Value] = []
        for arg in call.args:
            value = self.attempt(evaluate, arg.value, ns)
            values.append(UNKNOWN if value is None else value)
        args = bind_arguments(operation, call, values, units=self.units)
        with _at(call):
            operation.check_values(args, self.units)
            operation.check_files(args, CheckContext(
                units=self.units, resolve=self.resolver(call, values), base_dir=self.base_dir,
                sandbox=self.sandbox, cache=self.cache))

    def resolver(self, call: ast.OpCall, values: Sequence[object]):
        """``resolve`` for one call: a missing or refused file is reported at the argument
        that names it."""
        def resolve(value: str, kind: str = "rules") -> Path:
            try:
                return resolve_resource(value, kind, base_dir=self.base_dir,
                                        sandbox=self.sandbox)
            except (ResourceNotFoundError, ResourceAccessError) as error:
                span = next((a.span for a, v in zip(call.args, values) if v == value), None)
                raise DerivationError(str(error), span or call.span) from None
        return resolve


@contextlib.contextmanager
def _at(call: ast.OpCall) -> Iterator[None]:
    """Give a source error raised without a position the call's span, as a build does."""
    try:
        yield
    except SourceError as error:
        if error.span is None:
            error.span = call.span
        raise


def check_grammar(grammar: ast.Grammar, *, base_dir: str | Path | None = None,
                  operations: OperationRegistry | None = None,
                  allow_paths: Sequence[str | Path] = ()) -> list[CGAError]:
    """All static problems of a parsed grammar, in source order of the checks.

    Parameters
    ----------
    grammar:
        The parsed grammar.
    base_dir:
        Folder rule-table paths are resolved from (default: the grammar file's folder).
    operations:
        Operation table (default: the built-in operations).
    allow_paths:
        Folders besides ``base_dir``'s tree and the shipped data that files may be read
        from, as in a build (:mod:`cga.sandbox`).

    Returns
    -------
    list of CGAError
        Empty when the grammar is fine. Source errors carry spans.
    """
    folder = Path(base_dir) if base_dir is not None else Path(grammar.file).parent
    table = (operations or OperationRegistry()).copy()
    return _Checker(grammar, folder, table, Sandbox.for_grammar(folder, allow_paths)).run()


def check_file(path: str | Path, *, operations: OperationRegistry | None = None,
               allow_paths: Sequence[str | Path] = (), lot: str | None = None) -> list[CGAError]:
    """Parse and check a grammar file; source errors come with the file's text attached.
    ``lot`` is a ``--lot`` value, read as :func:`cga.pipeline.build` reads it (a file
    only inside the allowed folders and the working directory).

    Raises
    ------
    ResourceNotFoundError, UsageError, GrammarSyntaxError
        The file does not exist, is a folder or unreadable, or is not UTF-8 text
        (:func:`cga.parser.read_grammar`).
    """
    from .parser import parse, read_grammar

    file = Path(path)
    text = read_grammar(file)
    try:
        problems = check_grammar(parse(text, str(file)), base_dir=file.parent,
                                 operations=operations, allow_paths=allow_paths)
    except SourceError as error:
        problems = [error]
    for problem in problems:
        if isinstance(problem, SourceError) and problem.span is not None \
                and problem.span.file == str(file):
            problem.with_source(text)
    if lot is not None:
        from .lot import parse_lot

        sandbox = Sandbox.for_grammar(file.parent, allow_paths).with_working_directory()
        try:
            parse_lot(lot, sandbox=sandbox)
        except CGAError as error:
            problems.append(error)
    return problems
