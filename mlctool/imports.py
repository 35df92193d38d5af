"""Vendor exports -> plain IL (`mlc import`): GX Works2 and GX Developer instruction-list CSV,
WPLSoft CSV, plain IL text; and GX Works2 projects (.gxw, decoded by mlctool/gxw.py) and GX
Developer program bodies (.wpg, mlctool/wpg.py), whose instructions take the path of the CSV
rows (import_project, import_wpg).

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
from mlctool.limits import is_decimal
from mlctool.syntax.operands import OperandSyntaxError, format_operand, parse_operand
from mlctool.syntax.source import decode, read_source
from mlctool.targetapi.model import Target

FORMATS = ("gxworks2", "gxdeveloper", "wplsoft", "delta", "il")
# column -> the header texts naming it, lower case: English (GX Works2 "Step Number", GX
# Developer "Step No."), Japanese (GX Works2 / GX Developer, "PC情報:" title row), Simplified
# Chinese (GX Works2, "PLC信息:" title row) and Traditional Chinese. DECISION: the
# Traditional Chinese words are the Simplified ones in traditional characters (步號, 行間聲明,
# I/O(軟元件), 註解) — no export of that language version was found to confirm them.
_HEADER = {
    "step": ("step number", "step no.", "ステップ番号", "步号", "步號"),
    "statement": ("line statement", "行間ステートメント", "行间声明", "行間聲明"),
    "instruction": ("instruction", "命令", "指令"),
    "device": ("i/o(device)", "i/o(デバイス)", "i/oデバイス", "i/o(软元件)", "i/o(軟元件)", "device"),
    "note": ("note", "ノート", "注解", "註解"),
}
# the headerless CSV GX's "read from CSV" accepts: the columns in the export's order
_HEADERLESS = {"step": 0, "statement": 1, "instruction": 2, "device": 3, "note": 6}
_DELTA_HEADER = ("step", "instruction", "operand1")  # Step,Instruction,Operand1,Operand2,Operand3
_STEP6 = re.compile(r"\s*[0-9]{6}\s*[,\t]")
_LABEL = re.compile(r"[PI][0-9]+", re.IGNORECASE)
_FX_POINTER = re.compile(r"I([0-9]{1,3})", re.IGNORECASE)
# an X/Y written with a number: in an FX export octal, so X58 and X5B are no device (E913)
_IO_NUMBER = re.compile(r"[XY][0-9][0-9A-F]*", re.IGNORECASE)
# the family of each export's special devices (targets/<name>/specials.toml)
SOURCE_FAMILY = {"gxworks2": "fx", "gxdeveloper": "fx", "wplsoft": "dvp", "delta": "dvp", "gxw": "fx", "wpg": "fx"}


# the CPU row of a GX export: GX Works2 `"PLC Information:"<TAB>"FXCPU FX3U/FX3UC"` (Japanese
# `PC情報:`, Simplified Chinese `PLC信息:`, Traditional `PLC資訊:`), GX Developer `"PLC Type:FX3U(C)"`
_CPU_ROW = re.compile(r"(plc information|plc type|pc情報|pcタイプ|plc信息|plc資訊|plc类型|plc類型)\s*[:：]\s*(.*)",
                      re.IGNORECASE)
# FX0-FX3 (FX0S, FX1N, FX2N(C), FX3G, FX3U/FX3UC, FX3S ...): the dialect the VS follows
_FX_CPU = re.compile(r"FX\s*(0|1|2|3)", re.IGNORECASE)
# the MELSEC series whose programs the VS cannot run: hexadecimal X/Y, SM/SD, other steps
_OTHER_CPU = re.compile(r"\b(L\s*CPU|Q\s*CPU|QnA|QCPU|A\s*CPU|R\s*CPU|LCPU|Q[0-9]{2}|L[0-9]{2}|R[0-9]{2}|"
                        r"A[0-9][A-Z]|iQ-R)", re.IGNORECASE)


def export_cpu(text: str) -> str | None:
    """The CPU an export names in its first rows (GX Works2 / GX Developer), None if none."""
    for line in text.splitlines()[:4]:
        cells = [c.strip().strip('"').strip() for c in re.split(r"[\t,]", line)]
        for k, cell in enumerate(cells):
            m = _CPU_ROW.fullmatch(cell)
            if m:
                named = m[2].strip() or next((c for c in cells[k + 1:] if c), "")
                return named or None
    return None


def cpu_problem(path: str, cpu: str, target: Target) -> Diagnostic | None:
    """E910 for a CPU whose programs the target cannot run, W911 for one the importer does not
    know as an FX0-FX3; None for an FX0-FX3 or a model of the target itself (VS3)."""
    if _FX_CPU.search(cpu) or any(re.search(rf"\b{re.escape(m)}\b", cpu, re.IGNORECASE) for m in target.models):
        return None
    if _OTHER_CPU.search(cpu):
        return diag(path, Span.at(2), "E910", f"the export is from a {cpu}, not an FX CPU: its X/Y are hexadecimal "
                    f"(X62 is input 0x62, not the octal X62 of target {target.name}), its specials SM/SD, its "
                    "interrupts IMASK/IC*, and its steps count line statements and notes",
                    f"rewrite the program for target {target.name} (or an FX CPU, then export that): its X/Y "
                    "numbers, SM/SD specials and interrupt instructions have no one-to-one FX counterpart, so "
                    "nothing is converted (docs/formats.md, CPU and dialect)")
    return diag(path, Span.at(2), "W911", f"the export names CPU {cpu!r}, not one of FX0-FX3 whose dialect "
                f"target {target.name} follows: its rows are read as FX ones",
                f"check the result with `mlc check --target {target.name}`; an FX5 (iQ-F) program uses SM/SD "
                "specials the target does not have (docs/formats.md, CPU and dialect)")


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


def _cells(line: str) -> list[str]:
    return [c.strip().strip('"').strip().lower() for c in re.split(r"[\t,]", line)]


def detect(text: str) -> str:
    head = text.splitlines()[:12]
    for line in head:
        cells = _cells(line)
        if any(c in _HEADER["instruction"] for c in cells) and any(c in _HEADER["device"][:-1] for c in cells):
            return "gxworks2" if "\t" in line else "gxdeveloper"
        if tuple(cells[:3]) == _DELTA_HEADER:
            return "delta"
    if any(_STEP6.match(line) for line in head):
        return "wplsoft"
    if _delta_rows(head):
        return "delta"
    if _headerless(head):
        return "gxworks2" if any("\t" in line for line in head) else "gxdeveloper"
    return "il"


_MNEMONIC = re.compile(r"[a-z][a-z0-9<>=]*")


def _delta_rows(head: list[str]) -> bool:
    """Delta rows without the `Step,Instruction,...` header: `0,LD,X0,,` (a step number, the
    mnemonic in the second cell) or `LD,X0` (comma-separated IL, the mnemonic first), at least
    two rows and every instruction row so. GX's headerless rows have the mnemonic in the third
    cell, the second (the line statement) empty."""
    rows = [_cells(line) for line in head if line.strip() and not line.lstrip().startswith((";", "//"))]
    if len(rows) < 2 or any("\t" in line for line in head):
        return False

    def delta(r: list[str]) -> bool:
        if len(r) < 2 and not (r and _MNEMONIC.fullmatch(r[0]) and r[0] in ("end", "fend", "mpp", "mps", "mrd",
                                                                            "anb", "orb", "ret", "nop")):
            return False
        first = r[1:] if r[0].isdigit() else r
        return bool(first) and bool(_MNEMONIC.fullmatch(first[0])) and not any(" " in c for c in first)

    return all(delta(r) for r in rows)


def _headerless(head: list[str]) -> bool:
    """GX rows without the title and header rows: `"0","","LD","X000","","",""` — at least
    two rows of 4+ cells with a step number or nothing first, a mnemonic-like third cell."""
    rows = [_cells(line) for line in head if line.strip()]
    good = [r for r in rows if len(r) >= 4 and re.fullmatch(r"[0-9]*", r[0])
            and (re.fullmatch(r"[a-z][a-z0-9<>=]*", r[2]) or not r[2] and any(r[1:]))]
    if not any(r[2] for r in good):
        return False  # statement and note rows alone: no instruction
    return len(good) >= 2 and len(good) >= len(rows) - 1


class _Writer:
    """Collects IL lines; rewrites mnemonics and operands as the target writes them."""

    def __init__(self, path: str, target: Target, family: str = "", comments: dict[str, str] | None = None,
                 places: dict[int, str] | None = None):
        from mlctool.targetapi.specials import families

        self.path, self.t = path, target
        # row -> where it is in a binary file (a .gxw's POU and offset); there the row is the
        # instruction's number, the line of its diagnostics
        self.places = places
        self.family = families(target.name).get(family)  # the source's special devices
        self.comments = dict(comments or {})  # device as the target writes it -> its comment
        if self.family is not None:  # a comment on M8000 is one on the M9000 it becomes
            for device in list(self.comments):
                m = re.fullmatch(r"([A-Z]+)([0-9]+)", device)
                special = self.family.mapping.get((m[1], int(m[2]))) if m else None
                if special is not None:
                    self.comments[special.device] = self.comments.pop(device)
        self.lines: list[str] = []
        self.diags: list[Diagnostic] = []
        self.pending: list[str] | None = None  # the instruction whose operands may continue
        self.pending_step: tuple[int, int, str] | None = None  # (row, export step, row as written) of it
        self.kinds: list[str] = []  # of each diagnostic: rows of one kind are reported once
        self.referenced: set[str] = set()  # operands written, upper case: the labels jumped to
        self.maybe_labels: list[tuple[int, str, int]] = []  # (line index, name, row)
        self.steps: dict[int, tuple[int, int, str]] = {}  # IL line index -> (row, the export's step, its words)
        self.mapped: dict[str, dict[str, str]] = {}  # device kind -> {source: target (function)}
        self.unmapped: dict[str, list[int]] = {}  # source device -> rows
        self.renamed: dict[str, str] = {}  # the family's mnemonic -> the target's (DRVI -> DRVR)
        self.absent: dict[str, tuple[str, list[int]]] = {}  # source device the target lacks -> (area, rows)

    def at(self, row: int) -> str:
        """Where a row is, as messages say it: `row 5`, or a .gxw's `MAIN.Program.pou offset 0x5A`."""
        return f"row {row}" if self.places is None else self.places.get(row, f"instruction {row}")

    def error(self, row: int, kind: str, message: str, *notes: str) -> None:
        self.diags.append(diag(self.path, Span.at(row), "E907", message, *notes))
        self.kinds.append(kind)

    def warn(self, row: int, kind: str, code: str, message: str, *notes: str) -> None:
        self.diags.append(diag(self.path, Span.at(row), code, message, *notes))
        self.kinds.append(kind)

    def flush(self) -> None:
        if self.pending is not None:
            self.settle()
            if self.pending_step is not None:
                self.steps[len(self.lines)] = self.pending_step
            said = [f"{w} {self.comments[w]}" for w in self.pending[1:] if w in self.comments]
            if said:
                at = next((k for k, w in enumerate(self.pending) if w.startswith(";")), None)
                if at is None:
                    self.pending.append("; " + "; ".join(said))
                else:
                    self.pending[at] += "; " + "; ".join(said)
            self.lines.append(" ".join(self.pending))
            self.pending = self.pending_step = None

    def comment(self, text: str) -> None:
        self.flush()
        self.lines.append(f"; {text}")

    def label(self, text: str, row: int = 0, step: str = "") -> None:
        """A label row. A bare name (no colon, no P/I number) is a label only if the program
        jumps to it; otherwise it is an unknown instruction without operands (`NOPLF`),
        decided in finish(). An FX interrupt pointer (I001) gets the target's name (IX0P)."""
        self.flush()
        if row and not text.endswith((":", "：")) and not _LABEL.fullmatch(text):
            self.maybe_labels.append((len(self.lines), text, row))
        name = text.rstrip(":：").upper()
        if _FX_POINTER.fullmatch(name):
            name = self.pointer(name, row)
        if self.step_number(step, row) is not None:
            self.steps[len(self.lines)] = (row, int(step), text)
        self.lines.append(f"{name}:")

    def step_number(self, step: str, row: int) -> int | None:
        """The step field of a row: empty, or ASCII digits (mlctool/limits.py); anything else
        ("0²", "٣") is E907 at the row."""
        if not step:
            return None
        if not is_decimal(step):
            self.error(row, f"step {step}", f"row {row}: step number {step!r} is not a number (ASCII digits)")
            return None
        return int(step)

    def pointer(self, text: str, row: int) -> str:
        """FX interrupt pointer I001 / I610 / I010 (I0 = I000) -> the target's name (IX0P,
        ITA10, IHC0) by the I number the target keeps (target.toml [interrupts])."""
        from mlctool.check.interrupts import families, pointer_numbered

        if not families(self.t):
            return text
        p = pointer_numbered(int(text[1:]), self.t)
        if p is None:
            self.error(row, f"pointer {text}", f"{self.at(row)}: interrupt pointer {text} has no counterpart on target "
                       f"{self.t.name}", "the target's pointers are IX0P-IX7P/IX0F-IX7F (FX I001-I701/I000-I700), "
                       "ITA01-ITC99 (I601-I899), IHC0-IHC7 (I010-I080), IHHC1/IHHC2; rewrite the routine "
                       "for one of them (docs/vs.md, Interrupts)")
            return text
        return p.name

    def finish(self) -> None:
        self.flush()
        for index, name, row in self.maybe_labels:
            if name.upper() not in self.referenced:
                self.lines[index] = name
                self.unknown(name.upper(), row)
        if self.mapped:
            for kind, pairs in sorted(self.mapped.items()):
                shown = ", ".join(f"{a} -> {b}" for a, b in sorted(pairs.items(), key=lambda x: _natural(x[0])))
                self.diags.append(diag(self.path, Span.at(1), "N910", f"{self.family.title} special "
                                       f"{'relays' if kind == 'M' else 'registers'} mapped to target {self.t.name}'s by "
                                       f"function: {shown}", "targets/" + self.t.name + "/specials.toml cites the "
                                       "manual's row of each"))
                self.kinds.append(f"mapped {kind}")
        if self.renamed:
            shown = ", ".join(f"{a} -> {b}" for a, b in sorted(self.renamed.items()))
            self.diags.append(diag(self.path, Span.at(1), "N911", f"{self.family.title} instructions written as "
                                   f"target {self.t.name}'s of the same function and operands: {shown}",
                                   f"targets/{self.t.name}/specials.toml cites the manual's section of each"))
            self.kinds.append("renamed")
        for device, (area, rows) in self.absent.items():
            self.diags.append(diag(self.path, Span.at(rows[0]), "E911", f"{self.at(rows[0])}: {device} is a "
                                   f"{self.family.title} special device that target {self.t.name} does not have "
                                   f"({area}); `mlc check` refuses it too (E205)", *_absent_notes(device, self.t),
                                   *((f"also at {', '.join(map(self.at, rows[1:11]))}",) if rows[1:] else ())))
            self.kinds.append(f"absent {device}")
        for device, rows in self.unmapped.items():
            self.warn(rows[0], f"unmapped {device}", "W910", f"{self.at(rows[0])}: {device} is a {self.family.title} special "
                      f"device with no counterpart known on target {self.t.name}; kept as {device}, an ordinary "
                      "device there", *((f"also at {', '.join(map(self.at, rows[1:11]))}",) if rows[1:] else ()))

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

    def instruction(self, mnemonic: str, operands: list[str], row: int, note: str = "", step: str = "") -> None:
        self.flush()
        self.referenced.update(o.upper() for o in operands)
        self.pending = [self.mnemonic(mnemonic, row), *(self.operand(o, row) for o in operands if o)]
        if self.step_number(step, row) is not None:
            self.pending_step = (row, int(step), " ".join([mnemonic, *operands]))
        if note:
            self.pending.append(f"; {note}")

    def more(self, operand: str, row: int) -> None:
        if self.pending is None:
            self.error(row, "orphan", f"{self.at(row)}: operand {operand!r} without an instruction")
            return
        self.referenced.add(operand.upper())
        if self.pending_step is not None:
            row0, step, words = self.pending_step
            self.pending_step = (row0, step, f"{words} {operand}")
        at = next((k for k, w in enumerate(self.pending) if w.startswith(";")), len(self.pending))
        self.pending.insert(at, self.operand(operand, row))

    def settle(self) -> None:
        """Forms of the source family the target writes otherwise, once all operands are in:
        FX `MC N0 M100` where the target's MC takes the nesting level only (VS 3-6): the relay
        is dropped, said in a comment."""
        p = self.pending
        spec = self.t.instructions.get(p[0]) if p else None
        if spec is not None and spec.op == "mc" and len(spec.operands) == 1 and len(p) >= 3 \
                and not p[2].startswith(";"):
            dropped = p.pop(2)
            p.append(f"; the export's MC {p[1]} {dropped}: the {self.t.name} MC has no relay operand "
                     f"({spec.section})")

    def mnemonic(self, text: str, row: int) -> str:
        m = text.upper()
        if m in self.t.instructions or m in self.t.variants or m in self.t.unavailable:
            return m
        # the family's own spellings (Delta DVP's TMR T0 K50, CNT C0 K10, DCNT C200 K10 are the
        # target's OUT T0 K50 / OUT C0 K10 / OUT C200 K10: specials.toml `mnemonics`)
        if self.family is not None and m in self.family.mnemonics:
            self.renamed[m] = self.family.mnemonics[m]
            return self.family.mnemonics[m]
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
        self.error(row, f"unknown {mnemonic}", f"{self.at(row)}: unknown instruction {mnemonic!r} for target "
                   f"{self.t.name}{suggestion}", *notes)

    def operand(self, text: str, row: int = 0) -> str:
        # GX Works2 writes a unit's buffer memory U1\G3; the VS writes U1G3 (2-9-2)
        text = re.sub(r"^(U[0-9]+)\\(G)", r"\1\2", text, flags=re.IGNORECASE)
        if _FX_POINTER.fullmatch(text) and row:
            return self.pointer(text.upper(), row)  # DHSCS K100 C235 I010
        try:
            op = parse_operand(text, self.t.operand_syntax)
        except OperandSyntaxError as e:
            if _IO_NUMBER.fullmatch(text):  # the rule of the device-comment rows too (read_comments)
                self.diags.append(diag(self.path, Span.at(row), "E913", f"{self.at(row)}: {_octal_reason(text, e)}",
                                       _OCTAL_NOTE))
                self.kinds.append(f"octal {text.upper()}")
            return text  # a symbol, a label name, or an error `mlc check` reports
        if self.family is not None and not op.is_const and not op.is_group and not op.index \
                and self.family.is_special(op.kind, op.number):
            source = f"{op.kind}{op.number}"
            special = self.family.mapping.get((op.kind, op.number))
            if special is None:
                dev = self.t.devices.get(op.kind)
                gap = next((a for a in dev.areas if a.write == "absent" and a.lo <= op.number <= a.hi),
                           None) if dev is not None else None
                if gap is not None:  # `mlc check` refuses it (E205): so does the import
                    self.absent.setdefault(source, (f"{dev.name_of(gap.lo)}-{dev.name_of(gap.hi)}: {gap.name}",
                                                    []))[1].append(row)
                else:
                    self.unmapped.setdefault(source, []).append(row)
                return format_operand(op)
            self.mapped.setdefault(op.kind, {})[source] = f"{special.device} ({special.function})"
            mapped = parse_operand(special.device, self.t.operand_syntax)
            if op.is_bit_of_word:
                return f"{special.device}.{op.bit:X}"
            return format_operand(mapped)
        return format_operand(op) if not op.is_const or op.kind in ("K", "H") else text


