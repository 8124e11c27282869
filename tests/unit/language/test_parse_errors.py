"""Syntax errors: each message in words, its line and column, and the caret excerpt."""

from __future__ import annotations

import pytest

from cga.errors import GrammarSyntaxError
from cga.parser import parse, parse_file

# (source, words the message must contain, line, column)
CASES = [
    pytest.param("Rules:\nLot extrude(3) A", "expected `-->` after the rule name `Lot`",
                 2, 5, id="missing-arrow-first-rule"),
    pytest.param("Rules:\nLot -> extrude(3) A", "expected `-->` after the rule name `Lot`",
                 2, 5, id="short-arrow"),
    pytest.param("Rules:\nA --> op() B\nC -> D", "expected `-->` after the rule name `C`",
                 3, 3, id="short-arrow-after-rule"),
    pytest.param("Rules:\nA --> op() B\nC D", "expected `-->` after the rule name `C`",
                 3, 1, id="missing-arrow-after-rule"),
    pytest.param('Rules:\nA --> split("x"){ 2 : B | 1 : C\nD --> op() E',
                 "unclosed `{`: expected `}` before the rule `D -->`", 2, 17,
                 id="unclosed-brace"),
    pytest.param("Rules:\nA --> op(3", "unclosed `(`: expected `)` before the end of the file",
                 2, 9, id="unclosed-paren-at-end"),
    pytest.param("Rules:\nA --> op(a,\nB --> C", "unclosed `(`", 2, 9,
                 id="unclosed-paren-before-rule"),
    pytest.param("Lot: rectangle(1, 2\nRules:\nA --> B", "unclosed `(`: expected `)` before "
                 "`Rules:`", 1, 15, id="unclosed-paren-before-section"),
    pytest.param("Variables:\nx = [1;2\nRules:\nA --> B", "unclosed `[`", 2, 5,
                 id="unclosed-bracket"),
    pytest.param('Rules:\nA --> split("x"){ 2 : B | 1 : C ) D',
                 "missing `}` to close the `{` at line 2, column 17; found `)`", 2, 33,
                 id="missing-closing-brace"),
    pytest.param("Rules:\nA --> op(3} B", "missing `)` to close the `(` at line 2, column 9",
                 2, 11, id="missing-closing-paren"),
    pytest.param('Rules:\nA --> op("abc) B', "unterminated string", 2, 10,
                 id="unterminated-string"),
    pytest.param("Rules:\nA --> op() B @", "unexpected character `@`", 2, 14,
                 id="bad-character"),
    pytest.param("Rules:\nA --> op(3 Body", "unexpected name `Body`; expected `)`, `,` or an "
                 "operator", 2, 12, id="missing-comma"),
    pytest.param("Rules:\nA -->\nB --> C", "expected a rule body after `-->`, found the rule "
                 "`B -->`", 2, 6, id="empty-body"),
    pytest.param("Rules:\nA -->", "expected a rule body after `-->`, found the end of the file",
                 2, 6, id="empty-body-at-end"),
    pytest.param("Rules:\nA --> 30% : B | else :\nC --> D",
                 "expected a branch body after `:`", 2, 23, id="empty-branch"),
    pytest.param("Variables:\nx =\ny = 2\nRules:\nA --> B",
                 "expected an expression before the assignment `y =`", 2, 4,
                 id="missing-value"),
    pytest.param("Variables:\nx = 3 +", "expected an expression before the end of the file",
                 2, 8, id="unfinished-expression"),
    pytest.param("Variables:\n x = 3\n y 4\nRules:\nA --> B",
                 "expected `=` after the variable name `y`", 3, 4, id="missing-equals"),
    pytest.param("Lot rectangle(1, 2)\nRules:\nA --> B", "expected `:` after `Lot`", 1, 5,
                 id="lot-without-colon"),
    pytest.param("Rules:\nA --> case x > : B", "unexpected `:`; expected an expression", 2, 16,
                 id="incomplete-condition"),
    pytest.param("Rules:\nA --> op() {B C}", "unexpected name `C`", 2, 15,
                 id="successor-list-without-comma"),
    pytest.param("Rules:\nA --> op() else", "unexpected `else`", 2, 12,
                 id="keyword-as-successor"),
    # choices
    pytest.param("Rules:\nA --> 30% : B | case x : C",
                 "a choice cannot mix percentages and `case` conditions", 2, 17,
                 id="mixed-choice"),
    pytest.param("Rules:\nA --> else : B", "a choice cannot start with `else`", 2, 7,
                 id="else-first"),
    pytest.param("Rules:\nA --> 30% : B | else : C | 20% : D",
                 "`else` must be the last branch of a choice", 2, 17, id="else-not-last"),
    pytest.param("Rules:\nA --> 80% : B\n    | 30% : C | else : D",
                 "the percentages add up to 110%, more than 100%", 2, 7, id="over-100"),
    pytest.param("Rules:\nA --> 30% : B | 20% : C", "the percentages add up to 50%, not 100%",
                 2, 7, id="under-100-without-else"),
    # rule bodies
    pytest.param("Rules:\nA --> op() B C", "unexpected successor `C` after `B`", 2, 14,
                 id="two-successor-groups"),
    pytest.param("Rules:\nA --> {B, C}", "renames its shape to one symbol", 2, 7,
                 id="rename-to-several"),
    pytest.param("Rules:\nA --> B op() C", "successor `B` needs an operation before it",
                 2, 7, id="successor-first"),
    pytest.param("Rules:\nA --> { 1 : B | ~1 : C }", "sized parts need an operation", 2, 7,
                 id="parts-without-operation"),
    pytest.param("Rules:\nA --> op(x=1, 2) B",
                 "a positional argument cannot follow keyword arguments", 2, 15,
                 id="positional-after-keyword"),
    pytest.param("Rules:\nA --> op(x=1, x=2) B", "argument `x` is given twice", 2, 15,
                 id="duplicate-keyword"),
    pytest.param("Rules:\nA --> op(1e999) B", "number `1e999` is too large", 2, 10,
                 id="huge-number"),
    # statements and sections
    pytest.param("Rules:\nA --> B\nA --> C", "rule for `A` already defined at line 2", 3, 1,
                 id="duplicate-rule"),
    pytest.param("Rules:\nA --> B\nC --> D\n\n  A --> E",
                 "rule for `A` already defined at line 2", 5, 3, id="duplicate-rule-later"),
    pytest.param("Variables:\nx = 1;\nx = 2;\nRules:\nA --> B",
                 "variable `x` already defined at line 2", 3, 1, id="duplicate-variable"),
    pytest.param("units = 1;\nVariables:\nunits = 2;\nRules:\nA --> B",
                 "`units` already set at line 1", 3, 1, id="duplicate-units"),
    pytest.param("Lot: rectangle(1, 2)\nLot: rectangle(3, 4)\nRules:\nA --> B",
                 "`Lot:` already given at line 1", 2, 1, id="duplicate-lot"),
    pytest.param("Variables:\nx = 1", "the grammar has no `Rules:` section", 1, 1,
                 id="no-rules-section"),
    pytest.param("Variables:\nx = 1\nRules:\n# nothing yet\n",
                 "the `Rules:` section has no rules", 3, 1, id="empty-rules-section"),
    pytest.param("Variables:\nx = 1\nA --> B\nRules:\nC --> D",
                 "the rule for `A` is outside the `Rules:` section", 3, 1,
                 id="rule-outside-section"),
    pytest.param("Rules:\nA --> B\nx = 3", "the variable `x` is inside the `Rules:` section",
                 3, 1, id="variable-in-rules"),
    pytest.param("Variables:\nx = 1 y = 2\nRules:\nA --> B",
                 "missing `;` before this statement", 2, 7, id="missing-semicolon"),
]


