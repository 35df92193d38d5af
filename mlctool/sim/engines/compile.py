"""The compiled engine: the decoded program turned once into specialised Python code.

The reference interpreter (scan.py) runs one routine per step. This engine cuts the program
into basic blocks (a block starts at step 0, at every P label and after every program-flow
instruction) and generates one Python function per block in which

- the rung result is a local (`a`), ANB/ORB/MPS/MRD/MPP work on locals resolved at compile
  time, contacts and coils on plain devices are subscripts of the device arrays (held in
  locals), simple MOV/ADD/SUB/INC/DEC/CML/WAND/WOR/WXOR/TMR and compare contacts are inlined;
  the contacts of a rung become one short-circuit boolean expression (codegen.r_text: cheaper
  operands first), and `a` is not stored when the next step starts a new rung;
- every other instruction calls the reference routine of semantics.py (`step.run`), and
  program flow (CJ, CALL, SRET, FOR, NEXT, FEND, END) calls the flow routines of scan.py at
  the end of its block, so the semantics are the interpreter's by construction;
- the writer of each device (for failure messages) is recorded lazily: each group of writes
  with known devices stores one stamp when it runs (`R[g] = ws`, ws numbering block executions);
  `Writers`, the machine's writer dict while the engine runs it, works out the interpreter's
  records from the stamps when it is read (writes the engine cannot name at compile time, and
  every write from outside the generated code, are kept with their stamps in `spill`).

Faults name the same step as the interpreter (mapped from the generated line). The watchdog
is checked per block: a block that would pass the limit is run by the interpreter loop from
its first step, which stops at the same step. The code of a program is cached by a content
hash; binding it to a Machine is cheap.

Programs the engine does not handle (a rung stack left open across a block boundary, a
contact-class instruction it does not know) run on the reference interpreter: `scanner()`
falls back silently and `Scanner.engine` says which one runs. The Scanner, `Writers` and the
helpers the generated code calls at run time are in engine.py; the code of word, timer,
counter and float instructions is in compile_ops.py (a mixin of _Gen), what both share in
codegen.py, and how the blocks are laid out into the functions the driver calls in
compile_layout.py.
"""

from __future__ import annotations

import hashlib
import re
from collections import OrderedDict
from types import CodeType

from mlctool.sim import semantics
from mlctool.sim.decode import FLOW_OPS, Program, Step
from mlctool.sim.engines.codegen import (
    _ARITH,
    _CMP,
    _FLOAT,
    _LITTLE,
    BIT_KINDS,
    K8_MOD,
    RUNG_CLASSES,
    Unsupported,
    _bit_simple,
    _fold,
    _s16,
    _s32,
    _word,
    r_join,
    r_not,
    r_size,
    r_text,
)
from mlctool.sim.engines.compile_layout import _CALL, _GOTO, _SRET, _Body, _Layout, function_head
from mlctool.sim.engines.compile_ops import OpsCode
from mlctool.sim.engines.pycompile import compile_parts
from mlctool.sim.operands import BitRef, ConstRef, CounterRef, GroupRef
from mlctool.sim.state import s16, s32

COMPILER_VERSION = "14"


class Code:
    """A program compiled to Python: the code object and what the driver needs to run it."""

    def __init__(self, key: str, code: CodeType | tuple[CodeType, ...], filename: str, starts: list[int],
                 block_steps: list[int], linemap: list[int], source: str,
                 consts: dict[str, dict] | None = None, used: frozenset[str] = frozenset(),
                 groups: list[dict] | None = None, dyn: list[tuple] | None = None, funcs: list[str] | None = None):
        self.key = key
        self.code = code
        self.filename = filename
        self.starts = starts  # first step index of each block
        self.block_steps = block_steps  # steps executed by each block (for the watchdog)
        self.linemap = linemap  # generated line (0-based) -> step index
        self.source = source
        self.consts = consts or {}  # U<n>: constant writer records (dict updates)
        self.used = used  # machine containers the code reads (G_<name>)
        self.groups = groups or []  # writer record groups (Writers.groups)
        self.dyn = dyn or []  # index-modified stores (Writers.dyn_specs)
        self.funcs = funcs or []  # the function each block is entered through (_Layout)


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

# step ladder and master control (VS 4-6, 3-6) switch the rail every new rung's first load
# reads (decode._combine: `contact and m.bus`); programs with them run on the interpreter
_BUS_OPS = frozenset({"stl", "ret", "mc", "mcr"})
_ACC_FREE_FLOW = frozenset({"for", "next", "fend", "end", "sret"})  # run whatever the rung result


_BIT_READ = re.compile(r"b([A-Z])\[([0-9]+)\]")