_OCTAL_NOTE = ("FX numbers X and Y in octal; a hexadecimal X/Y (X5B) comes from a Q/L CPU's export, "
               "whose program the target cannot run (E910)")


def _octal_reason(text: str, e: OperandSyntaxError) -> str:
    reason = str(e)
    if "octal" not in reason:
        reason = f"{text!r}: {text[0].upper()} devices are numbered in octal; {text!r} is no octal number"
    return reason


def _absent_notes(device: str, target: Target) -> tuple[str, ...]:
    """What to do with an FX special the target has no device for."""
    kind, number = _natural(device)
    notes = ["FX3U/FX3G number the set-up relays of their extended functions M8192-M8511; rewrite "
             f"that part of the program for target {target.name} (its specials: manual 2-14), or delete it"]
    if kind == "M" and 8400 <= number <= 8439:
        notes.insert(0, "M8400-M8439 set up the FX3U's serial ports (M8411: the Modbus-slave set-up rung "
                     "`LD M8411 / MOV H.. D8400 ...`); on the VS a port's application, MODBUS Slave among "
                     "them, and its parameters are set in Ladder Master S, not by the program (VS manual "
                     "7-3-1, 7-3-5): delete the rung and set the port there")
    return tuple(notes)


def _natural(device: str) -> tuple[str, int]:
    m = re.fullmatch(r"([A-Z]+)([0-9]+)", device)
    return (m[1], int(m[2])) if m else (device, 0)


