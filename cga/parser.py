"""Grammar text → :class:`cga.ast.Grammar`: reading the file and the lark parser.

The language (docs/language.md) is described in ``cga/grammar.lark`` and read with
lark's LALR(1) parser. Parsing and building the AST are two steps:
:mod:`cga.ast_builder` turns the parse tree into the frozen dataclasses of :mod:`cga.ast`
(and checks what the context-free grammar cannot express), :mod:`cga.syntax_errors`
words lark's errors. Only these modules (and :mod:`cga.source_positions`) import lark;
the rest of the engine never sees a lark tree.

Every problem is raised as :class:`cga.errors.GrammarSyntaxError` with a span and the
source attached.
"""

from __future__ import annotations

from collections.abc import Iterator
from functools import cache, lru_cache
from pathlib import Path

from lark import Lark, Token
from lark.exceptions import UnexpectedInput, VisitError
from lark.lark import PostLex

from . import ast
from .ast_builder import AstBuilder
from .errors import CGAError, GrammarSyntaxError, ResourceNotFoundError, Span
from .resources import is_folder
from .syntax_errors import SyntaxErrorBuilder
from .textfiles import read_input_bytes

__all__ = ["parse", "parse_file", "read_grammar"]


@lru_cache(maxsize=8)
def parse(text: str, file: str = "<string>") -> ast.Grammar:
    """Parse grammar source text into a :class:`cga.ast.Grammar`.

    Parameters
    ----------
    text:
        The grammar source (reference: ``docs/language.md``).
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
    process, and the last few texts' trees are kept (the tree is immutable; a batch
    builds every house from one text). A leading byte-order mark is skipped (columns count as an editor shows them).
    """
    text = text.removeprefix("\ufeff")
    try:
        try:
            tree = _lark_parser().parse(text)
        except UnexpectedInput as error:
            raise SyntaxErrorBuilder(text, file).build(error) from None
        try:
            return AstBuilder(text, file).transform(tree)
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


_GRAMMAR_FILE = Path(__file__).with_name("grammar.lark")


@cache
def _lark_parser() -> Lark:
    """The LALR(1) parser, built once per process and its tables kept on disk.

    Building the tables from ``grammar.lark`` costs about 0.1 s of CPU; loading them is
    several times faster. lark's own cache (``cache=`` file) stores them, with a hash of
    the grammar, the options, lark's and Python's versions in the file; the file is
    named by that and by the terminals the post-lexer accepts everywhere (which lark's
    hash leaves out), in the on-disk cache folder (:mod:`cga.cache`, kind ``parser``). A
    file that cannot be read (a parallel build still writing it) is a miss: lark builds
    the tables and writes the file again.
    """
    import sys

    import lark

    from .cache import cache_root, digest

    key = digest("cga-parser-1", _GRAMMAR_FILE.read_bytes(), lark.__version__,
                 repr(sys.version_info[:2]), repr(_LexEverywhere.always_accept))
    path = cache_root() / "parser" / f"{key}.lark"
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError:
        cache_file: str | bool = False
    else:
        cache_file = str(path)
    return Lark.open(str(_GRAMMAR_FILE), parser="lalr", propagate_positions=True,
                     maybe_placeholders=True, postlex=_LexEverywhere(), cache=cache_file)
