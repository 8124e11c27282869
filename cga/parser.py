"""Grammar text → :class:`cga.ast.Grammar`.

The language (DESIGN §4) is described in ``cga/grammar.lark`` and read with lark's
LALR(1) parser. Parsing and building the AST are two steps, so every node keeps the
position lark recorded (``propagate_positions``); the AST is made of the frozen
dataclasses of :mod:`cga.ast` and the rest of the engine never sees a lark tree. This
is the only module that imports lark.

Besides building nodes, this module checks what the context-free grammar cannot
express: statements belong to sections (rules under ``Rules:``), a rule body is a list
of ``op(args) Successors`` groups, a choice uses one kind of guard with ``else`` last,
percentages add up, and no rule, variable, ``units`` or ``Lot:`` is given twice.

Every problem is raised as :class:`cga.errors.GrammarSyntaxError` with a span and the
source attached, phrased in words ("expected `-->` after the rule name `Lot`",
"unclosed `{`", "unterminated string") rather than in parser-state terms.
"""

from __future__ import annotations

import bisect
import math
import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Iterable, Iterator, NoReturn

from lark import Lark, Token, Transformer, Tree, v_args
from lark.lark import PostLex
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken, VisitError

from . import ast
from .errors import CGAError, GrammarSyntaxError, ResourceNotFoundError, Span
from .resources import is_folder
from .textfiles import read_input_bytes

__all__ = ["parse", "parse_file", "read_grammar"]


def parse(text: str, file: str = "<string>") -> ast.Grammar:
    """Parse grammar source text into a :class:`cga.ast.Grammar`.

    Parameters
    ----------
    text:
        The grammar source (DESIGN §4; reference in ``docs/language.md``).
    file:
        Name used in spans and error messages.

    Returns
    -------
    cga.ast.Grammar
        Rules, variables, ``units`` and ``Lot:``; every node carries its :class:`Span`.

    Raises
    ------
    GrammarSyntaxError
        The text does not follow the language, or breaks a rule of it that the syntax
        alone cannot express (duplicate rule, mixed choice, missing ``Rules:``...).
        The source text is attached, so ``str(error)`` shows the line and a caret.

    Notes
    -----
    Linear in the length of the text (LALR(1)); the lark parser is built once per
    process. A leading byte-order mark is skipped (columns count as an editor shows them).
    """
    text = text.removeprefix("\ufeff")
    try:
        try:
            tree = _lark_parser().parse(text)
        except UnexpectedInput as error:
            raise _SyntaxErrorBuilder(text, file).build(error) from None
        try:
            return _ToAst(text, file).transform(tree)
        except VisitError as error:
            if isinstance(error.orig_exc, CGAError):
                raise error.orig_exc from None
            if isinstance(error.orig_exc, RecursionError):
                raise _too_deep(file) from None
            raise
        except RecursionError:
            raise _too_deep(file) from None
    except GrammarSyntaxError as error:
        raise error.with_source(text)


MAX_GRAMMAR_BYTES = 1_000_000
"""Largest grammar file read (1 MB); the thesis grammars have about two kilobytes."""


def read_grammar(path: str | Path) -> str:
    """The text of a ``.grammar`` file (UTF-8, a byte-order mark and any line ending
    accepted; lines end in ``\n`` in the result).

    Raises
    ------
    ResourceNotFoundError
        ``path`` does not exist or is a folder.
    UsageError
        The file cannot be read.
    GrammarSyntaxError
        The file is not UTF-8 text; the span is the first byte that cannot be decoded.
    BudgetError
        The file is larger than :data:`MAX_GRAMMAR_BYTES`.
    """
    path = Path(path)
    if is_folder(path):
        raise ResourceNotFoundError("grammar", f"{path} (a folder, not a grammar file)")
    data = read_input_bytes(path, "grammar", MAX_GRAMMAR_BYTES)
    try:
        # a byte-order mark is dropped and old Mac line ends (CR only) become "\n"
        text = data.decode("utf-8-sig")
        return text.replace("\r\n", "\n").replace("\r", "\n")
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        column = error.start - (data.rfind(b"\n", 0, error.start) + 1) + 1
        raise GrammarSyntaxError(
            f"the file is not UTF-8 text (byte {error.start} cannot be decoded)",
            Span(str(path), line, column), hint="save the grammar as UTF-8 text") from None


