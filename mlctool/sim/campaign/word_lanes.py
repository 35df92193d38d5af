"""Word lanes of a batch (numpy): many scenarios of one program run together.

A straight-line program (no jumps, calls or loops) of contacts, compare contacts, coils,
TMR/CNT with K presets and 16/32-bit word arithmetic and moves on D (see `WordLaneProgram`),
with scenarios that set, force and expect plain bits and D/T/C words: every device is a numpy
array with one element per scenario (see `WordLaneProgram` for the types), a conditional
write is `np.where(a, new, old)`. Values are read and written through a scratch Machine and
DeviceView, so conversions are the single run's. mlctool/sim/campaign/batch.py decides which
scenarios run so and turns a failing lane into a single run.
"""

from __future__ import annotations

import sys
from itertools import compress

import numpy as np

from mlctool.program import Image
from mlctool.sim.campaign.lane_codegen import RungCodegen, lanes_target
from mlctool.sim.decode import Program, program_devices
from mlctool.sim.operands import BitRef, ConstRef, CounterRef, WordRef
from mlctool.sim.run.run import DEFAULT_SCAN_US, ExpectOutcome, RunResult
from mlctool.sim.scan import load_program
from mlctool.sim.state import DeviceView, Machine
from mlctool.sim.stimulus.stimulus import Stimulus
from mlctool.targetapi.model import Target

WORD_BIT_SPACES = ("X", "Y", "M", "A", "T", "C")  # bool arrays; words: D, TW (timer value),
# CW (counter value), TL/TF (timer last update, remainder); TR (running) and CP (pending) are bool
_W_CMP = {"cmp_eq": "==", "cmp_ne": "!=", "cmp_gt": ">", "cmp_lt": "<", "cmp_ge": ">=", "cmp_le": "<="}
_W_ARITH = {"add": "+", "sub": "-", "wand": "&", "wor": "|", "wxor": "^"}


def _lane_dtype(space: str):
    """Bits bool, D words int16 (the signed value), D pairs int32, the others (timer and
    counter values, the timers' remainders) int64."""
    if space in WORD_BIT_SPACES or space in ("TR", "CP"):
        return bool
    return np.int16 if space == "D" else np.int32 if space == "DD" else np.int64


def _raw(arr: np.ndarray) -> np.ndarray:
    """The lane array as raw 16-bit patterns (a view: writes go through); a D pair's array
    as its words, two per lane (in memory order: _HALVES)."""
    return arr.view(np.uint16) if arr.dtype == np.int16 or arr.dtype == np.int32 else arr


_HALVES = (0, 1) if sys.byteorder == "little" else (1, 0)  # the low and high word of an int32 in _raw


def _view_slots(v: DeviceView, m: Machine) -> list[tuple[tuple[str, int], object, int]] | None:
    """The lane slots a stimulus/result view covers, with where the scratch Machine keeps them
    (None: the view has no word-lane form)."""
    k, n = v.kind, v.number
    if v.view == "bit" and k in WORD_BIT_SPACES and k in m.bits:
        return [((k, n), m.bits[k], n)]
    if k == "D" and v.view in ("w", "h"):
        return [(("D", n), m.words["D"], n)]
    if k == "D" and v.view in ("d", "f") and n + 1 < len(m.words["D"]):
        return [(("D", n), m.words["D"], n), (("D", n + 1), m.words["D"], n + 1)]
    if k == "T" and v.view == "w":
        return [(("TW", n), m.words["T"], n)]
    if k == "C" and v.view == "w" and not m.is_c32(n):
        return [(("CW", n), m.cval, n)]
    return None


