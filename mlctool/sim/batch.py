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
- Processes (`jobs` > 1): the other scenarios are spread over worker processes.
"""

from __future__ import annotations

import os
import pickle
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field

from mlctool.program import Image
from mlctool.sim.decode import Program, program_devices
from mlctool.sim.operands import BitRef
from mlctool.sim.output import run_diagnostics
from mlctool.sim.run import (
    DEFAULT_SCAN_US,
    ExpectOutcome,
    RunResult,
    Simulation,
    build_models,
    plan_scans,
)
from mlctool.sim.scan import DEFAULT_WATCHDOG, load_program
from mlctool.sim.state import DeviceView
from mlctool.sim.stimulus import Stimulus, load_stimulus
from mlctool.sim.suite import Scenario
from mlctool.targets.model import Target

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


@dataclass
class BatchStats:
    lanes: int = 0  # scenarios run as lanes (and passed there)
    reruns: int = 0  # lane scenarios that failed and were run again on their own
    single: int = 0  # scenarios run one by one (in processes when jobs > 1)


# ---------------------------------------------------------------------------- one scenario

def run_one(image: Image, target: Target, path: str, opts: Options,
            loaded: tuple[Stimulus | None, list] | None = None) -> Scenario:
    """Exactly `mlc sim PROGRAM --stimulus PATH` (without --vcd/--report)."""
    st, diags = loaded if loaded is not None else load_stimulus(path, target)
    if st is None or any(d.severity == "error" for d in diags):
        return Scenario(path, None, diags, st.lines if st else [])
    models, model_diags = build_models(st, target)
    if any(d.severity == "error" for d in model_diags):
        return Scenario(path, None, diags + model_diags, st.lines)
    period = st.scan_us or opts.scan_us or DEFAULT_SCAN_US
    sim = Simulation(image, target, st, models, period, list(opts.watch), trace=False,
                     watchdog=opts.watchdog, engine=opts.engine)
    result = sim.run(plan_scans(st, period, opts.until_us, opts.scans))
    return Scenario(path, result, run_diagnostics(result, path), st.lines)


_WORKER: dict = {}


def _init_worker(blob: bytes) -> None:
    _WORKER["args"] = pickle.loads(blob)


def _run_in_worker(path: str) -> Scenario:
    image, target, opts = _WORKER["args"]
    return run_one(image, target, path, opts)


# ---------------------------------------------------------------------------- lanes

class LaneProgram:
    """The program as one Python function over bit-sliced devices."""

    def __init__(self, prog: Program):
        self.prog = prog
        self.slots: dict[tuple[str, int], int] = {}
        self.lines: list[str] = []
        self.blocks: list[str] = []
        self.stack: list[str] = []
        self.tmp = 0
        self.ok = self._generate()

    def slot(self, kind: str, num: int) -> int:
        return self.slots.setdefault((kind, num), len(self.slots))

    def _name(self, ref) -> str | None:
        if type(ref) is not BitRef or ref.ix is not None or ref.kind not in LANE_KINDS:
            return None
        self.slot(ref.kind, ref.num)
        return f"{ref.kind}{ref.num}"

    def _new(self, prefix: str) -> str:
        self.tmp += 1
        return f"{prefix}{self.tmp}"

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
            if op == "contact":
                c = name
            elif op == "contact_not":
                c = f"({name} ^ ALL)"
            elif op in ("contact_rise", "contact_fall"):
                e = self._new("e")
                out.append(f"    {e} = E[{i}]; E[{i}] = {name}")
                c = f"({name} & ({e} ^ ALL))" if op == "contact_rise" else f"({e} & ({name} ^ ALL))"
            else:
                return None
            if cls == "load":
                if s.new_rung:
                    self.blocks.clear()
                    self.stack.clear()
                else:
                    k = self._new("k")
                    out.append(f"    {k} = a")
                    self.blocks.append(k)
                out.append(f"    a = {c}")
            else:
                out.append(f"    a = a {'&' if cls == 'and' else '|'} {c}")
            return out
        if op in ("anb", "orb"):
            if self.blocks:
                out.append(f"    a = {self.blocks.pop()} {'&' if op == 'anb' else '|'} a")
        elif op == "mps":
            k = self._new("p")
            out.append(f"    {k} = a")
            self.stack.append(k)
        elif op == "mrd":
            if self.stack:
                out.append(f"    a = {self.stack[-1]}")
        elif op == "mpp":
            if self.stack:
                out.append(f"    a = {self.stack.pop()}")
        elif op == "inv":
            out.append("    a = a ^ ALL")
        elif op in ("nop", "label"):
            pass
        elif op in ("out", "set", "rst", "pls", "plf"):
            name = self._name(s.ops[0])
            if name is None:
                return None
            if op == "out":
                out.append(f"    {name} = a")
            elif op == "set":
                out.append(f"    {name} = {name} | a")
            elif op == "rst":
                out.append(f"    {name} = {name} & (a ^ ALL)")
            else:
                e = self._new("e")
                out.append(f"    {e} = E[{i}]; E[{i}] = a")
                out.append(f"    {name} = a & ({e} ^ ALL)" if op == "pls" else f"    {name} = {e} & (a ^ ALL)")
        else:
            return None
        return out


def _lane_ready(st: Stimulus, opts: Options, n_scans: int) -> bool:
    if st.models:
        return False
    for e in st.events:
        if e.kind not in ("set", "expect", "force", "release"):
            return False
        views = [v for v, _ in e.assigns] + [c.view for c in e.checks]
        if any(v.view != "bit" or v.kind not in LANE_KINDS for v in views):
            return False
        if e.kind == "expect" and e.scan_index(st.scan_us or opts.scan_us or DEFAULT_SCAN_US) >= n_scans:
            return False
    return all(v.view == "bit" and v.kind in LANE_KINDS for v in opts.watch)


def run_lanes(lp: LaneProgram, group: list[tuple[str, Stimulus]], period: int, n_scans: int,
              opts: Options) -> list[RunResult | None]:
    """Run the scenarios of `group` together; None for a scenario whose expectations failed."""
    slots = dict(lp.slots)
    for _, st in group:
        for e in st.events:
            for v in [v for v, _ in e.assigns] + [c.view for c in e.checks]:
                slots.setdefault((v.kind, v.number), len(slots))
    n = len(group)
    ALL = (1 << n) - 1
    sets: dict[int, dict[int, list[int]]] = {}  # scan -> slot -> [set mask, clear mask]
    forcing: dict[int, list[tuple[int, int, int | None]]] = {}  # scan -> [(slot, lane bit, value)]
    expects: dict[int, list[tuple[int, object]]] = {}
    for lane, (_, st) in enumerate(group):
        bit = 1 << lane
        for e in st.events:
            k = e.scan_index(period)
            if e.kind == "expect":
                expects.setdefault(k, []).append((lane, e))
                continue
            for v, value in e.assigns:
                slot = slots[(v.kind, v.number)]
                if e.kind == "set":
                    masks = sets.setdefault(k, {}).setdefault(slot, [0, 0])
                    if value:
                        masks[0] |= bit
                        masks[1] &= ~bit
                    else:
                        masks[1] |= bit
                        masks[0] &= ~bit
                else:
                    forcing.setdefault(k, []).append(
                        (slot, bit, (1 if value else 0) if e.kind == "force" else None))
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
    out: list[RunResult | None] = []
    names = program_devices(lp.prog) | set(opts.watch)
    base = sorted(names, key=DeviceView.sort_key)
    for lane, (_, st) in enumerate(group):
        if failed >> lane & 1:
            out.append(None)
            continue
        extra = st.devices() - names
        views = sorted(names | extra, key=DeviceView.sort_key) if extra else list(base)
        devices = {}
        for v in views:
            slot = slots.get((v.kind, v.number))
            devices[v.name] = (S[slot] >> lane) & 1 if slot is not None else 0
        outcomes = [ExpectOutcome(e.line, e.text, e.scan_index(period) * period, e.scan_index(period))
                    for e in st.events if e.kind == "expect"]
        outcomes.sort(key=lambda o: (o.scan, o.line))
        out.append(RunResult(period, n_scans, devices, views, outcomes, [], None, []))
    return out


# ---------------------------------------------------------------------------- the batch

def run_batch(image: Image, target: Target, paths: list[str], opts: Options, jobs: int = 1,
              lanes: bool = True) -> tuple[list[Scenario], BatchStats]:
    """One Scenario per path, in the order given."""
    stats = BatchStats()
    results: dict[str, Scenario] = {}
    loaded = {p: load_stimulus(p, target) for p in paths}
    rest = []
    lp = None
    if lanes and (opts.engine or "compiled") != "interp":
        prog = load_program(image, target)
        if prog.steps and sum(s.steps for s in prog.steps) <= opts.watchdog:
            lp = LaneProgram(prog)
            lp = lp if lp.ok else None
    groups: dict[tuple[int, int], list[tuple[str, Stimulus]]] = {}
    for p in paths:
        st, diags = loaded[p]
        if lp is None or st is None or any(d.severity == "error" for d in diags):
            rest.append(p)
            continue
        period = st.scan_us or opts.scan_us or DEFAULT_SCAN_US
        n_scans = plan_scans(st, period, opts.until_us, opts.scans)
        if _lane_ready(st, opts, n_scans):
            groups.setdefault((period, n_scans), []).append((p, st))
        else:
            rest.append(p)
    for (period, n_scans), group in groups.items():
        for (p, st), r in zip(group, run_lanes(lp, group, period, n_scans, opts)):
            if r is None:
                rest.append(p)
                stats.reruns += 1
            else:
                results[p] = Scenario(p, r, run_diagnostics(r, p), st.lines)
                stats.lanes += 1
    stats.single = len(rest) - stats.reruns
    rest = [p for p in paths if p in set(rest)]
    if jobs > 1 and len(rest) > 1:
        blob = pickle.dumps((image, target, opts))
        with ProcessPoolExecutor(max_workers=jobs, initializer=_init_worker, initargs=(blob,)) as pool:
            for p, sc in zip(rest, pool.map(_run_in_worker, rest, chunksize=max(1, len(rest) // (4 * jobs)))):
                results[p] = sc
    else:
        for p in rest:
            results[p] = run_one(image, target, p, opts, loaded[p])
    return [results[p] for p in paths], stats


def default_jobs() -> int:
    return max(1, min(os.cpu_count() or 1, 8))
