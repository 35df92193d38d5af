"""Random IL programs for comparing two ways of checking the same text (the checker's
shortcuts and caches against its plain way; the language server's incremental analysis
against a fresh `mlc check`). Lines are drawn from the target's own instruction table with
operands right and wrong, and from lines that exercise the other checks (labels, directives,
symbols, step numbers, noqa, syntax errors); about a third repeat an earlier line, as real
programs do, so that caches keyed by a line's text are hit."""

from __future__ import annotations

import random

from mlctool.targetapi import Target

# operands of every shape, legal somewhere or nowhere
OPERANDS = ["X0", "X7", "X8", "X17", "Y0", "Y10", "Y99999", "M0", "M5", "M8000", "M9000", "A3", "T0", "T255",
            "T999", "C0", "C200", "C235", "D0", "D1", "D100", "D9000", "D5V0", "D5Z1", "V0", "Z0", "K1", "K0",
            "K-5", "K70000", "K99999999999", "H1F", "HFFFF", "F1.5", "E1.5", "K2M0", "K4Y0", "K9M0", "P0",
            "P63", "P9999", "D0.3", "R0", "R1.F", "U1G3", "S0", "START", "VALVE", "LOOP", "@", "12"]
OTHER_LINES = ["P1:", "P2:", "P63:", "LOOP:", "  ", "; a comment", "LD X0 ; mlc: noqa", "OUT M0 // mlc: noqa W401",
               ".define START X0", ".define VALVE Y1", ".define START X2", ".define K5 X0", ".export P1",
               ".library", ".bogus", "@@", "LD X0 X1 X2", "FOO X0", "0000 LD X0", "0003 OUT Y0",
               "000013,LD,X0", "P1", "CALL LOOP", "CJ P2", "FEND", "SRET", "END", "MPS", "MRD", "MPP",
               "LD X123456789012345678901234", "MOV K1",
               # named labels (VS): their P numbers follow the order of definition
               "FILL:", "DONE:", "CALL FILL", "CJ DONE", "CALL DONE", "P255:"]


def random_line(rnd: random.Random, target: Target) -> str:
    if rnd.random() < 0.25:
        return rnd.choice(OTHER_LINES)
    mnemonic = rnd.choice(sorted(target.instructions))
    spec = target.instructions[mnemonic]
    n = len(spec.operands) + (rnd.choice((-1, 1)) if rnd.random() < 0.05 else 0)
    ops = []
    for k in range(max(n, 0)):
        kinds = sorted(spec.operands[k].kinds) if k < len(spec.operands) else []
        dev = target.devices.get(rnd.choice(kinds)) if kinds and rnd.random() < 0.6 else None
        if dev is not None and dev.kind != "pointer":
            ops.append(dev.name_of(rnd.choice((dev.lo, dev.hi, rnd.randint(dev.lo, dev.hi)))))
        else:
            ops.append(rnd.choice(OPERANDS))
    return " ".join([mnemonic.lower() if rnd.random() < 0.1 else mnemonic, *ops])


def random_program(rnd: random.Random, target: Target, lines: int) -> list[str]:
    out: list[str] = []
    for _ in range(lines):
        out.append(rnd.choice(out) if out and rnd.random() < 0.35 else random_line(rnd, target))
    return out


def random_edit(rnd: random.Random, target: Target, lines: list[str]) -> list[str]:
    """An edit as a user makes one: a line changed, inserted, deleted or duplicated."""
    lines = list(lines)
    k = rnd.randrange(len(lines) + 1)
    what = rnd.random()
    if what < 0.4 and k < len(lines):
        lines[k] = random_line(rnd, target)
    elif what < 0.7:
        lines.insert(k, random_line(rnd, target))
    elif what < 0.85 and k < len(lines):
        del lines[k]
    elif lines:
        lines.insert(k, rnd.choice(lines))
    return lines
