"""lark's parse errors → :class:`~cga.errors.GrammarSyntaxError` in words.

"expected `-->` after the rule name `Lot`", "unclosed `{`", "unterminated string" rather
than parser states: the wording for every syntax error :func:`cga.parser.parse` raises.
"""

from __future__ import annotations

from collections.abc import Iterable

from lark import Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from .errors import GrammarSyntaxError, Span
from .source_positions import Locator, end_of, start_of

__all__ = ["SyntaxErrorBuilder"]


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


class SyntaxErrorBuilder:
    """Turns a lark :class:`UnexpectedInput` into a :class:`GrammarSyntaxError` in words."""

    def __init__(self, text: str, file: str):
        self.loc = Locator(text, file)

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
                    and self.loc.first_on_line(*start_of(previous)):
                return self._missing_after_name(previous, _current_section(stack))
            if token.type == "NAME" and expected & {"PREDECESSOR", "ASSIGN_NAME"} \
                    and self.loc.first_on_line(*start_of(token)):
                return self._missing_after_name(token, _current_section(stack))

        return GrammarSyntaxError(f"unexpected {found}; expected {_readable(expected)}",
                                  at_token, hint=_hint(token.type, expected))

    def _missing_after_name(self, name: Token, section: str | None) -> GrammarSyntaxError:
        offset = self.loc.offset(*start_of(name)) + len(name)
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
        return Span(self.loc.file, *end_of(last))


_TOKEN_WORDS = {"NAME": "name `{}`", "PREDECESSOR": "the rule `{} -->`",
                "ASSIGN_NAME": "the assignment `{} =`", "NUMBER": "number `{}`",
                "STRING": "string {}", "PERCENT": "percentage `{}`"}
"""How a token met where it does not belong is named ({} is its text)."""


def _describe_token(token: Token) -> str:
    if token.type == "$END":
        return "the end of the file"
    return _TOKEN_WORDS.get(token.type, "`{}`").format(str(token))


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
