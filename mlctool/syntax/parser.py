"""Source text -> statements with source spans, using the lark grammar in grammars/il.lark.

The parser is LALR with an inline transformer (no parse tree is built), so a 64k-line file
parses in well under a second. A syntax error costs one diagnostic for its line; parsing
resumes on the next line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

from lark import Lark, Transformer, UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.syntax.source import SourceText

GRAMMAR = Path(__file__).resolve().parents[2] / "grammars" / "il.lark"
_PACKAGED_GRAMMAR = Path(__file__).resolve().parent / "il.lark"


@dataclass(slots=True)
class Word:
    """A token as written, with its 1-based column."""

    text: str
    col: int

    @property
    def end_col(self) -> int:
        return self.col + len(self.text)


@dataclass(slots=True)
class Statement:
    line: int
    kind: str  # "instr" | "label" | "directive"
    name: Word  # mnemonic, label or directive as written
    operands: list[Word]
    step: Word | None = None

    @property
    def span(self) -> Span:
        end = self.operands[-1].end_col if self.operands else self.name.end_col
        return Span(self.line, self.name.col, self.line, end)


@dataclass(slots=True)
class ParsedFile:
    path: str
    lines: list[str]  # source lines, for diagnostics
    statements: list[Statement]
    diagnostics: list[Diagnostic]
    noqa: dict[int, frozenset[str] | None] = field(default_factory=dict)


def _word(tok) -> Word:
    return Word(str(tok), tok.column)


class _ToStatements(Transformer):
    def start(self, items):
        # Steps and statements arrive flat; a step belongs to a statement on its own line.
        out = []
        step = None
        for it in items:
            if isinstance(it, Statement):
                if step is not None and step.line == it.line:
                    it.step = Word(str(step), step.column)
                out.append(it)
                step = None
            else:
                step = it
        return out

    def instr(self, items):
        head = items[0]
        return Statement(head.line, "instr", Word(str(head), head.column),
                         [Word(str(t), t.column) for t in items[1:]])

    def label(self, items):
        return Statement(items[0].line, "label", _word(items[0]), [])

    def directive(self, items):
        return Statement(items[0].line, "directive", _word(items[0]), [_word(t) for t in items[1:]])


@cache
def _parser() -> Lark:
    path = GRAMMAR if GRAMMAR.exists() else _PACKAGED_GRAMMAR
    # cache=True: lark keeps the compiled tables in the temp dir, keyed by the grammar's hash
    return Lark(path.read_text("utf-8"), parser="lalr", lexer="contextual", cache=True,
                transformer=_ToStatements(), propagate_positions=False, maybe_placeholders=False)


_EXPECT_NAMES = {
    "MNEMONIC": "an instruction", "OPERAND": "an operand", "_NL": "end of line",
    "STEP": "a step number", "DIRECTIVE": "a directive", "COLON": "':'",
}


def _expected(e: UnexpectedInput) -> str:
    names = sorted({_EXPECT_NAMES.get(t, t) for t in (getattr(e, "expected", None) or getattr(e, "allowed", None) or ())})
    return " or ".join(names) if names else "something else"


def _error_message(e: UnexpectedInput, line_text: str) -> tuple[int, str]:
    col = max(e.column, 1) if isinstance(e.column, int) else 1
    if isinstance(e, UnexpectedCharacters):
        ch = line_text[col - 1] if col - 1 < len(line_text) else "?"
        return col, f"unexpected character {ch!r}; expected {_expected(e)}"
    if isinstance(e, UnexpectedToken):
        tok = e.token
        what = "end of line" if tok.type == "_NL" else repr(str(tok))
        return col, f"unexpected {what}; expected {_expected(e)}"
    return col, "syntax error"


_NOQA = re.compile(r"(?:;|//).*?\bmlc:\s*noqa\b(?::?\s*([A-Z0-9, ]+))?", re.IGNORECASE)


def _noqa(lines: list[str]) -> dict[int, frozenset[str] | None]:
    found = {}
    for i, text in enumerate(lines, 1):
        if "noqa" in text:
            m = _NOQA.search(text)
            if m:
                codes = m.group(1)
                found[i] = frozenset(c.upper() for c in re.split(r"[ ,]+", codes) if c) if codes and codes.strip() else None
    return found


@cache
def _fast_line():
    """A regex for the common line shape, built from the grammar's own terminals.

    Lark's LALR loop costs ~5 us per token; most lines are `[STEP] MNEMONIC OPERAND...`, which
    this regex recognises directly. Every other line (labels, directives, errors) goes through
    lark. tests/test_parser.py checks that both give the same statements.
    """
    p = _parser()
    t = {name: p.get_terminal(name).pattern.to_regexp() for name in ("SEP", "COMMENT", "STEP", "MNEMONIC", "OPERAND")}
    line = (rf"(?:{t['SEP']})?(?:(?P<step>{t['STEP']})(?:{t['SEP']}))?(?P<name>{t['MNEMONIC']})"
            rf"(?P<ops>(?:(?:{t['SEP']})(?:{t['OPERAND']}))*)(?:{t['SEP']})?(?:{t['COMMENT']})?")
    return re.compile(line).fullmatch, re.compile(t["OPERAND"]).finditer


def _lark_line(parser: Lark, path: str, text: str, number: int, out: list, diagnostics: list) -> None:
    try:
        found = parser.parse(text + "\n")
    except UnexpectedInput as e:
        col, msg = _error_message(e, text)
        diagnostics.append(diag(path, Span.at(number, col), "E103", msg))
        return
    for s in found:
        s.line = number
        out.append(s)


def parse(src: SourceText, fast: bool = True) -> ParsedFile:
    lines = src.text.split("\n")[:-1]
    statements: list[Statement] = []
    diagnostics: list[Diagnostic] = []
    parser = _parser()
    match, operands = _fast_line()
    for number, text in enumerate(lines, 1):
        m = match(text) if fast else None
        if m is None:
            if text.strip():
                _lark_line(parser, src.path, text, number, statements, diagnostics)
            continue
        step = Word(m["step"], m.start("step") + 1) if m["step"] else None
        ops_at = m.start("ops") + 1
        statements.append(Statement(number, "instr", Word(m["name"], m.start("name") + 1),
                                    [Word(o.group(), ops_at + o.start()) for o in operands(m["ops"])], step))
    return ParsedFile(src.path, lines, statements, diagnostics, _noqa(lines))
