"""The compiled engine: the decoded program turned once into specialised Python code.

The reference interpreter (scan.py) runs one routine per step. This engine cuts the program
into basic blocks (a block starts at step 0, at every P label and after every program-flow
instruction) and generates one Python function per block in which

- the rung result is a local (`a`), ANB/ORB/MPS/MRD/MPP work on locals resolved at compile
  time, contacts and coils on plain devices are subscripts of the device arrays (held in
  locals), simple MOV/ADD/SUB/INC/DEC/CML/WAND/WOR/WXOR/TMR and compare contacts are inlined;
- every other instruction calls the reference routine of semantics.py (`step.run`), and
  program flow (CJ, CALL, SRET, FOR, NEXT, FEND, END) calls the flow routines of scan.py at
  the end of its block, so the semantics are the interpreter's by construction;
- the writer of each device (for failure messages) is recorded as the interpreter does; writes
  that always happen are batched into one dict update per block.

Faults name the same step as the interpreter (mapped from the generated line). The watchdog
is checked per block: a block that would pass the limit is run by the interpreter loop from
its first step, which stops at the same step. The code of a program is cached by a content
hash; binding it to a Machine is cheap.

Programs the engine does not handle (a rung stack left open across a block boundary, a
contact-class instruction it does not know) run on the reference interpreter: `scanner()`
falls back silently and `Scanner.engine` says which one runs.
"""

from __future__ import annotations

import hashlib
import math
import os
import struct
from collections import OrderedDict
from collections.abc import Callable
from types import CodeType

from mlctool.sim import scan as _scan
from mlctool.sim import semantics
from mlctool.sim.decode import Program, Step
from mlctool.sim.operands import BitRef, ConstRef, CounterRef, GroupRef, WordRef
from mlctool.sim.scan import DEFAULT_WATCHDOG, END_SCAN, Fault, end_of_scan, run_scan
from mlctool.sim.semantics import advance_timer
from mlctool.sim.state import Machine, SimFault, f32_bits, to_f32

ENGINES = ("compiled", "interp")
DEFAULT_ENGINE = "compiled"
ENGINE_ENV = "MLC_SIM_ENGINE"
COMPILER_VERSION = "2"

FLOW_OPS = frozenset({"cj", "call", "sret", "fend", "end", "for", "next"})
RUNG_CLASSES = frozenset({"load", "and", "or", "anb", "orb", "mps", "mrd", "mpp", "inv"})
BIT_KINDS = ("X", "Y", "M", "A", "T", "C")
WORD_KINDS = ("D", "V", "Z", "T")
_CMP = {"cmp_eq": "==", "cmp_ne": "!=", "cmp_gt": ">", "cmp_lt": "<", "cmp_ge": ">=", "cmp_le": "<="}
_FLOAT = {"fadd": "+", "fsub": "-", "fmul": "*"}
_ARITH = {"add": "+", "sub": "-", "wand": "&", "wor": "|", "wxor": "^"}


# what run_scan does before the first step, where the target defines it (system relays)
_before_scan = getattr(_scan, "system_relays", None)


_T01 = bytes.maketrans(b"\x00\x01", b"01")  # device bits -> binary digits (Kn groups)


_PACK_I, _UNPACK_F = struct.Struct("<I").pack, struct.Struct("<f").unpack


def _f32_of_bits(raw: int) -> float:
    """What `_float` makes of a D pair: to_f32(Ref.getf()) (identity but for NaN)."""
    x = _UNPACK_F(_PACK_I(raw & 0xFFFFFFFF))[0]
    return x if x == x else to_f32(x)


class Unsupported(Exception):
    """The program needs the reference interpreter."""


class Code:
    """A program compiled to Python: the code object and what the driver needs to run it."""

    def __init__(self, key: str, code: CodeType, filename: str, starts: list[int],
                 block_steps: list[int], linemap: list[int], source: str):
        self.key = key
        self.code = code
        self.filename = filename
        self.starts = starts  # first step index of each block
        self.block_steps = block_steps  # steps executed by each block (for the watchdog)
        self.linemap = linemap  # generated line (0-based) -> step index
        self.source = source


_CACHE: OrderedDict[str, Code | None] = OrderedDict()
_CACHE_SIZE = 32