def parse_file(path: str | Path) -> ast.Grammar:
    """Read and parse a ``.grammar`` file (UTF-8).

    Raises
    ------
    ResourceNotFoundError, UsageError, GrammarSyntaxError
        See :func:`read_grammar` and :func:`parse`; spans name ``path`` as given.
    """
    return parse(read_grammar(path), str(path))


def _too_deep(file: str) -> GrammarSyntaxError:
    return GrammarSyntaxError(
        "the grammar is nested too deeply to read (brackets or operators inside each "
        "other hundreds of levels deep)", Span(file, 1, 1))


class _LexEverywhere(PostLex):
    """Lex statement starts and keywords in every parser state, not only where valid.

    lark's contextual lexer reads only the terminals the current parser state accepts,
    so in ``op(a,`` + newline + ``B --> C`` it would read ``B - - >`` as a name and two
    minus signs, and ``case`` where no ``case`` may stand as a plain name. A name
    followed by ``-->`` (or ``=``), a section header or a keyword cannot mean anything
    else in a valid grammar, so lexing them everywhere changes no valid parse, keeps the
    keywords reserved, and lets a syntax error say "unclosed `(` before the rule `B -->`".
    """

    always_accept = ("PREDECESSOR", "ASSIGN_NAME", "VARIABLES_HEADER", "RULES_HEADER",
                     "LOT_HEADER", "CASE", "ELSE", "AND", "OR", "NOT")

    def process(self, stream: Iterator[Token]) -> Iterator[Token]:
        return stream


@cache
def _lark_parser() -> Lark:
    return Lark.open("grammar.lark", rel_to=__file__, parser="lalr",
                     propagate_positions=True, maybe_placeholders=True,
                     postlex=_LexEverywhere())


# ---------------------------------------------------------------------------------
# Spans
# ---------------------------------------------------------------------------------

class _Locator:
    """Turns lark positions (tokens, metas, character offsets) into :class:`Span` s."""

    def __init__(self, text: str, file: str):
        self.text = text
        self.file = file
        self._line_starts = [0] + [m.end() for m in re.finditer("\n", text)]

    def offset(self, line: int, column: int) -> int:
        return self._line_starts[line - 1] + column - 1

    def at_offset(self, offset: int, length: int = 1) -> Span:
        line = bisect.bisect_right(self._line_starts, offset)
        column = offset - self._line_starts[line - 1] + 1
        return Span(self.file, line, column, max(1, length))

    def token(self, token: Token) -> Span:
        return Span(self.file, token.line, token.column, max(1, len(token)))

    def meta(self, meta) -> Span:
        return Span(self.file, meta.line, meta.column, max(1, meta.end_pos - meta.start_pos))

    def join(self, first: Span, last: Span) -> Span:
        """The span from the start of ``first`` to the end of ``last``."""
        start = self.offset(first.line, first.column)
        end = self.offset(last.line, last.column) + last.length
        return Span(self.file, first.line, first.column, max(1, end - start))

    def first_on_line(self, line: int, column: int) -> bool:
        """Whether only whitespace precedes this position on its line."""
        start = self._line_starts[line - 1]
        return self.text[start:start + column - 1].strip() == ""

    def rest_of_line(self, line: int, column: int) -> int:
        start = self.offset(line, column)
        end = self.text.find("\n", start)
        return (len(self.text) if end < 0 else end) - start


# ---------------------------------------------------------------------------------
# Tree → AST
# ---------------------------------------------------------------------------------

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
    kind: str  # "percent" | "case" | "else"
    value: ast.Expr | None
    span: Span


