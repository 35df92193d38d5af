"""Program structure: END/FEND layout, labels, CJ/CALL targets, FOR/NEXT, rung stack balance."""

from __future__ import annotations

from bisect import bisect_right

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import FormIndex, Instr, Module, rung_starts
from mlctool.targetapi.model import Target

JUMPS = ("cj", "call")


def _at(ins: Instr, code: str, msg: str, *notes: str) -> Diagnostic:
    return diag(ins.file, Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic)), code, msg, *notes)


def check_rungs(module: Module, target: Target, broken: frozenset[int] = frozenset()) -> list[Diagnostic]:
    """Walk the contact/block/stack machine of each rung (2.2 ANB, ORB, MPS, MRD, MPP).

    `broken`: lines that did not parse or name no instruction (E103, E201; already reported).
    A rung next to such a line has lost an instruction, so its rung errors would only echo
    the first error: they are not reported."""
    out: list[Diagnostic] = []
    gaps = sorted(broken)
    tainted = hit = False
    depth_limit = target.settings["mps_depth"]
    acc = False  # a current result exists
    driven = False  # the current rung has driven at least one output
    after_out = False  # the current result is an output's (no load since): OR cannot reach back
    blocks = 0  # blocks waiting for ANB/ORB
    pushed: list[Instr] = []  # the open MPS instructions, innermost last
    last = None

    def emit(d: Diagnostic) -> None:
        if not tainted:
            out.append(d)

    def close(ins: Instr | None) -> None:
        nonlocal acc, driven, after_out, blocks, tainted
        where = ins or last
        if where is not None and acc and not driven:
            emit(_at(where, "E313", "rung ends without an output"))
        elif where is not None and blocks:
            emit(_at(where, "E313", f"{blocks} block(s) never combined with ANB/ORB"))
        if where is not None and pushed:  # at the MPS left open (the first), not where the rung ends
            emit(_at(pushed[0], "E308", f"{len(pushed)} MPS without MPP at the end of the rung",
                     f"the rung ends before {where.mnemonic} at line {where.line}" if where is ins
                     else f"the rung ends at line {where.line}"))
        acc = driven = after_out = False
        blocks = 0
        pushed.clear()
        tainted = hit  # a broken line just before `ins` may belong to the next rung too

    prev_line = 0
    starts = rung_starts(module.instrs)
    for n, ins in enumerate(module.instrs):
        if gaps:
            g = bisect_right(gaps, prev_line)
            hit = g < len(gaps) and gaps[g] < ins.line
            tainted = tainted or hit
        prev_line = ins.line
        cls = ins.spec.cls
        if cls == "load":
            if starts[n] and driven:
                close(ins)
            if acc:
                blocks += 1
            acc = True
            after_out = False
        elif cls in ("and", "or", "inv"):
            if not acc or after_out and cls == "or":
                emit(_at(ins, "E311", f"{ins.mnemonic} needs a preceding load (LD, LDI, LDP, LD=, ...)"))
            acc = True
        elif cls in ("anb", "orb"):
            if blocks < 1:
                emit(_at(ins, "E310", f"{ins.mnemonic} needs two blocks, each started by a load"))
            else:
                blocks -= 1
        elif cls == "mps":
            if not acc:
                emit(_at(ins, "E311", "MPS needs a current result"))
            pushed.append(ins)
            if len(pushed) > depth_limit:
                emit(_at(ins, "E309", f"MPS nested {len(pushed)} deep; the stack holds {depth_limit}"))
        elif cls in ("mrd", "mpp"):
            if not pushed:
                emit(_at(ins, "E308", f"{ins.mnemonic} without a preceding MPS"))
            elif cls == "mpp":
                pushed.pop()
        elif cls == "output":
            extra = max(len(ins.spec.inputs) - 1, 0)  # multi-input: one block per further input
            if not acc:
                emit(_at(ins, "E312", f"{ins.mnemonic} has no driving condition"))
            elif blocks < extra:
                emit(_at(ins, "E313", f"{ins.mnemonic} takes {len(ins.spec.inputs)} inputs "
                         f"({', '.join(ins.spec.inputs)}), one block each; got {blocks + 1}"))
                blocks = 0
            elif blocks > extra:
                blocks -= extra
                emit(_at(ins, "E313", f"{blocks} block(s) not combined with ANB/ORB before {ins.mnemonic}"))
                blocks = 0
            else:
                blocks = 0
            driven = after_out = True
            acc = True
        elif cls in ("free", "label", "interrupt"):
            close(ins)
        elif cls == "bus":  # STL: a new rail whose result exists; a load after it starts a rung
            close(ins)
            acc = driven = after_out = True
        last = ins
    hit = bool(gaps) and gaps[-1] > prev_line
    tainted = tainted or hit
    close(None)
    return out


def _cited(target: Target, key: str) -> str:
    """" (SECTION)" of the target's manual for a rule (target.toml `key`), or ""."""
    section = target.settings.get(key)
    return f" ({section})" if section else ""