def _pairs(steps) -> set[int]:
    """D pairs (n, n+1) the program only ever uses as one 32-bit value at n: they get one
    int32 lane array ("DD", n), so a 32-bit operation on them is one numpy call, not the
    joining and splitting of two 16-bit words (the stimulus and the results still address
    their words, through _Addresses)."""
    w16: set[int] = set()
    w32: set[int] = set()
    for s in steps:
        for k, ref in enumerate(s.ops):
            if type(ref) is WordRef and ref.kind == "D" and ref.ix is None:
                wide = ref.width == 32 or (s.ins.spec.op == "mul" and k == 2)
                (w32 if wide and ref.num + 1 <= ref.hi else w16).add(ref.num)
    return {n for n in w32 if not {n, n + 1} & w16 and not {n - 1, n + 1} & w32}


class WordLaneProgram(RungCodegen):
    """A straight-line program as one Python function over numpy lanes (one element per
    scenario). `ok` False: the program needs scenario-by-scenario runs.

    Numpy's cost here is per call (~0.3-1.3 us for 1024 lanes, the elements nearly free), so
    the generated code keeps the calls per instruction few: D words are int16 arrays holding
    the signed value (16-bit arithmetic wraps by itself, a compare is one call), 32-bit
    values int32/int64, timer and counter values int64 holding the raw 16-bit pattern (their
    contacts compare it unsigned, as the Machine does), bits bool (an edge `x & ~e` is `x > e`)."""

    def __init__(self, prog: Program):
        super().__init__(prog)
        self.counters: dict[int, list[int]] = {}  # counter -> the presets of its CNTs
        self.timers: set[int] = set()
        self.consts: dict[str, object] = {}
        self.body: list = []  # generated lines; a TMR or CNT is a tuple, expanded in scan_for
        self.scans: dict[int, object] = {}
        t = prog.target
        self.c32_lo = t.settings["counters32"][0]
        self.ok = self._generate() if lanes_target(t) else False

    def name(self, space: str, num: int) -> str:
        self.slots.setdefault((space, num), len(self.slots))
        return f"{space}_{num}"

    def invert(self, x: str) -> str:
        return f"(~{x})"

    def edge_memory(self, i: int) -> str:
        return f"E.get({i}, F)"

    def contact(self, op: str, x: str, i: int, out: list[str]) -> str | None:
        if op in ("contact_rise", "contact_fall"):  # on bools x & ~e is x > e: one call
            e = self._new("e")
            out.append(f"{e} = {self.edge_memory(i)}; E[{i}] = {x}")
            return f"({x} > {e})" if op == "contact_rise" else f"({e} > {x})"
        return super().contact(op, x, i, out)

    def coil(self, op: str, x: str, i: int, out: list[str]) -> None:
        if op == "rst":
            out.append(f"{x} = {x} > a")
        elif op in ("pls", "plf"):
            e = self._new("e")
            out.append(f"{e} = {self.edge_memory(i)}; E[{i}] = a")
            out.append(f"{x} = a > {e}" if op == "pls" else f"{x} = {e} > a")
        else:
            super().coil(op, x, i, out)

    def _generate(self) -> bool:
        steps = self.prog.steps
        if not steps or steps[-1].ins.spec.op != "end":
            return False
        self.pairs = _pairs(steps[:-1])
        try:
            for s in steps[:-1]:
                self.body += self._instr(s)
        except _NoLane:
            return False
        self.scan = self.scan_for(DEFAULT_SCAN_US)
        return True

    def scan_for(self, period: int, written: frozenset = frozenset()):
        """The scan function for scans `period` us apart (the timers' code depends on it) and
        scenarios that write the timer and counter lanes in `written` (("TW", n), ("C", n),
        ("CW", n)): the others are known to hold only what their TMR/CNT left."""
        written = written & {(sp, n) for n in self.timers for sp in ("TW",)} \
            | written & {(sp, n) for n in self.counters for sp in ("C", "CW")}
        scan = self.scans.get((period, written))
        if scan is None:
            body: list[str] = []
            for b in self.body:
                if type(b) is not tuple:
                    body.append(b)
                elif b[0] == "tmr":
                    body += self.tmr_code(period, *b[1:], alone=("TW", b[1]) not in written)
                else:
                    body += self.cnt_code(*b[1:], alone=self.counted_alone(b[1], written))
            for n, presets in self.counters.items():  # counter contacts act at the end of the scan (1.7)
                body.append(f"C_{n} = CW_{n} >= {self.const(presets[0], 64)}" if self.counted_alone(n, written)
                            else f"C_{n} = C_{n} | CP_{n}; CP_{n} = F")
            names = sorted(self.slots, key=self.slots.get)
            load = [f"    {sp}_{n} = S[{self.slots[(sp, n)]}]" for sp, n in names]
            store = [f"    S[{self.slots[(sp, n)]}] = {sp}_{n}" for sp, n in names]
            src = ("def scan(S, E, now, F, np):\n    a = F\n"
                   + "\n".join(load + ["    " + b for b in body] + store) + "\n")
            g: dict = dict(self.consts)
            exec(compile(src, "<mlc-word-lanes>", "exec"), g)  # noqa: S102 - our own generated code
            scan = self.scans[(period, written)] = g["scan"]
            self.source = src
        return scan

    # -- operands: (expression, bits) with bits 16/32/64 for arrays, or (value, None) for a constant
    def const(self, value: int, bits: int) -> str:
        """A numpy scalar of the lanes' type (a Python int would be cast per call, and numpy
        1.x and 2.x type mixed int16/int arithmetic differently)."""
        value = (value + (1 << bits - 1)) % (1 << bits) - (1 << bits - 1)
        name = f"K{bits}_{value}".replace("-", "m")
        self.consts[name] = {16: np.int16, 32: np.int32, 64: np.int64}[bits](value)
        return name

    def operand(self, ref) -> tuple:
        w = ref.width
        if type(ref) is ConstRef and ref.ix is None and not ref.is_f:
            return ref.get(None), None
        if type(ref) is WordRef and ref.ix is None and ref.kind == "D":
            if w == 16:
                return self.name("D", ref.num), 16
            if ref.num in self.pairs:
                return self.name("DD", ref.num), 32
            if ref.num + 1 <= ref.hi:
                hi, lo = self.name("D", ref.num + 1), self.name("D", ref.num)
                return f"(({hi}.astype(np.int32) << 16) | {lo}.view(np.uint16))", 32
        if type(ref) is WordRef and ref.ix is None and ref.kind == "T" and w == 16:
            return f"{self.name('TW', ref.num)}.astype(np.int16)", 16
        if type(ref) is CounterRef and ref.ix is None and w == 16 and ref.num < self.c32_lo:
            return f"{self.name('CW', ref.num)}.astype(np.int16)", 16
        raise _NoLane

    def value(self, ref, bits: int) -> str:
        """An operand as an array expression or constant of `bits` (values wrapped to it)."""
        x, b = self.operand(ref)
        return self.const(x, bits) if b is None else x

    def bit(self, ref) -> str:
        if type(ref) is BitRef and ref.ix is None and ref.kind in WORD_BIT_SPACES:
            return self.name(ref.kind, ref.num)
        raise _NoLane

    def dest(self, ref, width: int) -> list[str]:
        """The lanes a store writes: one D word, a D pair's two words, or its DD lanes."""
        if type(ref) is WordRef and ref.ix is None and ref.kind == "D":
            if width == 16:
                return [self.name("D", ref.num)]
            if ref.num in self.pairs:
                return [self.name("DD", ref.num)]
            if ref.num + 1 <= ref.hi:
                return [self.name("D", ref.num), self.name("D", ref.num + 1)]
        raise _NoLane

    def store(self, words: list[str], expr: str) -> list[str]:
        """`words` take `expr` where the rung is On: one int16 word its value (an int16
        expression), a DD pair its value (an int32 expression), two words its low and high
        16 bits. In place (np.putmask, ~0.8 us against np.where's ~1.2): no other name or
        slot holds a D or DD lane array (every write to one is this, a stimulus write into a
        copy, or a force's fresh array)."""
        if len(words) == 1:
            return [f"np.putmask({words[0]}, a, {expr})"]
        return [f"v = {expr}", f"np.putmask({words[0]}, a, v.astype(np.int16))",
                f"np.putmask({words[1]}, a, (v >> 16).astype(np.int16))"]

    def store_const(self, words: list[str], value: int) -> list[str]:
        if len(words) == 1:
            bits = 32 if words[0].startswith("DD_") else 16
            return [f"np.putmask({words[0]}, a, {self.const(value, bits)})"]
        return [f"np.putmask({words[0]}, a, {self.const(value, 16)})",
                f"np.putmask({words[1]}, a, {self.const(value >> 16, 16)})"]

    def compare(self, op: str, r0, r1) -> str:
        (x, bx), (y, by) = self.operand(r0), self.operand(r1)
        if bx is None and by is None:
            return f"(F | ({x!r} {_W_CMP[op]} {y!r}))"
        lo, hi = (-32768, 32767) if (bx or by) == 16 else (-2**31, 2**31 - 1)
        for c in (x if bx is None else None, y if by is None else None):
            if c is not None and not lo <= c <= hi:  # a constant outside the lanes' type: compare in int64
                x, y = (x if bx is None else f"{x}.astype(np.int64)"), (y if by is None else f"{y}.astype(np.int64)")
        return f"({x} {_W_CMP[op]} {y})"

    # -- instructions
    def _instr(self, s) -> list:
        spec = s.ins.spec
        op, cls, i = spec.op, spec.cls, s.index
        if getattr(spec, "pulse", False) or s.run is not semantics_action(op, s):
            raise _NoLane
        out: list = []
        if cls in ("load", "and", "or"):
            if op in _W_CMP:
                c = self.compare(op, s.ops[0], s.ops[1])
            else:
                c = self.contact(op, self.bit(s.ops[0]), i, out)
                if c is None:
                    raise _NoLane
            return self.combine(s, cls, c, out)
        if self.structure(op, out):
            pass
        elif op in ("out", "set", "rst", "pls", "plf") and type(s.ops[0]) is BitRef \
                and s.ops[0].kind in ("X", "Y", "M", "A"):
            self.coil(op, self.bit(s.ops[0]), i, out)
        elif op in ("mov", "inc", "dec", "cml") or op in _W_ARITH:
            w = s.width
            if op in ("inc", "dec"):
                ops, dst = (s.ops[0],), s.ops[0]
            elif op in ("mov", "cml"):
                ops, dst = (s.ops[0],), s.ops[1]
            else:
                ops, dst = (s.ops[0], s.ops[1]), s.ops[2]
            words = self.dest(dst, w)
            vals = [self.operand(r) for r in ops]
            if all(b is None for _, b in vals):  # constants: the value is known here
                v = [x for x, _ in vals]
                mask = (1 << w) - 1
                folded = {"mov": lambda: v[0], "inc": lambda: v[0] + 1, "dec": lambda: v[0] - 1,
                          "cml": lambda: ~v[0], "add": lambda: v[0] + v[1], "sub": lambda: v[0] - v[1],
                          "wand": lambda: v[0] & v[1], "wor": lambda: v[0] | v[1], "wxor": lambda: v[0] ^ v[1]}[op]()
                out += self.store_const(words, folded & mask)
                return out
            x = [self.value(r, w) for r in ops]
            if op == "mov":
                src = x[0]
            elif op in ("inc", "dec"):
                src = f"({x[0]} {'+' if op == 'inc' else '-'} {self.const(1, w)})"
            elif op == "cml":
                src = f"(~{x[0]})"
            else:
                src = f"({x[0]} {_W_ARITH[op]} {x[1]})"
            out += self.store(words, src)
        elif op == "mul" and s.width == 16:
            words = self.dest(s.ops[2], 32)
            (x, bx), (y, by) = self.operand(s.ops[0]), self.operand(s.ops[1])
            if bx is None and by is None:
                out += self.store_const(words, (x * y) & 0xFFFFFFFF)
            else:
                if bx is None:
                    (x, bx), (y, by) = (y, by), (x, bx)
                if by is None and not -32768 <= y <= 32767:  # in int64: a product with any constant fits
                    v = f"({x}.astype(np.int64) * {y})"
                    out += self.store(words, f"{v}.astype(np.int32)" if len(words) == 1 else v)
                else:  # a 16-bit product fits int32 (multiply casts the int16 operands: one call)
                    y = self.const(y, 32) if by is None else y
                    out += self.store(words, f"np.multiply({x}, {y}, dtype=np.int32)")
        elif op == "tmr":
            out.append(self.tmr(s))
        elif op == "cnt":
            out += self.cnt(s)
        else:
            raise _NoLane
        return out

    def tmr(self, s) -> tuple:
        t, pre = s.ops
        target = self.prog.target
        if t.ix is not None or type(pre) is not ConstRef or pre.ix is not None or pre.is_f \
                or target.timer_base(t.num).get("retentive") or target.settings.get("timer_preset_range") \
                or t.num in self.timers:
            raise _NoLane
        self.timers.add(t.num)
        for sp in ("TW", "T", "TR", "TF", "TJ"):
            self.name(sp, t.num)
        return ("tmr", t.num, pre.get(None) & 0xFFFF, target.timer_base_ms(t.num) * 1000)

    def tmr_code(self, period: int, n: int, p: int, base: int, alone: bool) -> list[str]:
        """semantics.tmr + advance_timer per lane. Every TMR runs once every scan (the program
        is straight-line and names each timer once), so a timer running since the last scan
        was last updated `period` ago: that is its elapsed time, no last-update word needed.

        `alone` (no scenario writes the timer's value): the value is the whole ticks in the
        scans it has run, capped at the preset, min(TJ * period // base, p) with TJ those
        scans: the remainders sum up exactly so. Otherwise the ticks are added scan by scan:
        a bool when a scan is shorter than the base, a constant when the base divides it."""
        tw, tb, tr, tf, tj = f"TW_{n}", f"T_{n}", f"TR_{n}", f"TF_{n}", f"TJ_{n}"
        k64 = lambda x: self.const(x, 64)  # noqa: E731
        if alone:  # TJ + TR: + 1 running since the last scan, 0 when starting (TJ was zeroed while Off)
            ticks = (tj if period == base else f"{tj} * {k64(period // base)}" if period % base == 0
                     else f"{tj} // {k64(base // period)}" if base % period == 0
                     else f"{tj} * {k64(period)} // {k64(base)}")
            out = [f"{tj} = ({tj} + {tr}) * a", f"{tw} = np.minimum({ticks}, {k64(p)})"]
        elif period % base == 0:  # r: running since the last scan and still On
            k = period // base
            out = [f"r = a & {tr}",
                   f"{tw} = ({tw} + (r & ({tw} < {p}))) * a" if k == 1 else
                   f"{tw} = np.where(r & ({tw} < {p}), np.minimum({tw} + {k}, {p}), {tw}) * a"]
        elif period < base:
            out = [f"r = a & {tr}", f"f = {tf} + {period}", f"q = f >= {base}", f"{tf} = (f - q * {base}) * r",
                   f"{tw} = ({tw} + (q & r & ({tw} < {p}))) * a"]
        else:
            out = [f"r = a & {tr}", f"q, f = np.divmod({tf} + {period}, {base})", f"{tf} = f * r",
                   f"{tw} = np.where(r & ({tw} < {p}), np.minimum({tw} + q, {p}), {tw}) * a"]
        out += [f"{tr} = a", f"{tb} = ({tw} >= {k64(p)})" if p else f"{tb} = a"]
        return out

    def cnt(self, s) -> list[str]:
        c, pre = s.ops
        if c.ix is not None or c.num >= self.c32_lo or type(pre) is not ConstRef or pre.ix is not None \
                or pre.is_f or self.prog.target.settings.get("counter16_preset_range"):
            raise _NoLane
        n, p = c.num, max(pre.get(None) & 0xFFFF, 1)
        for sp in ("CW", "C", "CP"):
            self.name(sp, n)
        self.counters.setdefault(n, []).append(p)
        return [("cnt", n, p, s.index, self._new("e"))]

    def counted_alone(self, n: int, written: frozenset) -> bool:
        """One CNT counts counter n and no scenario writes its value or contact."""
        return len(self.counters[n]) == 1 and ("CW", n) not in written and ("C", n) not in written

    def cnt_code(self, n: int, p: int, index: int, e: str, alone: bool) -> list[str]:
        """semantics.cnt per lane. `alone` (counted_alone): the value only rises, by this CNT,
        and stops at the preset, so the contact is value >= preset at the end of the scan
        (a pending contact would be set exactly then)."""
        out = [f"{e} = E.get({index}, F); E[{index}] = a"]
        if alone:
            return out + [f"CW_{n} = np.minimum(CW_{n} + (a > {e}), {self.const(p, 64)})"]
        return out + [f"CW_{n} = CW_{n} + ((a > {e}) & (CW_{n} < {p}))",
                      f"CP_{n} = CP_{n} | ((CW_{n} >= {p}) > C_{n})"]