def program_key(prog: Program) -> str:
    """Content hash of what the generated code depends on."""
    h = hashlib.sha256(f"{COMPILER_VERSION}\0{prog.target.name}\0".encode())
    for s in prog.steps:
        ins = s.ins
        h.update(repr((ins.spec.mnemonic, ins.spec.op, ins.operands, ins.table, s.steps, s.new_rung,
                       s.target)).encode())
        h.update(b"\n")
    return h.hexdigest()


def compile_program(prog: Program) -> Code | None:
    """The program's compiled code (cached by content hash), or None: use the interpreter."""
    key = program_key(prog)
    if key in _CACHE:
        _CACHE.move_to_end(key)
        return _CACHE[key]
    try:
        code = _Gen(prog, key).build()
    except Unsupported:
        code = None
    _CACHE[key] = code
    while len(_CACHE) > _CACHE_SIZE:
        _CACHE.popitem(last=False)
    return code


# ---------------------------------------------------------------------------- code generation

def _bit_simple(ref) -> bool:
    return type(ref) is BitRef and ref.ix is None and ref.kind in BIT_KINDS


def _s16(expr: str) -> str:
    return f"(({expr} ^ 32768) - 32768)"


def _s32(expr: str) -> str:
    return f"(({expr} ^ 2147483648) - 2147483648)"


