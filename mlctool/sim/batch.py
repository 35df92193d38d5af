"""Batch runs: one program, many stimulus files (`mlc sim PROGRAM --stimulus 'tests/*.stim'`).

Each scenario's result is the one `mlc sim PROGRAM --stimulus FILE` gives. Two ways to get
there faster than one run after the other:

- Lanes (bit-sliced vectorisation). When the program is pure bit logic (contacts, edges,
  ANB/ORB/MPS/MRD/MPP/INV, OUT/SET/RST/PLS/PLF on X/Y/M/A, END) and a scenario only sets,
  forces and expects bits, with no device model, power cycle or alarm line, the scenarios
  that share scan period and scan count run together: every device is one Python integer
  whose bit `l` is scenario `l`, so one `&` evaluates a contact for all of them. (Python's
  arbitrary-width integers beat numpy boolean arrays here: one C call per instruction for
  any number of lanes, and no temporaries.) A scenario that fails an expectation is run
  again on its own, so its failure report (last writer included) is exactly the single run's.
- Word lanes (numpy). A straight-line program (no jumps, calls or loops) of contacts, compare
  contacts, coils, TMR/CNT with K presets and 16/32-bit word arithmetic and moves on D (see
  `WordLaneProgram`), with scenarios that set, force and expect plain bits and D/T/C words:
  every device is a numpy array with one element per scenario (bits bool, words int64 holding
  the raw 16-bit pattern), a conditional write is `np.where(a, new, old)`. Values are read
  and written through a scratch Machine and DeviceView, so conversions are the single run's.
- Processes (`jobs` > 1): the other scenarios are spread over worker processes.
"""

from __future__ import annotations

import gc
import os
import pickle
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from itertools import compress
from operator import itemgetter

import numpy as np

from mlctool.diagnostics import Span, diag
from mlctool.program import Image
from mlctool.sim.decode import Program, program_devices
from mlctool.sim.operands import BitRef, ConstRef, CounterRef, WordRef
from mlctool.sim.output import run_diagnostics
from mlctool.sim.run import (
    DEFAULT_SCAN_US,
    ExpectOutcome,
    RunResult,
    RunTooLong,
    Simulation,
    build_models,
    plan_scans,
)
from mlctool.sim.scan import DEFAULT_WATCHDOG, load_program
from mlctool.sim.state import DeviceView, Machine
from mlctool.sim.stimulus import NameCache, Stimulus, load_stimulus
from mlctool.sim.suite import Scenario
from mlctool.targetapi.model import Target
from mlctool.targetapi.registry import simulation_of

LANE_KINDS = ("X", "Y", "M", "A")


@dataclass
class Options:
    """The `mlc sim` options that shape a run."""

    scan_us: int | None = None
    until_us: int | None = None
    scans: int | None = None
    watch: list[DeviceView] = field(default_factory=list)
    watchdog: int = DEFAULT_WATCHDOG
    engine: str | None = None
    preload: list = field(default_factory=list)  # --table: register tables loaded with the program


@dataclass
class BatchStats:
    lanes: int = 0  # scenarios run as lanes (and passed there)
    word_lanes: int = 0  # of them, scenarios run as numpy word lanes
    reruns: int = 0  # lane scenarios that failed and were run again on their own
    single: int = 0  # scenarios run one by one (in processes when jobs > 1)


# ---------------------------------------------------------------------------- one scenario

def run_one(image: Image, target: Target, path: str, opts: Options,
            loaded: tuple[Stimulus | None, list] | None = None) -> Scenario:
    """Exactly `mlc sim PROGRAM --stimulus PATH` (without --vcd/--report)."""
    start = time.perf_counter()
    sc = _run_one(image, target, path, opts, loaded)
    sc.seconds = time.perf_counter() - start
    return sc