class _NoLane(Exception):
    pass


def semantics_action(op: str, s):
    """The generic routine of an op (a target's own routine keeps the program off the lanes)."""
    from mlctool.sim import semantics

    if op in semantics.CONTACTS:
        return s.run  # contacts run through decode's combinator
    return semantics.ACTIONS.get(op)


def word_lane_ready(st: Stimulus, period: int, watch: list[DeviceView], n_scans: int, m: Machine) -> bool:
    """Whether scenario `st` (scan period `period`, `n_scans` scans) can run as a word lane."""
    if st.models:
        return False
    for e in st.events:
        if e.kind not in ("set", "expect", "force", "release"):
            return False
        views = [v for v, _ in e.assigns] + [c.view for c in e.checks]
        if any(_view_slots(v, m) is None for v in views):
            return False
        if e.kind == "expect" and e.scan_index(period) >= n_scans:
            return False
    return all(_view_slots(v, m) is not None for v in watch)


class _Scratch:
    """One Machine through which lane values are converted exactly as a single run does.
    Conversions are remembered (a value's raw slots, a raw pattern's value): a campaign
    writes and reads the same few values again and again."""

    def __init__(self, target: Target, n: int):
        self.m = Machine(target, n)
        self.raws: dict[tuple, list] = {}
        self.values: dict[tuple, int | float] = {}

    def raw(self, view: DeviceView, value) -> list[tuple[tuple[str, int], int]]:
        """The slot values `view.write(m, value)` leaves."""
        key = (view, type(value), value)
        hit = self.raws.get(key)
        if hit is None:
            hit = self.raws[key] = self._raw(view, value)
        return hit

    def value(self, view: DeviceView, keys: tuple, raws: tuple) -> int | float:
        """read() of the view whose slots `keys` hold `raws` (the same for every device of a
        kind and view: DeviceView.read indexes by the number, nothing else)."""
        key = (view.kind, view.view, raws) if view.special is None else (view, raws)
        hit = self.values.get(key)
        if hit is None:
            got = dict(zip(keys, raws))
            hit = self.values[key] = self.read(view, got.__getitem__)
        return hit

    def _raw(self, view: DeviceView, value) -> list[tuple[tuple[str, int], int]]:
        slots = _view_slots(view, self.m)
        view.write(self.m, value)
        out = [(key, int(arr[i])) for key, arr, i in slots]
        for _, arr, i in slots:
            arr[i] = 0
        return out

    def read(self, view: DeviceView, get) -> int | float:
        slots = _view_slots(view, self.m)
        for key, arr, i in slots:
            arr[i] = get(key)
        v = view.read(self.m)
        for _, arr, i in slots:
            arr[i] = 0
        return v


