"""Fuzzing the grammar parser: any text gives a Grammar or a CGAError, never a crash.

Also a generative check: random expressions, written out with parentheses, parse back
to the tree they were written from.
"""

from __future__ import annotations

import re

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cga import ast
from cga.errors import CGAError, SourceError, Span
from cga.parser import parse

SEED_GRAMMAR = r'''units = 10;
Lot: polygon((0,0),(14,0),(14,6),(8,6),(8,10),(0,10))
Variables:
  buildingHeight = 0.8;
  doorRoomWidth = [0.25;0.35];
  wallWidth = 0.05
Rules:
Lot --> extrude(buildingHeight) Body
#Body --> component_split("side_faces"){Facade,FrontFacade,Facade} component_split("top"){Top}
Body --> repeated_split("Y", 0.8){BaseFloorFacade, FloorFacade}
FloorFacade --> 30% : make_floor(4, wallWidth, 1>0.2>0.1, .09, 0.5) Floor1
              | else : make_floor(2, wallWidth, (1, 0.2, 0.1), key=3) Floor1
Floor1 --> case scope.sx > 12 and not area % 2 == 0 : type_rooms("D:\Rooms\Test.csv"){Typed}
         | else : ( 50% : Typed | else : Other )
Facade --> split("x"){ 2 : Wall | ~1 : Window | '0.3 : Wall }*
'''

# A tokenizer for the mutation strategy, written independently of the parser's grammar:
# it only needs to cut the seed into plausible pieces.
TOKEN = re.compile(r'"[^"\n]*"|#[^\n]*|-->|[<>=!]=|\d+(?:\.\d*)?%?|\.\d+|\w+|\S')
SEED_TOKENS = TOKEN.findall(SEED_GRAMMAR)
VOCABULARY = sorted(set(SEED_TOKENS)) + [
    "\n", " ", "(", ")", "{", "}", "[", "]", "|", ":", ";", ",", '"', "'", "%", "-->",
    "Rules:", "Variables:", "Lot:", "case", "else", "or", "not", "1e999", "\\", "\t"]

GRAMMARISH = st.lists(
    st.sampled_from(list("{}()[];:,|%~'\"*<>=-+/#.\\ \n\tabxyzLR019_") + [
        "-->", "Rules:", "Variables:", "Lot:", "case", "else", "and", "30%", " A ", "op("]),
    max_size=80).map("".join)


def check_never_crashes(text: str) -> None:
    """The property: a Grammar or a CGAError whose rendering points into the text."""
    try:
        grammar = parse(text, "fuzz.grammar")
    except CGAError as error:
        rendered = str(error)
        assert rendered
        if isinstance(error, SourceError) and error.span is not None:
            assert error.span.file == "fuzz.grammar"
            assert 1 <= error.span.line <= text.count("\n") + 1
            assert error.span.column >= 1
            assert rendered.startswith(f"fuzz.grammar:{error.span.line}:")
            assert error.source == text
        return
    assert isinstance(grammar, ast.Grammar)
    assert grammar.rules


def test_seed_grammar_parses():
    grammar = parse(SEED_GRAMMAR)
    assert len(grammar.rules) == 5


@settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.text(max_size=200))
def test_arbitrary_text(text):
    check_never_crashes(text)


@settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(GRAMMARISH)
def test_grammar_like_text(text):
    check_never_crashes(text)


EDIT = st.one_of(
    st.tuples(st.just("delete"), st.integers(0, len(SEED_TOKENS) - 1)),
    st.tuples(st.just("insert"), st.integers(0, len(SEED_TOKENS)), st.sampled_from(VOCABULARY)),
    st.tuples(st.just("duplicate"), st.integers(0, len(SEED_TOKENS) - 1)),
    st.tuples(st.just("swap"), st.integers(0, len(SEED_TOKENS) - 2)),
)


