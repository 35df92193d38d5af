"""IL -> the vendor tools' text forms (`mlc export`), the way back of mlctool/imports.py:

- `gxworks2`: the CSV GX Works2 reads with "Read from CSV File" and writes with "Write to CSV
  File" (docs/formats.md): UTF-16LE with a BOM, CRLF, tab-separated quoted fields; a
  program-name row, a `"PLC Information:"` row naming the CPU, the header row `Step Number`,
  `Line Statement`, `Instruction`, `I/O(Device)`, `Blank`, `PI Statement`, `Note`, then one
  row per instruction with its first operand, each further operand on a continuation row
  (empty step and instruction cells); X/Y written with three octal digits (`X000`).
- `wplsoft`: WPLSoft's `000000,LD,X0` rows (6-digit step number, mnemonic, operands).
- `winproladder`: a FATEK WinProladder project (.pdw): the program's words written into a
  project WinProladder saved (the template), by mlctool/winproladder.py (export_winproladder).

Written in the dialect of the file's `.dialect` (else the format's own: FX for GX, Delta DVP
for WPLSoft): the target's special devices go back to the family's numbers (M9000 -> M8000 /
M1000, specials.toml), its instructions to the family's spelling (DRVR -> DRVI, OUT T0 K10 ->
TMR T0 K10 for Delta), interrupt pointers to FX's I numbers (IX1P -> I101). The step column is
the address the target's step convention computes, which for the VS is FX3U's count: what GX
Works2 numbers (the corpus's exports agree, tests/test_corpus.py). Line comments become Line
Statement rows, a comment after an instruction its Note. Re-importing the output gives the
IL that was exported (tests/test_exports.py, on every corpus file).
"""

from __future__ import annotations

import re

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Instr, Module
from mlctool.syntax.operands import OperandSyntaxError, format_operand, parse_operand
from mlctool.targetapi.model import Target

FORMATS = ("gxworks2", "wplsoft", "winproladder")
FORMAT_FAMILY = {"gxworks2": "fx", "wplsoft": "dvp"}
_HEADER = ("Step Number", "Line Statement", "Instruction", "I/O(Device)", "Blank", "PI Statement", "Note")
_DIALECT = re.compile(r"\s*\.dialect\s+(\w+)", re.IGNORECASE)
# the relay of an FX MC the import dropped, kept in its comment (imports._Writer.settle)
_MC_RELAY = re.compile(r"the export's MC (N[0-9]+) ([A-Z]+[0-9]+)")
_MC_NOTE = re.compile(r"\s*;?\s*the export's MC N[0-9]+ [A-Z]+[0-9]+: the \S+ MC has no relay operand \([^)]*\)$")
_CPU = {"fx": "FXCPU FX3U/FX3UC"}


def export_text(path: str, text: str, target: Target, fmt: str) -> tuple[bytes | None, list[Diagnostic]]:
    """IL text -> the export's bytes, or None with the checker's errors."""
    rows, dialect, errors = family_rows(path, text, target, FORMAT_FAMILY[fmt])
    if rows is None:
        return None, errors
    return (_gx(rows, dialect) if fmt == "gxworks2" else _wplsoft(rows)), []


Row = tuple[int, str, str, list[str], str]  # (step, line statement, instruction, operands, note)


def family_rows(path: str, text: str, target: Target, default_dialect: str
                ) -> tuple[list[Row] | None, str, list[Diagnostic]]:
    """IL text -> its rows in the spelling of its `.dialect` (else `default_dialect`): each
    instruction at the address the target's step convention computes, with the family's
    mnemonic and operands; comment lines as line statements. None with the checker's errors."""
    from mlctool.targetapi.specials import families

    module, lines, errors = _checked(path, text, target)
    if module is None:
        return None, "", errors
    dialect = next((m[1].lower() for line in lines if (m := _DIALECT.match(line))), default_dialect)
    family = families(target.name).get(dialect)
    if family is None:
        return None, "", [diag(path, Span.at(1), "E105", f".dialect {dialect}: target {target.name} has no such family")]
    back = {(s.device): f"{kind}{number}" for (kind, number), s in family.mapping.items()}
    spelled = {v: k for k, v in family.mnemonics.items() if v != "OUT"}
    by_line = {ins.line: ins for ins in module.instrs}
    rows: list[Row] = []
    end = max((ins.addr + ins.steps for ins in module.instrs), default=0)
    for k, line in enumerate(lines, 1):
        code, _, note = line.partition(";")
        code, note = code.strip(), note.strip()
        ins = by_line.get(k)
        if ins is None:
            if code.startswith(".") or not (code or note):
                continue
            step = _next_addr(module.instrs, k, end)
            if code.endswith(":") and not code.startswith(";"):  # a named label (跳過:), no instruction
                rows.append((step, "", _label(code[:-1], target), [], note))
            elif note and not code:
                rows.append((step, note, "", [], ""))
            continue
        words = _words(ins, back, target)
        mnemonic = spelled.get(ins.spec.mnemonic, ins.spec.mnemonic)
        if dialect == "dvp" and ins.spec.mnemonic == "OUT" and len(words) == 2 and words[0][0] in "TC":
            mnemonic = "TMR" if words[0][0] == "T" else ("DCNT" if int(words[0][1:]) >= 200 else "CNT")
        if code.endswith(":"):  # P10:, IX1P:, a named label: a label row
            rows.append((ins.addr, "", _label(code[:-1].strip(), target), [], note))
            continue
        m = _MC_RELAY.search(note) if ins.spec.op == "mc" and dialect == "fx" else None
        if m and len(words) == 1:  # FX's MC N0 M100: the relay back, the import's comment dropped
            words.append(m[2])
            note = _MC_NOTE.sub("", note).strip()
        rows.append((ins.addr, "", mnemonic, words, note))
    return rows, dialect, []