class _Addresses:
    """Where a stimulus/result slot key (("D", 7), ("TW", 0), ...) lives: (lane array index,
    stride, offset) in its array's _raw view, lane `l` at `l * stride + offset`. A word of
    a DD pair is one half of each int32 lane."""

    def __init__(self, wp: WordLaneProgram):
        self.slots = dict(wp.slots)
        self.pairs = wp.pairs
        self.at: dict[tuple[str, int], tuple[int, int, int]] = {}
        for space, num in wp.slots:  # the program's devices (a pair as its two words): the results read them
            for key in [("D", num), ("D", num + 1)] if space == "DD" else [(space, num)]:
                self.of(key)

    def of(self, key: tuple[str, int]) -> tuple[int, int, int]:
        hit = self.at.get(key)
        if hit is None:
            space, num = key
            if space == "D" and num in self.pairs:
                hit = (self.slots[("DD", num)], 2, _HALVES[0])
            elif space == "D" and num - 1 in self.pairs:
                hit = (self.slots[("DD", num - 1)], 2, _HALVES[1])
            else:
                hit = (self.slots.setdefault(key, len(self.slots)), 1, 0)
            self.at[key] = hit
        return hit


def run_word_lanes(wp: WordLaneProgram, group: list[tuple[str, Stimulus]], period: int, n_scans: int,
                   watch: list[DeviceView], target: Target) -> list[RunResult | None]:
    """Run the scenarios of `group` as numpy lanes; None for a scenario whose expectations failed."""
    scratch = _Scratch(target, len(wp.prog.steps))
    addr = _Addresses(wp)
    n = len(group)
    # one pass over the events: the writes of each scan, by lane array, as raw index -> value
    sets: dict[int, dict[int, dict[int, int]]] = {}
    events: dict[int, list[tuple[int, object]]] = {}  # scan -> (lane, force/release/expect event)
    written: set[tuple[str, int]] = set()  # the keys the scenarios set or force
    for lane, (_, st) in enumerate(group):
        for e in st.events:
            k = e.scan_index(period)
            if e.kind == "set":
                per_scan = sets.setdefault(k, {})
                for v, value in e.assigns:
                    for key, raw in scratch.raw(v, value):
                        i, stride, off = addr.of(key)
                        per_scan.setdefault(i, {})[lane * stride + off] = raw
                        written.add(key)
            else:
                for v in [v for v, _ in e.assigns] + [c.view for c in e.checks]:
                    for key, _, _ in _view_slots(v, scratch.m):
                        addr.of(key)
                        if e.kind == "force":
                            written.add(key)
                events.setdefault(k, []).append((lane, e))
    slots = addr.slots
    space = {i: key[0] for key, i in slots.items()}
    S: list = [np.zeros(n, dtype=_lane_dtype(space[i])) for i in range(len(slots))]
    raw_type = [_raw(arr).dtype for arr in S]
    writes = {k: [(i, np.fromiter(d, dtype=np.intp, count=len(d)), np.fromiter(d.values(), dtype=raw_type[i], count=len(d)))
                  for i, d in per_scan.items()] for k, per_scan in sets.items()}
    forces: list[dict] = [{} for _ in range(n)]
    fslots: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    E: dict = {}
    F = np.zeros(n, dtype=bool)
    failed = set()
    scan = wp.scan_for(period, frozenset(written))

    def apply_forces():
        for i, (mask, val) in fslots.items():
            arr = S[i]
            S[i] = np.where(mask, val, _raw(arr)).view(arr.dtype)

    for k in range(n_scans):
        for i, at, raws in writes.get(k, ()):
            arr = S[i]
            if arr.dtype == bool or arr.dtype == np.int64:  # (arrays may be shared: `TR_0 = a`) D and DD are not
                S[i] = arr = arr.copy()
            _raw(arr)[at] = raws
        scan_events = events.get(k, ())
        if any(e.kind != "expect" for _, e in scan_events):
            for lane, e in scan_events:
                if e.kind == "force":
                    for v, value in e.assigns:
                        forces[lane][v] = value
                elif e.kind == "release":
                    for v, _ in e.assigns:
                        forces[lane].pop(v, None)
            masks: dict[int, dict[int, int]] = {}
            for lane, fs in enumerate(forces):
                for v, value in fs.items():
                    for key, raw in scratch.raw(v, value):
                        i, stride, off = addr.of(key)
                        masks.setdefault(i, {})[lane * stride + off] = raw
            fslots = {}
            for i, vals in masks.items():
                raw = _raw(S[i])
                mask = np.zeros(len(raw), dtype=bool)
                mask[list(vals)] = True
                val = np.zeros(len(raw), dtype=raw.dtype)
                val[list(vals)] = list(vals.values())
                fslots[i] = (mask, val)
        if fslots:
            apply_forces()
            scan(S, E, k * period, F, np)
            apply_forces()
        else:
            scan(S, E, k * period, F, np)
        for lane, e in scan_events:
            if e.kind == "expect" and lane not in failed:
                for c in e.checks:
                    keys = tuple(key for key, _, _ in _view_slots(c.view, scratch.m))
                    raws = []
                    for key in keys:
                        i, stride, off = addr.of(key)
                        raws.append(_raw(S[i])[lane * stride + off].item())
                    if not c.holds(scratch.value(c.view, keys, tuple(raws))):
                        failed.add(lane)
    final = {}
    for key, (i, stride, off) in addr.at.items():
        raw = _raw(S[i])
        final[key] = (raw[off::stride] if stride > 1 else raw).tolist()
    return _word_results(wp.prog, group, final, failed, period, n_scans, watch, scratch)


