"""W250-W253: the program's use of a target's signals (targetapi/signals.py; the NC5's MLC <->
NC and MLC <-> HMI special M/D of manual ch. 5).

Inside the special ranges the target's signal table is the authority (the area warning W212
is not given there):
- W250: a write to a row typed R: the NC (or the HMI, or the system) writes it, and the
  MLC's value is overwritten at its next update. A write is OUT/SET/RST/PLS/PLF/ALT, a
  destination operand, a Kn group, a ZRST range or a block a constant count sizes (the
  tables' `span`: DECO D0 M30996 K3 writes 2^3 bits) that covers the row. DECISION: a
  warning, not an error: the instruction is valid for the PLC and the vendor's tools accept
  it, and an error could be neither lowered nor silenced (mlc.toml [severity] makes W250 an
  error where a project wants that);
- W251: a number no row defines, read or written. A group or range that covers a signal
  is not warned about the undefined numbers it also covers (DECISION: K4M31000 reads the eight
  mode bits M31000-M31007 and eight spare bits; the spare bits are the group's padding);
- W252: a signal of a channel above the project's channel count (mlc.toml `channels`,
  default 1): on the machine nothing answers it;
- W253: a 32-bit signal used by halves (a 16-bit instruction on it, or a 32-bit one starting
  at its upper word), or a 32-bit instruction on a 16-bit signal.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Instr, Module
from mlctool.targetapi.model import Target

if TYPE_CHECKING:
    from mlctool.targetapi.signals import SignalAt, SignalTable

_CONTACTS = frozenset(("contact", "contact_not", "contact_rise", "contact_fall"))
_WRITERS = frozenset(("out", "set", "rst", "pls", "plf", "alt"))
_WRITTEN_BY = {"NC->MLC": "the NC", "HMI->MLC": "the HMI"}


def check_signals(module: Module, target: Target, lines: list[str], config_data: dict | None) -> list[Diagnostic]:
    header = target.settings.get("signals")
    if header is None:
        return []
    bounds: dict[str, tuple[int, int]] = {}
    for r in header["ranges"]:
        lo, hi = bounds.get(r["kind"], (r["lo"], r["hi"]))
        bounds[r["kind"]] = (min(lo, r["lo"]), max(hi, r["hi"]))
    # the first number an operand can start at and still reach the ranges: a Kn group is at
    # most 32 bits, a 32-bit operand a few words; ZRST ranges are looked at whole
    low = min(lo for lo, _ in bounds.values()) - 32
    table: SignalTable | None = None
    channels = 0
    out: list[Diagnostic] = []
    for ins in module.instrs:
        if ins.spec.op != "zrst":
            for o in ins.operands:  # (the usual instruction: no operand near; a constant's number is 0)
                if o.number >= low:
                    break
            else:
                continue  # (a 64k-step program's 40k instructions: some 9 ms)
        for k, kind, first, last, write, words in _accesses(ins, target):
            near = bounds.get(kind)
            if near is None or last < near[0] or first > near[1]:
                continue  # (the usual operand: no special device; the table is not even read)
            if table is None:
                # imported here: a check that touches no special device (and every check of a
                # target without signals) does not pay its classes (some 5-10 ms of a start)
                from mlctool.targetapi.signals import signals_of

                table = signals_of(target)
                channels = table.channel_count(config_data)
            found = _diagnostic(ins, k, kind, first, last, write, words, table, channels, lines)
            if found is not None:
                out.append(found)
    return out


def _accesses(ins: Instr, target: Target):
    """(operand index, device kind, first, last number, written, words of one access) of the
    devices an instruction reads or writes; `words` is 0 for bits and ranges."""
    spec = ins.spec
    ops = ins.operands
    if spec.op == "zrst" and len(ops) == 2 and not (ops[0].index or ops[1].index):
        a, b = ops
        yield 0, a.kind, min(a.number, b.number), max(a.number, b.number), True, 0
        return
    for k, (o, s) in enumerate(zip(ops, spec.operands, strict=False)):
        if o.is_const or o.index:
            continue
        if spec.api is None:
            write = k == 0 and spec.op in _WRITERS
            if not write and spec.op not in _CONTACTS:
                continue
        else:
            write = s.writes
        dev = target.devices.get(o.device)
        n = _span(spec, s, ops, dev, o)
        if o.is_group:
            yield k, o.device, o.number, o.number + 4 * o.digits * n - 1, write, 0
            continue
        if dev is None or dev.kind != "word" or o.is_bit_of_word:
            yield k, o.device, o.number, o.number + (s.bits if dev is not None and dev.kind == "bit" else 1) * n - 1, \
                write, 0
            continue
        width = 1 if spec.api is None else s.words[1] if spec.width == 32 else s.words[0]
        if n > 1:  # a block of n elements: looked at whole, as a range is (no halves)
            yield k, o.kind, o.number, o.number + width * n - 1, write, 0
            continue
        yield k, o.kind, o.number, o.number + width - 1, write, width


def _span(spec, s, ops, dev, o) -> int:
    """How many elements operand `o` covers when another operand counts them with a constant
    (the tables' `span`: DECO D covers 2^n bits), else 1. The count's own range check (E206,
    E208) says what is wrong with a count out of range: here it is capped."""
    if s.span is None or o.index or (s.span_kinds == "bit" and (dev is None or dev.kind != "bit" or o.is_group)):
        return 1
    value = spec.constant_count(s, ops)
    return 1 if value is None else s.span_count(max(1, min(value, 16)))


def _diagnostic(ins: Instr, k: int, kind: str, first: int, last: int, write: bool, words: int,
                table: SignalTable, channels: int, lines: list[str]) -> Diagnostic | None:
    found: list[SignalAt] = []
    undefined: list[int] = []
    for n in range(first, last + 1):
        if table.range_of(kind, n) is None:
            continue
        at = table.at(kind, n)
        if at is None:
            undefined.append(n)
        else:
            found.append(at)
    text = ins.texts[k] if k < len(ins.texts) else f"{kind}{first}"
    where = _operand_span(ins, k, text, lines)
    if not found:
        if not undefined:
            return None
        n = undefined[0]
        r = table.range_of(kind, n)
        devices = f"{kind}{n}" if len(undefined) == 1 else f"{kind}{undefined[0]}-{kind}{undefined[-1]}"
        by = _WRITTEN_BY.get(r.direction)
        return diag(ins.file, where, "W251",
                    f"{devices} is no signal of the manual's tables: an undefined number of the "
                    f"{r.direction} special range {kind}{r.lo}-{kind}{r.hi}"
                    + (f", written by {by}" if by and write else ""),
                    f"the rows are manual {table.section}; `mlc explain {_example(table, kind)}` prints one")
    fixed = [a for a in found if a.signal.read_only] if write else []
    if fixed:
        a = fixed[0]
        s = a.signal
        by = _WRITTEN_BY.get(s.direction, "the system")
        what = f"{s.name} ({s.english}, {s.direction}, manual {s.section})"
        more = f" and {len(fixed) - 1} more signal{'s' if len(fixed) > 2 else ''} {by} writes" if len(fixed) > 1 else ""
        if text.upper() == a.device and first == last:
            head = f"{a.device} is {what}"
        else:  # a group, a block or a ZRST range
            subject = text if text.upper() != a.device else f"{ins.mnemonic} {' '.join(ins.texts)}"
            head = f"{subject} writes {a.device}, {what}{more}"
        return diag(ins.file, where, "W250", f"{head}: {by} writes it (R), an MLC write fights {by}",
                    a.describe() + ("; the MLC drives the NC through the MLC->NC signals" if by == "the NC" else ""))
    beyond = [a for a in found if a.channel > channels]
    if beyond:
        a = beyond[0]
        return diag(ins.file, where, "W252",
                    f"{a.device}, {a.signal.name} ({a.signal.english}), is channel {a.channel}'s: the "
                    f"project's machine has {channels} channel{'s' if channels != 1 else ''}",
                    f"mlc.toml `{table.setting} = N` says how many channels the NC has "
                    f"(default {table.default_channels}, manual 5.1)")
    if words and len(found) == len(range(first, last + 1)):
        return _halves(ins, where, text, found, words)
    if words == 2 and len(found) == 1 and found[0].signal.words == 1:
        return _halves(ins, where, text, found, words)
    return None


def _example(table: SignalTable, kind: str) -> str:
    """A device of the kind that is a signal, for the hint (M21000 on the NC5)."""
    s = next(s for s in table.signals if s.kind == kind)
    return f"{kind}{s.number(table.channels[0] if 'x' in s.device else 0)}"


def _halves(ins: Instr, where: Span, text: str, found: list[SignalAt], words: int) -> Diagnostic | None:
    a = found[0]
    s = a.signal
    if words == 1 and s.words == 2:
        half = "upper" if a.high else "lower"
        return diag(ins.file, where, "W253",
                    f"{ins.mnemonic} {text}: a 16-bit access to the {half} word of the 32-bit signal "
                    f"{s.kind}{a.number - a.high} ({s.name}, {s.english}, manual {s.section})",
                    f"use the 32-bit form (D{ins.mnemonic}) on {s.kind}{a.number - a.high}")
    if words == 2 and (a.high or s.words == 1):
        what = (f"starts at the upper word of {s.kind}{a.number - 1}" if a.high
                else f"covers {a.device} ({s.name}, {s.english}, a 16-bit signal) and the word after it")
        return diag(ins.file, where, "W253", f"{ins.mnemonic} {text}: a 32-bit access that {what} "
                    f"(manual {s.section})", "a 16-bit signal takes the 16-bit form of the instruction")
    return None


def _operand_span(ins: Instr, k: int, text: str, lines: list[str]) -> Span:
    """Where operand k is written on the instruction's line (the mnemonic if not found)."""
    line = lines[ins.line - 1] if 0 < ins.line <= len(lines) else ""
    at = ins.col - 1 + len(ins.mnemonic)
    for j in range(k + 1):
        word = ins.texts[j] if j < len(ins.texts) else ""
        found = line.upper().find(word.upper(), at) if word else -1
        if found < 0:
            return Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic))
        if j == k:
            return Span(ins.line, found + 1, ins.line, found + 1 + len(text))
        at = found + len(word)
    return Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic))
