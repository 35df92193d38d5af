"""Lint: legal but suspicious programs (warnings; each code can be turned off)."""

from __future__ import annotations

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import FormIndex, Instr, Module
from mlctool.targetapi.model import Target


def _at(ins: Instr, _k: int | None, code: str, msg: str, *notes: str) -> Diagnostic:
    return diag(ins.file, Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic)), code, msg, *notes)


def _first_seen(instrs, key_of) -> list[tuple[Instr, Instr]]:
    """(later, first) pairs of instructions sharing a key."""
    first: dict = {}
    pairs = []
    for ins in instrs:
        key = key_of(ins)
        if key is None:
            continue
        if key in first:
            pairs.append((ins, first[key]))
        else:
            first[key] = ins
    return pairs


def _where(ins: Instr) -> str:
    return f"{ins.file}:{ins.line}"


def exclusive_regions(instrs: list[Instr]) -> list[int]:
    """Per instruction, the exclusive region it lies in (0: none). An instruction whose table
    entry says `region = "open"` (STL) starts a new region, `region = "close"` (RET) ends them:
    only one step of a flow is live, so a coil driven in two steps is no double coil (VS 4-4)."""
    out, region, count = [], 0, 0
    for ins in instrs:
        if ins.spec.region == "open":
            count += 1
            region = count
        elif ins.spec.region == "close":
            region = 0
        out.append(region)
    return out


def double_coils(instrs: list[Instr], code: str = "W401", forms: FormIndex | None = None) -> list[Diagnostic]:
    """OUT of one coil twice. Two OUTs in different exclusive regions (STL steps) are fine;
    twice in one region, or in a region and outside every region, is a double coil."""
    seen: dict = {}  # coil -> {region: first instruction}
    out = []
    forms = forms or FormIndex(instrs)
    # a program without STL steps (most) lies in no region: no pass to number them
    regions = exclusive_regions(instrs) if forms.matching(lambda spec: spec.region) else None
    if regions is None:  # one region: the first OUT of a coil is the one to name
        first: dict = {}
        for k in forms.where(ops=("out",)):
            ins = instrs[k]
            o = ins.operands[0]
            if o.index:
                continue
            f = first.setdefault((o.kind, o.number), ins)
            if f is not ins:
                out.append(_at(ins, None, code, f"{ins.texts[0]} is also driven at {_where(f)}; "
                               "the last OUT in the scan wins (1.3.2)"))
        return out
    for k in forms.where(ops=("out",)):
        ins = instrs[k]
        region = regions[k] if regions else 0
        o = ins.operands
        if o[0].index:
            continue
        by_region = seen.setdefault((o[0].kind, o[0].number), {})
        f = by_region.get(region) or (None if region else next(iter(by_region.values()), None)) \
            or by_region.get(0)
        if f is not None:
            out.append(_at(ins, None, code, f"{ins.texts[0]} is also driven at {_where(f)}; "
                           "the last OUT in the scan wins (1.3.2)"))
        by_region.setdefault(region, ins)
    return out


def _steps(instrs: list[Instr]) -> tuple[list[int | None], set[tuple[int, int]], dict[int, list[Instr]]]:
    """Per instruction the step (S number) whose STL block it lies in (None: none); the pairs of
    adjacent steps (one transfers to the other by SET/OUT S inside its block); per step the
    transfers written in it."""
    step_of_region: dict[int, int] = {}
    sources: dict[int, tuple[int, ...]] = {}  # region -> its steps: all of a merge's (STLs in series, 4-6-2)
    steps: list[int | None] = []
    regions = exclusive_regions(instrs)
    run: tuple[int, ...] = ()  # the steps of the STLs written one after the other so far
    for ins, region in zip(instrs, regions, strict=True):
        if ins.spec.region == "open":
            run = (*run, ins.operands[0].number)
            step_of_region[region] = ins.operands[0].number
            sources[region] = run
        else:
            run = ()
        steps.append(step_of_region.get(region) if region else None)
    adjacent: set[tuple[int, int]] = set()
    transfers: dict[int, list[Instr]] = {}
    for ins, step, region in zip(instrs, steps, regions, strict=True):
        if step is not None and ins.spec.op in ("step_set", "step_out") and ins.operands[0].kind == "S" \
                and not ins.operands[0].index:
            target = ins.operands[0].number
            for source in sources.get(region, (step,)):
                adjacent |= {(source, target), (target, source)}
            transfers.setdefault(step, []).append(ins)
    return steps, adjacent, transfers