def mutate(edits) -> str:
    pieces = [(m.group(), SEED_GRAMMAR[m.end():next_start])
              for m, next_start in _with_next_starts(TOKEN.finditer(SEED_GRAMMAR))]
    for edit in edits:
        if not pieces:
            break
        kind, index = edit[0], min(edit[1], len(pieces) - 1)
        if kind == "delete":
            del pieces[index]
        elif kind == "insert":
            pieces.insert(index, (edit[2], " "))
        elif kind == "duplicate":
            pieces.insert(index, pieces[index])
        elif index + 1 < len(pieces):
            pieces[index], pieces[index + 1] = pieces[index + 1], pieces[index]
    return "".join(token + gap for token, gap in pieces)


def _with_next_starts(matches):
    matches = list(matches)
    starts = [m.start() for m in matches[1:]] + [len(SEED_GRAMMAR)]
    return zip(matches, starts)


@settings(max_examples=600, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(EDIT, min_size=1, max_size=4))
def test_mutated_seed_grammar(edits):
    check_never_crashes(mutate(edits))


# ---- generated expressions parse back to their tree -----------------------------

X = Span("<expected>", 1, 1)
NAMES = st.from_regex(r"[a-z][A-Za-z0-9_]{0,6}", fullmatch=True).filter(
    lambda n: n not in {"and", "or", "not", "case", "else"})
LEAVES = st.one_of(
    st.integers(0, 10**6).map(lambda i: (str(i), ast.Number(float(i), X))),
    st.floats(0, 1e6, allow_nan=False, allow_infinity=False).map(
        lambda f: (repr(f), ast.Number(f, X))),
    NAMES.map(lambda n: (n, ast.Name(n, X))),
    # a backslash keeps the next character in the string, so a value cannot end in an
    # odd number of them (the closing quote would be escaped)
    st.text(alphabet="abc \\#:{}", max_size=8)
    .filter(lambda s: (len(s) - len(s.rstrip("\\"))) % 2 == 0)
    .map(lambda s: (f'"{s}"', ast.String(s, X))),
    st.tuples(NAMES, NAMES).map(lambda p: (f"{p[0]}.{p[1]}", ast.Attribute(p, X))),
)
BINARY = ["+", "-", "*", "/", "%", "<", "<=", ">", ">=", "==", "!=", "and", "or"]


def _compound(children):
    binary = st.tuples(st.sampled_from(BINARY), children, children).map(
        lambda t: (f"({t[1][0]} {t[0]} {t[2][0]})", ast.BinOp(t[0], t[1][1], t[2][1], X)))
    unary = st.tuples(st.sampled_from(["-", "not "]), children).map(
        lambda t: (f"({t[0]}{t[1][0]})", ast.UnaryOp(t[0].strip(), t[1][1], X)))
    ranged = st.tuples(children, children).map(
        lambda t: (f"[{t[0][0]};{t[1][0]}]", ast.RandomRange(t[0][1], t[1][1], X)))
    called = st.tuples(NAMES, st.lists(children, max_size=3)).map(
        lambda t: (f"{t[0]}({', '.join(c[0] for c in t[1])})",
                   ast.Call(t[0], tuple(c[1] for c in t[1]), X)))
    tupled = st.lists(children, min_size=2, max_size=3).map(
        lambda items: (f"({', '.join(c[0] for c in items)})",
                       ast.TupleExpr(tuple(c[1] for c in items), X)))
    return st.one_of(binary, unary, ranged, called, tupled)


EXPRESSIONS = st.recursive(LEAVES, _compound, max_leaves=12)
SPACING = st.sampled_from([" ", "  ", "\n   ", " # note\n "])


@settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(EXPRESSIONS, SPACING)
def test_generated_expressions_parse_to_their_tree(expression, spacing):
    text, tree = expression
    grammar = parse(f"Variables:{spacing}value ={spacing}{text};\nRules:\nA --> B\n")
    (assignment,) = grammar.variables
    assert assignment.value == tree
