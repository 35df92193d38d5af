"""Vendor exports -> plain IL (`mlc import`): GX Works2 and GX Developer instruction-list CSV,
WPLSoft CSV, plain IL text.

The shapes read (docs/vs.md "Imports"):
- GX Works2 "CSV": UTF-16 with BOM, tab-separated quoted fields; a program-name row and a
  "PLC Information:" row, then a header row naming the columns ("Step Number", "Line
  Statement", "Instruction", "I/O(Device)", ..., "Note"); an instruction's further operands
  follow on continuation rows with empty step and instruction cells; devices zero-padded
  (`X000`).
- GX Developer CSV: the same rows, comma-separated (UTF-8/ASCII or Shift-JIS).
- WPLSoft CSV: `000000,LD,X0` rows (6-digit step number, mnemonic, operands).
- Labels stand alone in the instruction cell (`P10`); on a target with named labels a name
  there that is no instruction (`SKIP_FILL`, `緊急停止`) is one too when it ends with a colon or
  the program jumps to it; another bare name (`NOPLF`) is an unknown instruction (E907).
- Plain IL: taken as it is, if it is IL (looks_like_il); anything else is E909.
The export's dialect decides the target when the command line names none (DIALECT_TARGET).
Step numbers are the exporting tool's own and are dropped (the target's step convention
computes the addresses); operands are rewritten as the target writes them (`X000` -> `X0`);
a 32-bit comparison in another vendor's spelling (`DLD>=`) becomes the target's (`LDD>=`).
"""

from __future__ import annotations

import csv
import dataclasses
import io
import re

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.syntax.operands import OperandSyntaxError, format_operand, parse_operand
from mlctool.syntax.source import decode, read_source
from mlctool.targetapi.model import Target

FORMATS = ("gxworks2", "gxdeveloper", "wplsoft", "il")
_HEADER = {  # column -> the header texts naming it (English and Japanese GX)
    "step": ("step number", "step no.", "ステップ番号"),
    "statement": ("line statement", "行間ステートメント"),
    "instruction": ("instruction", "命令"),
    "device": ("i/o(device)", "i/o(デバイス)", "device"),
    "note": ("note", "ノート"),
}
_STEP6 = re.compile(r"\s*[0-9]{6}\s*[,\t]")
_LABEL = re.compile(r"[PI][0-9]+", re.IGNORECASE)


def decode_export(path: str, data: bytes, encoding: str | None = None) -> tuple[str | None, list[Diagnostic]]:
    """Bytes -> text, line ends normalised, as sources are read (mlctool/syntax/source.py): a BOM
    (GX Works2 writes UTF-16), else `encoding`, else UTF-8, else a guess with a note (N108;
    GX Developer on Japanese Windows writes Shift-JIS, Taiwanese tools Big5)."""
    src, diags = decode(path, data, encoding)
    return (src.text if src is not None else None), diags


class _BadRow(Exception):
    """A row the csv module refuses (a field past its 131,072-character limit): E907."""

    def __init__(self, line: int, message: str):
        super().__init__(message)
        self.line = line
        self.message = message


def _rows(text: str, delimiter: str) -> list[list[str]]:
    reader = csv.reader(io.StringIO(text), delimiter=delimiter)
    out = []
    try:
        for row in reader:
            out.append([c.strip() for c in row])
    except csv.Error as e:
        limit = csv.field_size_limit()
        why = f"a field longer than {limit:,} characters" if "field limit" in str(e) else str(e)
        raise _BadRow(reader.line_num, f"line {reader.line_num}: {why}; no export has such a row") from None
    return out


def detect(text: str) -> str:
    head = text.splitlines()[:12]
    for line in head:
        cells = [c.strip().strip('"').lower() for c in re.split(r"[\t,]", line)]
        if any(c in _HEADER["instruction"] for c in cells) and any(c in _HEADER["device"][:2] for c in cells):
            return "gxworks2" if "\t" in line else "gxdeveloper"
    if any(_STEP6.match(line) for line in head):
        return "wplsoft"
    return "il"


