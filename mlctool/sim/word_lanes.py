"""Word lanes of a batch (numpy): many scenarios of one program run together.

A straight-line program (no jumps, calls or loops) of contacts, compare contacts, coils,
TMR/CNT with K presets and 16/32-bit word arithmetic and moves on D (see `WordLaneProgram`),
with scenarios that set, force and expect plain bits and D/T/C words: every device is a numpy
array with one element per scenario (bits bool, words int64 holding the raw 16-bit pattern),
a conditional write is `np.where(a, new, old)`. Values are read and written through a scratch
Machine and DeviceView, so conversions are the single run's. mlctool/sim/batch.py decides which
scenarios run so and turns a failing lane into a single run.
"""

from __future__ import annotations

from itertools import compress

import numpy as np

from mlctool.program import Image
from mlctool.sim.decode import Program, program_devices
from mlctool.sim.lane_codegen import RungCodegen, lanes_target
from mlctool.sim.operands import BitRef, ConstRef, CounterRef, WordRef
from mlctool.sim.run import ExpectOutcome, RunResult
from mlctool.sim.scan import load_program
from mlctool.sim.state import DeviceView, Machine
from mlctool.sim.stimulus import Stimulus
from mlctool.targetapi.model import Target

WORD_BIT_SPACES = ("X", "Y", "M", "A", "T", "C")  # bool arrays; words: D, TW (timer value),
# CW (counter value), TL/TF (timer last update, remainder); TR (running) and CP (pending) are bool
_W_CMP = {"cmp_eq": "==", "cmp_ne": "!=", "cmp_gt": ">", "cmp_lt": "<", "cmp_ge": ">=", "cmp_le": "<="}
_W_ARITH = {"add": "+", "sub": "-", "wand": "&", "wor": "|", "wxor": "^"}


def _bool_space(space: str) -> bool:
    return space in WORD_BIT_SPACES or space in ("TR", "CP")


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