def _run_one(image: Image, target: Target, path: str, opts: Options,
             loaded: tuple[Stimulus | None, list] | None) -> Scenario:
    st, diags = loaded if loaded is not None else load_stimulus(path, target)
    if st is None or any(d.severity == "error" for d in diags):
        return Scenario(path, None, diags, st.lines if st else [])
    models, model_diags = build_models(st, target)
    if any(d.severity == "error" for d in model_diags):
        return Scenario(path, None, diags + model_diags, st.lines)
    period = st.scan_us or opts.scan_us or DEFAULT_SCAN_US
    try:
        n_scans = plan_scans(st, period, opts.until_us, opts.scans)
    except RunTooLong as e:
        return Scenario(path, None, [diag(path, Span.at(1), "E601", str(e))], st.lines)
    sim = Simulation(image, target, st, models, period, list(opts.watch), trace=False,
                     watchdog=opts.watchdog, engine=opts.engine, preload=opts.preload)
    result = sim.run(n_scans)
    return Scenario(path, result, run_diagnostics(result, path), st.lines)


_WORKER: dict = {}


def _init_worker(blob: bytes) -> None:
    _WORKER["args"] = pickle.loads(blob)


def _run_in_worker(path: str) -> Scenario:
    image, target, opts = _WORKER["args"]
    return run_one(image, target, path, opts)


# ---------------------------------------------------------------------------- lanes

class _RungCodegen:
    """What both lane code generators share: the rung's result `a`, its ANB/ORB blocks and
    MPS stack (2.2), as generated statements. Subclasses say how a line is indented and how
    a lane word is inverted."""

    indent = ""

    def __init__(self, prog: Program):
        self.prog = prog
        self.slots: dict[tuple[str, int], int] = {}
        self.blocks: list[str] = []
        self.stack: list[str] = []
        self.tmp = 0

    def invert(self, x: str) -> str:
        raise NotImplementedError

    def edge_memory(self, i: int) -> str:
        """The expression reading step i's edge memory (2.2 LDP/LDF)."""
        raise NotImplementedError

    def contact(self, op: str, x: str, i: int, out: list[str]) -> str | None:
        """A bit contact's value as an expression (None: not a plain contact)."""
        if op == "contact":
            return x
        if op == "contact_not":
            return self.invert(x)
        if op in ("contact_rise", "contact_fall"):
            e = self._new("e")
            out.append(f"{self.indent}{e} = {self.edge_memory(i)}; E[{i}] = {x}")
            return f"({x} & {self.invert(e)})" if op == "contact_rise" else f"({e} & {self.invert(x)})"
        return None

    def coil(self, op: str, x: str, i: int, out: list[str]) -> None:
        """OUT/SET/RST/PLS/PLF of bit `x` driven by the rung result."""
        ind = self.indent
        if op == "out":
            out.append(f"{ind}{x} = a")
        elif op == "set":
            out.append(f"{ind}{x} = {x} | a")
        elif op == "rst":
            out.append(f"{ind}{x} = {x} & {self.invert('a')}")
        else:
            e = self._new("e")
            out.append(f"{ind}{e} = {self.edge_memory(i)}; E[{i}] = a")
            out.append(f"{ind}{x} = a & {self.invert(e)}" if op == "pls" else f"{ind}{x} = {e} & {self.invert('a')}")

    def _new(self, prefix: str) -> str:
        self.tmp += 1
        return f"{prefix}{self.tmp}"

    def combine(self, s, cls: str, contact: str, out: list[str]) -> list[str]:
        """A contact's value `contact` joins the rung result by the contact's class."""
        ind = self.indent
        if cls == "load":
            if s.new_rung:
                self.blocks.clear()
                self.stack.clear()
            else:
                k = self._new("k")
                out.append(f"{ind}{k} = a")
                self.blocks.append(k)
            out.append(f"{ind}a = {contact}")
        else:
            out.append(f"{ind}a = a {'&' if cls == 'and' else '|'} {contact}")
        return out

    def structure(self, op: str, out: list[str]) -> bool:
        """ANB/ORB/MPS/MRD/MPP/INV/NOP; False when `op` is none of them."""
        ind = self.indent
        if op in ("anb", "orb"):
            if self.blocks:
                out.append(f"{ind}a = {self.blocks.pop()} {'&' if op == 'anb' else '|'} a")
        elif op == "mps":
            k = self._new("p")
            out.append(f"{ind}{k} = a")
            self.stack.append(k)
        elif op == "mrd":
            if self.stack:
                out.append(f"{ind}a = {self.stack[-1]}")
        elif op == "mpp":
            if self.stack:
                out.append(f"{ind}a = {self.stack.pop()}")
        elif op == "inv":
            out.append(f"{ind}a = {self.invert('a')}")
        elif op != "nop":
            return False
        return True