def _gx(w: _Writer, text: str, delimiter: str) -> None:
    rows = _rows(text, delimiter)
    cols: dict[str, int] = {}
    headerless = _headerless(text.splitlines()[:12]) and detect_header(rows) is None
    if headerless:
        cols = dict(_HEADERLESS)
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
        step = cell("step")
        if statement:
            w.comment(statement)
        if instr:
            if not device and w.is_label(instr):
                w.label(instr, k, step)
            else:
                w.instruction(instr, device.split(), k, note, step)
        elif device:
            w.more(device, k)
        elif note:
            w.comment(note)
    if not cols:
        w.error(1, "header", "no header row naming the Instruction and I/O(Device) columns")


def detect_header(rows: list[list[str]]) -> int | None:
    """The index of the header row among the first 12, None when there is none."""
    for k, row in enumerate(rows[:12]):
        low = [c.lower() for c in row]
        if any(c in _HEADER["instruction"] for c in low) and any(c in _HEADER["device"] for c in low):
            return k
    return None


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
        _delta_row(w, k, cells[1:])


def _delta_row(w: _Writer, k: int, rest: list[str]) -> None:
    if not rest:
        return
    first = rest[0].split()
    words = first + rest[1:]
    if len(words) == 1 and w.is_label(words[0]):
        w.label(words[0], k)
    else:
        w.instruction(words[0], words[1:], k)


