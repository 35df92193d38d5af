"""IL rungs <-> ladder networks (series/parallel elements and a tree of output branches).

A rung is what the MLC evaluates between two loads that follow an output (2.2; the exact
rule, with its MPS exception, is program.rung_starts): contacts
combine into a result by LD/AND/OR, blocks by ANB/ORB, and MPS/MRD/MPP fork the output side.
Here the instruction sequence is evaluated *symbolically*: the accumulator holds a list of
series elements instead of a bit, so the same stack machine that the simulator runs yields
the picture a ladder editor would draw.

Output side: every point where lines split is a `Node` (an MPS, or a coil followed by more
of the rung: `LD X0 / OUT Y0 / AND X1 / OUT Y1`). Its `lines` are in execution order.

IL can express a little more than ladder: an OR or ORB after an MPS reaches back across the
branch point (`LD X0 / MPS / AND X1 / OR X2 / OUT Y1 / MPP ...`). Such a line is drawn fed
from the rail (`from_rail`) with a `Tap` contact standing for the power at the branch point.
No editor produces that form, so converting it back gives the rung's own instructions.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from mlctool.program import Instr, rung_starts
from mlctool.targetapi.model import InstrSpec, Target

CONTACT_CLASSES = ("load", "and", "or")  # a contact's class picks its LD/AND/OR form
ROW_CLASSES = ("label", "interrupt", "free")  # drawn as rows of their own; they end a rung


class LadderError(Exception):
    """A rung the converter cannot take apart: only for programs `mlc check` rejects."""

    def __init__(self, message: str, ins: Instr | None = None):
        super().__init__(message)
        self.message = message
        self.ins = ins


@dataclass(eq=False, slots=True)
class Leaf:
    """One instruction in a series line: a contact (any LD/AND/OR form), INV or NOP."""

    ins: Instr
    index: int  # position in the module's instruction list


@dataclass(eq=False, slots=True)
class Tap:
    """The power at a branch point, used where IL combines it with the rail (see module doc)."""

    node: Node


@dataclass(eq=False, slots=True)
class Parallel:
    branches: list[list]  # each branch: series elements, evaluated from the rail and ORed


@dataclass(eq=False, slots=True)
class Group:
    """A block evaluated on its own and put in series (ANB): scopes an INV inside it."""

    elems: list


@dataclass(eq=False, slots=True)
class Coil:
    """An output-class instruction: coil or application-instruction box."""

    ins: Instr
    index: int


@dataclass(eq=False, slots=True)
class Pin:
    """A further input of a multi-input instruction (FBs FUN140 EN/PAU/ABT: one block each,
    the first drives the Coil): the line ends at the box's input `name`."""

    coil: Coil
    name: str


@dataclass(eq=False, slots=True)
class Line:
    """Series elements from a branch point (or the rail) to a coil, an input pin of a
    multi-input box, a further branch point, or nothing (`to=None`: a trailing
    INV/NOP/contact the rung never uses)."""

    elems: list
    to: Coil | Pin | Node | None
    from_rail: bool = False  # fed from the rail, not from the branch point it hangs on


@dataclass(eq=False, slots=True)
class Node:
    lines: list[Line] = field(default_factory=list)
    addr: int = 0  # step address of the instruction that made the branch point


@dataclass(eq=False, slots=True)
class Rung:
    """A rung, or a whole step of a step ladder: STL's state box on the rail, and every rung
    of the step hanging on the step's own bus right of the box (VS 4-6-1: "內STL母線"), up
    to the next STL, RET or row."""

    root: Node  # the left rail: its lines start at the rail
    start: int  # index of the rung's first instruction in the module
    stop: int  # one past its last instruction
    has_tap: bool = False
    step: bool = False  # a step ladder step (starts with STL)
    pins: bool = False  # holds a multi-input instruction

    @property
    def addr(self) -> int:
        return self.root.addr

    @property
    def own_il(self) -> bool:
        """Converting back gives the rung's own instructions: forms with no editor IL of
        their own (a Tap, a step, a multi-input box)."""
        return self.has_tap or self.step or self.pins


@dataclass(eq=False, slots=True)
class Row:
    """A label (P10) or an instruction without a driving contact (FEND, SRET, FOR, NEXT, END,
    or a NOP outside any rung)."""

    ins: Instr
    index: int

    @property
    def addr(self) -> int:
        return self.ins.addr


Item = Rung | Row


# --------------------------------------------------------------- IL -> network


