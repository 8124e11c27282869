"""Argument kinds and conversion; expression operators, functions and static UNKNOWN values."""

from __future__ import annotations

import numpy as np
import pytest

from cga import ast
from cga.binding import bind_arguments
from cga.errors import DerivationError, Span
from cga.expressions import ATTRIBUTES, UNKNOWN, Namespace, evaluate
from cga.operation import Operation, Param

S = Span("k.grammar", 1, 1)


class Kinds(Operation):
    name = "kinds"
    params = (Param("length", "length"), Param("area", "area"), Param("count", "count"),
              Param("flag", "bool"), Param("axis", "axis"),
              Param("openings", "tuple", items=("count", "length", "length")),
              Param("cut", "range", default=(0.35, 0.65), keyword_only=True),
              Param("table", "path", default="types.csv"))


def value_node(v):
    if isinstance(v, tuple):
        return ast.TupleExpr(tuple(value_node(i) for i in v), S)
    if isinstance(v, str):
        return ast.String(v, S)
    return ast.Number(float(v), S)


def bind(*values, units=10.0, **keywords):
    args = [ast.Arg(value_node(v), None, Span("k.grammar", 1, 10 + i)) for i, v in enumerate(values)]
    args += [ast.Arg(value_node(v), k, Span("k.grammar", 2, 10 + i))
             for i, (k, v) in enumerate(keywords.items())]
    call = ast.OpCall("kinds", tuple(args), Span("k.grammar", 1, 1))
    return bind_arguments(Kinds(), call, [evaluate(a.value, Namespace({})) for a in args],
                          units=units)


GOOD = (0.3, 2, 4, 1, "Y", (2, 0.12, 0.1))


def test_conversions():
    bound = bind(*GOOD)
    assert bound["length"] == pytest.approx(3.0)          # × units
    assert bound["area"] == pytest.approx(200.0)          # × units²
    assert bound["count"] == 4 and isinstance(bound["count"], int)
    assert bound["flag"] is True and bound["axis"] == "y"
    assert bound["openings"] == pytest.approx((2, 1.2, 1.0))
    assert isinstance(bound["openings"][0], int)
    assert bound["cut"] == (0.35, 0.65) and bound["table"] == "types.csv"  # defaults as given


def test_keyword_only_and_range():
    assert bind(*GOOD, cut=(0.2, 0.8))["cut"] == (0.2, 0.8)
    with pytest.raises(DerivationError, match="expected low ≤ high"):
        bind(*GOOD, cut=(0.8, 0.2))
    with pytest.raises(DerivationError, match="takes 7 positional arguments, got 8"):
        bind(*GOOD, "t.csv", (0.1, 0.2))


@pytest.mark.parametrize("index,value,message", [
    (2, 2.5, "expected a whole number ≥ 0, got 2.5"),
    (2, -1, "expected a whole number ≥ 0, got -1"),
    (3, 7, "expected true/false"),
    (4, "w", "must be one of 'x', 'y', 'z'"),
    (5, (1, 2), "expected 3 values written a>b>c (count>length>length), got 2"),
    (5, (1.5, 2, 3), "whole number"),
])
def test_kind_errors_point_at_the_argument(index, value, message):
    values = list(GOOD)
    values[index] = value
    with pytest.raises(DerivationError) as info:
        bind(*values)
    assert str(info.value).startswith(f"k.grammar:1:{10 + index}: error: kinds: argument")
    assert message in str(info.value)
    assert "signature: kinds(length, area, count, flag, axis, openings, cut=(0.35, 0.65), " \
           "table='types.csv')" in str(info.value)


def test_positional_after_keyword_is_an_error():
    args = (ast.Arg(ast.Number(1.0, S), "length", Span("k.grammar", 3, 4)),
            ast.Arg(ast.Number(2.0, S), None, Span("k.grammar", 3, 9)))
    with pytest.raises(DerivationError, match="3:9: error: kinds: a positional argument cannot"):
        bind_arguments(Kinds(), ast.OpCall("kinds", args, S), [1.0, 2.0], units=1.0)


