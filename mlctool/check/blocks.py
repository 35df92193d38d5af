"""Program-wide rules that the target's tables switch on: once-per-program instructions (E904),
devices one instruction of the program may use (E240, constraint "unique-destination"),
master-control nesting (E903), step-ladder layout (E902), runs of ANB/ORB (E906).

Generic: an instruction takes part through its table entry (`once`, op mc/mcr, op stl/ret,
class anb/orb) and the limits come from target.toml (`mc_levels`, `block_ops_run`); a target
without such instructions or settings gets none of these diagnostics.
"""

from __future__ import annotations

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import FormIndex, Instr, Module
from mlctool.targetapi.model import Target

# where a program part ends: open MC levels and step blocks must be closed before these
_PART_ENDS = ("fend", "end", "sret", "iret")


def _at(ins: Instr, code: str, msg: str, *notes: str) -> Diagnostic:
    return diag(ins.file, Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic)), code, msg, *notes)


def check_blocks(module: Module, target: Target, forms: FormIndex | None = None) -> list[Diagnostic]:
    """`forms`: the module's FormIndex, if the caller has one."""
    instrs = module.instrs
    forms = forms or FormIndex(instrs)
    return (once_per_program(instrs, forms) + one_user_per_device(instrs, forms) + mc_nesting(instrs, target, forms)
            + step_ladder(instrs, module.library, forms) + block_runs(instrs, target))


def once_per_program(instrs: list[Instr], forms: FormIndex | None = None) -> list[Diagnostic]:
    """E904: a `once` instruction written twice (any of its forms: HKY and DHKY count as one)."""
    first: dict = {}
    out = []
    for k in (forms or FormIndex(instrs)).matching(lambda spec: spec.once):
        ins = instrs[k]
        key = ins.spec.api if ins.spec.api is not None else ins.mnemonic
        if key in first:
            f = first[key]
            out.append(_at(ins, "E904", f"{ins.mnemonic} may be used only once in a program; "
                           f"already at {f.file}:{f.line} ({ins.spec.section})"))
        else:
            first[key] = ins
    return out


def one_user_per_device(instrs: list[Instr], forms: FormIndex | None = None) -> list[Diagnostic]:
    """E240: the D operand of a "unique-destination" instruction names a device another such
    instruction of the program already drives (VS DUTY, 6-16: M9330-M9334 "不可以重複")."""
    first: dict = {}
    out = []
    for at in (forms or FormIndex(instrs)).matching(lambda spec: "unique-destination" in spec.constraints):
        ins = instrs[at]
        if not ins.operands:
            continue
        k = next((i for i, o in enumerate(ins.spec.operands) if o.role == "D"), len(ins.operands) - 1)
        o = ins.operands[k]
        if o.index:
            continue  # which device it names is known at run time only
        key = (ins.spec.api, o.kind, o.number)
        if key in first:
            f = first[key]
            out.append(_at(ins, "E240", f"{ins.texts[k]} is already driven by {f.mnemonic} at {f.file}:{f.line}; "
                           f"each {ins.spec.operands[k].role} device may be used by one {ins.mnemonic} "
                           f"of the program ({ins.spec.section})"))
        else:
            first[key] = ins
    return out


def mc_nesting(instrs: list[Instr], target: Target, forms: FormIndex | None = None) -> list[Diagnostic]:
    """E903: MC levels start at N0 and go N1, N2 ... inward without gaps; MCR Nn closes level n
    and every deeper one (as the simulator does); every level is closed before FEND/END."""
    out: list[Diagnostic] = []
    opened: list[Instr] = []
    limit = target.settings.get("mc_levels")
    for k in (forms or FormIndex(instrs)).where(ops=("mc", "mcr", *_PART_ENDS)):
        ins = instrs[k]
        op = ins.spec.op
        if op == "mc" and ins.operands:
            n = ins.operands[0].number
            if n != len(opened):
                want = f"N{len(opened)}"
                where = "the outermost level is N0" if not opened else \
                    f"inside MC N{len(opened) - 1} (line {opened[-1].line}) the next level is {want}"
                out.append(_at(ins, "E903", f"MC N{n}: {where}", f"levels go N0, N1 ... inward in order ({ins.spec.section})"))
            if limit is not None and len(opened) >= limit:
                out.append(_at(ins, "E903", f"MC nested {len(opened) + 1} deep; the limit is {limit}"))
            opened.append(ins)
        elif op == "mcr" and ins.operands:
            n = ins.operands[0].number
            # by the level as written, so one misnumbered MC does not also fail its MCR
            at = next((k for k in range(len(opened) - 1, -1, -1) if opened[k].operands[0].number == n), None)
            if at is None:
                written = " ".join(o.texts[0] for o in opened)
                out.append(_at(ins, "E903", f"MCR N{n} closes no open MC level"
                               + (f" (open: {written})" if opened else " (none is open)")))
            else:
                del opened[at:]
        elif op in _PART_ENDS:
            for o in opened:
                out.append(_at(o, "E903", f"MC N{o.operands[0].number} is not closed by MCR before {ins.mnemonic}"))
            opened.clear()
    for o in opened:
        out.append(_at(o, "E903", f"MC N{o.operands[0].number} is not closed by MCR"))
    return out