@dataclass(slots=True)
class _Value:
    """The symbolic accumulator: series elements fed from `origin` (None: from the rail)."""

    origin: Node | None
    elems: list


def _has_inv(elems: list) -> bool:
    return any(isinstance(e, Leaf) and e.ins.spec.cls == "inv" for e in elems)


def _series(a: list, b: list) -> list:
    # AND is associative, so b joins a's line, unless an INV in b would then invert a too
    return a + ([Group(b)] if _has_inv(b) else b)


def _parallel(a: list, b: list) -> list:
    def branches(x: list) -> list:
        return x[0].branches if len(x) == 1 and isinstance(x[0], Parallel) else [x]
    return [Parallel(branches(a) + branches(b))]


def _from_rail(v: _Value) -> list:
    return v.elems if v.origin is None else [Tap(v.origin)] + v.elems


class _Builder:
    """The rung stack machine of 2.2 over symbolic values; one instance per rung."""

    def __init__(self, rail: Node):
        self.rail = rail
        self.scope = rail  # where a line fed from the rail hangs (keeps execution order)
        self.acc: _Value | None = None
        self.blocks: list[_Value] = []
        self.stack: list[Node] = []
        self.has_tap = False
        self.has_pins = False

    def attach(self, to: Coil | Pin | Node | None, v: _Value | None = None) -> None:
        v = v or self.acc
        home = v.origin or self.scope
        self.has_tap = self.has_tap or any(isinstance(e, Tap) for e in _walk(v.elems))
        home.lines.append(Line(v.elems, to, from_rail=v.origin is None and home is not self.rail))

    def need_acc(self, ins: Instr) -> _Value:
        if self.acc is None:
            raise LadderError(f"{ins.mnemonic} has no current result to work on", ins)
        return self.acc

    def need_block(self, ins: Instr) -> _Value:
        if not self.blocks:
            raise LadderError(f"{ins.mnemonic} needs two blocks", ins)
        return self.blocks.pop()

    def need_fork(self, ins: Instr, pop: bool) -> Node:
        if not self.stack:
            raise LadderError(f"{ins.mnemonic} without MPS", ins)
        return self.stack.pop() if pop else self.stack[-1]

    # one method per instruction class; `step` dispatches on spec.cls
    def load(self, leaf: Leaf) -> None:
        if self.acc is not None:
            self.blocks.append(self.acc)
        self.acc = _Value(None, [leaf])

    def series(self, leaf: Leaf) -> None:  # and, inv, nop
        acc = self.need_acc(leaf.ins)
        self.acc = _Value(acc.origin, acc.elems + [leaf])

    def or_(self, leaf: Leaf) -> None:
        self.acc = _Value(None, _parallel(_from_rail(self.need_acc(leaf.ins)), [leaf]))

    def anb(self, leaf: Leaf) -> None:
        a = self.need_acc(leaf.ins)
        b = self.need_block(leaf.ins)
        self.acc = _Value(b.origin, _series(b.elems, _from_rail(a)))

    def orb(self, leaf: Leaf) -> None:
        a = self.need_acc(leaf.ins)
        b = self.need_block(leaf.ins)
        self.acc = _Value(None, _parallel(_from_rail(b), _from_rail(a)))

    def mps(self, leaf: Leaf) -> None:
        self.need_acc(leaf.ins)
        node = Node(addr=leaf.ins.addr)
        self.attach(node)
        self.stack.append(node)
        self.scope = node
        self.acc = _Value(node, [])

    def mrd(self, leaf: Leaf) -> None:
        self.scope = self.need_fork(leaf.ins, pop=False)
        self.acc = _Value(self.scope, [])

    def mpp(self, leaf: Leaf) -> None:
        self.scope = self.need_fork(leaf.ins, pop=True)
        self.acc = _Value(self.scope, [])

    def output(self, leaf: Leaf) -> None:
        acc = self.need_acc(leaf.ins)
        inputs = leaf.ins.spec.inputs
        if len(inputs) > 1:  # one block per input, the first (EN) pushed first
            self.multi_input(leaf, inputs)
            return
        if acc.elems or acc.origin is None:
            # the point after the condition: later outputs and ANDs of this rung hang on it
            node = Node(addr=leaf.ins.addr)
            self.attach(node)
            self.scope = node
            self.acc = acc = _Value(node, [])
        acc.origin.lines.append(Line([], Coil(leaf.ins, leaf.index)))

    def multi_input(self, leaf: Leaf, inputs: tuple[str, ...]) -> None:
        extra = len(inputs) - 1
        if len(self.blocks) < extra:
            raise LadderError(f"{leaf.ins.mnemonic} takes {len(inputs)} inputs, one block each", leaf.ins)
        values = self.blocks[len(self.blocks) - extra:] + [self.acc]
        del self.blocks[len(self.blocks) - extra:]
        coil = Coil(leaf.ins, leaf.index)
        self.attach(coil, values[0])
        for v, name in zip(values[1:], inputs[1:], strict=True):
            self.attach(Pin(coil, name), v)
        self.has_pins = True
        self.acc = _Value(None, [])

    def finish(self, last: Instr) -> None:
        if self.blocks:
            raise LadderError("a block is never combined with ANB/ORB", last)
        if self.stack:
            raise LadderError("MPS without MPP at the end of the rung", last)
        if self.acc is not None and self.acc.elems:
            self.attach(None)


