"""Evaluate grammar expressions: numbers, strings, variables, shape attributes, arithmetic.

One evaluator serves three callers: the variables section (no shape, ranges drawn from
each variable's own stream), rule arguments and guards (a shape's attributes and random
stream) and ``cga check`` (no shape at all: attributes and random draws evaluate to
:data:`UNKNOWN`, which every operator propagates, so static checks skip what only a
derivation can know).

Values are ``float``, ``bool``, ``str`` or ``tuple`` of values. Numbers are floats even
when written as integers; operations that want counts convert them (``cga.binding``).
Shape attributes are reported in grammar units (docs/architecture.md, "Units and frames"):
``scope.sx``, ``scope.sy``, ``scope.sz``, ``scope.tx``, ``scope.ty``, ``scope.tz``,
``area``, ``index``, ``floor``.
"""

from __future__ import annotations

import difflib
import math
import operator
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, TypeGuard, Union

import numpy as np

from . import ast
from .errors import DerivationError, Span

__all__ = [
    "UNKNOWN",
    "Value",
    "ATTRIBUTES",
    "FUNCTIONS",
    "Namespace",
    "evaluate",
    "describe",
    "shape_attributes",
]


class _Unknown:
    """A value only a derivation can know (a shape attribute seen by ``cga check``)."""

    _instance: "_Unknown | None" = None

    def __new__(cls) -> "_Unknown":
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __repr__(self) -> str:
        return "UNKNOWN"


UNKNOWN: Any = _Unknown()
"""Result of an expression whose value depends on the shape being derived."""

Value = Union[float, bool, str, tuple, _Unknown]

ATTRIBUTES: tuple[str, ...] = (
    "scope.sx", "scope.sy", "scope.sz", "scope.tx", "scope.ty", "scope.tz",
    "area", "index", "floor",
)
"""Shape attributes an expression inside a rule may read."""

_BOOLEANS = {"true": True, "false": False}


def _sqrt(x: float) -> float:
    if x < 0:
        raise ValueError(f"sqrt of a negative number ({describe(x)})")
    return math.sqrt(x)


FUNCTIONS: dict[str, tuple[Callable[..., float], int, int | None]] = {
    "min": (min, 1, None),
    "max": (max, 1, None),
    "abs": (abs, 1, 1),
    "round": (lambda x: float(round(x)), 1, 1),
    "floor": (lambda x: float(math.floor(x)), 1, 1),
    "ceil": (lambda x: float(math.ceil(x)), 1, 1),
    "sqrt": (_sqrt, 1, 1),
}
"""Numeric functions: name → (function, minimum, maximum argument count)."""

_ARITHMETIC: dict[str, Callable[[Any, Any], Any]] = {
    "+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv,
    "%": operator.mod,
}
_COMPARISON: dict[str, Callable[[Any, Any], bool]] = {
    "<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge,
    "==": operator.eq, "!=": operator.ne,
}


@dataclass
class Namespace:
    """What names mean while evaluating.

    ``variables``: the grammar's variables evaluated so far. ``attributes``: the current
    shape's attributes, None outside rules (the variables section), or all
    :data:`UNKNOWN` for static checks. ``rng``: the stream ``[a;b]`` draws from, None
    for static checks (draws are then :data:`UNKNOWN`). ``later``: variables defined
    further down, by span, to explain a forward reference.
    """

    variables: Mapping[str, Value]
    attributes: Mapping[str, Value] | None = None
    rng: np.random.Generator | None = None
    later: Mapping[str, Span] = field(default_factory=dict)


