"""lark parse tree → :class:`cga.ast.Grammar` (the second step of :func:`cga.parser.parse`).

Every node keeps the position lark recorded (``propagate_positions``); the AST is made of
the frozen dataclasses of :mod:`cga.ast`. Besides building nodes, this module checks what
the context-free grammar cannot express: statements belong to sections (rules under
``Rules:``), a rule body is a list of ``op(args) Successors`` groups, a choice uses one
kind of guard with ``else`` last, percentages add up, and no rule, variable, ``units`` or
``Lot:`` is given twice. Each problem is a :class:`~cga.errors.GrammarSyntaxError` with a
span.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Literal, NoReturn

from lark import Transformer, v_args

from . import ast
from .errors import GrammarSyntaxError, Span
from .source_positions import Locator

__all__ = ["AstBuilder"]


@dataclass(frozen=True)
class _SuccessorGroup:
    """``B`` or ``{B, C}`` as written after an operation call (or alone, for a rename)."""

    symbols: tuple[ast.Symbol, ...]
    braced: bool
    span: Span


@dataclass(frozen=True)
class _SplitGroup:
    """``{ 2 : A | ~1 : B }*``: sized parts of a split."""

    parts: tuple[ast.SplitPart, ...]
    repeat: bool
    span: Span


@dataclass(frozen=True)
class _Guard:
    kind: Literal["percent", "case", "else"]
    value: ast.Expr | None
    span: Span


@dataclass(frozen=True)
class _Statement:
    """A top-level statement with what the section and `;` checks need."""

    node: ast.Rule | ast.Assignment | ast.Call | str  # str: a section header name
    span: Span
    end_line: int
    has_semicolon: bool = True


_SPLIT_MODES: dict[str | None, ast.SplitMode] = {None: "absolute", "~": "floating",
                                                  "'": "relative"}
_PERCENT_TOLERANCE = 1e-9


def _unescape(body: str) -> str:
    """String contents: ``\\"`` is a quote, every other backslash stays as written."""
    return re.sub(r'\\(.)', lambda m: '"' if m.group(1) == '"' else m.group(0), body)