class _Writer:
    """Collects IL lines; rewrites mnemonics and operands as the target writes them."""

    def __init__(self, path: str, target: Target):
        self.path, self.t = path, target
        self.lines: list[str] = []
        self.diags: list[Diagnostic] = []
        self.pending: list[str] | None = None  # the instruction whose operands may continue
        self.kinds: list[str] = []  # of each diagnostic: rows of one kind are reported once
        self.referenced: set[str] = set()  # operands written, upper case: the labels jumped to
        self.maybe_labels: list[tuple[int, str, int]] = []  # (line index, name, row)

    def error(self, row: int, kind: str, message: str, *notes: str) -> None:
        self.diags.append(diag(self.path, Span.at(row), "E907", message, *notes))
        self.kinds.append(kind)

    def flush(self) -> None:
        if self.pending is not None:
            self.lines.append(" ".join(self.pending))
            self.pending = None

    def comment(self, text: str) -> None:
        self.flush()
        self.lines.append(f"; {text}")

    def label(self, text: str, row: int = 0) -> None:
        """A label row. A bare name (no colon, no P/I number) is a label only if the program
        jumps to it; otherwise it is an unknown instruction without operands (`NOPLF`),
        decided in finish()."""
        self.flush()
        if row and not text.endswith((":", "：")) and not _LABEL.fullmatch(text):
            self.maybe_labels.append((len(self.lines), text, row))
        self.lines.append(f"{text.rstrip(':：').upper()}:")

    def finish(self) -> None:
        self.flush()
        for index, name, row in self.maybe_labels:
            if name.upper() not in self.referenced:
                self.lines[index] = name
                self.unknown(name.upper(), row)

    def is_label(self, text: str) -> bool:
        """A label written alone in the instruction cell: P10 / I001, or on a target with named
        labels a name (`SKIP_FILL`, `緊急停止`, either with a colon) that is no instruction."""
        if _LABEL.fullmatch(text):
            return True
        name = text.rstrip(":：")
        m = name.upper()
        if not name or m in self.t.instructions or m in self.t.variants or m in self.t.unavailable:
            return False
        from mlctool.check.labels import is_label_name

        return bool(self.t.settings.get("named_labels")) and is_label_name(name, self.t)

    def instruction(self, mnemonic: str, operands: list[str], row: int, note: str = "") -> None:
        self.flush()
        self.referenced.update(o.upper() for o in operands)
        self.pending = [self.mnemonic(mnemonic, row), *(self.operand(o) for o in operands if o)]
        if note:
            self.pending.append(f"; {note}")

    def more(self, operand: str, row: int) -> None:
        if self.pending is None:
            self.error(row, "orphan", f"row {row}: operand {operand!r} without an instruction")
            return
        self.referenced.add(operand.upper())
        at = next((k for k, w in enumerate(self.pending) if w.startswith(";")), len(self.pending))
        self.pending.insert(at, self.operand(operand))

    def mnemonic(self, text: str, row: int) -> str:
        m = text.upper()
        if m in self.t.instructions or m in self.t.variants or m in self.t.unavailable:
            return m
        # another vendor's spelling of a 32-bit comparison (DLD>= for LDD>=): the same FNC
        short = self.t.instructions.get(m[1:]) if m.startswith("D") else None
        if short is not None and short.api is not None:
            for s in self.t.instructions.values():
                if s.api == short.api and s.width == 32 and s.cls == short.cls and not s.pulse:
                    return s.mnemonic
        self.unknown(m, row)
        return m

    def unknown(self, mnemonic: str, row: int) -> None:
        """An instruction the target does not have: the import cannot place it (as check's E201)."""
        from mlctool.check.resolve import unknown_instruction_hint

        suggestion, notes = unknown_instruction_hint(self.t, mnemonic)
        self.error(row, f"unknown {mnemonic}", f"row {row}: unknown instruction {mnemonic!r} for target "
                   f"{self.t.name}{suggestion}", *notes)

    def operand(self, text: str) -> str:
        try:
            op = parse_operand(text, self.t.operand_syntax)
        except OperandSyntaxError:
            return text  # a symbol, a label name, or an error `mlc check` reports
        return format_operand(op) if not op.is_const or op.kind in ("K", "H") else text


def _gx(w: _Writer, text: str, delimiter: str) -> None:
    rows = _rows(text, delimiter)
    cols: dict[str, int] = {}
    for k, row in enumerate(rows, 1):
        low = [c.lower() for c in row]
        if not cols:
            found = {name: low.index(t) for name, texts in _HEADER.items() for t in texts if t in low}
            if "instruction" in found and "device" in found:
                cols = found
            continue  # the program-name and "PLC Information:" rows before the header

        def cell(name: str, row=row, cols=cols) -> str:
            i = cols.get(name)
            return row[i] if i is not None and i < len(row) else ""

        instr, device, statement, note = cell("instruction"), cell("device"), cell("statement"), cell("note")
        if statement:
            w.comment(statement)
        if instr:
            if not device and w.is_label(instr):
                w.label(instr, k)
            else:
                w.instruction(instr, device.split(), k, note)
        elif device:
            w.more(device, k)
        elif note:
            w.comment(note)
    if not cols:
        w.error(1, "header", "no header row naming the Instruction and I/O(Device) columns")


