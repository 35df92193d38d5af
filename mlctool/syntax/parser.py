"""Source text -> statements with source spans, by the grammar in grammars/il.lark.

Lines of the common shapes (instructions, labels, directives) are read by regexes built from
the grammar's terminals; the rest (odd spacing, syntax errors) by lark
(mlctool/syntax/lark_parser.py), LALR with an inline transformer. A syntax error costs one diagnostic for its line; parsing resumes on the
next line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import cache

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.limits import clip, long_number, too_long_message
from mlctool.syntax.operands import CJK_RANGES
from mlctool.syntax.source import SourceText
from mlctool.syntax.statements import Statement, Word, grammar_text

__all__ = ["ParsedFile", "Statement", "Word", "grammar_text", "parse"]

@dataclass(slots=True)
class ParsedFile:
    path: str
    lines: list[str]  # source lines, for diagnostics
    statements: list[Statement]
    diagnostics: list[Diagnostic]
    noqa: dict[int, frozenset[str] | None] = field(default_factory=dict)


_NOQA = re.compile(r"(?:;|//).*?\bmlc:\s*noqa\b(?::?\s*([A-Z0-9, ]+))?", re.IGNORECASE)


def _noqa(lines: list[str], text: str = "") -> dict[int, frozenset[str] | None]:
    found: dict[int, frozenset[str] | None] = {}
    if text and "noqa" not in text:  # the usual file: one search instead of a loop over its lines
        return found
    for i, text in enumerate(lines, 1):
        if "noqa" in text:
            m = _NOQA.search(text)
            if m:
                codes = m.group(1)
                found[i] = frozenset(c.upper() for c in re.split(r"[ ,]+", codes) if c) if codes and codes.strip() else None
    return found


_TERMINAL = re.compile(r"^(?P<name>[A-Z_]+):\s*/(?P<re>(?:\\.|[^/\\\n])*)/", re.M)


@cache
def _terminals() -> dict[str, str]:
    """The grammar's terminal regexes by name (read once for the regexes below)."""
    return {m["name"]: m["re"] for m in _TERMINAL.finditer(grammar_text())}


@cache
def _fast_line(ascii_only: bool = False):
    """A regex for the common line shape, built from the grammar's own terminal definitions.

    Lark's LALR loop costs ~5 us per token, and importing lark and loading its tables about
    25 ms; most lines are `[STEP] MNEMONIC OPERAND...`, `[STEP] LABEL:` or `.DIRECTIVE
    OPERAND...`, which these regexes recognise directly. Every other line (errors, odd forms
    such as `0000P10:`) goes through lark (mlctool/syntax/lark_parser.py).
    tests/syntax/test_parser.py checks that both give the same statements.

    `ascii_only`: the regexes for a text of ASCII only, without the Han ranges of the names
    (which cannot match there): each class with them takes ~2 ms to compile, at every start.
    """
    t = dict(_terminals())
    if ascii_only:
        t = {name: rx.replace(CJK_RANGES, "") for name, rx in t.items()}
    head = rf"(?:{t['SEP']})?(?:(?P<step>{t['STEP']})(?:{t['SEP']}))?"
    ops = rf"(?P<ops>(?:(?:{t['SEP']})(?:{t['OPERAND']}))*)"
    tail = rf"(?:{t['SEP']})?(?:{t['COMMENT']})?"
    instr = re.compile(rf"{head}(?P<name>{t['MNEMONIC']}){ops}{tail}").fullmatch
    # `P10:` and `.define START X0`: labels and directives too, so a usual file never needs lark
    label = re.compile(rf"{head}(?P<name>{t['MNEMONIC']})(?:{t['SEP']})?:{tail}").fullmatch
    directive = re.compile(rf"{head}(?P<name>{t['DIRECTIVE']}){ops}{tail}").fullmatch
    blank = re.compile(tail).fullmatch  # nothing to parse
    return instr, label, directive, re.compile(t["OPERAND"]).findall, blank


