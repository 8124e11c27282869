"""Builders for hand-made grammar ASTs, so engine tests do not depend on the parser.

Every node gets a span; tests that check error positions pass ``at=(line, column)``.
Unspecified spans get distinct, increasing positions so an assertion can never pass by
accident on a shared default.
"""

from __future__ import annotations

import itertools
from types import SimpleNamespace

import pytest

from cga import ast
from cga.errors import Span

FILE = "test.grammar"
_counter = itertools.count(100)


def span(at=None, length=1):
    if at is None:
        return Span(FILE, next(_counter), 1, length)
    return Span(FILE, at[0], at[1], length)


def expr(value, at=None):
    """Python value → expression node (numbers, strings, names via ``name()``)."""
    if isinstance(value, (ast.Number, ast.String, ast.Name, ast.Attribute, ast.RandomRange,
                          ast.TupleExpr, ast.BinOp, ast.UnaryOp, ast.Call)):
        return value
    if isinstance(value, bool):
        return ast.Name("true" if value else "false", span(at))
    if isinstance(value, (int, float)):
        return ast.Number(float(value), span(at))
    if isinstance(value, str):
        return ast.String(value, span(at))
    if isinstance(value, tuple):
        return ast.TupleExpr(tuple(expr(v) for v in value), span(at))
    raise TypeError(value)


def name(text, at=None):
    if "." in text:
        return ast.Attribute(tuple(text.split(".")), span(at))
    return ast.Name(text, span(at))


def binop(op, left, right, at=None):
    return ast.BinOp(op, expr(left), expr(right), span(at))


def rnd(low, high, at=None):
    return ast.RandomRange(expr(low), expr(high), span(at))


def call(fn, *args, at=None):
    return ast.Call(fn, tuple(expr(a) for a in args), span(at))


def arg(value, kw=None, at=None):
    """An operation argument; ``at`` is the argument's own position."""
    node = expr(value, at)
    return ast.Arg(node, kw, node.span if at is not None else span())


def op(op_name, *args, at=None):
    wrapped = tuple(a if isinstance(a, ast.Arg) else arg(a) for a in args)
    return ast.OpCall(op_name, wrapped, span(at, len(op_name)))


def step(operation, *successors, at=None):
    syms = tuple(ast.Symbol(s, span()) for s in successors)
    return ast.Step(operation, syms, span=span(at))


def split_step(operation, parts, repeat=False, at=None):
    """``parts``: (mode, size, symbol) with mode "absolute" | "floating" | "relative"."""
    nodes = tuple(ast.SplitPart(mode, expr(size), ast.Symbol(sym, span()), span())
                  for mode, size, sym in parts)
    return ast.Step(operation, tuple(p.successor for p in nodes), nodes, repeat, span(at))


def seq(*steps):
    return ast.Sequence(tuple(steps), span())


def stochastic(*branches, at=None):
    """``branches``: (percent or None, body)."""
    return ast.Stochastic(tuple(ast.Branch(None if p is None else expr(p), b, span())
                                for p, b in branches), span(at))


def case(*branches, at=None):
    """``branches``: (guard expression or None, body)."""
    return ast.Conditional(tuple(ast.Branch(None if g is None else expr(g), b, span())
                                 for g, b in branches), span(at))


def rule(pred, body, at=None):
    if isinstance(body, ast.Step):
        body = seq(body)
    return ast.Rule(ast.Symbol(pred, span(at, len(pred))), body, span(at))


def var(var_name, value, at=None):
    return ast.Assignment(var_name, expr(value), span(at))


def grammar(*rules, variables=(), units=None, lot=None, file=FILE):
    return ast.Grammar(file=file, rules=tuple(rules), variables=tuple(variables),
                       units=None if units is None else expr(units), lot=lot)


@pytest.fixture
def g():
    """The AST builders as one namespace: ``g.rule("Lot", g.step(g.op("extrude", 6), "B"))``."""
    return SimpleNamespace(
        FILE=FILE, span=span, expr=expr, name=name, binop=binop, rnd=rnd, call=call, arg=arg,
        op=op, step=step, split_step=split_step, seq=seq, stochastic=stochastic, case=case,
        rule=rule, var=var, grammar=grammar)