class _Gen:
    def __init__(self, prog: Program, key: str):
        self.prog = prog
        self.key = key
        self.filename = f"<mlc-compiled {key[:16]}>"
        self.lines: list[str] = []
        self.linemap: list[int] = []
        self.c32_lo = prog.target.settings["counters32"][0]

    # -- output helpers
    def emit(self, text: str, step: int, depth: int = 1) -> None:
        self.lines.append("    " * depth + text)
        self.linemap.append(step)

    def build(self) -> Code:
        steps = self.prog.steps
        if not steps:
            raise Unsupported("empty program")
        starts = sorted({0} | {s.index for s in steps if s.ins.spec.cls == "label"}
                        | {s.index + 1 for s in steps if s.ins.spec.op in FLOW_OPS} - {len(steps)})
        bounds = starts + [len(steps)]
        block_of = {st: j for j, st in enumerate(starts)}
        self.block_of = block_of
        block_steps = []
        for j in range(len(starts)):
            block = steps[bounds[j]:bounds[j + 1]]
            block_steps.append(sum(s.steps for s in block))
            self.block(j, block, len(starts))
        source = "\n".join(self.lines) + "\n"
        code = compile(source, self.filename, "exec")
        return Code(self.key, code, self.filename, starts, block_steps, self.linemap, source)

    # -- one block
    def block(self, j: int, block: list[Step], nblocks: int) -> None:
        first = block[0].index
        self.emit(f"def b{j}(m):", first, 0)
        header_at = len(self.lines)
        self.used: set[str] = set()
        self.pending: dict[tuple[str, int], int] = {}
        self.blocks: list[str] = []  # symbolic ANB/ORB block stack: names of locals
        self.stack: list[str] = []  # symbolic MPS stack
        self.tmp = 0
        self.acc: str | None = None  # the rung result when not (yet) in `a`
        self.depth = 0
        self.emit("a = m.acc", first)
        ended = False
        for s in block:
            op = s.ins.spec.op
            if op in FLOW_OPS:
                self.flow(s, j)
                ended = True
                break
            self.instr(s)
        if not ended:
            self.settle(block[-1].index)
            self.exit_checks(block[-1])
            self.flush(block[-1].index)
            self.emit("m.acc = a", block[-1].index)
            self.emit(f"return {j + 1}", block[-1].index)
        header = [f"{name} = G_{name}" for name in sorted(self.used)]
        self.lines[header_at:header_at] = ["    " + h for h in header]
        self.linemap[header_at:header_at] = [first] * len(header)

    def exit_checks(self, s: Step) -> None:
        if self.blocks or self.stack:
            raise Unsupported(f"rung stack open across a block boundary at step {s.index}")

    def new_tmp(self, prefix: str) -> str:
        self.tmp += 1
        return f"{prefix}{self.tmp}"

    # -- device expressions
    def use(self, name: str) -> str:
        self.used.add(name)
        return name

    def bit(self, ref) -> str:
        return f"{self.use('b' + ref.kind)}[{ref.num}]"

    def value(self, ref, i: int, j: int) -> str:
        """Signed value of an operand as Ref.get gives it."""
        w = ref.width
        if type(ref) is ConstRef and ref.ix is None:
            return repr(ref.get(None))
        if type(ref) is WordRef and ref.ix is None and ref.kind in WORD_KINDS:
            arr = self.use("w" + ref.kind)
            n = ref.num
            if w == 16 or ref.kind == "Z":
                return _s16(f"{arr}[{n}]")
            if ref.kind == "V":
                return _s32(f"({self.use('wZ')}[{n}] << 16 | {arr}[{n}])")
            if n + 1 <= ref.hi:
                return _s32(f"({arr}[{n + 1}] << 16 | {arr}[{n}])")
        if type(ref) is GroupRef and ref.ix is None and ref.kind in ("X", "Y", "M", "A") \
                and ref.num + ref.n - 1 <= ref.hi:
            arr, a, n = self.use("b" + ref.kind), ref.num, ref.n
            expr = f"int({arr}[{a}:{a + n}][::-1].translate(T01), 2)"
            if n == w:  # K4 in 16-bit and K8 in 32-bit are signed (GroupRef.get)
                return _s16(expr) if w == 16 else _s32(expr)
            return expr
        if type(ref) is CounterRef and ref.ix is None:
            cv = self.use("cv")
            n = ref.num
            if w == 16:
                return _s16(f"({cv}[{n}] & 65535)")
            if n >= self.c32_lo:
                return _s32(f"({cv}[{n}] & 4294967295)")
            if n + 1 <= ref.hi:
                return _s32(f"(({cv}[{n + 1}] << 16 | {cv}[{n}]) & 4294967295)")
        return f"O{i}_{j}.get(m)"

    def store_keys(self, ref) -> list[tuple[str, int]] | None:
        """Writer keys of an inline store to `ref`, or None: Ref.set runs it."""
        if type(ref) is WordRef and ref.ix is None and ref.kind in WORD_KINDS:
            n = ref.num
            if ref.width == 16 or ref.kind == "Z":
                return [(ref.kind, n)]
            if ref.kind == "V":
                return [("V", n), ("Z", n)]
            if n + 1 <= ref.hi:
                return [(ref.kind, n), (ref.kind, n + 1)]
        return None

    def store(self, ref, expr: str, s: Step, j: int, depth: int) -> None:
        """Write of a signed value as Ref.set does; `prepare(store_keys(ref))` came first."""
        i = s.index
        keys = self.store_keys(ref)
        if keys is None:
            self.emit(f"m.pc = {i}", i, depth)
            self.emit(f"O{i}_{j}.set(m, {expr})", i, depth)
            return
        arr = self.use("w" + ref.kind)
        n = ref.num
        for k in keys:
            self.emit(f"W[{k!r}] = {i}", i, depth)
        if len(keys) == 1:
            self.emit(f"{arr}[{n}] = {expr} & 65535", i, depth)
            return
        hi_arr = self.use("wZ") if ref.kind == "V" else arr
        self.emit(f"v = {expr}", i, depth)
        self.emit(f"{arr}[{n}] = v & 65535", i, depth)
        self.emit(f"{hi_arr}[{keys[1][1]}] = (v >> 16) & 65535", i, depth)

    # -- writer tracking
    def prepare(self, keys, i: int) -> None:
        """Before a conditional write: pending writer records of the same device go first
        (all of them when the written devices are not known at compile time)."""
        if keys is None or any(k in self.pending for k in keys):
            self.flush(i)

    def cond_writer(self, keys, i: int, depth: int) -> None:
        for k in keys:
            self.emit(f"W[{k!r}] = {i}", i, depth)

    def defer_writer(self, key, i: int) -> None:
        self.pending.pop(key, None)
        self.pending[key] = i

    def flush(self, i: int) -> None:
        if not self.pending:
            return
        if len(self.pending) == 1:
            (k, v), = self.pending.items()
            self.emit(f"W[{k!r}] = {v}", i)
        else:
            self.emit(f"W.update({dict(self.pending)!r})", i)
        self.pending = {}

    # -- instructions
    def reference(self, s: Step) -> None:
        """Run the interpreter's routine for this step."""
        if s.ins.spec.cls in RUNG_CLASSES:
            raise Unsupported(f"no compiled form for {s.ins.mnemonic}")
        i = s.index
        self.flush(i)
        self.emit(f"m.acc = a; m.pc = {i}", i)
        self.emit(f"S{i}.run(m, S{i})", i)
        self.emit("a = m.acc", i)

    def contact(self, s: Step) -> str | None:
        """The contact's value as an expression without side effects; reads that can fault and
        edge memories are done first, on lines of their own (faults name this step)."""
        i = s.index
        op = s.ins.spec.op
        ref = s.ops[0]
        if op in _CMP:
            x, y = self.value(s.ops[0], i, 0), self.value(s.ops[1], i, 1)
            expr = f"({x} {_CMP[op]} {y})"
            if "(m)" in expr:
                t = self.new_tmp("c")
                self.emit(f"{t} = {expr}", i)
                return t
            return expr
        if op not in ("contact", "contact_not", "contact_rise", "contact_fall"):
            return None
        if _bit_simple(ref):
            b = self.bit(ref)
        else:
            b = self.new_tmp("c")
            self.emit(f"{b} = O{i}_0.bit(m)", i)
        if op == "contact":
            return b
        if op == "contact_not":
            return f"({b} ^ 1)"
        e = self.use("bE")
        c, p = self.new_tmp("c"), self.new_tmp("e")
        self.emit(f"{c} = {b}; {p} = {e}[{i}]; {e}[{i}] = {c}", i)
        return f"({c} & ({p} ^ 1))" if op == "contact_rise" else f"({p} & ({c} ^ 1))"

    # -- the rung result: an expression (`self.acc`) until something needs it in `a`
    def cur(self) -> str:
        return self.acc if self.acc is not None else "a"

    def set_acc(self, expr: str, i: int) -> None:
        self.acc = expr
        self.depth += 1
        if self.depth > 24:  # keep expressions shallow
            self.settle(i)

    def settle(self, i: int) -> None:
        if self.acc is not None:
            self.emit(f"a = {self.acc}", i)
            self.acc = None
        self.depth = 0

    def rung(self, s: Step) -> None:
        spec = s.ins.spec
        op, cls, i = spec.op, spec.cls, s.index
        if cls in ("load", "and", "or"):
            c = self.contact(s)
            if c is None:
                raise Unsupported(f"no compiled form for {s.ins.mnemonic}")
            if cls == "load":
                if s.new_rung:
                    self.blocks.clear()
                    self.stack.clear()
                    self.acc, self.depth = None, 0
                else:
                    k = self.new_tmp("k")
                    self.emit(f"{k} = {self.cur()}", i)
                    self.blocks.append(k)
                    self.depth = 0
                self.set_acc(c, i)
            elif cls == "and":
                self.set_acc(f"({self.cur()} & {c})", i)
            else:
                self.set_acc(f"({self.cur()} | {c})", i)
        elif op == "anb":
            if self.blocks:
                self.set_acc(f"({self.blocks.pop()} & {self.cur()})", i)
        elif op == "orb":
            if self.blocks:
                self.set_acc(f"({self.blocks.pop()} | {self.cur()})", i)
        elif op == "mps":
            k = self.new_tmp("p")
            self.emit(f"{k} = {self.cur()}", i)
            self.stack.append(k)
            self.acc, self.depth = k, 0
        elif op == "mrd":
            if self.stack:
                self.acc, self.depth = self.stack[-1], 0
        elif op == "mpp":
            if self.stack:
                self.acc, self.depth = self.stack.pop(), 0
        else:  # inv
            self.set_acc(f"({self.cur()} ^ 1)", i)

    def instr(self, s: Step) -> None:
        spec = s.ins.spec
        op, i = spec.op, s.index
        if getattr(spec, "pulse", False):  # pulse (P) forms: the decoder's wrapper decides
            if spec.cls in RUNG_CLASSES:
                raise Unsupported(f"no compiled form for {s.ins.mnemonic}")
            self.settle(i)
            self.reference(s)
            return
        if spec.cls in RUNG_CLASSES:
            if op not in ("anb", "orb", "mps", "mrd", "mpp", "inv") and spec.cls not in ("load", "and", "or"):
                raise Unsupported(f"no compiled form for {s.ins.mnemonic}")
            self.rung(s)
            return
        if op in ("nop", "label"):
            return
        if s.run is not semantics.ACTIONS.get(op):  # a target's own routine for this op
            self.settle(i)
            self.reference(s)
            return
        if op == "out" and _bit_simple(s.ops[0]) and s.ops[0].kind in ("Y", "M", "A"):
            dst = self.bit(s.ops[0])
            if self.acc is not None:
                self.emit(f"{dst} = a = {self.acc}", i)
                self.acc, self.depth = None, 0
            else:
                self.emit(f"{dst} = a", i)
            self.defer_writer((s.ops[0].kind, s.ops[0].num), i)
            return
        self.settle(i)
        if op in ("set", "rst", "pls", "plf") and _bit_simple(s.ops[0]) \
                and s.ops[0].kind in ("Y", "M", "A"):
            self.coil(s)
        elif op == "tmr":
            self.tmr(s)
        elif op in ("mov", "inc", "dec", "cml") or op in _ARITH:
            self.word_op(s)
        elif op == "mul":
            self.mul(s)
        elif op == "cnt":
            self.cnt(s)
        elif op in _FLOAT:
            self.float_op(s)
        else:
            self.reference(s)

    def coil(self, s: Step) -> None:
        op, i, ref = s.ins.spec.op, s.index, s.ops[0]
        key = (ref.kind, ref.num)
        dst = self.bit(ref)
        if op in ("set", "rst"):
            self.prepare([key], i)
            self.emit("if a:", i)
            self.emit(f"{dst} = {1 if op == 'set' else 0}", i, 2)
            self.cond_writer([key], i, 2)
        else:
            e = self.use("bE")
            self.emit(f"e = {e}[{i}]; {e}[{i}] = 1 if a else 0", i)
            cond = "a and not e" if op == "pls" else "e and not a"
            self.emit(f"{dst} = 1 if {cond} else 0", i)
            self.defer_writer(key, i)

    def tmr(self, s: Step) -> None:
        i = s.index
        t, pre = s.ops
        if t.ix is not None or not (type(pre) is ConstRef and pre.ix is None
                                    or type(pre) is WordRef and pre.ix is None and pre.kind == "D"):
            self.reference(s)
            return
        n = t.num
        preset = str(pre.get(None) & 0xFFFF) if type(pre) is ConstRef else f"{self.use('wD')}[{pre.num}]"
        self.emit(f"{self.use('ts')}[{n}] = 1", i)
        self.prepare([("T", n)], i)
        self.emit("if a:", i)
        self.cond_writer([("T", n)], i, 2)
        self.emit(f"adv(m, {n}, {preset})", i, 2)
        self.emit("else:", i)
        self.emit(f"m.reset_timer({n})", i, 2)

    def word_op(self, s: Step) -> None:
        op, i = s.ins.spec.op, s.index
        ops = s.ops
        if op == "mov":
            src, dst, di = self.value(ops[0], i, 0), ops[1], 1
        elif op in ("inc", "dec"):
            src, dst, di = f"({self.value(ops[0], i, 0)} {'+' if op == 'inc' else '-'} 1)", ops[0], 0
        elif op == "cml":
            src, dst, di = f"(~{self.value(ops[0], i, 0)})", ops[1], 1
        else:
            src = f"({self.value(ops[0], i, 0)} {_ARITH[op]} {self.value(ops[1], i, 1)})"
            dst, di = ops[2], 2
        if type(dst) is ConstRef:
            self.reference(s)
            return
        self.prepare(self.store_keys(dst), i)
        self.emit("if a:", i)
        self.store(dst, src, s, di, 2)

    def words_keys(self, ref, count: int) -> list[tuple[str, int]] | None:
        """Writer keys of `count` consecutive words from a plain D/T operand (set_words)."""
        if type(ref) is WordRef and ref.ix is None and ref.kind in ("D", "T") \
                and ref.num + count - 1 <= ref.hi:
            return [(ref.kind, ref.num + k) for k in range(count)]
        return None

    def mul(self, s: Step) -> None:
        """semantics.mul: the product in 2 (16-bit) or 4 (32-bit) words from D."""
        i = s.index
        count = 2 if s.width == 16 else 4
        keys = self.words_keys(s.ops[2], count)
        x, y = self.value(s.ops[0], i, 0), self.value(s.ops[1], i, 1)
        if keys is None or "(m)" in x + y:
            self.reference(s)
            return
        arr = self.use("w" + s.ops[2].kind)
        self.prepare(keys, i)
        self.emit("if a:", i)
        self.emit(f"v = {x} * {y}", i, 2)
        for k, key in enumerate(keys):
            self.emit(f"{arr}[{key[1]}] = (v >> {16 * k}) & 65535", i, 2)
            self.emit(f"W[{key!r}] = {i}", i, 2)

    def cnt(self, s: Step) -> None:
        """semantics.cnt for a 16-bit counter with a K or plain D preset."""
        i = s.index
        c, pre = s.ops
        if c.ix is not None or c.num >= self.c32_lo or not (
                type(pre) is ConstRef and pre.ix is None
                or type(pre) is WordRef and pre.ix is None and pre.kind == "D"):
            self.reference(s)
            return
        n = c.num
        preset = (str(max(pre.get(None) & 0xFFFF, 1)) if type(pre) is ConstRef
                  else f"max({self.use('wD')}[{pre.num}], 1)")
        e, cv, bc = self.use("bE"), self.use("cv"), self.use("bC")
        self.prepare([("C", n)], i)
        self.emit(f"pe = {e}[{i}]; {e}[{i}] = 1 if a else 0; v = {cv}[{n}]; pr = {preset}", i)
        self.emit("if a and not pe and v < pr:", i)
        self.emit(f"v += 1; {cv}[{n}] = v; W[('C', {n})] = {i}", i, 2)
        self.emit(f"if v >= pr and not {bc}[{n}]:", i)
        self.emit(f"m.c_pending[{n}] = 1", i, 2)

    def fvalue(self, ref, i: int, j: int) -> str | None:
        """The single-precision float `_float` computes from an operand, or None."""
        if type(ref) is ConstRef and ref.ix is None:
            x = to_f32(ref.getf(None))
            return repr(x) if math.isfinite(x) else None
        if type(ref) is WordRef and ref.ix is None and ref.kind == "D" and ref.num + 1 <= ref.hi:
            arr = self.use("wD")
            return f"FD({arr}[{ref.num + 1}] << 16 | {arr}[{ref.num}])"
        return None

    def float_op(self, s: Step) -> None:
        """FADD/FSUB/FMUL (semantics._float): operands and result in single precision."""
        i = s.index
        x, y = self.fvalue(s.ops[0], i, 0), self.fvalue(s.ops[1], i, 1)
        dst = s.ops[2]
        keys = self.words_keys(dst, 2) if type(dst) is WordRef and dst.kind == "D" else None
        if x is None or y is None or keys is None:
            self.reference(s)
            return
        arr = self.use("wD")
        self.prepare(keys, i)
        self.emit("if a:", i)
        self.emit(f"v = FB({x} {_FLOAT[s.ins.spec.op]} {y})", i, 2)
        self.emit(f"{arr}[{dst.num}] = v & 65535; {arr}[{dst.num + 1}] = (v >> 16) & 65535", i, 2)
        for key in keys:
            self.emit(f"W[{key!r}] = {i}", i, 2)

    def flow(self, s: Step, j: int) -> None:
        i = s.index
        self.settle(i)
        self.exit_checks(s)
        self.flush(i)
        self.emit(f"m.acc = a; m.pc = {i}", i)
        if s.ins.spec.op in ("fend", "end"):
            self.emit(f"S{i}.run(m, S{i})", i)
            self.emit("return -1", i)
            return
        self.emit(f"r = S{i}.run(m, S{i})", i)
        self.emit(f"if r is None: return {j + 1}", i)
        self.emit("return -1 if r == -1 else BLK[r]", i)