@dataclass(frozen=True)
class _Statement:
    """A top-level statement with what the section and `;` checks need."""

    node: ast.Rule | ast.Assignment | ast.Call | str  # str: a section header name
    span: Span
    end_line: int
    has_semicolon: bool = True


_SPLIT_MODES = {None: "absolute", "~": "floating", "'": "relative"}
_PERCENT_TOLERANCE = 1e-9


def _unescape(body: str) -> str:
    """String contents: ``\\"`` is a quote, every other backslash stays as written."""
    return re.sub(r'\\(.)', lambda m: '"' if m.group(1) == '"' else m.group(0), body)


@v_args(meta=True)
class _ToAst(Transformer):
    """Builds :mod:`cga.ast` nodes bottom-up; one method per rule of ``grammar.lark``."""

    def __init__(self, text: str, file: str):
        super().__init__()
        self.file = file
        self.loc = _Locator(text, file)

    def _error(self, message: str, span: Span, hint: str | None = None) -> NoReturn:
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


def _assemble(statements: list[_Statement], file: str, loc: _Locator) -> ast.Grammar:
    """Sort statements into sections and check duplicates (sections in any order)."""
    section: str | None = None
    rules_header: _Statement | None = None
    rules: dict[str, ast.Rule] = {}
    variables: dict[str, ast.Assignment] = {}
    units: ast.Assignment | None = None
    lot: _Statement | None = None
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
            lot = statement
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
        lot=lot.node if lot is not None else None,
    )


# ---------------------------------------------------------------------------------
# Syntax errors in words
# ---------------------------------------------------------------------------------

_BRACKETS = {"LPAR": ("(", "RPAR", ")"), "LBRACE": ("{", "RBRACE", "}"),
             "LSQB": ("[", "RSQB", "]")}
_CLOSERS = {closer: opener for opener, (_, closer, _) in _BRACKETS.items()}

# Terminals that start a new statement; meeting one inside brackets means a bracket
# was left open.
_STATEMENT_STARTS = {"PREDECESSOR", "ASSIGN_NAME", "VARIABLES_HEADER", "RULES_HEADER",
                     "LOT_HEADER", "$END"}
_EXPRESSION_STARTS = {"NUMBER", "STRING", "NAME", "LSQB", "LPAR", "MINUS", "NOT"}
_OPERATORS = {"PLUS", "MINUS", "STAR", "SLASH", "MODULO", "LT", "LE", "GT", "GE", "EQ",
              "NE", "AND", "OR"}
_COMPARISONS = {"LT", "LE", "GE", "EQ", "NE", "AND", "OR"}

# What to call each expected terminal, in the order they are listed.
_EXPECTED_WORDS = [
    ("ARROW", "`-->`"),
    ("EQUAL", "`=`"),
    ("COLON", "`:`"),
    ("RPAR", "`)`"),
    ("RBRACE", "`}`"),
    ("RSQB", "`]`"),
    ("COMMA", "`,`"),
    ("SEMICOLON", "`;`"),
    ("VBAR", "`|`"),
    ("DOT", "`.`"),
    ("GT", "`>`"),
    ("STAR", "`*`"),
    ("LPAR", "`(`"),
    ("LBRACE", "`{`"),
    ("OPERATORS", "an operator"),
    ("PERCENT", "a percentage such as `30%`"),
    ("CASE", "`case`"),
    ("ELSE", "`else`"),
    ("TILDE", "`~`"),
    ("QUOTE", "`'`"),
    ("NUMBER", "a number"),
    ("STRING", "a string"),
    ("NAME", "a name"),
    ("ASSIGN_NAME", "an assignment `name = value`"),
    ("PREDECESSOR", "a rule `Name --> ...`"),
    ("VARIABLES_HEADER", "`Variables:`"),
    ("RULES_HEADER", "`Rules:`"),
    ("LOT_HEADER", "`Lot:`"),
    ("$END", "the end of the file"),
]


