"""Reading source bytes into text: encodings vendor tools write, and junk rejected early."""

from __future__ import annotations

import codecs
from dataclasses import dataclass

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.fileio import read_input

MAX_BYTES = 64 * 1024 * 1024
MAX_LINES = 1_000_000


# What vendor tools on East Asian Windows write besides UTF-8 (Delta, Vigor, FATEK: Big5/cp950;
# mainland tools: GBK/GB18030; Mitsubishi GX and kin: Shift-JIS/cp932; LS: cp949); the
# detector only weighs these (a wider field gives wilder guesses). DECISION: no single-byte
# code page (cp1252, latin-1) is guessed: every byte string decodes in one, so junk would
# pass as text; such a file names its encoding (--encoding cp1252).
GUESSES = ("cp950", "big5", "gb18030", "cp932", "euc_jp", "cp949")
GUESSED = "N108"
# a guess is read with the vendor code page that extends it (cp950 has Big5's characters and more)
_SUPERSET = {"big5": "cp950", "shift_jis": "cp932", "gb2312": "gb18030", "gbk": "gb18030"}


@dataclass(frozen=True, slots=True)
class SourceText:
    path: str
    text: str  # always ends with a newline, line ends normalised to \n
    encoding: str = "utf-8"  # the codec the bytes were read with (utf-16-le, cp950, ...)
    bom: bool = False  # the file starts with a byte-order mark
    newline: str = "\n"  # the file's line ending (its first one): mlc fmt writes it back

    def encode(self, text: str) -> bytes:
        """`text` (lines ending in \\n) as this file's bytes: its encoding, BOM and line ending."""
        if self.newline != "\n":
            text = text.replace("\n", self.newline)
        data = text.encode(self.encoding)
        if self.bom:
            data = _BOMS[self.encoding] + data
        return data


_BOMS = {"utf-8": codecs.BOM_UTF8, "utf-16-le": codecs.BOM_UTF16_LE, "utf-16-be": codecs.BOM_UTF16_BE}


EXAMPLES = "e.g. cp950, big5, gb18030, cp932, utf-8"
_PROBE = "P1: LD X0 ; 註解\n"  # a source line: a text encoding reads back what it wrote


def known_encoding(name: str) -> str | None:
    """The codec's canonical name (`Big5` -> `big5`, `sjis` -> `shift_jis`), None if unknown
    or not a text encoding (`encoding_refusal` says which). UTF-16/32 named without a byte
    order mean little-endian (as Windows writes them), so a file without a BOM is written
    back without one."""
    try:
        canonical = codecs.lookup(name).name
    except (LookupError, ValueError):
        return None
    try:  # Python's bytes-to-bytes codecs (rot13, hex, base64, bz2, zip, uu) and `undefined` refuse
        _PROBE.encode(canonical, "replace").decode(canonical)
    except (LookupError, UnicodeError):
        return None
    return {"utf-16": "utf-16-le", "utf-32": "utf-32-le"}.get(canonical, canonical)


def encoding_refusal(name: str) -> str:
    """Why sources cannot be read in `name` (known_encoding gave None)."""
    try:
        codecs.lookup(name)
    except (LookupError, ValueError):
        return f"unknown encoding {name!r} ({EXAMPLES})"
    return f"{name!r} is not an encoding of text files ({EXAMPLES})"