# ---------------------------------------------------------------------------- running

class Scanner:
    """Runs scans of one program on one Machine; `engine` names the engine actually used."""

    def __init__(self, prog: Program, m: Machine, engine: str = DEFAULT_ENGINE):
        if engine not in ENGINES:
            raise ValueError(f"unknown engine {engine!r}; engines: {', '.join(ENGINES)}")
        self.prog = prog
        self.m = m
        self.code = compile_program(prog) if engine == "compiled" else None
        self.engine = "compiled" if self.code is not None else "interp"
        self._zero_t = bytes(len(m.t_seen))
        self._checked = False
        if self.code is not None:
            self._runs = [s.run for s in prog.steps]
            self._bind()

    def _bind(self) -> None:
        code, m, prog = self.code, self.m, self.prog
        g: dict = {"__builtins__": __builtins__, "adv": advance_timer, "W": m.writer,
                   "FD": _f32_of_bits, "FB": f32_bits, "T01": _T01,
                   "BLK": {st: j for j, st in enumerate(code.starts)}}
        for s in prog.steps:
            g[f"S{s.index}"] = s
            for k, ref in enumerate(s.ops):
                g[f"O{s.index}_{k}"] = ref
        self.g = g
        self._rebind()
        exec(code.code, g)  # noqa: S102 - our own generated code
        self.fns: list[Callable] = [g[f"b{j}"] for j in range(len(code.starts))]

    def _rebind(self) -> None:
        m, g = self.m, self.g
        for k, arr in m.bits.items():
            g["G_b" + k] = arr
        for k, arr in m.words.items():
            g["G_w" + k] = arr
        g["G_cv"] = m.cval
        g["G_bE"] = m.edge
        g["G_ts"] = m.t_seen
        g["W"] = m.writer
        self._bound = self._containers()

    def _containers(self) -> tuple:
        m = self.m
        return (m.edge, m.cval, m.t_seen, m.writer, *m.words.values(), *m.bits.values())

    def __call__(self, watchdog: int = DEFAULT_WATCHDOG) -> None:
        if self.code is None:
            run_scan(self.prog, self.m, watchdog)
            return
        if not self._checked:
            self._check_instrumented()
            if self.code is None:
                run_scan(self.prog, self.m, watchdog)
                return
        m = self.m
        m.t_seen[:] = self._zero_t
        if any(a is not b for a, b in zip(self._containers(), self._bound)):
            self._rebind()
        m.acc = False
        m.blocks.clear()
        m.stack.clear()
        m.calls = []
        m.fors = []
        if _before_scan is not None:
            _before_scan(m)
        fns = self.fns
        bsteps = self.code.block_steps
        nb = len(fns)
        j = 0
        ex = 0
        try:
            while True:
                n = bsteps[j]
                if ex + n > watchdog:
                    self._interp(self.code.starts[j], ex, watchdog)
                    break
                ex += n
                j = fns[j](m)
                if j < 0:
                    break
                if j == nb:
                    raise Fault("execution ran past the last instruction without END",
                                self.prog.steps[-1])
        except SimFault as e:
            raise Fault(e.message, self._fault_step(e)) from None
        end_of_scan(m)

    def _check_instrumented(self) -> None:
        """Steps whose routine was wrapped after decoding (coverage, the ladder report's power
        recorder) must run as wrapped: such a program runs on the interpreter."""
        self._checked = True
        if any(s.run is not r for s, r in zip(self.prog.steps, self._runs)):
            self.code = None
            self.engine = "interp"
        self._runs = []

    def _fault_step(self, e: BaseException) -> Step | None:
        tb = e.__traceback__
        line = None
        while tb is not None:
            if tb.tb_frame.f_code.co_filename == self.code.filename:
                line = tb.tb_lineno
            tb = tb.tb_next
        if line is None:
            return None
        return self.prog.steps[self.code.linemap[line - 1]]

    def _interp(self, pc: int, executed: int, watchdog: int) -> None:
        """The interpreter's loop (scan.run_scan) from step `pc` with `executed` steps done."""
        m = self.m
        steps = self.prog.steps
        n = len(steps)
        s = None
        try:
            while pc < n:
                s = steps[pc]
                m.pc = pc
                executed += s.steps
                if executed > watchdog:
                    raise SimFault(f"scan watchdog: more than {watchdog} steps executed in one scan "
                                   "(runaway loop?)")
                r = s.run(m, s)
                if r is None:
                    pc += 1
                elif r == END_SCAN:
                    break
                else:
                    pc = r
            else:
                raise SimFault("execution ran past the last instruction without END")
        except SimFault as e:
            raise Fault(e.message, s) from None

def default_engine() -> str:
    """MLC_SIM_ENGINE if it names an engine (the tests run everything on both), else compiled."""
    env = os.environ.get(ENGINE_ENV, "")
    return env if env in ENGINES else DEFAULT_ENGINE


def scanner(prog: Program, m: Machine, engine: str | None = None) -> Scanner:
    return Scanner(prog, m, engine or default_engine())
