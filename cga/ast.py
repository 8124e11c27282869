"""The grammar's abstract syntax tree: frozen dataclasses that keep source positions.

The parser (``cga.parser``) is the only module that knows about lark; it turns a parse
tree into these nodes. The evaluator works on these nodes only. Every node carries a
:class:`~cga.errors.Span` so any later error can point at the text that caused it.

Shape of a grammar (docs/language.md)::

    Grammar
      units: Expr | None          `units = 10;`
      lot: Call | None            `Lot: rectangle(14, 10)`
      variables: (Assignment, ...)
      rules: (Rule, ...)
    Rule(predecessor, body)
      body: Sequence | Stochastic | Conditional
    Sequence(steps): one or more `op(args) Successors` groups, applied to the same
      predecessor shape, in order (the thesis writes two component_splits on one line)
    Step(op: OpCall | None, successors, parts, repeat)
      successors: `A` or `{A, B}`; for `split(...) { 2 : A | ~1 : B }*` the sized
      parts are in `parts` and `repeat` marks the trailing `*`
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal, Union

from .errors import Span

__all__ = [
    "Number", "String", "Name", "Attribute", "RandomRange", "TupleExpr", "BinOp",
    "UnaryOp", "Call", "Expr", "Arg", "OpCall", "Symbol", "SplitMode", "SplitPart", "Step",
    "Sequence", "Branch", "Stochastic", "Conditional", "Body", "Rule", "Assignment",
    "Grammar",
]


SplitMode = Literal["absolute", "floating", "relative"]
"""How a split part's size counts: as written, ``~`` floating, ``'`` relative."""

@dataclass(frozen=True)
class Number:
    value: float
    span: Span = field(compare=False)


@dataclass(frozen=True)
class String:
    """A quoted string. Backslashes are kept as written (Windows paths in seed grammars)."""

    value: str
    span: Span = field(compare=False)


@dataclass(frozen=True)
class Name:
    """A variable reference, e.g. ``wallWidth``; also shape attributes ``area``, ``floor``."""

    name: str
    span: Span = field(compare=False)


@dataclass(frozen=True)
class Attribute:
    """A dotted shape attribute such as ``scope.sx``: ``parts == ("scope", "sx")``."""

    parts: tuple[str, ...]
    span: Span = field(compare=False)


@dataclass(frozen=True)
class RandomRange:
    """``[low;high]``: a uniform random number; drawn once per build for a variable."""

    low: "Expr"
    high: "Expr"
    span: Span = field(compare=False)


@dataclass(frozen=True)
class TupleExpr:
    """``a>b>c`` (seed style) or ``(a, b, c)``."""

    items: tuple["Expr", ...]
    span: Span = field(compare=False)


@dataclass(frozen=True)
class BinOp:
    """Binary operator: ``+ - * / % < <= > >= == != and or``."""

    op: str
    left: "Expr"
    right: "Expr"
    span: Span = field(compare=False)


@dataclass(frozen=True)
class UnaryOp:
    """Unary operator: ``-`` or ``not``."""

    op: str
    operand: "Expr"
    span: Span = field(compare=False)


@dataclass(frozen=True)
class Call:
    """A function call inside an expression or a lot: ``rectangle(14, 10)``, ``min(a, b)``."""

    name: str
    args: tuple["Expr", ...]
    span: Span = field(compare=False)


Expr = Union[Number, String, Name, Attribute, RandomRange, TupleExpr, BinOp, UnaryOp, Call]


@dataclass(frozen=True)
class Arg:
    """An operation argument; ``name`` is set for keyword arguments (``cut_range=...``)."""

    value: Expr
    name: str | None = None
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True)
class OpCall:
    name: str
    args: tuple[Arg, ...]
    span: Span = field(compare=False)


@dataclass(frozen=True)
class Symbol:
    """A successor (or predecessor) shape name."""

    name: str
    span: Span = field(compare=False)


@dataclass(frozen=True)
class SplitPart:
    """One ``size : Symbol`` entry of a split; ``mode`` is absolute, floating or relative."""

    mode: SplitMode
    size: Expr
    successor: Symbol
    span: Span = field(compare=False)


@dataclass(frozen=True)
class Step:
    """One ``op(args) Successors`` group. ``op`` is None for a bare ``A --> B`` rename."""

    op: OpCall | None
    successors: tuple[Symbol, ...]
    parts: tuple[SplitPart, ...] = ()
    repeat: bool = False
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Sequence:
    steps: tuple[Step, ...]
    span: Span = field(compare=False)


@dataclass(frozen=True)
class Branch:
    """One alternative of a choice. ``guard`` is a percentage (stochastic) or a condition
    (case); None means ``else``."""

    guard: Expr | None
    body: "Body"
    span: Span = field(compare=False)


@dataclass(frozen=True)
class Stochastic:
    """``30% : ... | 20% : ... | else : ...`` (CityEngine style)."""

    branches: tuple[Branch, ...]
    span: Span = field(compare=False)


@dataclass(frozen=True)
class Conditional:
    """``case expr : ... | case expr : ... | else : ...``."""

    branches: tuple[Branch, ...]
    span: Span = field(compare=False)


Body = Union[Sequence, Stochastic, Conditional]


@dataclass(frozen=True)
class Rule:
    predecessor: Symbol
    body: Body
    span: Span = field(compare=False)


@dataclass(frozen=True)
class Assignment:
    name: str
    value: Expr
    span: Span = field(compare=False)


@dataclass(frozen=True)
class Grammar:
    file: str
    rules: tuple[Rule, ...]
    variables: tuple[Assignment, ...] = ()
    units: Expr | None = None
    lot: Call | None = None
