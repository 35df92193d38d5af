"""Linked Image -> executable steps, decoded once: operand accessors, label and FOR/NEXT
targets, rung boundaries, and the routine each step runs (table-driven on `spec.op`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Image, Instr, rung_starts
from mlctool.sim import semantics
from mlctool.sim.operands import Ref, decode_operand
from mlctool.sim.state import DeviceView
from mlctool.targetapi.model import OperandSpec, Target
from mlctool.targetapi.registry import simulation_of


@dataclass(slots=True, eq=False)
class Step:
    ins: Instr
    index: int
    ops: tuple[Ref, ...]
    width: int
    steps: int
    table: tuple[int, ...]
    new_rung: bool = False  # a load that starts a rung (after an output, label or free instr)
    target: int = -1  # CJ/CALL: label index; FOR: its NEXT; NEXT: its FOR; STL: see decode()
    run: Callable = field(default=semantics.nop)


@dataclass
class Program:
    steps: list[Step]
    labels: dict[int, int]  # P number -> step index
    image: Image
    target: Target


# Step.target of an STL whose step the STL after it joins (read by the target's step ladder routine)
STL_JOINED = -2

# the ops that move the rail (VS 3-6 MC/MCR, 4-6-1 STL/RET): a program holding one has rungs
# whose rail may be Off (m.bus), and then every point of such a rung is Off (_railed)
RAIL_OPS = frozenset({"stl", "ret", "mc", "mcr"})
# the ones that set the rail themselves: they run whatever its state
_RAIL_SETTERS = frozenset({"stl", "ret", "mcr"})


def _combine(cls: str, contact: Callable, railed: bool = False) -> Callable:
    """Contacts update the rung result by their class (2.2 LD/AND/OR). A contact is always
    evaluated, even when the result is already decided, so edge memories stay current.
    `railed`: the program moves the rail, so an OR is ANDed with it too (a parallel branch
    hangs on the same dead rail as the load: VS 3-6)."""
    if cls == "load":
        def run(m, s):
            v = contact(m, s) and m.bus  # the rail is Off in an inactive MC block or STL step
            if s.new_rung:
                m.blocks.clear()
                m.stack.clear()
            else:
                m.blocks.append(m.acc)
            m.acc = v
    elif cls == "and":
        def run(m, s):
            v = contact(m, s)
            m.acc = m.acc and v
    elif railed:
        def run(m, s):
            v = contact(m, s)
            m.acc = (m.acc or v) and m.bus
    else:
        def run(m, s):
            v = contact(m, s)
            m.acc = m.acc or v
    return run


def _railed(run: Callable) -> Callable:
    """A step of a program that moves the rail: while the rail is Off (an MC block whose
    condition is Off, VS 3-6; a step ladder block run once more after its step went Off,
    4-1-3) the step's rung has no power, whatever its contacts, INV or block operators made
    of the result: the step runs with the result Off (OUT coils and ordinary timers Off,
    SET/RST, retentive timers, counters and application instructions idle) and leaves it Off."""
    def gated(m, s):
        if not m.bus:
            m.acc = False
            r = run(m, s)
            m.acc = False
            return r
        return run(m, s)
    return gated


class NotSimulated(Exception):
    """The program holds an instruction the simulator does not model (E905)."""

    def __init__(self, ins: Instr):
        super().__init__(f"{ins.mnemonic} at {ins.file}:{ins.line} is not simulated")
        self.ins = ins


# the program-flow ops: scan.py's flow_routines (CJ, CALL, SRET, FEND, END, FOR, NEXT)
FLOW_OPS = frozenset({"cj", "call", "sret", "fend", "end", "for", "next"})


def actions(target: Target | None) -> dict:
    """op -> routine: the engine's generic routines and over them the target's own
    (its Simulation, mlctool/targetapi/simulation.py)."""
    own = simulation_of(target).actions if target is not None else None
    return {**semantics.ACTIONS, **own} if own else semantics.ACTIONS


def simulated_ops(target: Target | None = None) -> frozenset[str]:
    return frozenset(semantics.CONTACTS) | frozenset(actions(target)) | FLOW_OPS


def unsimulated(image: Image, target: Target | None = None) -> list[Diagnostic]:
    """E905 for every instruction of the image whose op has no routine: `mlc sim` refuses
    the program up front instead of skipping them. `target`: its own instructions count
    (its Simulation's actions)."""
    known = simulated_ops(target)
    return [diag(ins.file, Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic)), "E905",
                 f"{ins.mnemonic} (line {ins.line}) is not simulated ({ins.spec.section})",
                 "the target's docs list the simulated instructions (docs/vs.md)")
            for ins in image.instrs if ins.spec.op not in known]