@cache
def _plain_line():
    """A regex for the plainest instruction line: a mnemonic and operands of the grammar's
    ASCII forms, separated by one space each, nothing before, after or between (`LD X0`,
    `MOV K10 D0`). Its words are found by splitting at the spaces, without the regex's groups;
    every other line takes _fast_line's regexes (tests/syntax/test_parser.py compares with
    lark, which reads every line the grammar's way)."""
    t = {name: rx.replace(CJK_RANGES, "") for name, rx in _terminals().items()}
    # (?!"): no "string" constant, which may hold spaces
    return re.compile(rf'(?:{t["MNEMONIC"]})(?: (?!")(?:{t["OPERAND"]}))*').fullmatch


def parse(src: SourceText, fast: bool = True, memo: dict | None = None) -> ParsedFile:
    """`memo`: line text -> its statement's parts, kept by the caller between parses of
    versions of the same text (the language server); each parse fills it. A line of the
    common shapes read once costs a dictionary look-up and a Statement the next times
    (programs repeat lines, and an edit leaves most lines of a file as they were)."""
    lines = src.text.split("\n")[:-1]
    statements: list[Statement] = []
    diagnostics: list[Diagnostic] = []
    seen: dict = {} if memo is None else memo
    instr, label, directive, operands, blank = _fast_line(src.text.isascii())
    plain = _plain_line() if fast else None
    add, known = statements.append, seen.get  # (the loop runs once per line)
    for number, text in enumerate(lines, 1):
        parts = known(text)
        if parts is not None:
            if parts:  # () for a blank or comment line
                add(Statement(number, *parts))
            continue
        if plain is not None and plain(text):  # `MNEMONIC OPERAND ...`, one space apart
            name, *written = text.split(" ")
            words = []
            col = len(name) + 2
            for o in written:
                words.append(Word(o, col))
                col += len(o) + 1
            parts = seen[text] = ("instr", Word(name, 1), words, None)
            add(Statement(number, *parts))
            continue
        kind = "instr"
        m = instr(text) if fast else None
        if m is None and fast:
            kind = "label"
            m = label(text)
            if m is None:
                kind = "directive"
                m = directive(text)
        if m is None:
            if not blank(text):
                from mlctool.syntax.lark_parser import parse_line  # lark loads when first needed

                parse_line(src.path, text, number, statements, diagnostics)
            elif fast:
                seen[text] = ()
            continue
        step_text = m["step"]
        step = Word(step_text, m.start("step") + 1) if step_text else None
        if kind == "label":
            words = []
        else:
            start, end = m.span("ops")
            words = []
            if end > start:  # each word found from where the last ended: between them are only
                pos = start  # separators, which no operand starts with (cheaper than a Match each)
                for o in operands(text, start, end):
                    pos = text.find(o, pos)
                    words.append(Word(o, pos + 1))
                    pos += len(o)
        # the words are shared by the statements of equal lines: nothing changes a Word or
        # a statement's list of operands after parsing
        parts = seen[text] = (kind, Word(m["name"], m.start("name") + 1), words, step)
        add(Statement(number, *parts))
    if long_number(src.text):  # rare: only then look at each word
        statements = _bounded(src.path, statements, diagnostics)
    return ParsedFile(src.path, lines, statements, diagnostics, _noqa(lines, src.text))


def _bounded(path: str, statements: list[Statement], diagnostics: list[Diagnostic]) -> list[Statement]:
    """Drop each statement with a number past limits.MAX_DIGITS (a step number, a label, an
    operand, a directive's argument), with a syntax error (E103) at that word."""
    out = []
    for st in statements:
        words = ([st.step] if st.step else []) + [st.name] + st.operands
        bad = next(((w, m) for w in words if (m := long_number(w.text))), None)
        if bad is None:
            out.append(st)
            continue
        w, m = bad
        diagnostics.append(diag(path, Span(st.line, w.col, st.line, w.end_col), "E103",
                                too_long_message(repr(clip(w.text)), len(m[0]))))
    return out
