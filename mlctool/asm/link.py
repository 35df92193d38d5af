"""Linker: modules -> one Image laid out as the manual requires (4.1 CALL/SRET/FEND).

Layout: the main module up to its END (its own FEND and subroutines included); if libraries
follow and the main module has no FEND, a FEND is inserted; then each library module's
subroutines in the order given; then END. Addresses are reassigned from 0.
"""

from __future__ import annotations

import dataclasses

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Image, Instr, Module
from mlctool.targets import Target


def _spec(target: Target, op: str):
    return next(s for s in target.instructions.values() if s.op == op)


def link_modules(modules: list[Module], target: Target) -> tuple[Image | None, list[Diagnostic]]:
    diags: list[Diagnostic] = []
    mains = [m for m in modules if not m.library]
    libs = [m for m in modules if m.library]
    if len(mains) != 1:
        where = mains[1].path if len(mains) > 1 else (modules[0].path if modules else "<link>")
        diags.append(diag(where, Span.at(1), "E301",
                          "a program needs exactly one main module (the others must be .library)"
                          + (f"; main modules: {', '.join(m.path for m in mains)}" if mains else "")))
        return None, diags
    main = mains[0]
    body = list(main.instrs)
    end = next((k for k, i in enumerate(body) if i.spec.op == "end"), None)
    tail_file, tail_line = main.path, body[-1].line if body else 1
    if end is not None:
        end_ins = body[end]
        body = body[:end]
    else:
        end_ins = Instr(_spec(target, "end"), (), (), 1, 0, tail_file, tail_line)
    placed: list[tuple[str, list[Instr]]] = [(main.path, body)]
    if libs and not any(i.spec.op == "fend" for i in body):
        body.append(Instr(_spec(target, "fend"), (), (), 1, 0, tail_file, tail_line))
    for lib in libs:
        placed.append((lib.path, list(lib.instrs)))
    placed[-1][1].append(end_ins) if libs else body.append(end_ins)

    instrs: list[Instr] = []
    ranges: list[tuple[str, int, int]] = []
    addr = 0
    for path, chunk in placed:
        start = addr
        for ins in chunk:
            instrs.append(dataclasses.replace(ins, addr=addr))
            addr += ins.steps
        ranges.append((path, start, addr))

    symbols: dict[str, str] = {}
    for m in modules:
        symbols.update(m.symbols)
    image = Image(target.name, instrs, ranges, symbols)
    # labels: duplicates and undefined, naming modules
    owner: dict[int, Instr] = {}
    for ins in instrs:
        if ins.spec.cls == "label":
            p = ins.operands[0].number
            if p in owner:
                diags.append(diag(ins.file, Span.at(ins.line, ins.col), "E504",
                                  f"P{p} is defined in {owner[p].file}:{owner[p].line} and in {ins.file}:{ins.line}"))
            else:
                owner[p] = ins
    for ins in instrs:
        if ins.spec.op in ("cj", "call") and ins.operands and not ins.operands[0].index:
            p = ins.operands[0].number
            if p not in owner:
                diags.append(diag(ins.file, Span.at(ins.line, ins.col), "E505",
                                  f"{ins.mnemonic} P{p}: no module defines P{p}"))
    if image.total_steps > target.capacity:
        diags.append(diag(main.path, Span.at(1), "E314",
                          f"linked program has {image.total_steps} steps; the target holds {target.capacity}"))
    return image, diags
