"""Interrupt pointers (target.toml `[interrupts]`, VS 2-12, 2-15-1, 6-2 IRET/EI/DI).

A pointer line `IX0P:` labels an interrupt routine. Pointers are a label class of their own
(instruction class "interrupt", operand kind I), so I numbers never meet P numbers. The
table names the families (prefix, units, suffixes) and how a name maps to its number; this
module reads names, and checks the layout rules of the manual (E908).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Instr, Module
from mlctool.targetapi.model import Target


@dataclass(frozen=True)
class Pointer:
    name: str  # as the manual writes it: IX0P, ITA10, IHC3
    number: int  # the I number kept in objects (FX numbering, target.toml)
    unit: int  # input number, period in ms, counter number
    suffix: str  # P / F of an input's edge, "" otherwise
    source: str  # "input" | "timer" | "counter" | "hardware"
    family: dict  # the target.toml family entry


def families(target: Target) -> list[dict]:
    return (target.settings.get("interrupts") or {}).get("families", [])


def pointer_named(text: str, target: Target) -> Pointer | None:
    """`IX0P` -> its Pointer, None when the text names no interrupt pointer of the target."""
    up = text.upper()
    for fam in families(target):
        suffixes = fam.get("suffixes", {})
        tail = "(" + "|".join(suffixes) + ")" if suffixes else "()"
        m = re.fullmatch(re.escape(fam["prefix"]) + rf"([0-9]{{{fam['digits']}}}){tail}", up)
        if not m:
            continue
        unit = int(m[1])
        lo, hi = fam["units"]
        if not lo <= unit <= hi:
            return None
        number = fam["base"] + fam["step"] * unit + suffixes.get(m[2], 0)
        return Pointer(up, number, unit, m[2], fam["source"], fam)
    return None


def pointer_numbered(number: int, target: Target) -> Pointer | None:
    """The inverse of pointer_named, for objects and the simulator."""
    for fam in families(target):
        suffixes = fam.get("suffixes") or {"": 0}
        for suffix, add in suffixes.items():
            unit, rest = divmod(number - fam["base"] - add, fam["step"])
            if rest == 0 and fam["units"][0] <= unit <= fam["units"][1]:
                return pointer_named(f"{fam['prefix']}{unit:0{fam['digits']}d}{suffix}", target)
    return None


def source_pointer(target: Target, source: str, k: int) -> int | None:
    """The I number of the k-th pointer (from 0) of the family fed by `source` ("hardware":
    IHHC1 for the first hardware counter), None when the target has none."""
    for fam in families(target):
        if fam["source"] == source and fam["units"][0] + k <= fam["units"][1]:
            return fam["base"] + fam["step"] * (fam["units"][0] + k)
    return None


def disable_relay(p: Pointer) -> int:
    """The special relay that disables this pointer's requests (M9050 + n for IXn ...)."""
    fam = p.family
    return fam["disable"] + fam.get("disable_step", 0) * (p.unit - fam["units"][0])


def _at(ins: Instr, msg: str, *notes: str) -> Diagnostic:
    return diag(ins.file, Span(ins.line, ins.col, ins.line, ins.col + max(1, len(ins.texts[0] if ins.texts
                                                                               else ins.mnemonic))),
                "E908", msg, *notes)


def check_interrupts(module: Module, target: Target) -> list[Diagnostic]:
    """E908: pointers after FEND, each once, IXnP and IXnF not both, each routine closed by IRET
    before the next label, pointer or END; IRET only closes a routine."""
    if not families(target):
        return []
    out: list[Diagnostic] = []
    instrs = module.instrs
    after_fend = module.library
    seen: dict[int, Instr] = {}
    units: dict[tuple[str, int], Instr] = {}
    routine: Instr | None = None  # the pointer whose routine is open
    section = target.settings["interrupts"].get("section", "")
    timers = target.settings["interrupts"].get("routine_timers")
    has_steps = any(i.spec.op == "stl" for i in instrs)
    for ins in instrs:
        cls, op = ins.spec.cls, ins.spec.op
        if routine is not None and timers and op == "tmr" and not ins.operands[0].index \
                and not timers[0] <= ins.operands[0].number <= timers[1]:
            out.append(diag(ins.file, Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic)), "W222",
                            f"{ins.texts[0]} in interrupt routine {routine.texts[0]}: a routine times with "
                            f"T{timers[0]}-T{timers[1]} only (2-5-3), which the CPU times at END"))
        if routine is not None and has_steps and op in ("set", "out", "step_set", "step_out") \
                and ins.operands and ins.operands[0].kind == "S":
            out.append(diag(ins.file, Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic)), "W223",
                            f"{ins.mnemonic} {ins.texts[0]} in interrupt routine {routine.texts[0]}: a program "
                            "with step ladder may not drive step relays from an interrupt routine (4-4)"))
        if cls == "interrupt":
            p = pointer_numbered(ins.operands[0].number, target)
            name = p.name if p else ins.texts[0]
            if routine is not None:
                out.append(_at(routine, f"interrupt routine {routine.texts[0]} has no IRET before "
                               f"{name} (line {ins.line})"))
            if not after_fend:
                out.append(_at(ins, f"interrupt pointer {name} before FEND; interrupt routines go "
                               f"after FEND ({section}, 6-2 FEND)"))
            if ins.operands[0].number in seen:
                out.append(_at(ins, f"{name} already labels line {seen[ins.operands[0].number].line}"))
            elif p and p.family.get("one_per_unit"):
                key = (p.family["prefix"], p.unit)
                other = units.setdefault(key, ins)
                if other is not ins and other.operands[0].number != ins.operands[0].number:
                    out.append(_at(ins, f"{name} and {other.texts[0]} (line {other.line}) both serve "
                                   f"input {p.family.get('device', '')}{p.unit}; one pointer per input "
                                   "(2-15-1)"))
            seen.setdefault(ins.operands[0].number, ins)
            routine = ins
        elif op == "iret":
            if routine is None:
                out.append(_at(ins, "IRET closes no interrupt routine (IRET ends the routine of an "
                               "interrupt pointer written after FEND)"))
            routine = None
        elif routine is not None and (cls == "label" or op in ("end", "fend", "sret")):
            out.append(_at(routine, f"interrupt routine {routine.texts[0]} has no IRET before "
                           f"{ins.texts[0] + ':' if cls == 'label' and ins.texts else ins.mnemonic} "
                           f"(line {ins.line})"))
            routine = None
        if op == "fend":
            after_fend = True
    if routine is not None:
        out.append(_at(routine, f"interrupt routine {routine.texts[0]} has no IRET"))
    return out