def _bit_key(tree) -> tuple[str, str, int] | None:
    """The cache key (_Gen.ixc) of a rung result that is one plain bit read, else None."""
    if type(tree) is str:
        match = _BIT_READ.fullmatch(tree)
        if match and match[1] in BIT_KINDS:
            return ("bit", match[1], int(match[2]))
    return None


def _reads_acc_at_entry(block: list[Step]) -> bool:
    """The block's first instruction uses the rung result it is entered with."""
    for s in block:
        spec = s.ins.spec
        if spec.cls == "label":
            continue
        return not (spec.cls == "load" and s.new_rung or spec.op in _ACC_FREE_FLOW)
    return False

PIECE_LINES = 2000  # a block longer than this goes on in functions of its own (split())


class _Gen(OpsCode):
    def __init__(self, prog: Program, key: str):
        self.prog = prog
        self.key = key
        self.filename = f"<mlc-compiled {key[:16]}>"
        self.lines: list[str] = []
        self.linemap: list[int] = []
        self.consts: dict[str, dict] = {}  # U<n>: writer records deferred before a fault
        self.groups: list[dict] = []  # writer record groups: `R[g] = ws` when one runs
        self.dyn: list[tuple] = []  # index-modified stores: `DY<n>[address] = ws`
        self.subpos = 0
        self.all_used: set[str] = set()
        settings = prog.target.settings
        self.c32_lo = settings["counters32"][0]
        self.for_depth = settings["for_depth"]
        self.call_depth = settings["call_depth"]
        # VS 3-9: presets outside a range are taken as 0 (timers) or 1 (counters)
        self.timer_range = settings.get("timer_preset_range")
        self.counter_range = settings.get("counter16_preset_range")
        # targets with status flags (VS M9020-M9025, 5-3): semantics.FLAG_OPS keep their routines
        self.flags = bool(settings.get("flags"))
        self.gopen = False  # an `if a:` group is open: application instructions under one rung result
        self.gpend: dict[tuple[str, int], int] = {}  # writer records of the open group
        self.known: dict[tuple[str, int], int] = {}

    # -- output helpers
    def emit(self, text: str, step: int, depth: int = 1) -> None:
        if depth == 1 and self.gopen:
            self.close_group(step)
        self.lines.append("    " * depth + text)
        self.linemap.append(step)

    def goto(self, target: int | str, step: int, depth: int = 1) -> None:
        """Control passes to block `target` (-1: the end of the scan; a str: an expression
        computed at run time); resolved when the blocks are laid out into functions
        (_Layout.transfer). It is the last statement of its path through the block."""
        self.emit(f"{_GOTO}{target}", step, depth)

    def new_buffer(self) -> None:
        """Start a function's body: its lines, the containers it names, whether it stamps."""
        self.lines, self.linemap = [], []
        self.used: set[str] = set()
        self.block_marks = False


    def build(self) -> Code:
        steps = self.prog.steps
        if not steps:
            raise Unsupported("empty program")
        bus = next((s for s in steps if s.ins.spec.op in _BUS_OPS), None)
        if bus is not None:
            raise Unsupported(f"{bus.ins.mnemonic}: the rail state (m.bus) is the interpreter's")
        starts = sorted({0} | {s.index for s in steps if s.ins.spec.cls == "label"}
                        | {s.target for s in steps if s.ins.spec.op in ("cj", "call") and s.target >= 0}
                        | {s.index + 1 for s in steps if s.ins.spec.op in FLOW_OPS} - {len(steps)})
        bounds = starts + [len(steps)]
        block_of = {st: j for j, st in enumerate(starts)}
        self.block_of = block_of
        # the rung result crosses a block boundary only when some block begins by using it;
        # if none does, blocks neither load nor leave it (m.acc is for the reference routines)
        self.acc_live = any(_reads_acc_at_entry(steps[bounds[j]:bounds[j + 1]]) for j in range(len(starts)))
        block_steps = []
        bodies = []
        self.pieces: list[tuple[list[str], list[int]]] = []  # pieces of long blocks (split())
        for j in range(len(starts)):
            block = steps[bounds[j]:bounds[j + 1]]
            block_steps.append(sum(s.steps for s in block))
            self.nsteps = block_steps[-1]
            bodies.append(self.block(j, block))
        lay = _Layout(bodies, block_steps, [steps[b - 1].ins.spec.op for b in bounds[1:]])
        lines, linemap = lay.lines, lay.linemap
        for piece_lines, piece_map in self.pieces:
            lines += piece_lines
            linemap += piece_map
        self.pieces = []
        source = "\n".join(lines) + "\n"
        code = compile_parts(lines, self.filename)  # (in parts: compile()'s memory, pycompile.py)
        return Code(self.key, code, self.filename, starts, block_steps, linemap, source,
                    self.consts, frozenset(self.all_used), self.groups, self.dyn, lay.funcs)

    # -- one block
    def block(self, j: int, block: list[Step]) -> _Body:
        """The body of block j (to be laid out into a function by _Layout): its lines at
        depth 1 and up, control leaving it by goto() lines."""
        first = block[0].index
        self.new_buffer()
        self.piece_at = 0  # line of the current buffer where its straight run of code began
        self.main = None  # (lines, linemap) of the block's body while a piece is being written
        self.self_loop: int | None = None  # the NEXT ending a FOR body of this one block
        self.pending: dict[tuple[str, int], int] = {}
        self.gopen, self.gpend = False, {}
        self.known: dict[tuple[str, int], int] = {}  # words of the open group holding a constant
        self.ixc: dict[tuple, str] = {}  # index register value, or ("bit", kind, n) -> local holding it (index(), settle())
        self.ix_dirty = False  # the open group wrote V/Z: no index values hoisted before it
        self.gopen_at = 0  # line of the open group's `if a:`
        self.blocks: list[str] = []  # symbolic ANB/ORB block stack: names of locals
        self.stack: list[str] = []  # symbolic MPS stack
        self.tmp = 0
        self.acc = None  # the rung result (a codegen.r_* tree) when not (yet) in `a`
        if self.acc_live:  # (else the function's `a = False` binds it: no block reads it first)
            self.emit("a = m.acc", first)
        ended = False
        for k, s in enumerate(block):
            op = s.ins.spec.op
            self.next_step = block[k + 1] if k + 1 < len(block) else None
            if (s.new_rung and s.ins.spec.cls == "load" and not self.blocks and not self.stack
                    and len(self.lines) - self.piece_at > PIECE_LINES):
                self.split(s.index)
            if op in FLOW_OPS:
                self.end_piece(s.index)
                self.flow(s, j)
                ended = True
                break
            self.instr(s)
        if not ended:
            last = block[-1].index
            self.end_piece(last)
            self.settle(last)
            self.exit_checks(block[-1])
            self.flush(last)
            if self.acc_live:
                self.emit("m.acc = a", last)
        if self.self_loop is not None:  # a FOR body of one block loops here (flow(), NEXT)
            # nothing in one block changes m.fors (flow ops end blocks): its frame is found once
            self.lines[:] = ["    " + line for line in self.lines]
            self.lines[:0] = ["    fs = m.fors", f"    lp = fs[-1] if fs and fs[-1][1] == {self.self_loop} else None",
                              "    while True:"]
            self.linemap[:0] = [first] * 3
        if self.self_loop is not None or not ended:
            self.goto(j + 1, block[-1].index)
        body = _Body(self.lines, self.linemap, self.used, self.block_marks, first)
        self.all_used |= self.used
        return body

    def split(self, i: int) -> None:
        """A long block goes on in a function of its own (`a = piece<n>(m, ws)`), so no function
        is huge (compile()'s memory grows with a function's size). Called where a new rung
        begins with no rung stack open: the rung result is dead there; what the generator
        holds for the code so far (deferred writer records, hoisted index values) is
        written out or dropped."""
        self.settle(i)
        self.flush(i)
        self.known = {}
        self.ixc = {}
        if self.main is None:
            self.main = (self.lines, self.linemap, self.used, self.block_marks)
        else:
            self.finish_piece(i)
        name = f"piece{len(self.pieces)}"
        main_lines, main_map = self.main[0], self.main[1]
        main_lines.append(f"    a = {name}(m, ws)")
        main_map.append(i)
        self.new_buffer()
        self.piece_name, self.piece_first = name, i
        self.piece_at = 0
        self.emit("a = False", i)

    def finish_piece(self, i: int) -> None:
        self.emit("return a", i)
        self.all_used |= self.used
        head = function_head(self.piece_name, "m, ws", self.used, self.block_marks)
        self.pieces.append((head + self.lines, [self.piece_first] * len(head) + self.linemap))

    def end_piece(self, i: int) -> None:
        """The block's last instructions: back in the block's body (its flow needs it)."""
        if self.main is None:
            return
        self.settle(i)
        self.flush(i)
        self.ixc = {}
        self.finish_piece(i)
        lines, linemap, used, marks = self.main
        self.lines, self.linemap, self.used, self.block_marks = lines, linemap, used, marks
        self.main = None

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

    def index(self, ref, i: int, j: int, depth: int, extent: int) -> str:
        """Emit the address of an index-modified operand (Ref.addr inline: number + signed
        index register, range-checked); a fault applies the deferred writer records first and
        lets Ref.addr raise its message. Returns the local holding the address."""
        x = self.new_tmp("x")
        n = ref.ixn
        wide = ref.width == 32 and ref.ix == "V"
        if wide:
            iv = _s32(f"({self.use('wZ')}[{n}] << 16 | {self.use('wV')}[{n}])")
        else:
            iv = _s16(f"{self.use('w' + ref.ix)}[{n}]")
        iv = self.ix_value((ref.ix, n, wide), iv, i, depth)
        self.emit(f"{x} = {ref.num} + {iv}", i, depth)
        done = dict(self.pending)
        done.update(self.gpend)
        # only the bounds the register's signed range can cross (V alone: 16 bits)
        lo_ix, hi_ix = (-(1 << 31), (1 << 31) - 1) if wide else (-32768, 32767)
        tests = [t for t, crossed in ((f"{x} < 0", ref.num + lo_ix < 0),
                                      (f"{x} > {ref.hi - extent + 1}", ref.num + hi_ix > ref.hi - extent + 1))
                 if crossed]
        if tests:
            self.emit(f"if {' or '.join(tests)}: FLT(m, {self.const(done)}, O{i}_{j}, {extent}, ws, {self.pos()})",
                      i, depth)
        return x

    def ix_value(self, key: tuple, expr: str, i: int, depth: int) -> str:
        """The signed value of an index register, held in a local from where it was first
        read in the block until a V/Z write or a reference routine (ix_clobber): computed on
        the spot at depth 1, or on a line inserted before the open group's `if a:` (reading
        V/Z cannot fault, and nothing in the group wrote V/Z before, else ix_dirty)."""
        name = self.ixc.get(key)
        if name is not None:
            return name
        if depth == 2 and self.ix_dirty:
            return expr
        name = self.new_tmp("iv")
        if depth == 1:
            self.emit(f"{name} = {expr}", i)
        else:
            self.lines.insert(self.gopen_at, f"    {name} = {expr}")
            self.linemap.insert(self.gopen_at, i)
            self.gopen_at += 1
        self.ixc[key] = name
        return name

    def ix_clobber(self) -> None:
        """V/Z may change from here on: index values are read again."""
        self.ixc = {}
        if self.gopen:
            self.ix_dirty = True

    def const(self, d: dict) -> str:
        if not d:
            return "None"
        name = f"U{len(self.consts)}"
        self.consts[name] = dict(d)
        return name

    def readable(self, ref) -> bool:
        """`value` reads the operand inline (no Ref.get call)."""
        if type(ref) is ConstRef:
            return ref.ix is None
        if _word(ref):
            return ref.ix is not None or ref.width == 16 or ref.kind in ("Z", "V") or ref.num + 1 <= ref.hi
        if type(ref) is GroupRef:
            return ref.ix is None and ref.kind in ("X", "Y", "M", "A") and ref.num + ref.n - 1 <= ref.hi
        if type(ref) is CounterRef:
            return ref.ix is None and (ref.width == 16 or ref.num >= self.c32_lo or ref.num + 1 <= ref.hi)
        return False

    def value(self, ref, i: int, j: int, depth: int = 1, unsigned: bool = False) -> str:
        """Value of an operand as Ref.get gives it (signed); `unsigned`: any expression equal
        to it modulo 2^width (enough for + - & | ^ and stores). Index-modified operands emit
        their address on lines of their own first (at `depth`)."""
        w = ref.width
        if type(ref) is ConstRef and ref.ix is None:
            v = ref.get(None)
            return repr(v & (0xFFFF if w == 16 else 0xFFFFFFFF)) if unsigned else repr(v)
        if _word(ref):
            arr = self.use("w" + ref.kind)
            one = w == 16 or ref.kind == "Z"
            if ref.ix is None:
                n, n1 = ref.num, str(ref.num + 1)
                if not one and ref.kind != "V" and ref.num + 1 > ref.hi:
                    return f"O{i}_{j}.get(m)"
                hk = ("Z", n) if ref.kind == "V" else (ref.kind, n + 1)
                if depth == 2 and (ref.kind, n) in self.known and (one or hk in self.known):
                    raw = self.known[(ref.kind, n)] if one else self.known[hk] << 16 | self.known[(ref.kind, n)]
                    if unsigned:
                        return repr(raw)
                    return repr(s16(raw) if one else s32(raw))
            else:
                n = self.index(ref, i, j, depth, 1 if one or ref.kind == "V" else 2)
                n1 = f"{n} + 1"
            if one:
                raw = f"{arr}[{n}]"
                return raw if unsigned else _s16(raw)
            hi = f"{self.use('wZ')}[{n}]" if ref.kind == "V" else f"{arr}[{n1}]"
            raw = f"({hi} << 16 | {arr}[{n}])"
            return raw if unsigned else _s32(raw)
        if type(ref) is GroupRef and ref.ix is None and ref.kind in ("X", "Y", "M", "A") \
                and ref.num + ref.n - 1 <= ref.hi:
            a, n = ref.num, ref.n
            if _LITTLE and a % 8 == 0 and n % 8 == 0 and a + n <= (ref.hi + 1) // 8 * 8:
                # 8 device bytes (0/1) at a time as one unsigned 64-bit word of the bit store
                # (a 'Q' view of the bytearray), turned into their 8 bits, already moved to
                # their place in the group, by a list indexed by the word modulo K8_MOD
                # (engine._KN: cheaper than a dict of the 64-bit patterns or big-int arithmetic)
                q = self.use("q" + ref.kind)
                parts = [f"{self.use(f'K{c}')}[{q}[{a // 8 + c}] % {K8_MOD}]" for c in range(n // 8)]
                expr = f"({' | '.join(parts)})" if len(parts) > 1 else f"({parts[0]})"
            else:
                arr = self.use("b" + ref.kind)
                expr = f"int({arr}[{a + n - 1}:{a - 1 if a else ''}:-1].translate(T01), 2)"
            if n == w and not unsigned:  # K4 in 16-bit and K8 in 32-bit are signed (GroupRef.get)
                return _s16(expr) if w == 16 else _s32(expr)
            return expr
        if type(ref) is CounterRef and ref.ix is None:
            cv = self.use("cv")
            n = ref.num
            if w == 16:
                return f"({cv}[{n}] & 65535)" if unsigned else _s16(f"({cv}[{n}] & 65535)")
            if n >= self.c32_lo:
                raw = f"({cv}[{n}] & 4294967295)"
            elif n + 1 <= ref.hi:
                raw = f"(({cv}[{n + 1}] << 16 | {cv}[{n}]) & 4294967295)"
            else:
                return f"O{i}_{j}.get(m)"
            return raw if unsigned else _s32(raw)
        return f"O{i}_{j}.get(m)"

    def store_keys(self, ref) -> list[tuple[str, int]] | None:
        """Writer keys of an inline store to a plain word operand (None: not known at compile
        time, or not a plain word)."""
        if _word(ref) and ref.ix is None:
            n = ref.num
            if ref.width == 16 or ref.kind == "Z":
                return [(ref.kind, n)]
            if ref.kind == "V":
                return [("V", n), ("Z", n)]
            if n + 1 <= ref.hi:
                return [(ref.kind, n), (ref.kind, n + 1)]
        return None

    def storable(self, ref) -> bool:
        return _word(ref) and (ref.ix is not None or self.store_keys(ref) is not None)

    def store(self, ref, expr: str, s: Step, j: int, masked: bool = False) -> None:
        """WordRef.set inline, inside the open group (`cond` came first). `masked`: expr is
        already an unsigned 16-bit value."""
        i = s.index
        arr = self.use("w" + ref.kind)
        one = ref.width == 16 or ref.kind == "Z"
        if ref.ix is None:
            n, n1 = ref.num, ref.num + 1
            hi_key = ("Z", n) if ref.kind == "V" else (ref.kind, n1)
        else:
            src = self.new_tmp("v")
            self.emit(f"{src} = {expr}", i, 2)  # the source is read before the destination's address
            expr = src
            n = self.index(ref, i, j, 2, 1 if one or ref.kind == "V" else 2)
            n1 = f"{n} + 1"
            hi_key = None
        c = _fold(expr) if ref.ix is None else None
        if one:
            if c is not None:
                self.emit(f"{arr}[{n}] = {c & 0xFFFF}", i, 2)
            else:
                self.emit(f"{arr}[{n}] = {expr}" if masked else f"{arr}[{n}] = {expr} & 65535", i, 2)
            if ref.ix is None:
                self.learn([(ref.kind, n)], None if c is None else [c & 0xFFFF])
                self.gwrite([(ref.kind, n)], i)
            else:
                self.emit(f"{self.dyn_store(((ref.kind, 0),), i)}[{n}] = ws", i, 2)
            return
        hi = f"{self.use('wZ')}[{n}]" if ref.kind == "V" else f"{arr}[{n1}]"
        if c is not None:
            words = [c & 0xFFFF, (c >> 16) & 0xFFFF]
            self.emit(f"{arr}[{n}] = {words[0]}; {hi} = {words[1]}", i, 2)
        else:
            v = expr if expr.isidentifier() else "v"
            if v == "v":
                self.emit(f"v = {expr}", i, 2)
            self.emit(f"{arr}[{n}] = {v} & 65535; {hi} = ({v} >> 16) & 65535", i, 2)
        if ref.ix is None:
            self.learn([(ref.kind, n), hi_key], None if c is None else words)
            self.gwrite([(ref.kind, n), hi_key], i)
        else:
            parts = ((ref.kind, 0), ("Z", 0) if ref.kind == "V" else (ref.kind, 1))
            self.emit(f"{self.dyn_store(parts, i)}[{n}] = ws", i, 2)

    # -- writer tracking
    def cond(self, keys, i: int, kinds: tuple[str, ...] = ()) -> None:
        """Open (or stay in) the `if a:` group before a conditional write. Writer records
        deferred from earlier steps that the write could overwrite go first; `keys` None: a
        store whose address is known at run time only, to a device of `kinds`."""
        if keys is None:
            if any(k[0] in kinds for k in self.pending):
                self.flush(i)
            if any(k[0] in kinds for k in self.gpend):
                self.emit_records(self.gpend, i, 2)
                self.gpend = {}
            for k in [k for k in self.known if k[0] in kinds]:
                del self.known[k]
        elif any(k in self.pending for k in keys):
            self.flush(i)
        if not self.gopen:
            self.gopen_at = len(self.lines)
            self.emit("if a:", i)
            self.gopen = True
            self.ix_dirty = False
        if "V" in kinds or "Z" in kinds or keys is not None and any(k[0] in ("V", "Z") for k in keys):
            self.ix_clobber()

    def direct(self, key, i: int) -> None:
        """Before a writer record written on the spot (outside any group)."""
        if key in self.pending:
            self.flush(i)

    def learn(self, keys, words: list[int] | None) -> None:
        """Words the open group just wrote: constants later reads in the group fold in."""
        for k, key in enumerate(keys):
            if words is None:
                self.known.pop(key, None)
            else:
                self.known[key] = words[k]

    def gwrite(self, keys, i: int) -> None:
        for k in keys:
            self.gpend[k] = i

    def close_group(self, i: int) -> None:
        self.gopen = False
        self.known = {}
        if self.gpend:
            self.emit_records(self.gpend, i, 2)
            self.gpend = {}

    def emit_records(self, d: dict, i: int, depth: int) -> None:
        self.emit(self.mark(d), i, depth)

    def mark(self, d: dict) -> str:
        """The statement recording that a group of writes ran (Writers)."""
        self.groups.append(dict(d))
        self.subpos = 0
        self.block_marks = True
        return f"R[{len(self.groups) - 1}] = ws"

    def dyn_store(self, parts: tuple, i: int) -> str:
        """The dict recording the addresses an index-modified store wrote (Writers.dyn)."""
        self.dyn.append((self.pos(), parts, i))
        return f"DY{len(self.dyn) - 1}"

    def pos(self) -> float:
        """The position of a write outside the groups: after the groups emitted so far and the
        other writes since the last of them."""
        self.subpos += 1
        return len(self.groups) - 1 + self.subpos / (1 << 20)

    def defer_writer(self, key, i: int) -> None:
        self.pending.pop(key, None)
        self.pending[key] = i

    def flush(self, i: int) -> None:
        if self.gopen:
            self.close_group(i)
        if self.pending:
            pending, self.pending = self.pending, {}
            self.emit_records(pending, i, 1)

    # -- instructions
    def reference(self, s: Step) -> None:
        """Run the interpreter's routine for this step."""
        if s.ins.spec.cls in RUNG_CLASSES:
            raise Unsupported(f"no compiled form for {s.ins.mnemonic}")
        i = s.index
        self.flush(i)
        self.ix_clobber()
        if self.blocks:  # FBs functions take their extra inputs from the block stack (m.blocks)
            self.emit(f"m.blocks[:] = [{', '.join(self.blocks)}]", i)
            self.blocks = []
        self.emit(f"m.acc = a; m.pc = {i}; AT[0] = ws; AT[1] = {self.pos()}", i)
        self.emit(f"S{i}.run(m, S{i})", i)
        self.emit("a = m.acc", i)

    def contact(self, s: Step) -> str | None:
        """The contact's value as an expression without side effects; reads that can fault and
        edge memories are done first, on lines of their own (faults name this step)."""
        i = s.index
        op = s.ins.spec.op
        if not s.ops:
            return None
        ref = s.ops[0]
        if op in _CMP:
            expr = self.compare_const(s) or f"({self.value(s.ops[0], i, 0)} {_CMP[op]} {self.value(s.ops[1], i, 1)})"
            if "(m)" in expr:
                t = self.new_tmp("c")
                self.flush(i)
                self.emit(f"{t} = {expr}", i)
                return t
            return expr
        if op not in ("contact", "contact_not", "contact_rise", "contact_fall"):
            return None
        if _bit_simple(ref):
            b = self.ixc.get(("bit", ref.kind, ref.num)) or self.bit(ref)
        elif type(ref) is BitRef and ref.kind in BIT_KINDS:
            b = f"{self.use('b' + ref.kind)}[{self.index(ref, i, 0, 1, 1)}]"
        else:
            b = self.new_tmp("c")
            self.flush(i)
            self.emit(f"{b} = O{i}_0.bit(m)", i)
        if op == "contact":
            return b
        if op == "contact_not":
            return ("not", b)
        e = self.use("bE")
        c, p = self.new_tmp("c"), self.new_tmp("e")
        self.emit(f"{c} = {b}; {p} = {e}[{i}]; {e}[{i}] = {c}", i)
        return ("and", (c, ("not", p))) if op == "contact_rise" else ("and", (p, ("not", c)))

    def compare_const(self, s: Step) -> str | None:
        """A register compared with a constant, without making the register's value signed:
        x -> x ^ 2^(w-1) maps the signed order onto the unsigned one, so signed(u) > c is
        (u ^ bias) > c + bias (one operation fewer). None: not that shape."""
        x, y = s.ops
        consts = [type(r) is ConstRef and r.ix is None for r in (x, y)]
        reg_ref = y if consts[0] else x
        # the register's unsigned read must be as wide as the comparison (Z in a 32-bit
        # compare is read as 16 bits and sign-extended: not this shape)
        if consts[0] == consts[1] or not _word(reg_ref) or s.width == 32 and reg_ref.kind == "Z":
            return None
        bias = 1 << (s.width - 1)
        j = 1 if consts[0] else 0
        reg = f"({self.value(s.ops[j], s.index, j, unsigned=True)} ^ {bias})"
        c = str(s.ops[1 - j].get(None) + bias)
        left, right = (c, reg) if consts[0] else (reg, c)
        return f"({left} {_CMP[s.ins.spec.op]} {right})"

    # -- the rung result: a tree of pure expressions (`self.acc`, codegen.r_*) until something
    # needs it in `a`
    def cur(self):
        return self.acc if self.acc is not None else "a"

    def set_acc(self, tree, i: int) -> None:
        self.acc = tree
        if r_size(tree) > 48:  # keep expressions shallow
            self.settle(i)

    def settle(self, i: int) -> None:
        if self.acc is not None:
            key = _bit_key(self.acc)
            if key is not None and key not in self.ixc:
                # a rung of one plain contact (`LD M1000` before each group of a unit): its bit
                # is kept in a local that later loads of it read until the bit may change
                # (bit_written, ix_clobber: reference routines), with the index values
                name = self.new_tmp("bv")
                self.ixc[key] = name
                self.emit(f"a = {name} = {self.acc}", i)
            else:
                self.emit(f"a = {r_text(self.acc)}", i)
            self.acc = None

    def bit_written(self, kind: str, num: int) -> None:
        """An inline write to a bit: later reads read the device again."""
        self.ixc.pop(("bit", kind, num), None)

    def rung(self, s: Step) -> None:
        spec = s.ins.spec
        op, cls, i = spec.op, spec.cls, s.index
        if op in ("result_rise", "result_fall"):  # MEP/MEF (VS 3-3): the edge of the result so far
            e, c, p = self.use("bE"), self.new_tmp("c"), self.new_tmp("e")
            self.emit(f"{c} = {r_text(self.cur())}; {p} = {e}[{i}]; {e}[{i}] = {c}", i)
            self.acc = ("and", (c, ("not", p))) if op == "result_rise" else ("and", (p, ("not", c)))
        elif cls in ("load", "and", "or"):
            c = self.contact(s)
            if c is None:
                raise Unsupported(f"no compiled form for {s.ins.mnemonic}")
            if cls == "load":
                if s.new_rung:
                    self.blocks.clear()
                    self.stack.clear()
                    self.acc = None
                else:
                    k = self.new_tmp("k")
                    self.emit(f"{k} = {r_text(self.cur())}", i)
                    self.blocks.append(k)
                self.set_acc(c, i)
            else:
                self.set_acc(r_join(cls, self.cur(), c), i)
        elif op in ("anb", "orb"):
            if self.blocks:
                self.set_acc(r_join("and" if op == "anb" else "or", self.blocks.pop(), self.cur()), i)
        elif op == "mps":
            k = self.new_tmp("p")
            self.emit(f"{k} = {r_text(self.cur())}", i)
            self.stack.append(k)
            self.acc = k
        elif op == "mrd":
            if self.stack:
                self.acc = self.stack[-1]
        elif op == "mpp":
            if self.stack:
                self.acc = self.stack.pop()
        else:  # inv
            self.set_acc(r_not(self.cur()), i)

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
        # a target's own routine for this op, or one that sets the target's status flags
        generic = semantics.ACTIONS.get(op)
        if s.run is not generic and getattr(s.run, "generic", None) is not generic \
                or self.flags and op in semantics.FLAG_OPS:
            self.settle(i)
            self.reference(s)
            return
        if op == "out" and _bit_simple(s.ops[0]) and s.ops[0].kind in ("Y", "M", "A"):
            dst = self.bit(s.ops[0])
            if self.acc is not None:
                # the rung result is not kept when the next step starts a new rung
                nxt = self.next_step
                dead = nxt is not None and nxt.ins.spec.cls == "load" and nxt.new_rung
                self.emit(f"{dst} = {'' if dead else 'a = '}{r_text(self.acc)}", i)
                self.acc = None
            else:
                self.emit(f"{dst} = a", i)
            self.defer_writer((s.ops[0].kind, s.ops[0].num), i)
            self.bit_written(s.ops[0].kind, s.ops[0].num)
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
        self.bit_written(ref.kind, ref.num)
        if op in ("set", "rst"):
            self.cond([key], i)
            self.emit(f"{dst} = {1 if op == 'set' else 0}", i, 2)
            self.gwrite([key], i)
        else:
            e = self.use("bE")
            self.emit(f"e = {e}[{i}]; {e}[{i}] = 1 if a else 0", i)
            cond = "a and not e" if op == "pls" else "e and not a"
            self.emit(f"{dst} = 1 if {cond} else 0", i)
            self.defer_writer(key, i)

    # -- program flow (scan.py's routines inline; their fault and alarm paths call them)
    def flow(self, s: Step, j: int) -> None:
        i = s.index
        op = s.ins.spec.op
        self.settle(i)
        self.exit_checks(s)
        self.flush(i)
        if self.acc_live:
            self.emit("m.acc = a", i)
        # fault and alarm paths: the routine itself (it reads the rung result from m.acc)
        ref_call = f"m.acc = a; m.pc = {i}; AT[0] = ws; AT[1] = {self.pos()}; S{i}.run(m, S{i})"
        if op in ("fend", "end"):
            self.emit("if m.calls or m.fors:", i)
            self.emit(ref_call, i, 2)
            self.goto(-1, i)
        elif op == "for" and s.target >= 0 and (type(s.ops[0]) is ConstRef and s.ops[0].ix is None
                                                or _word(s.ops[0]) and s.ops[0].ix is None):
            self.emit("fs = m.fors", i)
            self.emit(f"if len(fs) >= {self.for_depth}:", i)
            self.emit(ref_call, i, 2)  # a fault, or an operation error that skips the FOR
            self.emit("else:", i)
            self.emit(f"n = {self.value(s.ops[0], i, 0, 2)}", i, 2)
            self.emit(f"fs.append([{i}, {s.target}, n if n > 1 else 1])", i, 2)
            self.goto(j + 1, i)
        elif op == "next" and s.target >= 0 and s.target + 1 in self.block_of \
                and self.block_of[s.target + 1] == j:
            # the body is this block: the next iteration runs here (block() wraps the block in
            # `while True:`) with its own stamp (ws + 1) and its steps counted as the layout
            # counts a block's; one that would pass the watchdog goes back to the driver, which
            # runs it on the interpreter. After the loop, block() falls through to the next block.
            self.self_loop = i
            n = self.nsteps
            self.emit("if lp is not None:", i)  # lp: the loop's frame, found before `while` (block())
            self.emit("c = lp[2] - 1; lp[2] = c", i, 2)
            self.emit("if c > 0:", i, 2)
            self.emit(f"if ex + {n} > WD: LX[0] = ws; LX[1] = ex; return {-2 - j}", i, 3)
            self.emit(f"ws += 1; ex += {n}; continue", i, 3)
            self.emit("fs.pop()", i, 2)
            self.emit("break", i)
        elif op == "next" and s.target >= 0 and s.target + 1 in self.block_of:
            self.emit("fs = m.fors", i)
            self.emit(f"if fs and fs[-1][1] == {i}:", i)
            self.emit("lp = fs[-1]; lp[2] -= 1", i, 2)
            self.emit("if lp[2] > 0:", i, 2)
            self.goto(self.block_of[s.target + 1], i, 3)  # the body begins before: not a fall
            self.emit("fs.pop()", i, 2)
            self.goto(j + 1, i)
        elif op == "cj" and s.target in self.block_of:
            self.emit("if a:", i)
            self.emit(f"if m.fors: JMP(m, {s.target})", i, 2)
            self.goto(self.block_of[s.target], i, 2)
            self.goto(j + 1, i)
        elif op == "call" and s.target in self.block_of:
            self.emit("if a:", i)
            self.emit(f"if len(m.calls) < {self.call_depth}:", i, 2)
            self.emit(f"m.calls.append({i + 1})", i, 3)
            self.emit(f"{_CALL}{self.block_of[s.target]} {j + 1}", i, 3)
            self.emit("else:", i, 2)
            self.emit(ref_call, i, 3)  # the 6th level: the routine raises the alarm
            self.goto(j + 1, i)
        elif op == "sret":
            self.emit("if not m.calls:", i)
            self.emit(ref_call, i, 2)
            self.goto(_SRET[len(_GOTO):], i)
        else:
            self.emit(f"m.acc = a; m.pc = {i}; AT[0] = ws; AT[1] = {self.pos()}", i)
            self.emit(f"r = S{i}.run(m, S{i})", i)
            self.emit("if r is not None:", i)
            self.goto("-1 if r == -1 else BLK[r]", i, 2)
            self.goto(j + 1, i)