def _call_nesting(instrs: list[Instr], labels: dict[int, int], sub_start: int, target: Target) -> list[Diagnostic]:
    """A CALL that would open level call_depth+1, as the target's manual rules it (target.toml
    `call_beyond`, issue 30.17): "error", E307 (VS 6-2 "巢狀式子程序呼叫不可超過 5層", error
    6702); "skipped" (the default), W613: the CPU does not run that subroutine and the scan
    goes on (NC5 4.1 API-01 "若進入第六層則該副程式不執行"), as the simulator does on every
    target. A subroutine runs from its label to its first SRET; only CALLs of a written P
    number are followed (an indexed one is the simulator's to see)."""
    limit = target.settings["call_depth"]
    error = target.settings.get("call_beyond", "skipped") == "error"
    section = _cited(target, "call_section")
    def calls(first: int, last: int) -> list[Instr]:
        return [i for i in instrs[first:last] if i.spec.op == "call" and not i.operands[0].index]

    def body(p: int) -> list[Instr]:
        k = labels.get(p)
        if k is None:
            return []
        end = next((j for j in range(k + 1, len(instrs)) if instrs[j].spec.op in ("sret", "end")), len(instrs))
        return calls(k + 1, end)

    out: list[Diagnostic] = []
    reported: set[int] = set()

    def walk(ins: Instr, level: int, chain: tuple[int, ...]) -> None:
        p = ins.operands[0].number
        if level > limit:
            if id(ins) not in reported:
                reported.add(id(ins))
                path = " -> ".join(f"P{q}" for q in chain + (p,))
                out.append(_at(ins, "E307" if error else "W613", f"CALL nested {level} deep ({path}); the "
                               f"limit is {limit}: the CPU does not run it{section}"))
            return
        for inner in body(p):
            walk(inner, level + 1, chain + (p,))

    for ins in calls(0, sub_start):
        walk(ins, 1, ())
    return out


def check_layout(module: Module, target: Target, exported: dict[int, str], is_called: set[int],
                 broken: frozenset[int] = frozenset(), forms: FormIndex | None = None) -> list[Diagnostic]:
    """END, FEND, labels, jumps, FOR/NEXT. `exported` maps P -> module of every module's exports;
    `forms`: the module's FormIndex, if the caller has one."""
    out: list[Diagnostic] = []
    instrs = module.instrs
    forms = forms or FormIndex(instrs)
    ends = forms.where(ops=("end",))
    if module.library:
        for k in ends:
            out.append(_at(instrs[k], "E305", "a .library module has no END; the linker adds it"))
    elif not ends:
        # a broken last line is most likely the END itself, already reported
        if not (broken and max(broken) > (instrs[-1].line if instrs else 0)):
            line = instrs[-1].line if instrs else 1
            out.append(diag(module.path, Span.at(line), "E301", "program has no END"))
    elif ends[0] != len(instrs) - 1:
        out.append(_at(instrs[ends[0] + 1], "E302", "code after END is never scanned"))
    fends = forms.where(ops=("fend",))
    sub_start = 0 if module.library else (fends[0] + 1 if fends else len(instrs))

    # labels
    labels: dict[int, int] = {}
    ends = target.end_labels
    for k in forms.where(classes=("label",)):
        ins = instrs[k]
        p = ins.operands[0].number
        if p in ends:
            out.append(_at(ins, "E303", f"P{p} stands for END on target {target.name} (CJ P{p} jumps "
                           "to END); it cannot label a line"))
        elif p in labels:
            name = ins.texts[0] if ins.texts else f"P{p}"  # a named label as written
            out.append(_at(ins, "E303", f"{name} already labels line {instrs[labels[p]].line}"))
        else:
            labels[p] = k
    cj_targets: dict[int, Instr] = {}
    call_targets: dict[int, Instr] = {}
    for k in forms.where(ops=JUMPS):
        ins = instrs[k]
        if not ins.operands[0].index:
            p = ins.operands[0].number
            (call_targets if ins.spec.op == "call" else cj_targets).setdefault(p, ins)
            if p in ends and ins.spec.op == "call":
                out.append(_at(ins, "E305", f"CALL P{p}: P{p} stands for END; only CJ may use it"))
            elif p not in labels and p not in exported and not (p in ends and ins.spec.op == "cj"):
                out.append(_at(ins, "E304", f"{ins.mnemonic} P{p}: no such label"
                               + (" (labels of other modules must be .export-ed)" if p not in labels else "")))
    shared = set(cj_targets) & (set(call_targets) | is_called)
    for p in sorted(shared):
        out.append(_at(cj_targets[p], "E305", f"P{p} is used by CALL, so CJ may not use it (4.1 API-00)"))
    for p, ins in sorted(call_targets.items()):
        if p in labels and labels[p] < sub_start:
            out.append(_at(ins, "E305", f"CALL target P{p} lies before FEND; subroutines go after FEND (4.1 API-01)"))
    for p, ins in sorted(cj_targets.items()):
        if p in labels and p not in shared and ((labels[p] >= sub_start) != (instrs.index(ins) >= sub_start)):
            out.append(_at(ins, "E305", f"CJ P{p} jumps between the main program and the subroutine area"))
    for k in forms.where(ops=("sret",)):
        if k < sub_start:
            out.append(_at(instrs[k], "E305", "SRET before FEND: subroutines go after FEND"))

    # FOR/NEXT pairing per program part
    limit = target.settings["for_depth"]
    stack: list[Instr] = []
    for k in forms.where(ops=("for", "next", "fend", "end", "sret")):
        ins = instrs[k]
        op = ins.spec.op
        if op == "for":
            stack.append(ins)
            if len(stack) > limit:
                out.append(_at(ins, "E307", f"FOR nested {len(stack)} deep; the limit is {limit}"
                               f"{_cited(target, 'for_section')}"))
        elif op == "next":
            if not stack:
                out.append(_at(ins, "E306", "NEXT without FOR"))
            else:
                stack.pop()
        elif op in ("fend", "end", "sret"):
            for f in stack:
                out.append(_at(f, "E306", f"FOR without NEXT before {ins.mnemonic}"))
            stack.clear()
    for f in stack:
        out.append(_at(f, "E306", "FOR without NEXT"))
    out += _call_nesting(instrs, labels, sub_start, target)

    capacity = target.capacity
    total = module.total_steps
    if total > capacity:
        out.append(diag(module.path, Span.at(instrs[-1].line), "E314",
                        f"program has {total} steps; the target holds {capacity}"))
    return out