def _delta(w: _Writer, text: str) -> None:
    """Delta's `Step,Instruction,Operand1,Operand2,Operand3` CSV: a header row, then one row per
    instruction with its operands in their own cells; `;` rows are comments. The header row
    is optional, and so is the step number (`0,LD,X0,,` and `LD,X0` rows)."""
    for k, row in enumerate(_rows(text, ","), 1):
        cells = [c for c in row if c != ""]
        if not cells:
            continue
        if k == 1 and tuple(c.lower() for c in row[:3]) == _DELTA_HEADER:
            continue
        if cells[0].startswith((";", "//")):
            w.comment(",".join(row).lstrip(";/ "))
            continue
        _delta_row(w, k, cells[1:] if cells[0].isdigit() else cells)


def import_text(path: str, text: str, target: Target, fmt: str | None = None,
                comments: dict[str, str] | None = None) -> tuple[str | None, str, list[Diagnostic]]:
    """-> (IL text or None on errors, the format read, diagnostics)."""
    if fmt is None:
        fmt = detect(text)
        if fmt == "il" and not looks_like_il(path, text):
            return None, "", [diag(path, Span.at(1), "E909", "not recognised as a GX Works2, GX Developer, "
                                   "WPLSoft or Delta export, nor as instruction-list text",
                                   "name the format with --from if it is one (docs/vs.md, Imports)")]
    if fmt == "il":
        return (text if text.endswith("\n") else text + "\n"), fmt, []
    cpu = export_cpu(text) if fmt in ("gxworks2", "gxdeveloper") else None
    said = cpu_problem(path, cpu, target) if cpu else None
    if said is not None and said.severity == "error":
        return None, fmt, [said]
    w = _Writer(path, target, SOURCE_FAMILY.get(fmt, ""), comments)
    if said is not None:
        w.diags.append(said)
        w.kinds.append("cpu")
    try:
        if fmt in ("gxworks2", "gxdeveloper"):
            _gx(w, text, "\t" if fmt == "gxworks2" or "\t" in text.split("\n", 3)[-1] else ",")
        elif fmt == "delta":
            _delta(w, text)
        else:
            _wplsoft(w, text)
    except _BadRow as e:
        return None, fmt, [diag(path, Span.at(e.line), "E907", e.message)]
    w.finish()
    return _assemble(path, fmt, w, target, _step_counts(w.steps) if SOURCE_FAMILY.get(fmt) == "fx" else {})