class LaneProgram(_RungCodegen):
    """The program as one Python function over bit-sliced devices."""

    indent = "    "

    def __init__(self, prog: Program):
        super().__init__(prog)
        self.lines: list[str] = []
        self.ok = self._generate()

    def invert(self, x: str) -> str:
        return f"({x} ^ ALL)"

    def edge_memory(self, i: int) -> str:
        return f"E[{i}]"

    def slot(self, kind: str, num: int) -> int:
        return self.slots.setdefault((kind, num), len(self.slots))

    def _name(self, ref) -> str | None:
        if type(ref) is not BitRef or ref.ix is not None or ref.kind not in LANE_KINDS:
            return None
        self.slot(ref.kind, ref.num)
        return f"{ref.kind}{ref.num}"

    def _generate(self) -> bool:
        steps = self.prog.steps
        if not steps or steps[-1].ins.spec.op != "end":
            return False
        body = []
        for s in steps[:-1]:
            line = self._instr(s)
            if line is None:
                return False
            body += line
        names = sorted({f"{k}{n}" for k, n in self.slots}, key=lambda x: self.slots[(x[0], int(x[1:]))])
        load = [f"    {n} = S[{self.slots[(n[0], int(n[1:]))]}]" for n in names]
        store = [f"    S[{self.slots[(n[0], int(n[1:]))]}] = {n}" for n in names]
        src = "def scan(S, E, ALL):\n    a = 0\n" + "\n".join(load + body + store) + "\n"
        g: dict = {}
        exec(compile(src, "<mlc-lanes>", "exec"), g)  # noqa: S102 - our own generated code
        self.scan = g["scan"]
        self.source = src
        return True

    def _instr(self, s) -> list[str] | None:
        spec = s.ins.spec
        op, cls, i = spec.op, spec.cls, s.index
        if getattr(spec, "pulse", False):
            return None
        out: list[str] = []
        if cls in ("load", "and", "or"):
            name = self._name(s.ops[0]) if s.ops else None
            if name is None:
                return None
            c = self.contact(op, name, i, out)
            return None if c is None else self.combine(s, cls, c, out)
        if op == "label" or self.structure(op, out):
            pass
        elif op in ("out", "set", "rst", "pls", "plf"):
            name = self._name(s.ops[0])
            if name is None:
                return None
            self.coil(op, name, i, out)
        else:
            return None
        return out


def _lane_ready(st: Stimulus, opts: Options, n_scans: int) -> bool:
    if st.models:
        return False
    period = st.scan_us or opts.scan_us or DEFAULT_SCAN_US
    for e in st.events:
        kind = e.kind
        if kind == "expect":
            if e.scan_index(period) >= n_scans:
                return False
            for c in e.checks:
                if c.view.view != "bit" or c.view.kind not in LANE_KINDS:
                    return False
        elif kind in ("set", "force", "release"):
            for v, _ in e.assigns:
                if v.view != "bit" or v.kind not in LANE_KINDS:
                    return False
        else:
            return False
    return all(v.view == "bit" and v.kind in LANE_KINDS for v in opts.watch)