_STEP = {
    "load": _Builder.load, "and": _Builder.series, "inv": _Builder.series, "nop": _Builder.series,
    "or": _Builder.or_, "anb": _Builder.anb, "orb": _Builder.orb, "mps": _Builder.mps,
    "mrd": _Builder.mrd, "mpp": _Builder.mpp, "output": _Builder.output,
}


def _walk(elems: list):
    """Every element, nested ones included."""
    for e in elems:
        yield e
        if isinstance(e, Parallel):
            for b in e.branches:
                yield from _walk(b)
        elif isinstance(e, Group):
            yield from _walk(e.elems)


def _normalize(node: Node) -> None:
    """Splice branch points that split nothing: `Line([], node)` joins its parent, and a line
    into a node with a single line continues straight on."""
    out: list[Line] = []
    for line in node.lines:
        if isinstance(line.to, Node):
            _normalize(line.to)
            inner = line.to.lines
            if not line.elems and not line.from_rail:
                out.extend(inner)
                continue
            if len(inner) == 1 and not inner[0].from_rail:
                line = Line(line.elems + inner[0].elems, inner[0].to, line.from_rail)
        out.append(line)
    node.lines = out


def split_rungs(instrs: list[Instr], starts: list[bool] | None = None) -> list[tuple[int, int] | int]:
    """Rung boundaries as the simulator and `mlc check` see them (program.rung_starts):
    (start, stop) for a rung, an index for a row of its own. A step (STL) is one item from
    its STL to the next STL, RET or row: its rungs hang on the step's bus."""
    out: list[tuple[int, int] | int] = []
    start: int | None = None
    in_step = False
    starts = starts if starts is not None else rung_starts(instrs)
    for k, ins in enumerate(instrs):
        cls = ins.spec.cls
        if cls in ROW_CLASSES or (start is None and cls == "nop"):
            if start is not None:
                out.append((start, k))
                start = None
            in_step = False
            out.append(k)
            continue
        if cls == "bus":
            if start is not None and not (in_step and instrs[k - 1].spec.cls == "bus"):
                out.append((start, k))
                start = None
            if start is None:
                start, in_step = k, True
        elif cls == "load" and (start is None or starts[k] and not in_step):
            if start is not None:
                out.append((start, k))
            start = k
        elif start is None:
            raise LadderError(f"{ins.mnemonic} needs a preceding load", ins)
    if start is not None:
        out.append((start, len(instrs)))
    return out


def build_rung(instrs: list[Instr], start: int, stop: int, starts: list[bool] | None = None) -> Rung:
    rail = Node(addr=instrs[start].addr)
    b = _Builder(rail)
    first = start  # the first instruction the stack machine runs
    step = instrs[start].spec.cls == "bus"
    if step:
        # the state box(es) on the rail (several STL in a row: steps joining, drawn in series);
        # the step's bus right of them carries the power of the step
        boxes = []
        while first < stop and instrs[first].spec.cls == "bus":
            boxes.append(Leaf(instrs[first], first))
            first += 1
        inner = Node(addr=instrs[start].addr)
        rail.lines.append(Line(boxes, inner))
        starts = starts if starts is not None else rung_starts(instrs)
        b.rail = b.scope = inner
        b.acc = _Value(None, [])  # coils may hang on the step's bus directly (4-6-1 (1))
    for k in range(first, stop):
        ins = instrs[k]
        if step and starts[k]:  # the next rung of the step, fed from the step's bus
            b.finish(instrs[k - 1])
            b.scope, b.acc = b.rail, None
        fn = _STEP.get(ins.spec.cls)
        if fn is None:  # pragma: no cover - split_rungs keeps rows out of rungs
            raise LadderError(f"{ins.mnemonic} cannot be part of a rung", ins)
        fn(b, Leaf(ins, k))
    b.finish(instrs[stop - 1])
    _normalize(rail)
    # one line leaves the rail (the inputs of a multi-input box: one each)
    if not rail.lines or rail.lines[0].from_rail or len(rail.lines) > 1 and not b.has_pins:  # pragma: no cover
        raise LadderError("rung does not start at the rail", instrs[start])
    return Rung(rail, start, stop, b.has_tap, step=step, pins=b.has_pins)