class WordLaneProgram(RungCodegen):
    """A straight-line program as one Python function over numpy lanes (one element per
    scenario). `ok` False: the program needs scenario-by-scenario runs."""

    def __init__(self, prog: Program):
        super().__init__(prog)
        self.counters: list[int] = []
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

    def _generate(self) -> bool:
        steps = self.prog.steps
        if not steps or steps[-1].ins.spec.op != "end":
            return False
        body: list[str] = []
        try:
            for s in steps[:-1]:
                body += self._instr(s)
        except _NoLane:
            return False
        for n in self.counters:  # counter contacts act at the end of the scan (1.7)
            body.append(f"C_{n} = C_{n} | CP_{n}; CP_{n} = F")
        names = sorted(self.slots, key=self.slots.get)
        load = [f"    {sp}_{n} = S[{self.slots[(sp, n)]}]" for sp, n in names]
        store = [f"    S[{self.slots[(sp, n)]}] = {sp}_{n}" for sp, n in names]
        src = ("def scan(S, E, now, F, np):\n    a = F\n" + "\n".join(load + ["    " + b for b in body] + store)
               + "\n")
        g: dict = {}
        exec(compile(src, "<mlc-word-lanes>", "exec"), g)  # noqa: S102 - our own generated code
        self.scan = g["scan"]
        self.source = src
        return True

    # -- operands
    def signed(self, ref) -> str:
        w = ref.width
        if type(ref) is ConstRef and ref.ix is None and not ref.is_f:
            return repr(ref.get(None))
        if type(ref) is WordRef and ref.ix is None and ref.kind in ("D", "T"):
            sp = "D" if ref.kind == "D" else "TW"
            if w == 16:
                return f"(({self.name(sp, ref.num)} ^ 32768) - 32768)"
            if ref.kind == "D" and ref.num + 1 <= ref.hi:
                return f"((({self.name('D', ref.num + 1)} << 16 | {self.name('D', ref.num)}) ^ 2147483648) - 2147483648)"
        if type(ref) is CounterRef and ref.ix is None and w == 16 and ref.num < self.c32_lo:
            return f"(({self.name('CW', ref.num)} ^ 32768) - 32768)"
        raise _NoLane

    def bit(self, ref) -> str:
        if type(ref) is BitRef and ref.ix is None and ref.kind in WORD_BIT_SPACES:
            return self.name(ref.kind, ref.num)
        raise _NoLane

    def dest(self, ref, width: int) -> list[str]:
        """D words a store writes (1 or 2)."""
        if type(ref) is WordRef and ref.ix is None and ref.kind == "D":
            if width == 16:
                return [self.name("D", ref.num)]
            if ref.num + 1 <= ref.hi:
                return [self.name("D", ref.num), self.name("D", ref.num + 1)]
        raise _NoLane

    def store(self, words: list[str], expr: str) -> list[str]:
        if len(words) == 1:
            return [f"{words[0]} = np.where(a, ({expr}) & 65535, {words[0]})"]
        return [f"v = {expr}", f"{words[0]} = np.where(a, v & 65535, {words[0]})",
                f"{words[1]} = np.where(a, (v >> 16) & 65535, {words[1]})"]

    # -- instructions
    def _instr(self, s) -> list[str]:
        spec = s.ins.spec
        op, cls, i = spec.op, spec.cls, s.index
        if getattr(spec, "pulse", False) or s.run is not semantics_action(op, s):
            raise _NoLane
        out: list[str] = []
        if cls in ("load", "and", "or"):
            if op in _W_CMP:
                c = f"({self.signed(s.ops[0])} {_W_CMP[op]} {self.signed(s.ops[1])})"
                if c.count("(") == c.count(")") and "_" not in c:  # two constants
                    c = f"(F | {c})"
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
            mask = 65535 if w == 16 else 4294967295
            if op == "mov":
                src, dst = self.signed(s.ops[0]), s.ops[1]
            elif op in ("inc", "dec"):
                src, dst = f"({self.signed(s.ops[0])} {'+' if op == 'inc' else '-'} 1)", s.ops[0]
            elif op == "cml":
                src, dst = f"(~{self.signed(s.ops[0])} & {mask})", s.ops[1]
            else:
                src = f"({self.signed(s.ops[0])} {_W_ARITH[op]} {self.signed(s.ops[1])})"
                dst = s.ops[2]
            out += self.store(self.dest(dst, w), src)
        elif op == "mul" and s.width == 16:
            words = self.dest(s.ops[2], 32)
            out += self.store(words, f"({self.signed(s.ops[0])} * {self.signed(s.ops[1])})")
        elif op == "tmr":
            out += self.tmr(s)
        elif op == "cnt":
            out += self.cnt(s)
        else:
            raise _NoLane
        return out

    def tmr(self, s) -> list[str]:
        """semantics.tmr + advance_timer per lane (every TMR runs every scan: nothing skips it)."""
        t, pre = s.ops
        target = self.prog.target
        if t.ix is not None or type(pre) is not ConstRef or pre.ix is not None or pre.is_f \
                or target.timer_base(t.num).get("retentive") or target.settings.get("timer_preset_range"):
            raise _NoLane
        n, p, base = t.num, pre.get(None) & 0xFFFF, target.timer_base_ms(t.num) * 1000
        tw, tb, tr, tl, tf = (self.name(sp, n) for sp in ("TW", "T", "TR", "TL", "TF"))
        return [f"q, f = np.divmod(now - {tl} + {tf}, {base})",
                f"v = np.where({tw} < {p}, np.minimum({tw} + q, {p}), {tw})",
                f"{tw} = np.where(a, np.where({tr}, v, {tw}), 0)",
                f"{tf} = np.where(a & {tr}, f, 0)",
                f"{tl} = np.where(a, now, {tl})",
                f"{tr} = a",
                f"{tb} = a & ({tw} >= {p})"]

    def cnt(self, s) -> list[str]:
        c, pre = s.ops
        if c.ix is not None or c.num >= self.c32_lo or type(pre) is not ConstRef or pre.ix is not None \
                or pre.is_f or self.prog.target.settings.get("counter16_preset_range"):
            raise _NoLane
        n, p = c.num, max(pre.get(None) & 0xFFFF, 1)
        cw, cb, cp = self.name("CW", n), self.name("C", n), self.name("CP", n)
        if n not in self.counters:
            self.counters.append(n)
        e = self._new("e")
        return [f"{e} = E.get({s.index}, F); E[{s.index}] = a",
                f"{cw} = {cw} + (a & ~{e} & ({cw} < {p}))",
                f"{cp} = {cp} | (({cw} >= {p}) & ~{cb})"]


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
        """read() of the view whose slots `keys` hold `raws`."""
        key = (view, raws)
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