def _checked(path: str, text: str, target: Target) -> tuple[Module | None, list[str], list[Diagnostic]]:
    """The IL checked: its module and lines, or None with the checker's errors."""
    from mlctool.check import check_texts
    from mlctool.syntax.source import SourceText

    src = SourceText(path, text if text.endswith("\n") else text + "\n")
    result = check_texts([src], target)
    errors = [d for d in result.diagnostics if d.severity == "error"]
    if errors:
        return None, [], errors
    return next(m for m in result.modules if m.path == path), src.text.split("\n"), []


def _next_addr(instrs: list[Instr], line: int, end: int) -> int:
    return next((ins.addr for ins in instrs if ins.line > line), end)


def _label(name: str, target: Target) -> str:
    """A label line as the family writes it: IX1P -> I101, P10 -> P10, a name as it is."""
    from mlctool.check.interrupts import pointer_named

    p = pointer_named(name, target)
    return f"I{p.number:03d}" if p is not None else name.upper() if re.fullmatch(r"[Pp][0-9]+", name) else name


def _words(ins: Instr, back: dict[str, str], target: Target) -> list[str]:
    """The operands as the family writes them: its special numbers, FX's I pointers."""
    from mlctool.check.interrupts import pointer_named

    if ins.spec.cls == "label" and ins.texts:
        return [_label(ins.texts[0], target)]
    out = []
    for text in ins.texts:
        p = pointer_named(text, target)
        if p is not None:
            out.append(f"I{p.number:03d}")
            continue
        try:
            op = parse_operand(text, target.operand_syntax)
        except OperandSyntaxError:
            out.append(text)
            continue
        shown = format_operand(op)
        base = re.fullmatch(r"([A-Z]+[0-9]+)(\.[0-9A-F])?", shown)
        if base and base[1] in back and not op.is_const and not op.index:
            shown = back[base[1]] + (base[2] or "")
        out.append(shown)
    return out


def _pad(word: str) -> str:
    """GX writes X and Y with three octal digits: X000, Y017."""
    m = re.fullmatch(r"([XY])([0-7]+)", word)
    return f"{m[1]}{int(m[2]):03d}" if m and len(m[2]) < 3 else word


def _q(cell: str) -> str:
    return '"' + cell.replace('"', '""') + '"'


def _gx(rows, dialect: str) -> bytes:
    out = ['"MAIN"', "\t".join(_q(c) for c in ("PLC Information:", _CPU.get(dialect, "FXCPU FX3U/FX3UC"))),
           "\t".join(_q(c) for c in _HEADER)]
    for step, statement, instruction, operands, note in rows:
        first = _pad(operands[0]) if operands else ""
        out.append("\t".join(_q(c) for c in (str(step), statement, instruction, first, "", "", note)))
        out += ["\t".join(_q(c) for c in ("", "", "", _pad(o), "", "", "")) for o in operands[1:]]
    return "\ufeff".encode("utf-16-le") + ("\r\n".join(out) + "\r\n").encode("utf-16-le")


def _wplsoft(rows) -> bytes:
    out = []
    for step, statement, instruction, operands, note in rows:
        if statement:
            out.append(f"; {statement}")
            continue
        out.append(",".join([f"{step:06d}", instruction, *operands]) + (f" ; {note}" if note else ""))
    return ("\r\n".join(out) + "\r\n").encode("utf-8")


def export_winproladder(path: str, text: str, target: Target, template: bytes
                        ) -> tuple[bytes | None, list[Diagnostic]]:
    """IL text -> a WinProladder project: `template` (a .pdw WinProladder saved) with its program
    replaced by the IL's, each instruction's words from mlctool/winproladder_words.toml read
    backwards. END must be the last instruction and gives no word (the project keeps the
    program's length). None with the checker's errors, E930 for an instruction with no word,
    E931 for a template the writer cannot use."""
    from mlctool.winproladder import FatekError, encode, write_pdw

    module, _, errors = _checked(path, text, target)
    if module is None:
        return None, errors
    words: list[int] = []
    problems = []
    instrs = sorted(module.instrs, key=lambda i: i.addr)
    for k, ins in enumerate(instrs):
        if ins.spec.op == "end" and k == len(instrs) - 1:
            break
        shown = " ".join([ins.spec.mnemonic, *ins.texts])
        operand = format_operand(ins.operands[0]) if len(ins.operands) == 1 else ""
        got = encode(ins.spec.mnemonic, operand) if operand and not ins.operands[0].index else None
        if got is None:
            problems.append(diag(path, Span.at(ins.line), "E930", f"{shown}: no WinProladder word the public notes "
                                 "establish", "the writer knows the forms of mlctool/winproladder_words.toml "
                                 "(docs/formats.md, FATEK WinProladder)"))
        elif not problems and (len(got) != ins.steps or ins.addr != len(words)):
            problems.append(diag(path, Span.at(ins.line), "E930", f"{shown}: {len(got)} words at word {len(words)}, "
                                 f"where target {target.name} counts {ins.steps} steps at {ins.addr}"))
        else:
            words += got
    if not instrs or instrs[-1].spec.op != "end":
        problems.append(diag(path, Span.at(1), "E930", "the program does not end with END"))
    if problems:
        return None, problems
    try:
        return write_pdw(template, words), []
    except FatekError as e:
        return None, [diag(path, Span.at(1), e.code, e.message, *e.notes)]