def _assemble(path: str, fmt: str, w: _Writer, target: Target, counts: dict[int, tuple[int, int, str, str]]
              ) -> tuple[str | None, str, list[Diagnostic]]:
    """The IL of what the writer read (finished): the dialect, the device comments, the lines;
    W107 where the source's own step count of an instruction (`counts`: IL line index -> (row,
    count, the row as written, the source's word for it)) is not the target's."""
    if not any(line and not line.startswith(";") and not line.endswith(":") for line in w.lines) \
            and not any(d.severity == "error" for d in w.diags):
        return None, fmt, [diag(path, Span.at(1), "E912", f"no instruction read from the file as a {fmt} export",
                                "name the format with --from if it is another (docs/vs.md, Imports)")]
    head = [f"; {dev}  {text}" for dev, text in sorted(w.comments.items(), key=lambda x: _natural(x[0]))]
    if w.family is not None:  # the dialect of origin, for the checker's W217 (docs/formats.md)
        head.insert(0, f".dialect {w.family.name}")
    lines = head + w.lines
    out = "\n".join(lines) + "\n"
    if counts and not any(d.severity == "error" for d in w.diags):
        for d, kind in _count_check(w, out, target, {k + len(head): v for k, v in counts.items()}):
            w.diags.append(d)
            w.kinds.append(kind)
    diags = _once_per_kind(w.diags, w.kinds, "row" if w.places is None else "instruction")
    if any(d.severity == "error" for d in diags):
        return None, fmt, diags
    return out, fmt, diags


def _step_counts(steps: dict[int, tuple[int, int, str]]) -> dict[int, tuple[int, int, str, str]]:
    """An export's step column -> each row's own count: the difference of consecutive step
    numbers (the last row, END, has no successor and is not counted)."""
    rows = sorted(steps.items())
    return {index: (row, next_step - step, words, f"the export (step {step} to {next_step})")
            for (index, (row, step, words)), (_, (_, next_step, _)) in zip(rows, rows[1:], strict=False)}


def _count_check(w: _Writer, text: str, target: Target, counts: dict[int, tuple[int, int, str, str]]
                 ) -> list[tuple[Diagnostic, str]]:
    """W107 at each row whose instruction the source counts in other steps than the target's
    step convention does. The message quotes the row as the source writes it (M8000, not the
    M9000 it became; every operand)."""
    by_line = {ins.line: ins for ins in _resolved(w.path, text, target).instrs}
    out = []
    for index, (row, count, words, source) in sorted(counts.items()):
        ins = by_line.get(index + 1)
        if ins is None or count == ins.steps:
            continue
        kind = f"steps {ins.spec.mnemonic} {ins.operands[0].kind if ins.operands else ''}"
        out.append((diag(w.path, Span.at(row), "W107", f"{w.at(row)}: {words} is {count} steps in {source}, "
                         f"{ins.steps} by target {target.name}'s step convention", "the source's step count is the "
                         "vendor tool's; the target's addresses follow its own convention (docs/vs.md, Steps)"), kind))
    return out