def run_lanes(lp: LaneProgram, group: list[tuple[str, Stimulus]], period: int, n_scans: int,
              opts: Options) -> list[RunResult | None]:
    """Run the scenarios of `group` together; None for a scenario whose expectations failed."""
    slots = dict(lp.slots)
    n = len(group)
    ALL = (1 << n) - 1
    sets: dict[int, dict[int, list[int]]] = {}  # scan -> slot -> [set mask, clear mask]
    forcing: dict[int, list[tuple[int, int, int | None]]] = {}  # scan -> [(slot, lane bit, value)]
    expects: dict[int, list[tuple[int, object]]] = {}
    for lane, (_, st) in enumerate(group):  # one pass over the events (a batch has ~20 k of them)
        bit = 1 << lane
        for e in st.events:
            k = e.scan if e.scan is not None else -(-e.time_us // period)  # Event.scan_index
            kind = e.kind
            if kind == "expect":
                expects.setdefault(k, []).append((lane, e))
                for c in e.checks:
                    slots.setdefault((c.view.kind, c.view.number), len(slots))
                continue
            for v, value in e.assigns:
                key = (v.kind, v.number)
                slot = slots.get(key)
                if slot is None:
                    slot = slots[key] = len(slots)
                if kind == "set":
                    per_scan = sets.get(k)
                    if per_scan is None:
                        per_scan = sets[k] = {}
                    masks = per_scan.get(slot)
                    if masks is None:  # the usual case: one write of this device in this scan
                        per_scan[slot] = [bit, 0] if value else [0, bit]
                    elif value:
                        masks[0] |= bit
                        masks[1] &= ~bit
                    else:
                        masks[1] |= bit
                        masks[0] &= ~bit
                else:
                    forcing.setdefault(k, []).append(
                        (slot, bit, (1 if value else 0) if kind == "force" else None))
    S = [0] * len(slots)
    E = [0] * len(lp.prog.steps)
    fmask: dict[int, int] = {}
    fval: dict[int, int] = {}
    failed = 0
    scan = lp.scan
    for k in range(n_scans):
        for slot, (on, off) in sets.get(k, {}).items():
            S[slot] = (S[slot] | on) & ~off
        for slot, bit, value in forcing.get(k, ()):
            if value is None:
                fmask[slot] = fmask.get(slot, 0) & ~bit
            else:
                fmask[slot] = fmask.get(slot, 0) | bit
                fval[slot] = (fval.get(slot, 0) & ~bit) | (bit if value else 0)
        for slot, fm in fmask.items():
            S[slot] = (S[slot] & ~fm) | (fval[slot] & fm)
        scan(S, E, ALL)
        for slot, fm in fmask.items():
            S[slot] = (S[slot] & ~fm) | (fval[slot] & fm)
        for lane, e in expects.get(k, ()):
            for c in e.checks:
                if not c.holds((S[slots[(c.view.kind, c.view.number)]] >> lane) & 1):
                    failed |= 1 << lane
    return _lane_results(lp.prog, group, S, slots, failed, period, n_scans, opts)


_BITS = bytes.maketrans(b"01", b"\x00\x01")


def _picker(indices: list[int]):
    """seq -> tuple of seq[k] for k in indices (itemgetter, also for one index or none)."""
    if len(indices) > 1:
        return itemgetter(*indices)
    return lambda seq: tuple(seq[k] for k in indices)


def _lane_results(prog: Program, group: list[tuple[str, Stimulus]], S: list[int], slots: dict,
                  failed: int, period: int, n_scans: int, opts: Options) -> list[RunResult | None]:
    """Each passing lane's RunResult, as a single run reports it: the program's devices and
    the scenario's own, sorted, by name. The lane words are turned into per-lane rows once
    (one bit string per device, transposed by zip) and the names and order are worked out
    once for the union of all lanes' devices, not per lane."""
    n = len(group)
    names = program_devices(prog) | set(opts.watch)
    # the scenarios' own devices (Stimulus.devices()), by object first: a batch's views are
    # shared objects (NameCache), and hashing a DeviceView is a Python call
    objs: dict[int, DeviceView] = {}
    lane_ids = []
    for _, st in group:
        own = {id(v): v for e in st.events for v, _ in e.assigns}
        own.update({id(c.view): c.view for e in st.events for c in e.checks})
        objs.update(own)
        lane_ids.append(own)
    order = sorted(names.union(objs.values()), key=DeviceView.sort_key)
    rank = {v: k for k, v in enumerate(order)}
    rank_of = {i: rank[v] for i, v in objs.items()}
    labels = [v.name for v in order]
    zeros = bytes(n)
    columns = []
    for v in order:
        slot = slots.get((v.kind, v.number))
        columns.append(zeros if slot is None else
                       format(S[slot] & ((1 << n) - 1), f"0{n}b")[::-1].encode().translate(_BITS))
    rows = zip(*columns) if columns else iter([()] * n)  # rows[lane][k]: the lane's value of order[k]
    base_set = {rank[v] for v in names}
    base = sorted(base_set)
    base_views = [order[k] for k in base]
    base_labels = [labels[k] for k in base]
    pick_base = _picker(base)
    base_flags = bytes(1 if k in base_set else 0 for k in range(len(order)))
    extras = [{rank_of[i] for i in ids} - base_set for ids in lane_ids]
    out: list[RunResult | None] = []
    for lane, ((_, st), extra, row) in enumerate(zip(group, extras, rows)):
        if failed >> lane & 1:
            out.append(None)
            continue
        if extra:  # the program's devices and the lane's own, in `order`
            flags = bytearray(base_flags)
            for k in extra:
                flags[k] = 1
            views = list(compress(order, flags))
            devices = dict(zip(compress(labels, flags), compress(row, flags)))
        else:
            views = list(base_views)
            devices = dict(zip(base_labels, pick_base(row)))
        outcomes = [ExpectOutcome(e.line, e.text, e.scan_index(period) * period, e.scan_index(period))
                    for e in st.events if e.kind == "expect"]
        outcomes.sort(key=lambda o: (o.scan, o.line))
        out.append(RunResult(period, n_scans, devices, views, outcomes, [], None, []))
    return out


# ---------------------------------------------------------------------------- word lanes (numpy)

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


class WordLaneProgram(_RungCodegen):
    """A straight-line program as one Python function over numpy lanes (one element per
    scenario). `ok` False: the program needs scenario-by-scenario runs."""

    def __init__(self, prog: Program):
        super().__init__(prog)
        self.counters: list[int] = []
        t = prog.target
        self.c32_lo = t.settings["counters32"][0]
        self.ok = self._generate() if _lanes_target(t) else False

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


def _lanes_target(target: Target) -> bool:
    """Targets whose scans the lanes model: no system relays, no simulation extension."""
    own = simulation_of(target)
    return (not target.settings.get("system_relays")
            and own.before_scan is None and own.views is None)


def _word_lane_ready(st: Stimulus, opts: Options, n_scans: int, m: Machine) -> bool:
    if st.models:
        return False
    period = st.scan_us or opts.scan_us or DEFAULT_SCAN_US
    for e in st.events:
        if e.kind not in ("set", "expect", "force", "release"):
            return False
        views = [v for v, _ in e.assigns] + [c.view for c in e.checks]
        if any(_view_slots(v, m) is None for v in views):
            return False
        if e.kind == "expect" and e.scan_index(period) >= n_scans:
            return False
    return all(_view_slots(v, m) is not None for v in opts.watch)


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
                   opts: Options, target: Target) -> list[RunResult | None]:
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
    return _word_results(wp.prog, group, final, failed, period, n_scans, opts, scratch)