def build_items(instrs: list[Instr]) -> list[Item]:
    """A module's instructions -> rungs and rows, in program order."""
    items: list[Item] = []
    starts = rung_starts(instrs)
    for part in split_rungs(instrs, starts):
        if isinstance(part, int):
            items.append(Row(instrs[part], part))
        else:
            items.append(build_rung(instrs, *part, starts))
    return items


# --------------------------------------------------------------- network -> IL


def form_table(target: Target) -> dict[tuple[str, str, int], InstrSpec]:
    """(class, op, width) -> spec: the LD, AND and OR forms of one contact."""
    return {(s.cls, s.op, s.width): s for s in target.instructions.values()}


class _Emitter:
    def __init__(self, instrs: list[Instr], forms: dict):
        self.src = instrs
        self.forms = forms
        self.out: list[Instr] = []

    def contact(self, leaf: Leaf, cls: str) -> None:
        spec = leaf.ins.spec
        if spec.cls in CONTACT_CLASSES:
            spec = self.forms[(cls, spec.op, spec.width)]
        self.out.append(dataclasses.replace(leaf.ins, spec=spec))

    def plain(self, op: str) -> None:
        spec = self.forms[(op, op, 16)]
        self.out.append(Instr(spec, (), (), spec.steps, 0, "", 0))

    def block(self, e) -> None:
        """e starts a new block (LD ...)."""
        if isinstance(e, Leaf):
            self.contact(e, "load")
        elif isinstance(e, Parallel):
            self.series(e.branches[0], True)
            for b in e.branches[1:]:
                if len(b) == 1 and isinstance(b[0], Leaf) and b[0].ins.spec.cls in CONTACT_CLASSES:
                    self.contact(b[0], "or")
                else:
                    self.series(b, True)
                    self.plain("orb")
        elif isinstance(e, Group):
            self.series(e.elems, True)
        else:
            raise LadderError(f"{type(e).__name__} cannot start a block")

    def series(self, elems: list, first: bool) -> None:
        for k, e in enumerate(elems):
            if first and k == 0:
                self.block(e)
            elif isinstance(e, Leaf):
                self.contact(e, "and")
            else:
                self.block(e)
                self.plain("anb")

    def line(self, line: Line, first: bool) -> None:
        self.series(line.elems, first)
        if isinstance(line.to, Coil):
            self.out.append(line.to.ins)
        elif isinstance(line.to, Node):
            self.node(line.to)

    def node(self, node: Node) -> None:
        """A branch point: MPS before the first line that changes the result, MRD/MPP to
        get it back; lines of bare coils need neither (an output keeps the result)."""
        pushed = dirty = False
        n = len(node.lines)
        for k, line in enumerate(node.lines):
            last = k == n - 1
            changes = bool(line.elems) or not isinstance(line.to, Coil)
            if pushed:
                if last:
                    self.plain("mpp")
                elif dirty:
                    self.plain("mrd")
            elif changes and not last:
                self.plain("mps")
                pushed = True
            self.line(line, False)
            dirty = changes


def rung_to_il(rung: Rung, instrs: list[Instr], forms: dict) -> list[Instr]:
    """An equivalent instruction sequence for the rung (LD/AND/OR forms, ANB/ORB, MPS/MRD/MPP
    chosen as a ladder editor would). Rungs with no editor form (Rung.own_il) give back their
    own instructions."""
    if rung.own_il:
        return list(instrs[rung.start:rung.stop])
    em = _Emitter(instrs, forms)
    em.line(rung.root.lines[0], True)
    return em.out


def items_to_il(items: list[Item], instrs: list[Instr], target: Target) -> list[Instr]:
    """The whole module back to IL, with step addresses recomputed."""
    forms = form_table(target)
    out: list[Instr] = []
    for it in items:
        out += rung_to_il(it, instrs, forms) if isinstance(it, Rung) else [it.ins]
    addr = 0
    for k, ins in enumerate(out):
        out[k] = dataclasses.replace(ins, addr=addr)
        addr += ins.steps
    return out