def _pulsed(run: Callable) -> Callable:
    """P-suffix form: the routine runs only in the scan its condition goes Off->On; its edge
    memory is the step's own (pulse forms never have another use for it)."""
    def pulse(m, s):
        prev = m.edge[s.index]
        m.edge[s.index] = m.acc
        if m.acc and not prev:
            return run(m, s)
        return None
    return pulse


def _allowed(o: OperandSpec, op, width: int) -> tuple[tuple[int, int], ...]:
    """The numbers an operand's table entry narrows its kind to (ranges, devices16/32)."""
    narrow = o.devices32 if width == 32 else o.devices16
    spans = tuple(o.allowed(op.kind) or ())
    if narrow:
        spans = tuple((max(a, narrow[0]), min(b, narrow[1])) for a, b in spans or (narrow,)
                      if max(a, narrow[0]) <= min(b, narrow[1]))
    return spans


def decode(image: Image, target: Target, flow: dict[str, Callable], probe=None) -> Program:
    """`flow`: the program-flow routines of scan.py (CJ, CALL, SRET, FEND, END, FOR, NEXT).
    `probe`: a coverage recorder (mlctool/sim/campaign/coverage.py) whose wrappers every step runs through."""
    steps: list[Step] = []
    starts = rung_starts(image.instrs)
    routines = actions(target)
    # accessors are read-only after construction: one per distinct (operand, width, text,
    # use), shared by the steps (an object's decoded operands are shared objects, so the
    # operand's id names it; ids stay valid while `image` holds the operands)
    refs: dict[tuple, Ref] = {}
    combined: dict[tuple[str, str], Callable] = {}
    railed = any(ins.spec.op in RAIL_OPS for ins in image.instrs)
    for k, ins in enumerate(image.instrs):
        spec = ins.spec
        contact_like = spec.cls in ("load", "and", "or") and spec.api is None
        ops = []
        for o_spec, op, text in zip(spec.operands, ins.operands, ins.texts, strict=False):
            as_bits = contact_like or (spec.op == "vrt" and o_spec.role == "S")
            allowed = _allowed(o_spec, op, spec.width) if op.index else ()
            key = (id(op), spec.width, text, as_bits, allowed)
            ref = refs.get(key)
            if ref is None:
                dev = target.devices.get(op.device) if not op.is_const else None
                if dev is not None and dev.kind == "pointer":
                    ref = Ref(op, 16, dev.hi, text)
                else:
                    ref = decode_operand(op, spec.width, target, text, as_bits)
                ref.allowed = allowed
                refs[key] = ref
            ops.append(ref)
        step = Step(ins, k, tuple(ops), spec.width, ins.steps, ins.table,
                    new_rung=starts[k])
        op = spec.op
        if op in semantics.CONTACTS:
            contact = semantics.CONTACTS[op]
            if probe:
                step.run = _combine(spec.cls, probe.contact(contact), railed)
            else:  # the step comes as an argument: one routine per (class, contact) serves all
                key = (spec.cls, op)
                step.run = combined.get(key) or combined.setdefault(key, _combine(spec.cls, contact, railed))
        elif op in routines:
            step.run = routines[op]
        elif op in flow:
            step.run = flow[op]
        else:  # refused up front by unsimulated(); never a silent no-op
            raise NotSimulated(ins)
        if spec.pulse:
            step.run = _pulsed(step.run)
        if probe:
            step.run = probe.step(step.run, spec.cls)
        if railed and op not in semantics.CONTACTS and op not in _RAIL_SETTERS:
            step.run = _railed(step.run)  # outside the probe: it sees the rung as it runs
        steps.append(step)
    labels = {s.ins.operands[0].number: s.index for s in steps if s.ins.spec.cls == "label"}
    end = next((s.index for s in steps if s.ins.spec.op == "end"), None)
    for p in target.end_labels if end is not None else ():  # CJ P63: to END (VS 2-10)
        labels.setdefault(p, end)
    for s in steps:
        if s.ins.spec.op in ("cj", "call") and not s.ins.operands[0].index:
            s.target = labels.get(s.ins.operands[0].number, -1)
    # STL: the next block's first STL or the RET, where an inactive step's block ends (4-6-1);
    # STL_JOINED for an STL the next instruction (an STL) joins: their steps are one block
    # (a parallel merge, 4-3-3), decided at its last STL
    following = -1
    for s in reversed(steps):
        if s.ins.spec.op == "stl":
            joins = s.index > 0 and steps[s.index - 1].ins.spec.op == "stl"
            joined = s.index + 1 < len(steps) and steps[s.index + 1].ins.spec.op == "stl"
            s.target = STL_JOINED if joined else following
            if not joins:
                following = s.index
        elif s.ins.spec.op == "ret":
            following = s.index
    open_fors: list[Step] = []
    for s in steps:  # FOR/NEXT pair by nesting in program order (4.1 API-07/08)
        if s.ins.spec.op == "for":
            open_fors.append(s)
        elif s.ins.spec.op == "next" and open_fors:
            f = open_fors.pop()
            f.target, s.target = s.index, f.index
    return Program(steps, labels, image, target)