def _timers_driven_twice(instrs: list[Instr], forms: FormIndex, steps: list[int | None] | None,
                         adjacent: set[tuple[int, int]]) -> list[Diagnostic]:
    """W402: a timer or counter driven by two instructions. ANS times its own timer ("請勿在程序
    中使用已在本指令中使用過的計時器編號", VS 6-6). Two steps of a step ladder that are not
    adjacent may share a timer, with different presets ("非相接的狀態，可以使用同一編號的計時器",
    VS 4-4): only one of them is live at a time. `steps`, `adjacent`: _steps()'s (None: the
    program has no step ladder, no instruction lies in a step)."""
    first: dict[tuple[str, int], list[tuple[Instr, int | None]]] = {}
    out = []
    for k in forms.where(ops=("tmr", "cnt", "ans")):
        ins = instrs[k]
        step = steps[k] if steps is not None else None
        key = (ins.operands[0].kind, ins.operands[0].number)
        seen = first.setdefault(key, [])
        clash = next((f for f, fs in seen if step is None or fs is None or fs == step or (fs, step) in adjacent), None)
        if clash is not None:
            out.append(_at(ins, None, "W402", f"{ins.texts[0]} is also driven at {_where(clash)}"))
        seen.append((ins, step))
    return out


def _step_branches(transfers: dict[int, list[Instr]], limit: int = 8) -> list[Diagnostic]:
    """W224: more than 8 transfers out of one step ("每一個選擇性分歧或並進式分歧，最多只能有 8個
    分歧點", VS 4-4). `transfers`: _steps()'s."""
    out = []
    for step, moves in transfers.items():
        targets = list(dict.fromkeys(m.operands[0].number for m in moves))
        if len(targets) > limit:
            first_over = next(m for m in moves if m.operands[0].number == targets[limit])
            out.append(_at(first_over, None, "W224", f"step S{step} branches to {len(targets)} steps; "
                           f"a divergence has at most {limit} branches (4-4)"))
    return out


def _span(first: int, words: int) -> str:
    """Registers as the manual writes a pair: (D1, D0); D0-D3 for longer spans."""
    return f"(D{first + 1}, D{first})" if words == 2 else f"D{first}-D{first + words - 1}"


def lint_module(module: Module, target: Target, referenced: set[int],
                forms: FormIndex | None = None) -> list[Diagnostic]:
    """`forms`: the module's FormIndex, if the caller has one."""
    instrs = module.instrs
    forms = forms or FormIndex(instrs)
    out = double_coils(instrs, forms=forms)

    # the steps of a step ladder (STL), worked out once for both rules, and only in a program
    # that has one (most have none: no instruction then lies in a step)
    if forms.matching(lambda spec: spec.region == "open"):
        steps, adjacent, transfers = _steps(instrs)
    else:
        steps, adjacent, transfers = None, set(), {}
    out += _timers_driven_twice(instrs, forms, steps, adjacent)
    out += _step_branches(transfers)

    # multi-word D operands (32-bit pairs, the 32-bit product of a 16-bit MUL, the quotient and
    # remainder of DIV: OperandSpec.words) overlapping other uses of their registers
    words16: dict[int, Instr] = {}
    spans: dict[int, tuple[Instr, int]] = {}  # first register -> (instruction, words)
    widest = 1
    words_of: dict[int, tuple[int, ...]] = {}  # id(form) -> the words each of its operands occupies
    for k in forms.matching(lambda spec: spec.api is not None):
        ins = instrs[k]
        words = words_of.get(id(ins.spec))
        if words is None:
            words = words_of[id(ins.spec)] = tuple(s.words[1] if ins.spec.width == 32 else s.words[0]
                                                   for s in ins.spec.operands)
        for n, o in zip(words, ins.operands, strict=False):
            if o.kind != "D" or o.index:
                continue
            if n > 1:
                for other in range(o.number - widest + 1, o.number + n):
                    hit = spans.get(other)
                    if other != o.number and hit is not None and hit[0] is not ins \
                            and other + hit[1] > o.number:
                        out.append(_at(ins, None, "W403", f"{_span(o.number, n)} overlaps "
                                       f"{_span(other, hit[1])} used at {_where(hit[0])}"))
                for high in range(o.number + 1, o.number + n):
                    if high in words16:
                        out.append(_at(ins, None, "W403", f"{_span(o.number, n)} overlaps D{high} used as a "
                                       f"16-bit word at {_where(words16[high])}"))
                spans.setdefault(o.number, (ins, n))
                widest = max(widest, n)
            else:
                for first in range(o.number - widest + 1, o.number):
                    hit = spans.get(first)
                    if hit is not None and first + hit[1] > o.number:
                        out.append(_at(ins, None, "W403", f"D{o.number} is a high word of "
                                       f"{_span(first, hit[1])} used at {_where(hit[0])}"))
                words16.setdefault(o.number, ins)

    # labels nobody jumps to
    for k in forms.where(classes=("label",)):
        ins = instrs[k]
        p = ins.operands[0].number
        if p not in referenced and p not in module.exports:
            name = ins.texts[0] if ins.texts else f"P{p}"  # a named label as written
            out.append(_at(ins, None, "W404", f"{name} is never the target of CJ or CALL"))
    return out + _dead_code(instrs, forms)