def _word_results(prog: Program, group: list[tuple[str, Stimulus]], final: dict, failed: set[int],
                  period: int, n_scans: int, opts: Options, scratch: _Scratch) -> list[RunResult | None]:
    """As _lane_results: the union of all lanes' views sorted and named once, each view's
    values for all lanes converted once per distinct raw pattern, then one row per lane."""
    n = len(group)
    names = program_devices(prog) | set(opts.watch)
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


# ---------------------------------------------------------------------------- the batch

def _take_lanes(group, outcomes, results: dict, rest: list, stats: BatchStats, seconds: float) -> int:
    """Scenarios that passed as lanes become results (each with an even share of the group's
    wall time); the others are run again on their own. Returns how many passed."""
    passed = 0
    for (p, st), r in zip(group, outcomes):
        if r is None:
            rest.append(p)
            stats.reruns += 1
        else:
            results[p] = Scenario(p, r, run_diagnostics(r, p), st.lines, seconds=seconds / len(group))
            passed += 1
    stats.lanes += passed
    return passed


def run_batch(image: Image, target: Target, paths: list[str], opts: Options, jobs: int = 1,
              lanes: bool = True, cluster: str | None = None,
              loaded: dict[str, tuple[Stimulus | None, list]] | None = None) -> tuple[list[Scenario], BatchStats]:
    """One Scenario per path, in the order given. `cluster`: a Dask scheduler's address, the
    scenarios run there in chunks (mlctool/sim/cluster.py; ClusterError when it cannot)."""
    stats = BatchStats()
    results: dict[str, Scenario] = {}
    paused = gc.isenabled()
    gc.disable()  # see _run_batch_lanes
    try:
        if loaded is None:
            names = NameCache(target)
            loaded = {p: load_stimulus(p, target, names) for p in paths}
        if cluster is None:
            rest = _run_batch_lanes(image, target, paths, opts, lanes, loaded, results, stats)
    finally:
        if paused:
            gc.enable()
    if cluster is not None:
        return _run_on_cluster(cluster, image, target, paths, opts, lanes, loaded)
    stats.single = len(rest) - stats.reruns
    rest_set = set(rest)
    rest = [p for p in paths if p in rest_set]
    if jobs > 1 and len(rest) > 1:
        blob = pickle.dumps((image, target, opts))
        with ProcessPoolExecutor(max_workers=jobs, initializer=_init_worker, initargs=(blob,)) as pool:
            for p, sc in zip(rest, pool.map(_run_in_worker, rest, chunksize=max(1, len(rest) // (4 * jobs)))):
                results[p] = sc
    else:
        for p in rest:
            results[p] = run_one(image, target, p, opts, loaded[p])
    return [results[p] for p in paths], stats


def _run_batch_lanes(image: Image, target: Target, paths: list[str], opts: Options, lanes: bool,
                     loaded: dict, results: dict[str, Scenario], stats: BatchStats) -> list[str]:
    """The scenarios that can run as lanes, run so (into `results`); returns the others'
    paths. The cyclic garbage collector is paused meanwhile (and while the stimulus files
    are read): a batch builds ~100 k small objects (events, tuples, results) that form no
    cycles and live to the end, and the collector walking them again and again cost a
    third of a 1024-scenario batch. The scenarios run one by one are outside the pause."""
    rest: list[str] = []
    lp = wp = None
    if lanes and (opts.engine or "compiled") != "interp" and _lanes_target(target) and not opts.preload:
        prog = load_program(image, target)
        if prog.steps and sum(s.steps for s in prog.steps) <= opts.watchdog:
            lp = LaneProgram(prog)
            lp = lp if lp.ok else None
            wp = _LazyWordLanes(image, target)
    groups: dict[tuple[int, int], list[tuple[str, Stimulus]]] = {}
    wgroups: dict[tuple[int, int], list[tuple[str, Stimulus]]] = {}
    scratch = Machine(target, 1)
    for p in paths:
        st, diags = loaded[p]
        if lp is None and wp is None or st is None or any(d.severity == "error" for d in diags):
            rest.append(p)
            continue
        period = st.scan_us or opts.scan_us or DEFAULT_SCAN_US
        try:
            n_scans = plan_scans(st, period, opts.until_us, opts.scans)
        except RunTooLong:  # run one by one, where _run_one reports it
            rest.append(p)
            continue
        if lp is not None and _lane_ready(st, opts, n_scans):
            groups.setdefault((period, n_scans), []).append((p, st))
        elif wp is not None and wp.program() is not None and _word_lane_ready(st, opts, n_scans, scratch):
            wgroups.setdefault((period, n_scans), []).append((p, st))
        else:
            rest.append(p)
    for (period, n_scans), group in wgroups.items():
        if len(group) < 2:  # one scenario: the compiled engine is faster than numpy lanes
            rest += [p for p, _ in group]
            continue
        start = time.perf_counter()
        outcomes = run_word_lanes(wp.program(), group, period, n_scans, opts, target)
        stats.word_lanes += _take_lanes(group, outcomes, results, rest, stats, time.perf_counter() - start)
    for (period, n_scans), group in groups.items():
        start = time.perf_counter()
        outcomes = run_lanes(lp, group, period, n_scans, opts)
        _take_lanes(group, outcomes, results, rest, stats, time.perf_counter() - start)
    return rest


class _LazyWordLanes:
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


def _run_on_cluster(address: str, image: Image, target: Target, paths: list[str], opts: Options,
                    lanes: bool, loaded: dict) -> tuple[list[Scenario], BatchStats]:
    from mlctool.sim.cluster import map_chunks

    parts = map_chunks(address, _run_chunk, (image, target, opts, lanes), [(p, loaded[p]) for p in paths])
    stats = BatchStats()
    scenarios = []
    for part_scenarios, part_stats in parts:
        scenarios += part_scenarios
        for name in vars(stats):
            setattr(stats, name, getattr(stats, name) + getattr(part_stats, name))
    return scenarios, stats


def _run_chunk(shared, chunk: list[tuple[str, tuple]]) -> tuple[list[Scenario], BatchStats]:
    """A cluster worker's part of a batch: run as a local batch of these scenarios."""
    image, target, opts, lanes = shared
    return run_batch(image, target, [p for p, _ in chunk], opts, lanes=lanes, loaded=dict(chunk))


def default_jobs() -> int:
    return max(1, min(os.cpu_count() or 1, 8))
