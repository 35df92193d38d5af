"""Rendering diagnostics: text for people, JSON for CI (SARIF: mlctool/sarif.py)."""

from __future__ import annotations

import os
import sys

from mlctool.diagnostics import Diagnostic
from mlctool.syntax.source import display_width

# ANSI SGR codes of the styles: bold; bold red, yellow, cyan
_BOLD = "\x1b[1m"
_RESET = "\x1b[0m"
_STYLE = {"error": "\x1b[1;31m", "warning": "\x1b[1;33m", "note": "\x1b[1;36m"}
# control characters (C0 but tab and newline, DEL, C1) from a file name, message or source
# line are shown escaped, `\x1b`: a terminal would act on them (ESC[2J clears the screen)
_ESCAPE_CONTROLS = str.maketrans({c: f"\\x{c:02x}" for c in (*range(0x20), 0x7F, *range(0x80, 0xA0))
                                  if c not in (9, 10)})
# diagnostics written per stream.write (stderr is line buffered: one flush per write)
_CHUNK = 2048

SHOW_PER_CODE = 50  # `mlc check` text output: diagnostics shown per code without --show-all


def use_color(stream) -> bool:
    if os.environ.get("NO_COLOR"):
        return False
    if os.environ.get("FORCE_COLOR"):
        return True
    return hasattr(stream, "isatty") and stream.isatty()


def render_text(diags: list[Diagnostic], lines: dict[str, list[str]], stream=None,
                per_code: int | None = None) -> None:
    """Diagnostics as `file:line:col: severity[CODE]: message`, the source line and carets.

    Plain text written straight to the stream in chunks (a diagnostic costs a few
    microseconds; through rich it cost about 0.6 ms). Colour only when use_color says so.
    With `per_code`, only the first `per_code` diagnostics of each code are written; a line
    per code then says how many more there are."""
    if not diags:
        return
    stream = stream or sys.stderr
    color = use_color(stream)
    out: list[str] = []
    shown: dict[str, int] = {}
    hidden: dict[str, int] = {}
    for d in diags:
        if per_code is not None:
            n = shown.get(d.code, 0)
            if n >= per_code:
                hidden[d.code] = hidden.get(d.code, 0) + 1
                continue
            shown[d.code] = n + 1
        span = d.span
        where = f"{d.file}:{span.line}:{span.col}:".translate(_ESCAPE_CONTROLS)
        label = f"{d.severity}[{d.code}]".translate(_ESCAPE_CONTROLS)
        message = d.message.translate(_ESCAPE_CONTROLS)
        header = f"{where} {label}: {message}"
        if "\t" in header:
            out.append(_expand_tabs(header) + "\n")  # no colour then: tabs are rare here
        elif color:
            style = _STYLE.get(d.severity, _BOLD)
            out.append(f"{_BOLD}{where}{_RESET} {style}{label}{_RESET}: {message}\n")
        else:
            out.append(header + "\n")
        src = lines.get(d.file)
        if src and 1 <= span.line <= len(src):
            text = src[span.line - 1].replace("\t", " ")
            if len(text) > 200:
                text = text[:200] + " ..."
            end = min(span.end_col, len(text) + 1) if span.end_line == span.line else span.col + 1
            # columns count characters; the carets go by display width (Chinese names take two)
            lead = display_width(text[:span.col - 1].translate(_ESCAPE_CONTROLS))
            carets = "^" * max(1, display_width(text[span.col - 1:end - 1].translate(_ESCAPE_CONTROLS)))
            if color:
                carets = f"{_STYLE.get(d.severity, _BOLD)}{carets}{_RESET}"
            out.append(f"  {span.line:>5} | {text.translate(_ESCAPE_CONTROLS)}\n        | {' ' * lead}{carets}\n")
        for n in d.notes:
            out.append(_expand_tabs(f"        = note: {n.translate(_ESCAPE_CONTROLS)}") + "\n")
        if len(out) >= _CHUNK:
            stream.write("".join(out))
            out.clear()
    for code in sorted(hidden):
        out.append(f"... and {hidden[code]:,} more {code} (use --show-all to see them)\n")
    stream.write("".join(out))


def _expand_tabs(text: str) -> str:
    """Tabs to blanks, stops every 8 display columns of each line (as a terminal shows them)."""
    if "\t" not in text:
        return text
    lines = []
    for line in text.split("\n"):
        *pieces, last = line.split("\t")
        col = 0
        done = []
        for piece in pieces:
            col += display_width(piece) + 1
            fill = -col % 8
            col += fill
            done.append(piece + " " * (1 + fill))
        lines.append("".join(done) + last)
    return "\n".join(lines)


def summary_line(errors: int, warnings: int) -> str:
    return f"{errors} error{'s' if errors != 1 else ''}, {warnings} warning{'s' if warnings != 1 else ''}"


def to_json(diags: list[Diagnostic]) -> str:
    data = {
        "diagnostics": [d.as_dict() for d in diags],
        "errors": sum(d.severity == "error" for d in diags),
        "warnings": sum(d.severity == "warning" for d in diags),
    }
    import json  # here: `mlc check` with text output never needs it (a few ms of every start)

    return json.dumps(data, indent=2, ensure_ascii=False) + "\n"