@v_args(meta=True)
class AstBuilder(Transformer):
    """Builds :mod:`cga.ast` nodes bottom-up; one method per rule of ``grammar.lark``."""

    def __init__(self, text: str, file: str):
        super().__init__()
        self.file = file
        self.loc = Locator(text, file)

    def _error(self, message: str, span: Span | None, hint: str | None = None) -> NoReturn:
        raise GrammarSyntaxError(message, span, hint=hint)

    # ---- expressions ------------------------------------------------------------

    def number(self, meta, children) -> ast.Number:
        (token,) = children
        value = float(token)
        if not math.isfinite(value):
            self._error(f"number `{token}` is too large", self.loc.token(token))
        return ast.Number(value, self.loc.token(token))

    def string(self, meta, children) -> ast.String:
        (token,) = children
        return ast.String(_unescape(token[1:-1]), self.loc.token(token))

    def name(self, meta, children) -> ast.Name:
        (token,) = children
        return ast.Name(str(token), self.loc.token(token))

    def attribute(self, meta, children) -> ast.Attribute:
        return ast.Attribute(tuple(str(t) for t in children), self.loc.meta(meta))

    def random_range(self, meta, children) -> ast.RandomRange:
        low, high = children
        return ast.RandomRange(low, high, self.loc.meta(meta))

    def paren_tuple(self, meta, children) -> ast.TupleExpr:
        return ast.TupleExpr(tuple(children), self.loc.meta(meta))

    def gt_tuple(self, meta, children) -> ast.TupleExpr:
        return ast.TupleExpr(tuple(children), self.loc.meta(meta))

    def binop(self, meta, children) -> ast.BinOp:
        left, op, right = children
        return ast.BinOp(str(op), left, right, self.loc.meta(meta))

    def unary(self, meta, children) -> ast.UnaryOp:
        op, operand = children
        return ast.UnaryOp(str(op), operand, self.loc.meta(meta))

    def call(self, meta, children) -> ast.Call:
        name, args = children
        return ast.Call(str(name), tuple(args or ()), self.loc.meta(meta))

    def call_arguments(self, meta, children) -> list[ast.Expr]:
        return children

    # ---- operation calls and successors -----------------------------------------

    def keyword_argument(self, meta, children) -> ast.Arg:
        name, value = children
        return ast.Arg(value, str(name), self.loc.meta(meta))

    def arguments(self, meta, children) -> tuple[ast.Arg, ...]:
        args = tuple(c if isinstance(c, ast.Arg) else ast.Arg(c, None, c.span)
                     for c in children)
        seen: dict[str, ast.Arg] = {}
        for arg in args:
            if arg.name is None:
                if seen:
                    self._error("a positional argument cannot follow keyword arguments",
                                arg.span, hint="put positional arguments first")
            elif arg.name in seen:
                self._error(f"argument `{arg.name}` is given twice", arg.span)
            else:
                seen[arg.name] = arg
        return args

    def op_call(self, meta, children) -> ast.OpCall:
        name, args = children
        return ast.OpCall(str(name), args or (), self.loc.meta(meta))

    def symbol(self, meta, children) -> _SuccessorGroup:
        (token,) = children
        span = self.loc.token(token)
        return _SuccessorGroup((ast.Symbol(str(token), span),), False, span)

    def successor_list(self, meta, children) -> _SuccessorGroup:
        symbols = tuple(ast.Symbol(str(t), self.loc.token(t)) for t in children)
        return _SuccessorGroup(symbols, True, self.loc.meta(meta))

    def split_part(self, meta, children) -> ast.SplitPart:
        mode, size, name = children
        return ast.SplitPart(_SPLIT_MODES[mode and str(mode)], size,
                             ast.Symbol(str(name), self.loc.token(name)), self.loc.meta(meta))

    def split_parts(self, meta, children) -> _SplitGroup:
        *parts, star = children
        return _SplitGroup(tuple(parts), star is not None, self.loc.meta(meta))

    def sequence(self, meta, children) -> ast.Sequence:
        return ast.Sequence(tuple(self._steps(children)), self.loc.meta(meta))

    def _steps(self, items: list) -> Iterator[ast.Step]:
        """Group ``op(args) Successors`` items into steps; see the module docstring."""
        first = items[0]
        if not isinstance(first, ast.OpCall):
            if len(items) == 1 and isinstance(first, _SuccessorGroup):
                if len(first.symbols) > 1:
                    self._error("a rule without an operation renames its shape to one "
                                "symbol; it cannot have several successors", first.span,
                                hint="call an operation that makes several shapes, e.g. "
                                     "`component_split(\"side_faces\"){A, B}`")
                yield ast.Step(None, first.symbols, span=first.span)
                return
            self._no_operation(first)
        index = 0
        while index < len(items):
            op = items[index]
            if not isinstance(op, ast.OpCall):
                # a group that does not follow an operation call: the item before it is
                # the previous call's successor group
                self._extra_successor(items[index - 1], op)
            index += 1
            following = items[index] if index < len(items) else None
            if isinstance(following, _SuccessorGroup):
                index += 1
                yield ast.Step(op, following.symbols,
                               span=self.loc.join(op.span, following.span))
            elif isinstance(following, _SplitGroup):
                index += 1
                yield ast.Step(op, (), following.parts, following.repeat,
                               span=self.loc.join(op.span, following.span))
            else:
                yield ast.Step(op, (), span=op.span)

    def _no_operation(self, group: _SuccessorGroup | _SplitGroup) -> NoReturn:
        if isinstance(group, _SplitGroup):
            self._error("sized parts need an operation before them", group.span,
                        hint='write e.g. `split("x"){ 2 : A | ~1 : B }`')
        self._error(f"successor {_describe_group(group)} needs an operation before it",
                    group.span,
                    hint="write `op(args) Successor`; only a plain rename `A --> B` has no "
                         "operation")

    def _extra_successor(self, before: _SuccessorGroup | _SplitGroup,
                         group: _SuccessorGroup | _SplitGroup) -> NoReturn:
        if isinstance(group, _SplitGroup):
            self._error("sized parts must directly follow an operation call", group.span)
        if not group.braced and self.loc.first_on_line(group.span.line, group.span.column):
            name = group.symbols[0].name
            self._error(f"expected `-->` after the rule name `{name}`", group.span,
                        hint=f"if `{name}` is another successor of the line above, "
                             "list them in braces: `{A, B}`")
        self._error(f"unexpected successor {_describe_group(group)} after "
                    f"{_describe_group(before)}", group.span,
                    hint="an operation call takes one successor or a brace list "
                         "`{A, B}`; to call an operation write `name(args)`")

    # ---- choices ----------------------------------------------------------------

    def percent_guard(self, meta, children) -> _Guard:
        (token,) = children
        span = self.loc.token(token)
        value = float(token.rstrip("% \t"))
        return _Guard("percent", ast.Number(value, span), span)

    def case_guard(self, meta, children) -> _Guard:
        _case, expr = children
        return _Guard("case", expr, self.loc.meta(meta))

    def else_guard(self, meta, children) -> _Guard:
        (token,) = children
        return _Guard("else", None, self.loc.token(token))

    def branch(self, meta, children) -> tuple[_Guard, ast.Branch]:
        guard, body = children
        return guard, ast.Branch(guard.value, body, self.loc.meta(meta))

    def choice(self, meta, children) -> ast.Stochastic | ast.Conditional:
        guards = [guard for guard, _ in children]
        branches = tuple(branch for _, branch in children)
        span = self.loc.meta(meta)
        kind = guards[0].kind
        if kind == "else":
            self._error("a choice cannot start with `else`", guards[0].span,
                        hint="start with a percentage (`30% : ...`) or a condition "
                             "(`case area > 50 : ...`)")
        for index, guard in enumerate(guards[1:], start=1):
            if guard.kind == "else":
                if index != len(guards) - 1:
                    self._error("`else` must be the last branch of a choice", guard.span)
            elif guard.kind != kind:
                self._error(
                    "a choice cannot mix percentages and `case` conditions", guard.span,
                    hint="nest one choice in parentheses, e.g. "
                         "`case area > 50 : (30% : A | else : B) | else : C`")
        if kind == "case":
            return ast.Conditional(branches, span)
        total = sum(guard.value.value for guard in guards if guard.kind == "percent")
        has_else = guards[-1].kind == "else"
        if total > 100 + _PERCENT_TOLERANCE:
            self._error(f"the percentages add up to {total:g}%, more than 100%", span)
        if not has_else and abs(total - 100) > _PERCENT_TOLERANCE:
            self._error(f"the percentages add up to {total:g}%, not 100%", span,
                        hint="add an `else : ...` branch for the rest, or make them add "
                             "up to 100%")
        return ast.Stochastic(branches, span)

    # ---- statements -------------------------------------------------------------

    def rule(self, meta, children) -> _Statement:
        name, body = children
        span = self.loc.meta(meta)
        node = ast.Rule(ast.Symbol(str(name), self.loc.token(name)), body, span)
        return _Statement(node, span, meta.end_line)

    def assignment(self, meta, children) -> _Statement:
        name, value, semicolon = children
        span = self.loc.meta(meta)
        return _Statement(ast.Assignment(str(name), value, span), span, meta.end_line,
                          semicolon is not None)

    def lot(self, meta, children) -> _Statement:
        _header, call, semicolon = children
        return _Statement(call, self.loc.meta(meta), meta.end_line, semicolon is not None)

    def section(self, meta, children) -> _Statement:
        (header,) = children
        name = header.rstrip(": \t").capitalize()
        return _Statement(name, self.loc.token(header), header.end_line)

    def start(self, meta, children) -> ast.Grammar:
        return _assemble(children, self.file, self.loc)