def describe(value: Value) -> str:
    """A value as the grammar would write it (``3``, ``2.5``, ``"x"``, ``(1, 2)``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return str(int(value)) if value.is_integer() else f"{value:g}"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, tuple):
        return "(" + ", ".join(describe(v) for v in value) + ")"
    return repr(value)


def _kind(value: Value) -> str:
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "a string"
    return "a tuple"


def _is_number(value: Value) -> TypeGuard[float]:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _number(value: Value, span: Span, what: str) -> float:
    if not _is_number(value):
        raise DerivationError(f"{what} must be a number, got {_kind(value)} {describe(value)}", span)
    return float(value)


def shape_attributes(scope_size: tuple[float, float, float],
                     scope_origin: tuple[float, float, float], area: float,
                     attrs: Mapping[str, Any], units: float) -> dict[str, Value]:
    """A shape's attributes in grammar units, for :attr:`Namespace.attributes`.

    ``scope_size``/``scope_origin`` and ``area`` are in metres / m²; they are divided
    by ``units`` / ``units²``. ``index`` and ``floor`` come from ``attrs`` (0 if unset).
    """
    sx, sy, sz = (float(v) / units for v in scope_size)
    tx, ty, tz = (float(v) / units for v in scope_origin)
    return {
        "scope.sx": sx, "scope.sy": sy, "scope.sz": sz,
        "scope.tx": tx, "scope.ty": ty, "scope.tz": tz,
        "area": float(area) / units ** 2,
        "index": float(attrs.get("index", 0)),
        "floor": float(attrs.get("floor", 0)),
    }


def _lookup_name(name: str, span: Span, ns: Namespace) -> Value:
    if name in ns.variables:
        return ns.variables[name]
    if name in _BOOLEANS:
        return _BOOLEANS[name]
    if name in ATTRIBUTES:
        if ns.attributes is None:
            raise DerivationError(
                f"shape attribute '{name}' is only available inside rules", span,
                hint="the Variables section is evaluated once, before any shape exists")
        return ns.attributes[name]
    if name in ns.later:
        raise DerivationError(
            f"variable '{name}' is used before it is defined (at line {ns.later[name].line})",
            span, hint="variables are evaluated in order; move its definition up")
    choices = list(ns.variables) + (list(ATTRIBUTES) if ns.attributes is not None else [])
    close = difflib.get_close_matches(name, choices, n=1)
    hint = f"did you mean '{close[0]}'?" if close else (
        "define it in the Variables section" if ns.variables else
        "add a Variables: section that defines it")
    raise DerivationError(f"undefined variable '{name}'", span, hint=hint)


def _attribute(node: ast.Attribute, ns: Namespace) -> Value:
    name = ".".join(node.parts)
    if name not in ATTRIBUTES:
        close = difflib.get_close_matches(name, ATTRIBUTES, n=1)
        hint = f"did you mean '{close[0]}'?" if close else (
            "shape attributes: " + ", ".join(ATTRIBUTES))
        raise DerivationError(f"unknown shape attribute '{name}'", node.span, hint=hint)
    return _lookup_name(name, node.span, ns)


def _binary(node: ast.BinOp, ns: Namespace) -> Value:
    if node.op in ("and", "or"):
        left = evaluate(node.left, ns)
        if left is UNKNOWN:
            evaluate(node.right, ns)
            return UNKNOWN
        if node.op == "and" and not left:
            return False
        if node.op == "or" and left:
            return True
        right = evaluate(node.right, ns)
        return UNKNOWN if right is UNKNOWN else bool(right)
    left, right = evaluate(node.left, ns), evaluate(node.right, ns)
    if left is UNKNOWN or right is UNKNOWN:
        return UNKNOWN
    if node.op in ("==", "!="):
        return _COMPARISON[node.op](left, right)
    if node.op == "+" and isinstance(left, str) and isinstance(right, str):
        return left + right
    if node.op in _COMPARISON:
        if isinstance(left, str) and isinstance(right, str):
            return _COMPARISON[node.op](left, right)
        function = _COMPARISON[node.op]
    elif node.op in _ARITHMETIC:
        function = _ARITHMETIC[node.op]
    else:  # the parser only produces the operators above
        raise DerivationError(f"unknown operator '{node.op}'", node.span)
    a = _number(left, node.left.span, f"left side of '{node.op}'")
    b = _number(right, node.right.span, f"right side of '{node.op}'")
    if node.op in ("/", "%") and b == 0:
        raise DerivationError(f"division by zero ({describe(a)} {node.op} 0)", node.span)
    return function(a, b)


def _unary(node: ast.UnaryOp, ns: Namespace) -> Value:
    value = evaluate(node.operand, ns)
    if value is UNKNOWN:
        return UNKNOWN
    if node.op == "not":
        return not value
    return -_number(value, node.operand.span, "operand of unary '-'")


def _range(node: ast.RandomRange, ns: Namespace) -> Value:
    low, high = evaluate(node.low, ns), evaluate(node.high, ns)
    if low is UNKNOWN or high is UNKNOWN or ns.rng is None:
        return UNKNOWN
    a = _number(low, node.low.span, "lower end of a [a;b] range")
    b = _number(high, node.high.span, "upper end of a [a;b] range")
    if a > b:
        raise DerivationError(f"range [{describe(a)};{describe(b)}] has its lower end above "
                              f"its upper end", node.span, hint=f"write [{describe(b)};{describe(a)}]")
    return float(ns.rng.uniform(a, b))


def _call(node: ast.Call, ns: Namespace) -> Value:
    if node.name not in FUNCTIONS:
        close = difflib.get_close_matches(node.name, FUNCTIONS, n=1)
        hint = f"did you mean '{close[0]}'?" if close else (
            "functions: " + ", ".join(FUNCTIONS))
        raise DerivationError(f"unknown function '{node.name}'", node.span, hint=hint)
    function, least, most = FUNCTIONS[node.name]
    count = len(node.args)
    if count < least or (most is not None and count > most):
        expected = str(least) if least == most else f"at least {least}"
        raise DerivationError(f"{node.name}() takes {expected} argument"
                              f"{'' if expected == '1' else 's'}, got {count}", node.span)
    values = [evaluate(a, ns) for a in node.args]
    if any(v is UNKNOWN for v in values):
        return UNKNOWN
    numbers = [_number(v, a.span, f"argument of {node.name}()") for v, a in zip(values, node.args)]
    try:
        return float(function(*numbers))
    except ValueError as error:
        raise DerivationError(str(error), node.span) from None


def evaluate(expr: ast.Expr, ns: Namespace) -> Value:
    """The value of ``expr`` in ``ns``.

    Raises
    ------
    DerivationError
        Undefined variable (with a did-you-mean), unknown attribute or function, an
        operator applied to the wrong kind of value, division by zero, a reversed range.
    """
    if isinstance(expr, ast.Number):
        return float(expr.value)
    if isinstance(expr, ast.String):
        return expr.value
    if isinstance(expr, ast.Name):
        return _lookup_name(expr.name, expr.span, ns)
    if isinstance(expr, ast.Attribute):
        return _attribute(expr, ns)
    if isinstance(expr, ast.TupleExpr):
        return tuple(evaluate(item, ns) for item in expr.items)
    if isinstance(expr, ast.BinOp):
        return _binary(expr, ns)
    if isinstance(expr, ast.UnaryOp):
        return _unary(expr, ns)
    if isinstance(expr, ast.RandomRange):
        return _range(expr, ns)
    if isinstance(expr, ast.Call):
        return _call(expr, ns)
    raise TypeError(f"not an expression node: {expr!r}")
