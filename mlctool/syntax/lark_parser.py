"""The lark side of the IL parser: the LALR parser of grammars/il.lark, for the lines the
fast path of parser.py does not take (labels, directives, syntax errors with what was expected).
Imported only when such a line occurs."""

from __future__ import annotations

from functools import cache

from lark import Lark, Transformer, UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from mlctool.diagnostics import Span, diag
from mlctool.syntax.statements import Statement, Word, grammar_text


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
def lark_parser() -> Lark:
    # cache=True: lark keeps the compiled tables in the temp dir, keyed by the grammar's hash
    return Lark(grammar_text(), parser="lalr", lexer="contextual", cache=True,
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



def parse_line(path: str, text: str, number: int, out: list, diagnostics: list) -> None:
    """Parse one line with lark: its statements go to `out`, a syntax error to `diagnostics`."""
    try:
        found = lark_parser().parse(text + "\n")
    except UnexpectedInput as e:
        col, msg = _error_message(e, text)
        diagnostics.append(diag(path, Span.at(number, col), "E103", msg))
        return
    for s in found:
        s.line = number
        out.append(s)
