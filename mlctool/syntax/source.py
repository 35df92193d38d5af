"""Reading source bytes into text: encodings vendor tools write, and junk rejected early."""

from __future__ import annotations

import codecs
from dataclasses import dataclass

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.fileio import open_input

MAX_BYTES = 64 * 1024 * 1024
MAX_LINES = 1_000_000


@dataclass(frozen=True, slots=True)
class SourceText:
    path: str
    text: str  # always ends with a newline, line ends normalised to \n


def decode(path: str, data: bytes) -> tuple[SourceText | None, list[Diagnostic]]:
    """Decode bytes as UTF-8 (BOM optional) or UTF-16 with BOM; diagnose anything else."""
    if len(data) > MAX_BYTES:
        return None, [diag(path, Span.at(1), "E104", f"file is {len(data)} bytes; the limit is {MAX_BYTES}")]
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            text = data.decode("utf-16")
        except UnicodeDecodeError as e:
            return None, [diag(path, Span.at(1), "E102", f"invalid UTF-16 ({e.reason})")]
    else:
        nul = data.find(b"\0")
        if nul >= 0:
            line = data.count(b"\n", 0, nul) + 1
            col = nul - (data.rfind(b"\n", 0, nul) + 1) + 1
            return None, [diag(path, Span.at(line, col), "E101", "file contains a NUL byte: not a text source")]
        try:
            text = data.decode("utf-8-sig")
        except UnicodeDecodeError as e:
            line = data.count(b"\n", 0, e.start) + 1
            col = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
            return None, [diag(path, Span.at(line, col), "E102",
                               f"byte 0x{data[e.start]:02X} is not valid UTF-8 (save the file as UTF-8)")]
        if "\0" in text:
            return None, [diag(path, Span.at(1), "E101", "file contains a NUL character")]
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    if text.count("\n") > MAX_LINES:
        return None, [diag(path, Span.at(MAX_LINES + 1), "E104", f"more than {MAX_LINES} lines")]
    if not text.endswith("\n"):
        text += "\n"
    return SourceText(path, text), []


def read_source(path: str) -> tuple[SourceText | None, list[Diagnostic]]:
    try:
        with open_input(path) as f:
            data = f.read(MAX_BYTES + 1)
    except OSError as e:
        return None, [diag(path, Span.at(1), "E100", f"cannot read: {e.strerror or e}")]
    return decode(path, data)


def display_width(text: str) -> int:
    """Columns `text` takes in a terminal or editor: East Asian wide and fullwidth characters
    (Chinese label names, the ideographic space) take two, combining marks none. For aligning
    text (`mlc fmt`, the carets under a diagnostic); diagnostic columns count characters."""
    import unicodedata

    if text.isascii():
        return len(text)
    return sum(0 if unicodedata.combining(c) else 2 if unicodedata.east_asian_width(c) in "WF" else 1
               for c in text)


def pad(text: str, width: int) -> str:
    """`text` filled with blanks to `width` display columns (as f"{text:<width}" for ASCII)."""
    return text + " " * max(0, width - display_width(text))