@pytest.mark.parametrize("source, words, line, column", CASES)
def test_message_and_position(source, words, line, column):
    with pytest.raises(GrammarSyntaxError) as caught:
        parse(source, "g.grammar")
    error = caught.value
    assert words in error.message
    assert (error.span.file, error.span.line, error.span.column) == ("g.grammar", line, column)
    assert error.source == source


@pytest.mark.parametrize("source, words, line, column", CASES)
def test_str_shows_location_line_and_caret(source, words, line, column):
    with pytest.raises(GrammarSyntaxError) as caught:
        parse(source, "g.grammar")
    shown = str(caught.value).split("\n")
    assert shown[0].startswith(f"g.grammar:{line}:{column}: error: ")
    assert words in shown[0]
    source_line = source.split("\n")[line - 1]
    if not source_line.strip():
        return  # nothing to show (empty file)
    gutter = f"{line:>4} | "
    assert shown[1] == gutter + source_line
    caret_line = shown[2]
    assert caret_line.strip().startswith("^")
    assert caret_line.index("^") == len(gutter) + column - 1
    assert set(caret_line.strip()) <= {"^", "~"}


def test_underline_covers_the_unterminated_string_to_the_line_end():
    with pytest.raises(GrammarSyntaxError) as caught:
        parse('Rules:\nA --> op("abc) B\nC --> D', "g.grammar")
    assert str(caught.value).split("\n")[2].strip() == "^" + "~" * (len('"abc) B') - 1)
    assert caught.value.hint is not None


def test_exact_rendering_of_a_typical_error():
    source = "Variables:\n  h = 3;\nRules:\nLot --> extrude(h Body\nBody --> X\n"
    with pytest.raises(GrammarSyntaxError) as caught:
        parse(source, "house.grammar")
    assert str(caught.value) == (
        "house.grammar:4:19: error: unexpected name `Body`; expected `)`, `,` or an operator\n"
        "   4 | Lot --> extrude(h Body\n"
        "                         ^~~~")


@pytest.mark.parametrize("source, hint_words", [
    ("Rules:\nA --> op(a >= b) B", "put comparisons"),
    ("Rules:\nA --> op(a and b) B", "put comparisons"),
    ("Rules:\nA --> op('x') B", "double quotes"),
    ("Rules:\nA --> op() B\n   | 30% : C", "every branch starts with a guard"),
    ("Rules:\nA --> case x > 1 : 30% : B | else : C\n   | else : D", "goes in parentheses"),
    ("Rules:\nA --> 30% : case x : B | else : C", "goes in parentheses"),
])
def test_hints(source, hint_words):
    with pytest.raises(GrammarSyntaxError) as caught:
        parse(source)
    assert hint_words in caught.value.hint
    assert f"hint: {caught.value.hint}" in str(caught.value)


def test_deep_nesting_is_a_syntax_error_not_a_crash():
    source = "Rules:\nA --> op(" + "-" * 5000 + "1) B"
    with pytest.raises(GrammarSyntaxError, match="nested too deeply"):
        parse(source)


def test_parse_file_error_names_the_path(tmp_path):
    path = tmp_path / "bad.grammar"
    path.write_text("Rules:\nLot extrude(3) A\n", encoding="utf-8")
    with pytest.raises(GrammarSyntaxError) as caught:
        parse_file(path)
    assert str(caught.value).startswith(f"{path}:2:5: error: expected `-->`")


def test_parse_file_rejects_non_utf8(tmp_path):
    path = tmp_path / "latin1.grammar"
    path.write_bytes("Rules:\nK\xfcche --> B\n".encode("latin-1"))
    with pytest.raises(GrammarSyntaxError, match="not UTF-8"):
        parse_file(path)