def _wplsoft(w: _Writer, text: str) -> None:
    for k, row in enumerate(_rows(text, ","), 1):
        cells = [c for c in row if c != ""]
        if not cells:
            continue
        if cells[0].startswith((";", "//")):
            w.comment(",".join(row).lstrip(";/ "))
            continue
        if not re.fullmatch(r"[0-9]{6}", cells[0]):
            if k == 1:
                continue  # a title row
            w.error(k, "step", f"row {k}: expected a 6-digit step number, got {cells[0]!r}")
            continue
        rest = cells[1:]
        if not rest:
            continue
        first = rest[0].split()
        words = first + rest[1:]
        if len(words) == 1 and w.is_label(words[0]):
            w.label(words[0], k)
        else:
            w.instruction(words[0], words[1:], k)


def import_text(path: str, text: str, target: Target, fmt: str | None = None
                ) -> tuple[str | None, str, list[Diagnostic]]:
    """-> (IL text or None on errors, the format read, diagnostics)."""
    if fmt is None:
        fmt = detect(text)
        if fmt == "il" and not looks_like_il(path, text):
            return None, "", [diag(path, Span.at(1), "E909", "not recognised as a GX Works2, GX Developer or "
                                   "WPLSoft export, nor as instruction-list text",
                                   "name the format with --from if it is one (docs/vs.md, Imports)")]
    if fmt == "il":
        return (text if text.endswith("\n") else text + "\n"), fmt, []
    w = _Writer(path, target)
    try:
        if fmt in ("gxworks2", "gxdeveloper"):
            _gx(w, text, "\t" if fmt == "gxworks2" or "\t" in text.split("\n", 3)[-1] else ",")
        else:
            _wplsoft(w, text)
    except _BadRow as e:
        return None, fmt, [diag(path, Span.at(e.line), "E907", e.message)]
    w.finish()
    diags = _once_per_kind(w.diags, w.kinds)
    if any(d.severity == "error" for d in diags):
        return None, fmt, diags
    return "\n".join(w.lines) + "\n", fmt, diags


def _once_per_kind(diags: list[Diagnostic], kinds: list[str]) -> list[Diagnostic]:
    """One diagnostic per kind of problem (a file that is no WPLSoft export gave 220 identical
    "expected a 6-digit step number"): the first, with the rows of the others in a note."""
    first: dict[str, int] = {}
    rows: dict[str, list[int]] = {}
    for k, (d, kind) in enumerate(zip(diags, kinds, strict=True)):
        if kind in first:
            rows[kind].append(d.span.line)
        else:
            first[kind], rows[kind] = k, []
    out = []
    for kind, k in first.items():
        d, more = diags[k], rows[kind]
        if more:
            shown = ", ".join(map(str, more[:10])) + (", ..." if len(more) > 10 else "")
            d = dataclasses.replace(d, notes=d.notes + (f"and {len(more)} more row{'s' if len(more) > 1 else ''} "
                                                       f"like it: {shown}",))
        out.append(d)
    return sorted(out, key=Diagnostic.sort_key)


def looks_like_il(path: str, text: str) -> bool:
    """Plain IL: parses without a syntax error, and most of its instructions are mnemonics of
    some target (a README or a data table parses as `WORD WORD ...` too)."""
    from mlctool.syntax.parser import parse
    from mlctool.syntax.source import SourceText
    from mlctool.targetapi import available_targets, load_target

    parsed = parse(SourceText(path, text if text.endswith("\n") else text + "\n"))
    if parsed.diagnostics:
        return False
    names = [st.name.text.upper() for st in parsed.statements if st.kind == "instr"]
    if not names:
        return False
    known: set[str] = set()
    for t in map(load_target, available_targets()):
        known |= set(t.instructions) | set(t.variants) | set(t.unavailable)
    return 2 * sum(n in known for n in names) >= len(names)


# The target of each export's dialect, when the command line names none: GX Works2 and GX
# Developer export Mitsubishi FX programs, WPLSoft Delta DVP ones, both FX-style IL, which the
# Vigor VS target follows (docs/vs.md).
DIALECT_TARGET = {"gxworks2": "vs", "gxdeveloper": "vs", "wplsoft": "vs"}


def import_file(path: str, target: Target, fmt: str | None = None) -> tuple[str | None, str, list[Diagnostic]]:
    text, diags = read_export(path)
    if text is None:
        return None, fmt or "", diags
    return import_text(path, text, target, fmt)


def read_export(path: str, encoding: str | None = None) -> tuple[str | None, list[Diagnostic]]:
    """The text of an export file, line ends normalised, or None; and the diagnostics."""
    src, diags = read_source(path, encoding)
    return (src.text if src is not None else None), diags
