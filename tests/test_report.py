"""Text rendering of diagnostics (mlctool/report.py): the plain output is byte for byte what
rich printed before (the reference below), colour only where asked, and the per-code limit."""

from __future__ import annotations

import io

from hypothesis import assume, given, settings
from hypothesis import strategies as st

from mlctool.diagnostics import Diagnostic, Span
from mlctool.report import render_text
from mlctool.syntax.source import display_width


def shown(text: str) -> str:
    """Control characters as the renderer shows them (issue 21: ESC[2J would clear the
    terminal): C0 but tab and newline, DEL and C1 as `\\xNN`."""
    return "".join(f"\\x{ord(c):02x}" if (c < " " and c not in "\t\n") or "\x7f" <= c <= "\x9f" else c
                   for c in text)


def rich_reference(diags, lines, stream) -> None:
    """The renderer as it was (rich, no colour) on the text with its control characters
    escaped: the format the plain renderer keeps."""
    from rich.console import Console
    from rich.markup import escape

    console = Console(file=stream, no_color=True, highlight=False, soft_wrap=True, force_terminal=False,
                      emoji=False)
    for d in diags:
        style = {"error": "bold red", "warning": "bold yellow", "note": "bold cyan"}[d.severity]
        console.print(f"[bold]{escape(shown(d.file))}:{d.span.line}:{d.span.col}:[/bold] "
                      f"[{style}]{d.severity}[{escape(d.code)}][/{style}]: {escape(shown(d.message))}")
        src = lines.get(d.file)
        if src and 1 <= d.span.line <= len(src):
            text = src[d.span.line - 1].replace("\t", " ")
            if len(text) > 200:
                text = text[:200] + " ..."
            end = min(d.span.end_col, len(text) + 1) if d.span.end_line == d.span.line else d.span.col + 1
            lead = display_width(shown(text[:d.span.col - 1]))
            width = max(1, display_width(shown(text[d.span.col - 1:end - 1])))
            console.print(f"  {d.span.line:>5} | {escape(shown(text))}")
            console.print(f"        | {' ' * lead}[{style}]{'^' * width}[/{style}]")
        for n in d.notes:
            console.print(f"        = note: {escape(shown(n))}")


PIECES = list("aZ09 :;,.-_[]\\/@#=<>\"'") + [
    "[bold]", "[/]", "[red]", "\x07", "\x08", "\x0b", "\x0c", "\r", "\x1b", "\x1b[2J", "\x7f", "\x85", "\t",
    "\u3000", "中", "é", "e\u0301", "\U0001F600", "\x01", "LD X0", "K99999" * 40]
TEXT = st.lists(st.sampled_from(PIECES), max_size=12).map("".join)


@settings(max_examples=300, deadline=None)
@given(TEXT, TEXT, TEXT, st.lists(TEXT, max_size=2), st.integers(1, 4), st.integers(1, 14),
       st.integers(-1, 14), st.sampled_from(["error", "warning", "note"]))
def test_plain_output_is_what_rich_printed(file, message, line, notes, number, col, length, severity):
    # rich's markup escape does not round-trip a backslash before '[' or at the end of a text
    # (it prints `\[` as `[` and a final `\` twice): the plain renderer prints the text as is
    assume(not any("\\[" in t or t.endswith("\\") for t in [file, message, line, *notes]))
    d = Diagnostic(file or "x.il", Span(number, col, number + (length < 0), col + abs(length)), severity,
                   "E201", message, tuple(notes))
    lines = {d.file: ["LD X0", line, "\tOUT Y0"]}
    plain, rich = io.StringIO(), io.StringIO()
    render_text([d, d], lines, plain)
    rich_reference([d, d], lines, rich)
    assert plain.getvalue() == rich.getvalue()


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _one() -> tuple[list[Diagnostic], dict]:
    return [Diagnostic("a.il", Span.at(1, 4, 2), "error", "E205", "out of range")], {"a.il": ["LD X9"]}


def test_colour_only_on_a_terminal_without_no_color(monkeypatch):
    diags, lines = _one()
    monkeypatch.delenv("NO_COLOR", raising=False)
    tty, pipe = _Terminal(), io.StringIO()
    render_text(diags, lines, tty)
    render_text(diags, lines, pipe)
    assert tty.getvalue() == ("\x1b[1ma.il:1:4:\x1b[0m \x1b[1;31merror[E205]\x1b[0m: out of range\n"
                              "      1 | LD X9\n        |    \x1b[1;31m^^\x1b[0m\n")
    assert "\x1b" not in pipe.getvalue()
    monkeypatch.setenv("NO_COLOR", "1")
    plain = _Terminal()
    render_text(diags, lines, plain)
    assert plain.getvalue() == pipe.getvalue()


def test_per_code_limit_counts_the_rest():
    diags = [Diagnostic("a.il", Span.at(k), "warning", "W401", f"m{k}") for k in range(1, 1300)]
    diags += [Diagnostic("a.il", Span.at(k), "error", "E205", f"e{k}") for k in range(1, 4)]
    out = io.StringIO()
    render_text(diags, {}, out, per_code=50)
    text = out.getvalue().splitlines()
    assert sum("[W401]" in t for t in text) == 50 and sum("[E205]" in t for t in text) == 3
    assert text[-1] == "... and 1,249 more W401 (use --show-all to see them)"
    everything = io.StringIO()
    render_text(diags, {}, everything)
    assert sum("[W401]" in t for t in everything.getvalue().splitlines()) == 1299


def test_control_characters_in_a_source_line_are_shown_escaped():
    """A source line with ESC[2J (clear screen) echoed into a diagnostic reached the terminal
    raw (issue 21 item 16); it is shown as `\\x1b[2J`, the carets still under the operand."""
    line = "LD \x1b[2JX9\x07"
    d = Diagnostic("a\x1b.il", Span.at(1, 8, 2), "error", "E205", "bad \x1b[31m operand")
    out = io.StringIO()
    render_text([d], {"a\x1b.il": [line]}, out)
    text = out.getvalue()
    assert "\x1b" not in text and "\x07" not in text
    assert "a\\x1b.il:1:8:" in text and "bad \\x1b[31m operand" in text
    src, carets = text.splitlines()[1:3]
    assert src.endswith("LD \\x1b[2JX9\\x07")
    assert src.index("X9") == carets.index("^^")
