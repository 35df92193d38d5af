"""What the parsers produce (parser.py's regex, lark_parser.py's grammar): statements of
words with their columns; and the grammar both read (grammars/il.lark)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from mlctool.diagnostics import Span

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


def grammar_text() -> str:
    path = GRAMMAR if GRAMMAR.exists() else _PACKAGED_GRAMMAR
    return path.read_text("utf-8")