def test_unknown_values_skip_kind_checks():
    call = ast.OpCall("kinds", tuple(ast.Arg(ast.Number(0.0, S)) for _ in GOOD), S)
    bound = bind_arguments(Kinds(), call, [UNKNOWN, 2.0, UNKNOWN, True, "x", (UNKNOWN, 1.0, 1.0)],
                           units=1.0)
    assert bound["length"] is UNKNOWN and bound["openings"][0] is UNKNOWN


# -- expressions ---------------------------------------------------------------------------------

def n(v):
    return ast.Number(float(v), S)


def b(op, left, right):
    return ast.BinOp(op, left, right, S)


def test_arithmetic_comparison_logic_and_functions():
    ns = Namespace(variables={"a": 3.0, "s": "x"})
    assert evaluate(b("+", ast.Name("a", S), b("*", n(2), n(4))), ns) == 11
    assert evaluate(b("%", n(7), n(3)), ns) == 1
    assert evaluate(b("<=", ast.Name("a", S), n(3)), ns) is True
    assert evaluate(b("and", ast.Name("true", S), ast.UnaryOp("not", ast.Name("false", S), S)), ns) is True
    assert evaluate(b("+", ast.Name("s", S), ast.String("y", S)), ns) == "xy"
    assert evaluate(ast.Call("max", (n(1), n(5), n(2)), S), ns) == 5
    assert evaluate(ast.Call("floor", (n(2.7),), S), ns) == 2
    assert evaluate(ast.UnaryOp("-", ast.Name("a", S), S), ns) == -3


@pytest.mark.parametrize("expr,message", [
    (b("/", n(1), n(0)), "division by zero"),
    (b("-", ast.String("x", S), n(1)), "left side of '-' must be a number, got a string"),
    (ast.Call("sqroot", (n(4),), S), "unknown function 'sqroot'"),
    (ast.Call("abs", (n(1), n(2)), S), "abs() takes 1 argument, got 2"),
    (ast.Call("sqrt", (n(-1),), S), "sqrt of a negative number"),
    (ast.Attribute(("scope", "sw"), S), "unknown shape attribute 'scope.sw'"),
    (ast.RandomRange(n(5), n(3), S), "lower end above its upper end"),
])
def test_expression_errors(expr, message):
    ns = Namespace(variables={}, attributes=dict.fromkeys(ATTRIBUTES, 1.0),
                   rng=np.random.default_rng(0))
    with pytest.raises(DerivationError, match=message.replace("(", r"\(").replace(")", r"\)")):
        evaluate(expr, ns)


def test_unknown_propagates_in_static_evaluation():
    ns = Namespace(variables={}, attributes=dict.fromkeys(ATTRIBUTES, UNKNOWN))
    assert evaluate(b("*", ast.Attribute(("scope", "sx"), S), n(2)), ns) is UNKNOWN
    assert evaluate(ast.RandomRange(n(1), n(2), S), ns) is UNKNOWN
    assert evaluate(b("or", ast.Name("area", S), n(1)), ns) is UNKNOWN
    assert evaluate(b("and", ast.Name("false", S), ast.Name("area", S)), ns) is False


@pytest.mark.parametrize("index,value,message", [
    (0, float("inf"), "expected a finite number, got inf"),
    (0, float("nan"), "expected a finite number"),
    (0, 1e5, "is 1e+06 m; lengths are limited to 100,000 m"),
    (1, 1e12, "m²; lengths are limited to 100,000 m"),
])
def test_non_finite_and_absurd_lengths_are_refused(index, value, message):
    values = list(GOOD)
    values[index] = value
    with pytest.raises(DerivationError) as info:
        bind(*values)
    assert message in str(info.value)