# Float instructions whose operand holds a 32-bit integer, not a float (4.8 API-63/64).
_INTEGER_ROLE = {"fint": "D", "fdot": "S"}


def program_devices(prog: Program) -> set[DeviceView]:
    """Every device the program names, in the view its instruction uses it."""
    out: set[DeviceView] = set()
    seen: set[tuple] = set()  # (spec, operands) by id: a repeated instruction names nothing new
    for s in prog.steps:
        spec = s.ins.spec
        form = (id(spec), *map(id, s.ins.operands))
        if form in seen:
            continue
        seen.add(form)
        for o_spec, op in zip(spec.operands, s.ins.operands, strict=False):
            out.update(_views(prog.target, spec, o_spec, op, s.ins.operands))
    return out


def _views(target: Target, spec, o_spec, op, all_ops) -> list[DeviceView]:
    if op.is_const or op.kind == "P" or op.unit:  # U1G3: module memory, not a PLC device (5-1: not monitored)
        return []
    dev = target.devices[op.device]
    if dev.kind == "pointer":  # N (MC levels), Q (tables)
        return []
    if op.is_group:
        return [DeviceView("K", op.number, "group", op.digits, op.device, dev.radix)]
    if op.is_bit_of_word:
        return [DeviceView(op.device, op.number, "w")]
    if dev.kind == "bit":
        count = o_spec.bits
        if spec.op in ("deco", "enco", "vrt"):
            n_op = next(o for o, so in zip(all_ops, spec.operands, strict=False) if so.role == "n")
            count = n_op.value if spec.op == "vrt" else 1 << n_op.value
        return [DeviceView(op.kind, op.number + k, "bit", radix=dev.radix) for k in range(count)
                if op.number + k <= dev.hi]
    if dev.kind in ("timer", "counter"):
        value = "w" if dev.kind == "timer" or not target.is_counter32(op.number) else "d"
        contact = spec.api is None or spec.op in ("tmr", "cnt", "vrt")
        data = spec.api is not None or spec.op == "rst"
        views = [DeviceView(op.kind, op.number, "bit")] if contact else []
        return views + ([DeviceView(op.kind, op.number, value)] if data else [])
    if op.kind == "Z" or spec.api is None or spec.op in ("for", "wrtl", "rdtl", "deco", "enco", "bon"):
        return [DeviceView(op.kind, op.number, "w")]
    if spec.width == 16:
        words, size, view = o_spec.words[0], 1, "w"
    else:
        words, size = o_spec.words[1], 2
        view = "f" if spec.is_float and _INTEGER_ROLE.get(spec.op) != o_spec.role else "d"
    if op.kind == "V":
        return [DeviceView("V", op.number, view)]
    return [DeviceView(op.kind, op.number + k, view) for k in range(0, words, size)
            if op.number + k + size - 1 <= dev.hi]