class _SyntaxErrorBuilder:
    """Turns a lark :class:`UnexpectedInput` into a :class:`GrammarSyntaxError` in words."""

    def __init__(self, text: str, file: str):
        self.loc = _Locator(text, file)

    def build(self, error: UnexpectedInput) -> GrammarSyntaxError:
        if isinstance(error, UnexpectedToken):
            return self._unexpected_token(error)
        if isinstance(error, UnexpectedCharacters):
            return self._unexpected_character(error)
        return GrammarSyntaxError("unexpected end of the grammar text",
                                  Span(self.loc.file, error.line, error.column))

    def _unexpected_character(self, error: UnexpectedCharacters) -> GrammarSyntaxError:
        if error.char == '"':
            span = Span(self.loc.file, error.line, error.column,
                        self.loc.rest_of_line(error.line, error.column))
            return GrammarSyntaxError("unterminated string", span,
                                      hint='close it with `"` on the same line')
        span = Span(self.loc.file, error.line, error.column)
        return GrammarSyntaxError(f"unexpected character `{error.char}`", span)

    def _unexpected_token(self, error: UnexpectedToken) -> GrammarSyntaxError:
        token = error.token
        expected = set(error.accepts or error.expected)
        stack = list(error.state.value_stack) if error.state is not None else []
        found = _describe_token(token)
        at_token = (self._eof_span(stack) if token.type == "$END"
                    else self.loc.token(token))

        unclosed = _unclosed_bracket(stack)
        if unclosed is not None:
            opener, closer_type, closer = _BRACKETS[unclosed.type]
            if token.type in _STATEMENT_STARTS:
                return GrammarSyntaxError(
                    f"unclosed `{opener}`: expected `{closer}` before {found}",
                    self.loc.token(unclosed))
            if token.type in _CLOSERS and closer_type in expected:
                return GrammarSyntaxError(
                    f"missing `{closer}` to close the `{opener}` at line {unclosed.line}, "
                    f"column {unclosed.column}; found {found}", at_token)

        previous = stack[-1] if stack else None
        if token.type in _STATEMENT_STARTS and previous is not None:
            # The statement before this one is unfinished: point just after it.
            after_previous = self._eof_span(stack)
            if isinstance(previous, Token) and previous.type in ("ARROW", "COLON") \
                    and "LBRACE" in expected:
                if previous.type == "ARROW":
                    what, choice = "rule", "`30% : A | else : B`"
                else:
                    what, choice = "branch", "one in parentheses `(30% : A | else : B)`"
                return GrammarSyntaxError(
                    f"expected a {what} body after `{previous}`, found {found}",
                    after_previous,
                    hint=f"e.g. `extrude(3) Mass`, a rename `Mass`, or a choice {choice}")
            return GrammarSyntaxError(
                f"expected {_readable(expected)} before {found}", after_previous)

        if unclosed is None:
            if isinstance(previous, Token) and previous.type == "NAME" \
                    and token.type != "LPAR" \
                    and self.loc.first_on_line(previous.line, previous.column):
                return self._missing_after_name(previous, _current_section(stack))
            if token.type == "NAME" and expected & {"PREDECESSOR", "ASSIGN_NAME"} \
                    and self.loc.first_on_line(token.line, token.column):
                return self._missing_after_name(token, _current_section(stack))

        return GrammarSyntaxError(f"unexpected {found}; expected {_readable(expected)}",
                                  at_token, hint=_hint(token.type, expected))

    def _missing_after_name(self, name: Token, section: str | None) -> GrammarSyntaxError:
        offset = self.loc.offset(name.line, name.column) + len(name)
        while offset < len(self.loc.text) and self.loc.text[offset] in " \t":
            offset += 1
        span = self.loc.at_offset(offset)
        if section == "Rules":
            return GrammarSyntaxError(f"expected `-->` after the rule name `{name}`", span)
        if name == "Lot":
            return GrammarSyntaxError("expected `:` after `Lot`", span,
                                      hint="give the lot as e.g. `Lot: rectangle(14, 10)`")
        return GrammarSyntaxError(f"expected `=` after the variable name `{name}`", span,
                                  hint="rules go after a `Rules:` line" if section is None
                                  else None)

    def _eof_span(self, stack: list) -> Span:
        """The position just after the last token read."""
        last = _last_token(stack)
        if last is None:
            return Span(self.loc.file, 1, 1)
        return Span(self.loc.file, last.end_line, last.end_column)