def _dead_code(instrs: list[Instr], forms: FormIndex) -> list[Diagnostic]:
    """W406, unreachable: after FEND, SRET or IRET, until the next label or interrupt pointer.
    Only the stretches that start at one of those are walked (END, FEND, NOP in the stretch
    keep it dead)."""
    out = []
    walked = 0  # instructions before this one were walked as part of a stretch
    for start in forms.where(ops=("fend", "sret", "iret")):
        if start < walked:
            continue
        dead = True
        k = start + 1
        while dead and k < len(instrs):
            ins = instrs[k]
            if ins.spec.cls in ("label", "interrupt"):
                dead = False
            elif ins.spec.op not in ("end", "fend", "nop"):
                out.append(_at(ins, None, "W406", f"{ins.mnemonic} is never executed: it follows FEND/SRET/IRET "
                               "and no label"))
                dead = False  # one warning per dead stretch
            if ins.spec.op in ("fend", "sret", "iret"):
                dead = True
            k += 1
        walked = k
    return out


def set_without_reset(modules: list[Module], forms: list[FormIndex] | None = None) -> list[Diagnostic]:
    """W405 over one program (a main module and its libraries): a SET device that nothing
    resets (RST, ZRST, OUT, or an application instruction writing it). `forms`: the modules'
    FormIndex, in their order, if the caller has them."""
    if forms is not None and not any(f.where(ops=("set",)) for f in forms):
        return []  # (the usual program SETs little or nothing: no walk to find out)
    instrs = [ins for m in modules for ins in m.instrs]
    sets = [ins for ins in instrs if ins.spec.op == "set" and not ins.operands[0].index]
    if not sets:  # nothing to look for (the usual program SETs little or nothing)
        return []
    reset: set = set()
    ranges: list = []
    writing: dict[int, tuple[bool, ...]] = {}  # id(form) -> which operands it writes
    for ins in instrs:
        if ins.spec.op in ("rst", "out", "alt", "pls", "plf") and not ins.operands[0].index:
            reset.add((ins.operands[0].kind, ins.operands[0].number))
        elif ins.spec.op == "zrst":
            a, b = ins.operands
            ranges.append((a.kind, min(a.number, b.number), max(a.number, b.number)))
        elif ins.spec.api is not None:
            writes = writing.get(id(ins.spec))
            if writes is None:
                writes = writing[id(ins.spec)] = tuple(s.writes for s in ins.spec.operands)
            for o, w in zip(ins.operands, writes, strict=False):
                if w:
                    reset.add((o.kind, o.number))
                    if o.is_group:
                        ranges.append((o.device, o.number, o.number + 4 * o.digits - 1))
    out, seen = [], set()
    for ins in sets:
        key = (ins.operands[0].kind, ins.operands[0].number)
        if key in reset or key in seen or any(k == key[0] and lo <= key[1] <= hi for k, lo, hi in ranges):
            continue
        seen.add(key)
        out.append(_at(ins, None, "W405", f"{ins.texts[0]} is SET but never reset"))
    return out


def referenced_labels(modules: list[Module], forms: list[FormIndex] | None = None) -> tuple[set[int], set[int]]:
    """(all P referenced by CJ/CALL, P referenced by CALL). `forms`: the modules' FormIndex,
    in their order, if the caller has them."""
    refs, calls = set(), set()
    for k, m in enumerate(modules):
        jumps = m.instrs if forms is None else [m.instrs[j] for j in forms[k].where(ops=("cj", "call"))]
        for ins in jumps:
            if ins.spec.op in ("cj", "call") and not ins.operands[0].index:
                refs.add(ins.operands[0].number)
                if ins.spec.op == "call":
                    calls.add(ins.operands[0].number)
    return refs, calls


def cross_module_coils(modules: list[Module]) -> list[Diagnostic]:
    """W401 for a coil driven by OUT in two modules of one program (first module wins the
    'first' role: the main program comes first)."""
    first: dict = {}
    out = []
    for m in modules:
        for ins in m.instrs:
            if ins.spec.op != "out" or ins.operands[0].index:
                continue
            key = (ins.operands[0].kind, ins.operands[0].number)
            f = first.setdefault(key, ins)
            if f.file != ins.file:
                out.append(_at(ins, None, "W401", f"{ins.texts[0]} is also driven at {_where(f)}; "
                               "the last OUT in the scan wins (1.3.2)"))
    return out