def decode(path: str, data: bytes, encoding: str | None = None) -> tuple[SourceText | None, list[Diagnostic]]:
    """Bytes -> text. A BOM decides (UTF-8, UTF-16); else `encoding` when given (--encoding,
    mlc.toml `encoding`); else UTF-8, and bytes that are not UTF-8 are guessed among GUESSES
    with a note (N108) naming the guess. Only that last case imports the detector."""
    if len(data) > MAX_BYTES:
        return None, [diag(path, Span.at(1), "E104", f"file is {len(data)} bytes; the limit is {MAX_BYTES}")]
    found: list[Diagnostic] = []
    bom = next((enc for enc, mark in (("utf-16-le", codecs.BOM_UTF16_LE), ("utf-16-be", codecs.BOM_UTF16_BE),
                                      ("utf-8", codecs.BOM_UTF8)) if data.startswith(mark)), None)
    if bom is not None and bom != "utf-8":
        try:
            text = data[2:].decode(bom)
        except UnicodeDecodeError as e:
            return None, [diag(path, Span.at(1), "E102", f"invalid UTF-16 ({e.reason})")]
        used = bom
    else:
        wide = bool(encoding) and encoding.startswith(("utf-16", "utf-32"))  # NULs are part of the code
        nul = -1 if wide and bom is None else data.find(b"\0")
        if nul >= 0:
            line = data.count(b"\n", 0, nul) + 1
            col = nul - (data.rfind(b"\n", 0, nul) + 1) + 1
            return None, [diag(path, Span.at(line, col), "E101", "file contains a NUL byte: not a text source")]
        body = data[3:] if bom else data
        used = "utf-8" if bom else (encoding or "utf-8")
        try:
            text = body.decode(used)
        except UnicodeDecodeError as e:
            line = body.count(b"\n", 0, e.start) + 1
            col = e.start - (body.rfind(b"\n", 0, e.start) + 1) + 1
            guess = None if bom or encoding else _guess(body)
            if guess is None:
                how = "UTF-8 (save the file as UTF-8, or name its encoding with --encoding)" \
                    if used == "utf-8" else f"{used} (the encoding named by --encoding or mlc.toml)"
                return None, [diag(path, Span.at(line, col), "E102", f"byte 0x{body[e.start]:02X} is not valid {how}")]
            used, text = guess
            col = len(body[body.rfind(b"\n", 0, e.start) + 1:e.start].decode(used, "replace")) + 1  # characters
            found.append(diag(path, Span.at(line, col), GUESSED,
                              f"not UTF-8 (byte 0x{body[e.start]:02X}): read as {used}, a guess; "
                              f"say so with --encoding {used} or mlc.toml `encoding = \"{used}\"`"))
        except UnicodeError as e:  # a codec that says no position (punycode, idna): where it failed is unknown
            return None, [diag(path, Span.at(1), "E102", f"not valid {used} (the encoding named by --encoding or "
                               f"mlc.toml): {e}")]
        if "\0" in text:
            return None, [diag(path, Span.at(1), "E101", "file contains a NUL character")]
    first = text.find("\r")
    newline = "\n" if first < 0 or 0 <= text.find("\n") < first else ("\r\n" if text[first:first + 2] == "\r\n" else "\r")
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    if text.count("\n") > MAX_LINES:
        return None, [diag(path, Span.at(MAX_LINES + 1), "E104", f"more than {MAX_LINES} lines")]
    if not text.endswith("\n"):
        text += "\n"
    return SourceText(path, text, used, bom is not None, newline), found


def _guess(data: bytes) -> tuple[str, str] | None:
    """(encoding, text) of the most plausible of GUESSES, or None."""
    try:
        from charset_normalizer import from_bytes
    except ImportError:  # a broken install: no guess, the file is E102 as without detection
        return None
    best = from_bytes(data, cp_isolation=list(GUESSES)).best()
    if best is None:
        return None
    name = known_encoding(best.encoding) or best.encoding
    name = _SUPERSET.get(name, name)
    try:
        return name, data.decode(name)
    except (UnicodeDecodeError, LookupError):
        return None


def read_source(path: str, encoding: str | None = None) -> tuple[SourceText | None, list[Diagnostic]]:
    try:
        data = read_input(path, MAX_BYTES + 1)
    except OSError as e:
        return None, [diag(path, Span.at(1), "E100", f"cannot read: {e.strerror or e}")]
    return decode(path, data, encoding)


def source_encoding(config) -> tuple[str | None, list[Diagnostic]]:
    """The encoding sources are read with: --encoding (the CLI puts it in the configuration's
    data), else mlc.toml `encoding`; None: UTF-8 with detection. An unknown name is E110 at the
    key (or the option)."""
    data = getattr(config, "data", None) or {}
    name = data.get("encoding")
    if not isinstance(name, str):  # absent (a wrong type is the config reader's E110)
        return None, []
    canonical = known_encoding(name)
    if canonical is not None:
        return canonical, []
    where, span = config.locate("encoding") if hasattr(config, "locate") else ("mlc.toml", Span.at(1))
    return None, [diag(where, span, "E110", encoding_refusal(name))]


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