def _describe_token(token: Token) -> str:
    kind, value = token.type, str(token)
    if kind == "$END":
        return "the end of the file"
    if kind == "NAME":
        return f"name `{value}`"
    if kind == "PREDECESSOR":
        return f"the rule `{value} -->`"
    if kind == "ASSIGN_NAME":
        return f"the assignment `{value} =`"
    if kind == "NUMBER":
        return f"number `{value}`"
    if kind == "STRING":
        return f"string {value}"
    if kind == "PERCENT":
        return f"percentage `{value}`"
    return f"`{value}`"


def _readable(expected: Iterable[str]) -> str:
    """Expected terminal names in words, most useful first: "`)`, `,` or an operator"."""
    names = set(expected) - {"DOT"}
    groups = {}
    if names & {"NUMBER", "STRING"}:
        names -= _EXPRESSION_STARTS
        groups["NUMBER"] = "an expression"
    if len(names & _OPERATORS) > 2:
        # After an operand: `(` (a call) and `.` (an attribute) are rarely what is missing.
        names -= _OPERATORS | {"LPAR"}
        groups["OPERATORS"] = "an operator"
    if "PREDECESSOR" in names and "$END" in names:
        names -= _STATEMENT_STARTS
        groups["$END"] = "the next rule or section"
    if "ASSIGN_NAME" in names and "NUMBER" in groups:
        groups["ASSIGN_NAME"] = "a keyword argument `name=value`"
    words = [groups.get(name) or word for name, word in _EXPECTED_WORDS
             if name in names or name in groups]
    if len(words) == 1:
        return words[0]
    return ", ".join(words[:-1]) + " or " + words[-1]


def _hint(found: str, expected: set[str]) -> str | None:
    if found in _COMPARISONS and "GT" in expected and "COMMA" in expected:
        return ("in an argument `a>b` builds a tuple; put comparisons and `and`/`or` in "
                "parentheses, e.g. `(a >= b)`")
    if found in ("PERCENT", "CASE") and {"LPAR", "LBRACE"} <= expected:
        return ("a choice inside a branch goes in parentheses: "
                "`case area > 50 : (30% : A | else : B) | else : C`")
    if found == "QUOTE":
        return 'strings are written in double quotes: "text"'
    if found == "VBAR":
        return ("`|` separates the branches of a choice, and every branch starts with a "
                "guard: `A --> 30% : B | else : C` or `A --> case area > 50 : B | else : C`")
    return None


def _unclosed_bracket(stack: list) -> Token | None:
    """The innermost opening bracket on the parser stack that has no closing one."""
    open_brackets: list[Token] = []
    for value in stack:
        if not isinstance(value, Token):
            continue
        if value.type in _BRACKETS:
            open_brackets.append(value)
        elif value.type in _CLOSERS and open_brackets:
            open_brackets.pop()
    return open_brackets[-1] if open_brackets else None


def _current_section(stack: list) -> str | None:
    """The last section header already read (`Variables` or `Rules`), if any."""
    for value in reversed(stack):
        tokens = [value] if isinstance(value, Token) else \
            list(value.scan_values(lambda v: isinstance(v, Token))) \
            if isinstance(value, Tree) else []
        headers = [t for t in tokens if t.type in ("VARIABLES_HEADER", "RULES_HEADER")]
        if headers:
            return headers[-1].rstrip(": \t").capitalize()
    return None


def _last_token(stack: list) -> Token | None:
    for value in reversed(stack):
        if isinstance(value, Token):
            return value
        if isinstance(value, Tree):
            tokens = list(value.scan_values(lambda v: isinstance(v, Token)))
            if tokens:
                return tokens[-1]
    return None
