"""Bind a call's evaluated arguments to an operation's declared parameters.

Shared by the evaluator (real values) and ``cga check`` (values that depend on the shape
are :data:`~cga.expressions.UNKNOWN` and skip the kind check). Binding follows Python's
rules: positional arguments fill the parameters that are not keyword-only in order,
keywords fill by name; a parameter given twice, an unknown keyword, a missing required
parameter or one argument too many is an error pointing at the offending argument, with
the operation's signature as a hint.

Kinds (``cga.operation`` lists them) are checked and converted here, so operations
receive clean Python values: ``length`` × units (metres, at most
:data:`~cga.lot.MAX_EXTENT`), ``area`` × units² (m²), numbers finite,
``count`` → ``int``, ``bool`` → ``bool``, ``axis`` → ``"x"|"y"|"z"``, ``tuple`` → tuple
with each item converted by ``Param.items``, ``range`` → ``(lo, hi)``. Defaults are
already in metres and are passed through unconverted.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Sequence
from typing import Any, get_args

from . import ast
from .errors import DerivationError, Span
from .expressions import UNKNOWN, Value, describe
from .lot import MAX_EXTENT
from cga.operation import Operation, Param, ParamKind

__all__ = ["KINDS", "bind_arguments", "convert"]

KINDS: tuple[ParamKind, ...] = get_args(ParamKind)
"""Parameter kinds this module converts (see :mod:`cga.operation`)."""

_AXES = ("x", "y", "z")
_TRUE = {"true", "1", "yes"}
_FALSE = {"false", "0", "no"}


class _KindError(Exception):
    """A value does not fit a kind; the message says what was expected."""


def _describe_kind(value: Value) -> str:
    if isinstance(value, bool):
        return f"the boolean {describe(value)}"
    if isinstance(value, (int, float)):
        return f"the number {describe(value)}"
    if isinstance(value, str):
        return f"the string {describe(value)}"
    return f"the tuple {describe(value)}"


def _as_number(value: Value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _KindError(f"expected a number, got {_describe_kind(value)}")
    if not math.isfinite(value):
        raise _KindError(f"expected a finite number, got {describe(value)}")
    return float(value)


def _as_length(value: Value, units: float, power: int) -> float:
    """A length (``power`` 1) or area (2) in metres, at most :data:`MAX_EXTENT` long."""
    number = _as_number(value) * units ** power
    if abs(number) > MAX_EXTENT ** power:
        unit = "m" if power == 1 else "m²"
        raise _KindError(f"is {number:.4g} {unit}; lengths are limited to "
                         f"{MAX_EXTENT:,.0f} m")
    return number


def _convert_scalar(kind: str, value: Value, units: float) -> Any:
    if value is UNKNOWN:
        return UNKNOWN
    if kind == "length":
        return _as_length(value, units, 1)
    if kind == "area":
        return _as_length(value, units, 2)
    if kind == "number":
        return _as_number(value)
    if kind == "count":
        number = _as_number(value)
        if number < 0 or not number.is_integer():
            raise _KindError(f"expected a whole number ≥ 0, got {describe(value)}")
        return int(number)
    if kind == "bool":
        if isinstance(value, bool):
            return value
        text = describe(value).strip('"').lower()
        if text in _TRUE:
            return True
        if text in _FALSE:
            return False
        raise _KindError(f"expected true/false (or 1/0), got {_describe_kind(value)}")
    if kind in ("string", "path"):
        if not isinstance(value, str):
            raise _KindError(f"expected a quoted string, got {_describe_kind(value)}")
        return value
    if kind == "axis":
        if not isinstance(value, str) or value.lower() not in _AXES:
            raise _KindError(f"must be one of 'x', 'y', 'z', got {_describe_kind(value)}")
        return value.lower()
    raise ValueError(f"unknown parameter kind {kind!r}")


def convert(param: Param, value: Value, units: float) -> Any:
    """Check ``value`` against ``param.kind`` and convert it (see the module docstring).

    Raises
    ------
    _KindError
        Internal; :func:`bind_arguments` turns it into a :class:`DerivationError`.
    """
    if param.kind == "tuple":
        items = value if isinstance(value, tuple) else (value,)
        if param.items and len(items) != len(param.items):
            written = ">".join(param.items)
            raise _KindError(f"expected {len(param.items)} values written a>b>c "
                             f"({written}), got {len(items)}: {describe(items)}")
        kinds = param.items or ("number",) * len(items)
        return tuple(_convert_scalar(kind, item, units) for kind, item in zip(kinds, items))
    if param.kind == "range":
        if value is UNKNOWN:
            return UNKNOWN
        if not isinstance(value, tuple) or len(value) != 2:
            raise _KindError(f"expected a pair (low, high), got {_describe_kind(value)}")
        low, high = (_convert_scalar("number", v, units) for v in value)
        if low is not UNKNOWN and high is not UNKNOWN and low > high:
            raise _KindError(f"expected low ≤ high, got {describe(value)}")
        return (low, high)
    return _convert_scalar(param.kind, value, units)


def _arg_span(arg: ast.Arg, call: ast.OpCall) -> Span:
    return arg.span or getattr(arg.value, "span", None) or call.span


def bind_arguments(operation: Operation, call: ast.OpCall, values: Sequence[Value], *,
                   units: float) -> dict[str, Any]:
    """Map ``call``'s arguments (already evaluated, in order) to ``operation.params``.

    Parameters
    ----------
    operation:
        The operation being called; its ``params`` are the signature.
    call:
        The call node (for spans of the arguments).
    values:
        ``values[i]`` is the evaluated ``call.args[i].value``.
    units:
        Metres per grammar unit, for ``length`` and ``area`` parameters.

    Returns
    -------
    dict
        Parameter name → converted value, defaults filled in.

    Raises
    ------
    DerivationError
        Too many arguments, unknown or repeated keyword, missing required argument, or a
        value of the wrong kind; the span is the offending argument (the call for a
        missing one) and the hint gives the signature.
    """
    hint = f"signature: {operation.signature()}"
    params = {p.name: p for p in operation.params}
    positional = [p for p in operation.params if not p.keyword_only]
    given: dict[str, tuple[Value, ast.Arg]] = {}
    position = 0
    seen_keyword = False
    for arg, value in zip(call.args, values):
        span = _arg_span(arg, call)
        if arg.name is None:
            if seen_keyword:
                raise DerivationError(f"{operation.name}: a positional argument cannot follow "
                                      f"a keyword argument", span, hint=hint)
            if position >= len(positional):
                count = len(positional)
                raise DerivationError(
                    f"{operation.name} takes {count} positional argument{'s' * (count != 1)}, "
                    f"got {sum(1 for a in call.args if a.name is None)}", span, hint=hint)
            param = positional[position]
            position += 1
        else:
            seen_keyword = True
            if arg.name not in params:
                close = difflib.get_close_matches(arg.name, params, n=1)
                extra = f"did you mean '{close[0]}'? " if close else ""
                raise DerivationError(f"{operation.name} has no parameter '{arg.name}'", span,
                                      hint=extra + hint)
            param = params[arg.name]
            if param.name in given:
                raise DerivationError(f"{operation.name}: argument '{param.name}' given twice",
                                      span, hint=hint)
        given[param.name] = (value, arg)

    bound: dict[str, Any] = {}
    for param in operation.params:
        if param.name not in given:
            if param.required:
                raise DerivationError(f"{operation.name}: missing argument '{param.name}'",
                                      call.span, hint=hint)
            bound[param.name] = param.default
            continue
        value, arg = given[param.name]
        try:
            bound[param.name] = convert(param, value, units)
        except _KindError as error:
            raise DerivationError(f"{operation.name}: argument '{param.name}' ({param.kind}) "
                                  f"{error}", _arg_span(arg, call), hint=hint) from None
    return bound