def _word_results(prog: Program, group: list[tuple[str, Stimulus]], final: dict, failed: set[int],
                  period: int, n_scans: int, watch: list[DeviceView], scratch: _Scratch) -> list[RunResult | None]:
    """As batch._lane_results: the union of all lanes' views sorted and named once, each view's
    values for all lanes converted once per distinct raw pattern, then one row per lane."""
    n = len(group)
    names = program_devices(prog) | set(watch)
    own = [st.devices() for _, st in group]
    order = sorted(names.union(*own), key=DeviceView.sort_key)
    rank = {v: k for k, v in enumerate(order)}
    labels = [v.name for v in order]
    columns = []
    for v in order:
        slots = _view_slots(v, scratch.m)
        if slots is None:  # a device the lanes never touch: as at power-on
            columns.append([v.read(scratch.m)] * n)
            continue
        keys = tuple(key for key, _, _ in slots)
        cols = [final.get(key) or [0] * n for key in keys]
        lanes = cols[0] if len(cols) == 1 else list(zip(*cols))
        value = {raws: scratch.value(v, keys, raws if len(cols) > 1 else (raws,)) for raws in set(lanes)}
        columns.append(list(map(value.__getitem__, lanes)))
    base_set = {rank[v] for v in names}
    base_flags = bytes(1 if k in base_set else 0 for k in range(len(order)))
    out: list[RunResult | None] = []
    for lane, ((_, st), views_of_lane, row) in enumerate(zip(group, own, zip(*columns) if columns else [()] * n)):
        if lane in failed:
            out.append(None)
            continue
        flags = bytearray(base_flags)
        for v in views_of_lane:
            flags[rank[v]] = 1
        views = list(compress(order, flags))
        devices = dict(zip(compress(labels, flags), compress(row, flags)))
        outcomes = [ExpectOutcome(e.line, e.text, e.scan_index(period) * period, e.scan_index(period))
                    for e in st.events if e.kind == "expect"]
        outcomes.sort(key=lambda o: (o.scan, o.line))
        out.append(RunResult(period, n_scans, devices, views, outcomes, [], None, []))
    return out


class LazyWordLanes:
    """The WordLaneProgram of an image, generated when a scenario first needs it (a batch of
    bit-only scenarios never does)."""

    def __init__(self, image: Image, target: Target):
        self.image, self.target = image, target
        self.done = False
        self.wp: WordLaneProgram | None = None

    def program(self) -> WordLaneProgram | None:
        if not self.done:
            self.done = True
            wp = WordLaneProgram(load_program(self.image, self.target))
            self.wp = wp if wp.ok else None
        return self.wp
