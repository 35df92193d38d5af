"""Linker: object modules -> one linked program laid out as the manual requires.

Layout (4.1 CALL/SRET/FEND: subroutines go after FEND, END closes the program): the main
module up to its END (its own FEND and subroutines included); a FEND when libraries follow
and the main module has none; each library module in the order given; END last. Addresses
are reassigned from 0. P labels are the manual's global P0-P255: a P may be defined by one
module only, and another module may use it only if it is `.export`-ed.
"""

from __future__ import annotations

import dataclasses
from collections import defaultdict

from mlctool.asm.objfile import ObjectFile, Unit
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Instr
from mlctool.targetapi import Target


def _at(ins: Instr, code: str, msg: str, *notes: str) -> Diagnostic:
    return diag(ins.file, Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic)), code, msg, *notes)


def _where(ins: Instr) -> str:
    return f"{ins.file}:{ins.line}"


def _moved(ins: Instr, addr: int) -> Instr:
    # dataclasses.replace costs 7 us an instruction; this is a quarter of that
    return Instr(ins.spec, ins.operands, ins.texts, ins.steps, addr, ins.file, ins.line, ins.col,
                 ins.table, ins.valid)


def _spec(target: Target, op: str):
    return next(s for s in target.instructions.values() if s.op == op)


def check_labels(objs: list[ObjectFile]) -> list[Diagnostic]:
    """Duplicate and undefined P labels across modules, and CJ/CALL sharing a P (4.1 API-00)."""
    out: list[Diagnostic] = []
    owner: dict[int, tuple[ObjectFile, Instr]] = {}
    for obj in objs:
        for ins in obj.instrs:
            if ins.spec.cls != "label":
                continue
            p = ins.operands[0].number
            if p in owner and owner[p][0] is not obj:
                first = owner[p][1]
                out.append(_at(ins, "E504", f"P{p} is defined by two modules: {first.file} "
                               f"(line {first.line}) and {ins.file} (line {ins.line})"))
            owner.setdefault(p, (obj, ins))
    jumps: dict[str, dict[int, Instr]] = {"cj": {}, "call": {}}
    for obj in objs:
        for ins in obj.instrs:
            if ins.spec.op in jumps and not ins.operands[0].index:
                jumps[ins.spec.op].setdefault(ins.operands[0].number, ins)
        for k, p in obj.relocations():
            ins = obj.instrs[k]
            if p not in owner:
                out.append(_at(ins, "E505", f"{ins.mnemonic} P{p} in {obj.units[0].path}: no module defines P{p}"))
                continue
            other, label = owner[p]
            if p not in other.units[0].exports:
                out.append(_at(ins, "E505", f"{ins.mnemonic} P{p}: P{p} is local to {label.file} "
                               f"(line {label.line}); export it there with `.export P{p}`"))
            elif ins.spec.op == "cj":
                out.append(_at(ins, "E305", f"CJ P{p} jumps into another module ({label.file}); "
                               "only CALL may reach a library's subroutines"))
    for p in sorted(set(jumps["cj"]) & set(jumps["call"])):
        cj, call = jumps["cj"][p], jumps["call"][p]
        if cj.file != call.file:
            out.append(_at(cj, "E305", f"P{p} is used by CALL at {_where(call)}, so CJ may not use it (4.1 API-00)"))
    return out


def double_coils(instrs: list[Instr], checked_together: frozenset[str]) -> list[Diagnostic]:
    """OUT of one device in two modules (W506); pairs the checker already saw together skip."""
    first: dict[tuple[str, int], Instr] = {}
    out = []
    for ins in instrs:
        if ins.spec.op != "out" or ins.operands[0].index:
            continue
        key = (ins.operands[0].kind, ins.operands[0].number)
        f = first.setdefault(key, ins)
        if f.file != ins.file and not {f.file, ins.file} <= checked_together:
            out.append(_at(ins, "W506", f"{ins.texts[0]} is also driven by OUT in {_where(f)}; "
                           "the last OUT in the scan wins (1.3.2)"))
    return out


def link(objs: list[ObjectFile], target: Target,
         checked_together: frozenset[str] = frozenset()) -> tuple[ObjectFile | None, list[Diagnostic]]:
    """Object modules -> a linked program (kind "program"), or None with the errors."""
    mains = [o for o in objs if not o.units[0].library]
    libs = [o for o in objs if o.units[0].library]
    if len(mains) != 1:
        names = ", ".join(o.units[0].path for o in mains) or "none"
        where = objs[0].units[0].path if objs else "<link>"
        return None, [diag(where, Span.at(1), "E507", f"a program needs exactly one main module "
                           f"(all others `.library`); main modules: {names}")]
    diags = check_labels(objs)
    main = mains[0]
    body = list(main.instrs)
    end_at = next((k for k, i in enumerate(body) if i.spec.op == "end"), None)
    if end_at is None:  # a checked main module has END; keep the linker total anyway
        last = body[-1] if body else None
        end_ins = Instr(_spec(target, "end"), (), (), 1, 0, main.units[0].path, last.line if last else 1)
    else:
        end_ins = body.pop(end_at)
    inserted: set[int] = set()
    if libs and not any(i.spec.op == "fend" for i in body):
        inserted.add(len(body))
        body.append(Instr(_spec(target, "fend"), (), (), 1, 0, end_ins.file, end_ins.line, end_ins.col))

    instrs: list[Instr] = []
    unit_of: list[int] = []
    units: list[Unit] = []
    addr = 0
    for k, (obj, chunk) in enumerate([(main, body)] + [(lib, lib.instrs) for lib in libs]):
        u = obj.units[0]
        start = addr
        for ins in chunk:
            instrs.append(_moved(ins, addr))
            unit_of.append(k)
            addr += ins.steps
        units.append(dataclasses.replace(u, first=start, end=addr, symbols=dict(u.symbols)))
    instrs.append(_moved(end_ins, addr))
    unit_of.append(0)
    program = ObjectFile("program", target.name, units, instrs, unit_of, frozenset(inserted))

    diags += double_coils(instrs, checked_together)
    total = program.total_steps
    if total > target.capacity:
        diags.append(diag(main.units[0].path, Span.at(1), "E314",
                          f"the linked program has {total} steps; the target holds {target.capacity}",
                          "capacity is a setting: target.toml `capacity`, or `capacity` in mlc.toml"))
    if any(d.severity == "error" for d in diags):
        return None, diags
    return program, diags


def labels_by_number(obj: ObjectFile) -> dict[int, list[int]]:
    """P -> indices of the instructions defining it (for maps and objdump)."""
    out: dict[int, list[int]] = defaultdict(list)
    for k, ins in enumerate(obj.instrs):
        if ins.spec.cls == "label":
            out[ins.operands[0].number].append(k)
    return out