def _describe_group(group: _SuccessorGroup | _SplitGroup) -> str:
    if isinstance(group, _SplitGroup):
        return "the sized parts `{...}`"
    names = ", ".join(s.name for s in group.symbols)
    return f"`{{{names}}}`" if group.braced else f"`{names}`"


def _assemble(statements: list[_Statement], file: str, loc: Locator) -> ast.Grammar:
    """Sort statements into sections and check duplicates (sections in any order)."""
    section: str | None = None
    rules_header: _Statement | None = None
    rules: dict[str, ast.Rule] = {}
    variables: dict[str, ast.Assignment] = {}
    units: ast.Assignment | None = None
    lot: _Statement | None = None
    lot_call: ast.Call | None = None
    previous: _Statement | None = None
    for statement in statements:
        if previous is not None and not previous.has_semicolon \
                and statement.span.line == previous.end_line:
            raise GrammarSyntaxError("missing `;` before this statement", statement.span,
                                     hint="end each assignment with `;` or a line break")
        previous = statement
        node = statement.node
        if isinstance(node, str):
            section = node
            if node == "Rules" and rules_header is None:
                rules_header = statement
        elif isinstance(node, ast.Rule):
            name = node.predecessor.name
            if section != "Rules":
                raise GrammarSyntaxError(
                    f"the rule for `{name}` is outside the `Rules:` section", node.span,
                    hint="write `Rules:` on a line above the rules")
            if name in rules:
                raise GrammarSyntaxError(
                    f"rule for `{name}` already defined at line {rules[name].span.line}",
                    node.predecessor.span,
                    hint="give each predecessor one rule; use `30% : ... | else : ...` or "
                         "`case ... : ... | else : ...` for alternatives")
            rules[name] = node
        elif isinstance(node, ast.Assignment):
            if node.name == "units":
                if units is not None:
                    raise GrammarSyntaxError(
                        f"`units` already set at line {units.span.line}", node.span)
                units = node
                continue
            if section == "Rules":
                raise GrammarSyntaxError(
                    f"the variable `{node.name}` is inside the `Rules:` section",
                    node.span, hint="move it under `Variables:`")
            if node.name in variables:
                raise GrammarSyntaxError(
                    f"variable `{node.name}` already defined at line "
                    f"{variables[node.name].span.line}", node.span)
            variables[node.name] = node
        else:
            if lot is not None:
                raise GrammarSyntaxError(
                    f"`Lot:` already given at line {lot.span.line}", statement.span)
            lot, lot_call = statement, node
    if rules_header is None:
        raise GrammarSyntaxError(
            "the grammar has no `Rules:` section", loc.at_offset(0),
            hint="add `Rules:` followed by rules such as `Lot --> extrude(10) Mass`")
    if not rules:
        raise GrammarSyntaxError(
            "the `Rules:` section has no rules", rules_header.span,
            hint="add a rule such as `Lot --> extrude(10) Mass`")
    return ast.Grammar(
        file=file,
        rules=tuple(rules.values()),
        variables=tuple(variables.values()),
        units=units.value if units is not None else None,
        lot=lot_call,
    )