def _resolved(path: str, text: str, target: Target):
    """The IL's instructions with their steps and addresses by the target's step convention."""
    # the resolver alone (addresses), not mlctool.check: the checker imports this module
    from mlctool.check.labels import assign_named_labels, restrict_names
    from mlctool.check.resolve import resolve
    from mlctool.syntax.parser import parse
    from mlctool.syntax.source import SourceText

    parsed = restrict_names(parse(SourceText(path, text)), target)
    names, _ = assign_named_labels([parsed], target)
    module, _ = resolve(parsed, target, {}, names.get(parsed.path))
    return module


def _once_per_kind(diags: list[Diagnostic], kinds: list[str], unit: str = "row") -> list[Diagnostic]:
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
            d = dataclasses.replace(d, notes=d.notes + (f"and {len(more)} more {unit}{'s' if len(more) > 1 else ''} "
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


# the device-comment CSV's header words (GX Works2 English / Japanese / Chinese, GX Developer)
_COMMENT_HEADER = {"device": ("device name", "device", "デバイス名", "软元件名", "軟元件名"),
                   "comment": ("comment", "コメント", "注释", "註釋", "註解")}


def read_comments(path: str, target: Target, encoding: str | None = None
                  ) -> tuple[dict[str, str] | None, list[Diagnostic]]:
    """Device comments -> {device as the target writes it: comment}, from a GX Works2 / GX
    Developer device-comment CSV (`"COMMENT"` title row, a header row `"Device Name","Comment"`
    in the tool's language, then one device a row; UTF-16 tab or comma separated) or a GX
    Developer comment file (`COMMENT.wcd`, a program's `MAIN.wcd`: mlctool/wcd.py), told apart
    by their content."""
    from mlctool.fileio import read_input
    from mlctool.syntax.source import MAX_BYTES
    from mlctool.wcd import is_wcd

    try:
        data = read_input(path, MAX_BYTES + 1)
    except OSError as e:
        return None, [diag(path, Span.at(1), "E100", f"cannot read: {e.strerror or e}")]
    if not data or is_wcd(data):  # nothing is no CSV either: the .wcd reader says "empty file"
        return _wcd_comments(path, data, target, encoding)
    src, diags = decode(path, data, encoding)
    if src is None:
        return None, diags
    text = src.text
    delimiter = "\t" if "\t" in text else ","
    cols: tuple[int, int] | None = None
    out: dict[str, str] = {}
    try:
        rows = _rows(text, delimiter)
    except _BadRow as e:
        return None, [diag(path, Span.at(e.line), "E907", e.message)]
    for k, row in enumerate(rows, 1):
        low = [c.lower() for c in row]
        if cols is None:
            dev = next((low.index(t) for t in _COMMENT_HEADER["device"] if t in low), None)
            com = next((low.index(t) for t in _COMMENT_HEADER["comment"] if t in low), None)
            if dev is not None and com is not None:
                cols = (dev, com)
            continue
        if len(row) <= max(cols) or not row[cols[0]] or not row[cols[1]]:
            continue
        try:
            op = parse_operand(row[cols[0]], target.operand_syntax)
        except OperandSyntaxError as e:
            if _IO_NUMBER.fullmatch(row[cols[0]]):  # one rule with the program's rows (_Writer.operand)
                return None, [diag(path, Span.at(k), "E913", f"row {k}: {_octal_reason(row[cols[0]], e)}",
                                   _OCTAL_NOTE)]
            return None, [diag(path, Span.at(k), "E907", f"row {k}: {row[cols[0]]!r} is no device of target "
                               f"{target.name}")]
        out[format_operand(op)] = " ".join(row[cols[1]].split())
    if cols is None:
        return None, [diag(path, Span.at(1), "E909", "not recognised as a device-comment CSV: no header row "
                           "naming the Device Name and Comment columns")]
    return out, []


def _wcd_comments(path: str, data: bytes, target: Target, encoding: str | None
                  ) -> tuple[dict[str, str] | None, list[Diagnostic]]:
    """A GX Developer comment file's comments, each device (as FX writes it) through the
    target's operand syntax as a CSV row's. DECISION: a device's text is its comment; an alias
    alone is the text; both are `alias: comment`."""
    from mlctool.wcd import WcdError, read

    try:
        found = read(data, encoding)
    except WcdError as e:
        return None, [diag(path, Span.at(1), e.code, str(e), *e.notes)]
    out: dict[str, str] = {}
    for c in found.comments:  # X/Y are octal already: the target's syntax takes every one
        text = f"{c.alias}: {c.text}" if c.alias and c.text else c.alias or c.text
        out[format_operand(parse_operand(c.device, target.operand_syntax))] = " ".join(text.split())
    return out, []


# The target of each export's dialect, when the command line names none: GX Works2 and GX
# Developer export Mitsubishi FX programs, WPLSoft Delta DVP ones, both FX-style IL, which the
# Vigor VS target follows (docs/vs.md).
DIALECT_TARGET = {"gxworks2": "vs", "gxdeveloper": "vs", "wplsoft": "vs", "delta": "vs", "gxw": "vs", "wpg": "vs"}


# Vendor project files (binary) not read: what each is and what the public record holds about
# it (docs/formats.md). Their program bodies are not publicly described well enough to decode
# reliably, and a guess is never written (E914 says what to do instead). A GX Works2 `.gxw`,
# and any other compound (OLE2) file, goes to the project reader (import_project); a GX
# Developer `.wpg` to import_wpg; a FATEK WinProladder `.pdw` / `.ldr` to import_winproladder.
PROJECT_FILES = {
    ".gx3": ("GX Works3 project", "undocumented"),
    ".dvp": ("WPLSoft project", "undocumented"),
    ".isp": ("ISPSoft project", "undocumented"),
}


def project_file(path: str, head: bytes) -> Diagnostic | None:
    """E914 for a vendor's binary project file mlctool does not read (by its name), else None."""
    import os

    what = PROJECT_FILES.get(os.path.splitext(path)[1].lower())
    if what is None:
        return None
    name, facts = what
    return diag(path, Span.at(1), "E914", f"offset 0: a {name}: starting {head[:8].hex(' ') or '(empty)'}; "
                f"mlctool reads no such file ({facts} in public sources: docs/formats.md)",
                "export the program as text from the vendor's tool and import that: its instruction-list or CSV "
                "export (WPLSoft and ISPSoft: the instruction list as text)")


def is_gx_project(path: str, head: bytes) -> bool:
    """A GX Works2 project to read with import_project: named .gxw, or a compound file."""
    import os

    from mlctool.gxw import is_compound_file

    return os.path.splitext(path)[1].lower() == ".gxw" or is_compound_file(head)


def import_project(path: str, data: bytes, target: Target, comments: dict[str, str] | None = None,
                   program: str | None = None) -> tuple[str | None, str, list[Diagnostic]]:
    """A GX Works2 project (.gxw) -> (IL or None, "gxw", diagnostics): its program POU decoded
    (mlctool/gxw.py), then the path of the CSV imports (the FX dialect's specials and
    spellings, the device comments of --comments, `.dialect fx`). Each application
    instruction's stored width is its step count in GX Works2; W107 where the target counts
    otherwise. The diagnostics of a decoded instruction are at the line of its number in the
    POU and name its offset."""
    from mlctool.gxw import GxwError, read_program

    try:
        prog = read_program(data, program)
    except GxwError as e:
        return None, "gxw", [diag(path, Span.at(1), e.code, e.message, *e.notes)]
    places = {k: f"{prog.name} offset 0x{ins.offset:X}" for k, ins in enumerate(prog.instructions, 1)}
    w = _Writer(path, target, "fx", comments, places)
    for code, message, notes in prog.warnings:
        if code == "W912" and comments is not None:
            continue  # the comments came from --comments
        w.warn(1, code, code, message, *notes)
    counts = _decoded(w, prog.instructions, "the project (its stored width)")
    w.finish()
    return _assemble(path, "gxw", w, target, counts)


def _decoded(w: _Writer, instructions, source: str) -> dict[int, tuple[int, int, str, str]]:
    """A decoded program (mlctool/gxw.py) into the writer: each instruction its IL line, a label
    its label line, a line statement a comment line where it stands, a note a comment on the
    instruction before it. -> the stored step counts (application and 2-byte headers) by IL line
    index, for W107."""
    counts = {}
    for k, ins in enumerate(instructions, 1):
        if ins.text is not None:
            if ins.note and w.pending is not None:
                w.pending.append(f"; {ins.text}")  # on the instruction's line, as an export's note cell
            else:
                w.comment(ins.text)
            continue
        if ins.label:
            w.label(ins.operands[0] + ":", k)
            continue
        w.instruction(ins.mnemonic, list(ins.operands), k)
        if ins.width is not None:  # its line is the next the writer appends
            counts[len(w.lines)] = (k, ins.width, " ".join([ins.mnemonic, *ins.operands]), source)
    return counts


def is_wpg(path: str) -> bool:
    """A GX Developer program body to read with import_wpg: by its name (its signature is 4 bytes)."""
    import os

    return os.path.splitext(path)[1].lower() == ".wpg"


# A GX Developer project folder as every public one is laid out (docs/formats.md, .wpg): the
# project file Gppw.gpj, the program bodies in Resource/POU/Body (or an older project's
# Pou/Body; GX Developer writes POU or Pou), the device comments in Resource/Others/COMMENT.wcd
# (Others/COMMENT.wcd). Names are matched without case, as Windows, which wrote them, does.
GX_DEVELOPER_PROJECT = "gppw.gpj"
_BODY_FOLDERS = (("resource", "pou", "body"), ("pou", "body"))
_COMMENT_FILES = (("resource", "others", "comment.wcd"), ("others", "comment.wcd"))


def is_gx_developer_project(path: str) -> bool:
    """A folder holding a GX Developer project file (Gppw.gpj)."""
    import os

    return os.path.isdir(path) and _child(path, GX_DEVELOPER_PROJECT) is not None


def gx_developer_project(folder: str, program: str | None = None
                         ) -> tuple[str | None, str | None, list[Diagnostic]]:
    """A GX Developer project folder -> (its program body, its device comment file or None,
    diagnostics): the body named by `program`, else the only one; E934 where there is none or
    several and no `program` (the order GX Developer runs them in is in the project's
    parameters, which are not read)."""
    import os

    bodies: dict[str, str] = {}
    for parts in _BODY_FOLDERS:
        where = _walk(folder, parts)
        if where is not None:
            for name in sorted(os.listdir(where)):
                if name.lower().endswith(".wpg") and os.path.isfile(os.path.join(where, name)):
                    bodies.setdefault(name[:-4].upper(), os.path.join(where, name))
            break
    comments = next((c for c in (_walk(folder, parts) for parts in _COMMENT_FILES)
                     if c is not None and os.path.isfile(c)), None)
    listed = ", ".join(bodies) or "none"
    at = Span.at(1)
    if program is not None:
        body = bodies.get(program.upper().removesuffix(".WPG"))
        if body is None:
            return None, None, [diag(folder, at, "E934", f"GX Developer project: no program body {program!r} "
                                     f"(the project's: {listed})")]
        return body, comments, []
    if len(bodies) == 1:
        return next(iter(bodies.values())), comments, []
    if not bodies:
        return None, None, [diag(folder, at, "E934", "GX Developer project: no program body (*.wpg) in "
                                 "Resource/POU/Body or Pou/Body")]
    return None, None, [diag(folder, at, "E934", f"GX Developer project: {len(bodies)} program bodies ({listed}); "
                             "the order in which the CPU runs them is in the project's parameters, which are "
                             "not read", "import one with --program NAME (each gives its own IL file)")]


def _child(folder: str, name: str) -> str | None:
    """The entry of `folder` named `name` without regard to case (None if there is none)."""
    import os

    try:
        entries = sorted(os.listdir(folder))
    except OSError:
        return None
    return next((os.path.join(folder, e) for e in entries if e.lower() == name), None)


def _walk(folder: str, parts: tuple[str, ...]) -> str | None:
    for part in parts:
        folder = _child(folder, part)
        if folder is None:
            return None
    return folder


def import_wpg(path: str, data: bytes, target: Target, comments: dict[str, str] | None = None
               ) -> tuple[str | None, str, list[Diagnostic]]:
    """A GX Developer program body (.wpg) -> (IL or None, "wpg", diagnostics): its program
    decoded (mlctool/wpg.py, with gxw.py's token decoder), then the path of the CSV imports as
    a .gxw's. W107 where an application instruction's stored width is not the target's count;
    W916 where the target's steps and the NOP fill after END make no FX program memory size:
    GX Developer's count of the whole program is not the target's."""
    from mlctool.gxw import GxwError
    from mlctool.wpg import CAPACITIES, read_program

    fmt = "wpg"
    try:
        prog = read_program(data)
    except GxwError as e:
        return None, fmt, [diag(path, Span.at(1), e.code, e.message, *e.notes)]
    places = {k: f"offset 0x{ins.offset:X}" for k, ins in enumerate(prog.instructions, 1)}
    w = _Writer(path, target, "fx", comments, places)
    counts = _decoded(w, prog.instructions, "the file (its stored width)")
    w.finish()
    text, fmt, diags = _assemble(path, fmt, w, target, counts)
    if text is None:
        return text, fmt, diags
    steps = sum(ins.steps for ins in _resolved(path, text, target).instrs)
    if steps + prog.fill not in CAPACITIES:
        size = min((c for c in CAPACITIES if c > prog.fill), key=lambda c: abs(c - steps - prog.fill),
                   default=CAPACITIES[-1])
        diags = sorted(diags + [diag(
            path, Span.at(len(prog.instructions)), "W916",
            f"offset 0x{prog.fill_offset:X}: {prog.fill} NOP steps follow END, and target {target.name} counts "
            f"the program as {steps} steps: {steps + prog.fill}, no FX program memory size "
            f"({', '.join(map(str, CAPACITIES))} steps); GX Developer counts it as {size - prog.fill} steps if its "
            f"memory is {size}",
            "the vendor's step addresses are not the target's somewhere in the program: W107 names an instruction "
            "whose stored width differs; else a special device or an operand counted otherwise (docs/formats.md)")],
            key=Diagnostic.sort_key)
    return text, fmt, diags


# the target a WinProladder program is for: its words are FATEK FBs instructions and devices
WINPROLADDER_TARGET = "fbs"


def is_winproladder(path: str, head: bytes) -> bool:
    """A FATEK WinProladder project (.pdw) or ladder resource (.ldr): by its name or signature."""
    import os

    from mlctool.winproladder import kind_of

    return os.path.splitext(path)[1].lower() in (".pdw", ".ldr") or kind_of(head) is not None


def import_winproladder(path: str, data: bytes, target: Target) -> tuple[str | None, str, list[Diagnostic]]:
    """A WinProladder .pdw / .ldr -> (IL or None, "winproladder", diagnostics): its program's
    words decoded (mlctool/winproladder.py), one IL line per form, END last (the file keeps
    the program's length, no END word). A form with no counterpart on the target is E927 at
    its offset; W107 where the target's step count of an instruction is not its words."""
    import os

    from mlctool.winproladder import FatekError, read

    fmt = "winproladder"
    if target.name != WINPROLADDER_TARGET:
        return None, fmt, [diag(path, Span.at(1), "E927", f"a WinProladder program is a FATEK FBs program; target "
                                f"{target.name} is another PLC", f"import it with --target {WINPROLADDER_TARGET}")]
    try:
        prog = read(data, os.path.splitext(path)[1])
    except FatekError as e:
        return None, fmt, [diag(path, Span.at(1), e.code, e.message, *e.notes)]
    places = {k: f"offset 0x{it.offset:X} (program word {it.index})" for k, it in enumerate(prog.items, 1)}
    w = _Writer(path, target, "", None, places)
    for code, message in prog.warnings:
        w.warn(1, code, code, message)
    counts = {}
    for k, it in enumerate(prog.items, 1):
        shown = " ".join(f"{x:04X}" for x in it.words)
        if it.il == ";":
            w.comment(f"{it.fatek} ({shown})")
        elif not it.il:
            w.warn(k, f"none {it.fatek}", "E927", f"{w.at(k)}: {shown}: {it.fatek}: no counterpart on target "
                   f"{target.name}: {it.why}", "rewrite that rung for the target's instructions (docs/formats.md)")
        else:
            w.flush()
            counts[len(w.lines)] = (k, len(it.words), it.fatek, "the file (its words)")
            w.instruction(it.il, [it.operand] if it.operand else [], k)
    w.instruction("END", [], len(prog.items) + 1)
    w.finish()
    return _assemble(path, fmt, w, target, counts)


def import_file(path: str, target: Target, fmt: str | None = None) -> tuple[str | None, str, list[Diagnostic]]:
    text, diags = read_export(path)
    if text is None:
        return None, fmt or "", diags
    return import_text(path, text, target, fmt)


def read_export(path: str, encoding: str | None = None) -> tuple[str | None, list[Diagnostic]]:
    """The text of an export file, line ends normalised, or None; and the diagnostics."""
    src, diags = read_source(path, encoding)
    return (src.text if src is not None else None), diags