def step_ladder(instrs: list[Instr], library: bool, forms: FormIndex | None = None) -> list[Diagnostic]:
    """E902, the step-ladder rules of the manual (VS 4-4, 4-6-1): no STL after FEND
    (subroutines, interrupt routines) or in a library; each step relay opens one STL block;
    MPS not directly on the STL bus (before the step's first load); no MC/MCR inside a step;
    the step blocks end with RET before FEND/END."""
    out: list[Diagnostic] = []
    if not (forms or FormIndex(instrs)).where(ops=("stl", "ret")):
        return out
    after_fend = library
    step: Instr | None = None  # the open STL block
    on_bus = False  # directly on the STL bus: no load since the STL
    seen: dict[int, Instr] = {}  # step -> the STL of its own block
    merged: dict[int, Instr] = {}  # step -> the STL naming it in a merge
    merge = _merges(instrs)
    for k, ins in enumerate(instrs):
        op, cls = ins.spec.op, ins.spec.cls
        if op == "stl" and ins.operands:
            s = ins.operands[0].number
            if after_fend:
                out.append(_at(ins, "E902", "STL after FEND: step ladder may not be used in subroutines "
                               "or interrupt routines"))
            # a merge's STLs in series name steps that may have their own block too (4-6-2's
            # parallel merge: STL S22 / OUT Y20 ... STL S22 / STL S24 / LD X3 / SET S25)
            if k in merge:
                if s in merged:
                    out.append(_at(ins, "E902", f"STL {ins.texts[0]}: the step already merges at line "
                                   f"{merged[s].line}; a step leaves through one merge"))
                merged.setdefault(s, ins)
                if merge[k] == 8:
                    out.append(_at(ins, "W320", f"{merge[k] + 1}th step merged here; a merge joins 2 to 8 "
                                   "steps (4-3-3)"))
            else:
                if s in seen:
                    out.append(_at(ins, "E902", f"STL {ins.texts[0]}: the step already has a block at line "
                                   f"{seen[s].line}; each step relay opens one block"))
                seen.setdefault(s, ins)
            step, on_bus = ins, True
            continue
        if op == "ret":
            if step is None:
                out.append(_at(ins, "E902", "RET without a preceding STL block"))
            step = None
            on_bus = False
            continue
        if step is not None:
            if cls == "load":
                on_bus = False
            elif cls == "mps" and on_bus:
                out.append(_at(ins, "E902", "MPS directly on the STL bus; start the branch with a load (4-6-1)"))
            if op in ("mc", "mcr"):
                out.append(_at(ins, "E902", f"{ins.mnemonic} inside the step block of {step.texts[0]} "
                               f"(line {step.line}); MC/MCR may not be used in step ladder"))
            if op in _PART_ENDS:
                out.append(_at(step, "E902", f"the step ladder opened by STL {step.texts[0]} has no RET "
                               f"before {ins.mnemonic} (line {ins.line})"))
                step = None
        if op == "fend":
            after_fend = True
    if step is not None:
        out.append(_at(step, "E902", f"the step ladder opened by STL {step.texts[0]} has no RET"))
    return out


def _merges(instrs: list[Instr]) -> dict[int, int]:
    """The STLs written one after the other (a merge: 4-3-3, 4-6-2): instruction index ->
    how many STLs of its run come before it."""
    out: dict[int, int] = {}
    run: list[int] = []
    for k, ins in enumerate([*instrs, None]):
        if ins is not None and ins.spec.op == "stl":
            run.append(k)
            continue
        if len(run) > 1:
            out.update((at, n) for n, at in enumerate(run))
        run = []
    return out


def block_runs(instrs: list[Instr], target: Target) -> list[Diagnostic]:
    """E906: more consecutive ANB/ORB than the target allows (VS 3-4: at most 8)."""
    limit = target.settings.get("block_ops_run")
    if limit is None:
        return []
    out, run = [], 0
    for ins in instrs:
        if ins.spec.cls in ("anb", "orb"):
            run += 1
            if run == limit + 1:
                out.append(_at(ins, "E906", f"{run} ANB/ORB in a row; the limit is {limit}",
                               "combine blocks as they are written (LD ... ORB LD ... ORB) instead of batching them"))
        else:
            run = 0
    return out