def run_word_lanes(wp: WordLaneProgram, group: list[tuple[str, Stimulus]], period: int, n_scans: int,
                   watch: list[DeviceView], target: Target) -> list[RunResult | None]:
    """Run the scenarios of `group` as numpy lanes; None for a scenario whose expectations failed."""
    scratch = _Scratch(target, len(wp.prog.steps))
    slots = dict(wp.slots)
    n = len(group)
    for _, st in group:
        for e in st.events:
            for v in [v for v, _ in e.assigns] + [c.view for c in e.checks]:
                for key, _, _ in _view_slots(v, scratch.m):
                    slots.setdefault(key, len(slots))
    space = {i: key[0] for key, i in slots.items()}
    S: list = [np.zeros(n, dtype=bool if _bool_space(space[i]) else np.int64) for i in range(len(slots))]
    by_scan: dict[int, list[tuple[int, object]]] = {}
    for lane, (_, st) in enumerate(group):
        for e in st.events:
            by_scan.setdefault(e.scan_index(period), []).append((lane, e))
    forces: list[dict] = [{} for _ in range(n)]
    fslots: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    E: dict = {}
    F = np.zeros(n, dtype=bool)
    failed = set()
    scan = wp.scan

    def apply_forces():
        for i, (mask, val) in fslots.items():
            S[i] = np.where(mask, val, S[i])

    for k in range(n_scans):
        events = by_scan.get(k, ())
        sets: dict[int, dict[int, int]] = {}
        forces_changed = False
        for lane, e in events:
            if e.kind == "set":
                for v, value in e.assigns:
                    for key, raw in scratch.raw(v, value):
                        sets.setdefault(slots[key], {})[lane] = raw
            elif e.kind == "force":
                for v, value in e.assigns:
                    forces[lane][v] = value
                forces_changed = True
            elif e.kind == "release":
                for v, _ in e.assigns:
                    forces[lane].pop(v, None)
                forces_changed = True
        for i, vals in sets.items():
            arr = S[i].copy()
            arr[list(vals)] = list(vals.values())
            S[i] = arr
        if forces_changed:
            masks: dict[int, dict[int, int]] = {}
            for lane, fs in enumerate(forces):
                for v, value in fs.items():
                    for key, raw in scratch.raw(v, value):
                        masks.setdefault(slots[key], {})[lane] = raw
            fslots = {}
            for i, vals in masks.items():
                mask = np.zeros(n, dtype=bool)
                mask[list(vals)] = True
                val = np.zeros(n, dtype=S[i].dtype)
                val[list(vals)] = list(vals.values())
                fslots[i] = (mask, val)
        apply_forces()
        scan(S, E, k * period, F, np)
        apply_forces()
        for lane, e in events:
            if e.kind == "expect" and lane not in failed:
                for c in e.checks:
                    keys = tuple(key for key, _, _ in _view_slots(c.view, scratch.m))
                    raws = tuple(S[slots[key]][lane].item() for key in keys)
                    if not c.holds(scratch.value(c.view, keys, raws)):
                        failed.add(lane)
    final = {key: S[i].tolist() for key, i in slots.items()}
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
        columns.append([scratch.value(v, keys, raws) for raws in zip(*cols)])
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
