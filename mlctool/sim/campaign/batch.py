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
- Word lanes (numpy, mlctool/sim/campaign/word_lanes.py). A straight-line program of contacts, compare
  contacts, coils, TMR/CNT and word arithmetic and moves on D, with scenarios that set, force
  and expect plain bits and D/T/C words: every device is a numpy array with one element per
  scenario.
- Processes (`jobs` > 1): the other scenarios are spread over worker processes.
"""

from __future__ import annotations

import gc
import os
import pickle
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field

from mlctool.diagnostics import Span, diag
from mlctool.program import Image
from mlctool.sim.campaign.lane_codegen import RungCodegen, lanes_target
from mlctool.sim.campaign.suite import Scenario
from mlctool.sim.campaign.word_lanes import LazyWordLanes, run_word_lanes, word_lane_ready
from mlctool.sim.decode import Program, program_devices
from mlctool.sim.operands import BitRef
from mlctool.sim.run.output import run_diagnostics
from mlctool.sim.run.run import (
    DEFAULT_SCAN_US,
    ExpectOutcome,
    RunResult,
    RunTooLong,
    Simulation,
    build_models,
    model_inputs,
    plan_scans,
)
from mlctool.sim.scan import DEFAULT_WATCHDOG, load_program
from mlctool.sim.state import DeviceView, Machine
from mlctool.sim.stimulus.stimulus import NameCache, Stimulus, load_stimulus
from mlctool.targetapi.model import Target

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
    return Scenario(path, result, run_diagnostics(result, path), st.lines, inputs=tuple(model_inputs(models)))


_WORKER: dict = {}


def _init_worker(blob: bytes) -> None:
    _WORKER["args"] = pickle.loads(blob)


def _run_in_worker(path: str) -> Scenario:
    image, target, opts = _WORKER["args"]
    return run_one(image, target, path, opts)


# ---------------------------------------------------------------------------- lanes

class LaneProgram(RungCodegen):
    """The program as one Python function over bit-sliced devices."""

    indent = "    "

    def __init__(self, prog: Program):
        super().__init__(prog)
        self.lines: list[str] = []
        self.written: set[str] = set()  # the devices a coil writes
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
        # every device to a local in one unpacking of the program's slots (0..K-1, the order of
        # self.slots; the lane words of a batch's other devices follow them in S); only the
        # devices a coil writes are stored back (a scan: ~half the time of bool1000's 1000
        # instructions went to 640 loads and 640 stores one by one)
        names = [f"{k}{n}" for k, n in self.slots]
        load = [f"    {', '.join(names)}, = S[:{len(names)}]"] if names else []
        store = [f"    S[{self.slots[(n[0], int(n[1:]))]}] = {n}" for n in names if n in self.written]
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
            self.written.add(name)
            self.coil(op, name, i, out)
        else:
            return None
        return out


def _lane_ready(st: Stimulus, opts: Options, n_scans: int) -> bool:
    if st.models:
        return False
    period = st.scan_us or opts.scan_us or DEFAULT_SCAN_US
    for e in st.entries:  # (set lines possibly as SetLine tuples, read so: no Events made)
        if type(e) is tuple:
            for v, _ in e[6]:
                if v.view != "bit" or v.kind not in LANE_KINDS:
                    return False
            continue
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
    slots = dict(lp.slots)  # (kind, number) -> slot; the program's first, then the scenarios' own
    new_views: dict[int, DeviceView] = {}  # a slot past the program's -> the view that named it first
    owns: list[set[int]] = []  # per lane: the slots of its own devices (Stimulus.devices())
    n = len(group)
    ALL = (1 << n) - 1
    sets: dict[int, dict[int, list[int]]] = {}  # scan -> slot -> [set mask, clear mask]
    forcing: dict[int, list[tuple[int, int, int | None]]] = {}  # scan -> [(slot, lane bit, value)]
    expects: dict[int, list[tuple[int, object]]] = {}
    for lane, (_, st) in enumerate(group):  # one pass over the events (a batch has ~20 k of them)
        bit = 1 << lane
        own: set[int] = set()
        owns.append(own)
        for e in st.entries:  # (set lines possibly as SetLine tuples: no Events made for them)
            if type(e) is tuple:
                _, k, time_us, _, _, _, assigns = e
                if k is None:
                    k = -(-time_us // period)  # Event.scan_index
                kind = "set"
            else:
                k = e.scan if e.scan is not None else -(-e.time_us // period)  # Event.scan_index
                kind = e.kind
                assigns = e.assigns
            if kind == "expect":
                expects.setdefault(k, []).append((lane, e))
                for c in e.checks:
                    key = (c.view.kind, c.view.number)
                    slot = slots.get(key)
                    if slot is None:
                        slot = slots[key] = len(slots)
                        new_views[slot] = c.view
                    own.add(slot)
                continue
            for v, value in assigns:
                key = (v.kind, v.number)
                slot = slots.get(key)
                if slot is None:
                    slot = slots[key] = len(slots)
                    new_views[slot] = v
                own.add(slot)
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
    no_sets: dict = {}
    for k in range(n_scans):
        for slot, (on, off) in sets.get(k, no_sets).items():  # (a 1024-bit operation is ~50 ns: the fewest)
            x = S[slot] | on if on else S[slot]
            S[slot] = x & ~off if off else x
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
    outcomes: list[list[ExpectOutcome]] = [[] for _ in range(n)]  # a passing lane's, as Simulation.run's
    for k in sorted(expects):
        for lane, e in expects[k]:
            outcomes[lane].append(ExpectOutcome(e.line, e.text, k * period, k))
    for expected in outcomes:
        if len(expected) > 1:
            expected.sort(key=lambda o: (o.scan, o.line))
    return _lane_results(lp, S, slots, new_views, owns, failed, period, n_scans, opts, outcomes)


class _LaneTable:
    """The final lane words of one group and how a lane's result names them: `order` is the
    union of every lane's devices (the program's, the watched and the scenario's own), sorted
    and named once; a lane shows the program's and watched devices (`base`, ranks in order)
    and its own. The words are turned into a device x lane matrix of 0/1 bytes on the first
    read (numpy unpackbits), and a lane's row is one column of it. Pickles as the words."""

    def __init__(self, order: list[DeviceView], words: list[int], base: list[int], n: int):
        self.order = order
        self.words = words  # words[k]: order[k]'s lane word (bit l: lane l), 0 where never touched
        self.base = base
        self.n = n
        self._bits = None

    def __getstate__(self) -> dict:
        return {"order": self.order, "words": self.words, "base": self.base, "n": self.n, "_bits": None}

    def final(self, lane: int, extra: tuple[int, ...]) -> tuple[dict[str, int], list[DeviceView]]:
        if self._bits is None:
            import numpy as np  # (word_lanes.py imports it anyway; a batch that reads no values never does here)

            nbytes = (self.n + 7) // 8
            flat = np.frombuffer(b"".join(w.to_bytes(nbytes, "little") for w in self.words), np.uint8)
            self._bits = np.unpackbits(flat, bitorder="little").reshape(len(self.words), 8 * nbytes)
            self._labels = [v.name for v in self.order]
        row = self._bits[:, lane].tobytes()  # row[k]: the lane's value of order[k]
        ranks = sorted(self.base + list(extra)) if extra else self.base
        order, labels = self.order, self._labels
        return {labels[k]: row[k] for k in ranks}, [order[k] for k in ranks]


class _LaneFinal:
    """RunResult.lazy's `final` of one lane: its devices and views, from the group's table."""

    __slots__ = ("table", "lane", "extra")

    def __init__(self, table: _LaneTable, lane: int, extra: tuple[int, ...]):
        self.table, self.lane, self.extra = table, lane, extra

    def __getstate__(self):
        return self.table, self.lane, self.extra

    def __setstate__(self, state) -> None:
        self.table, self.lane, self.extra = state

    def __call__(self) -> tuple[dict[str, int], list[DeviceView]]:
        return self.table.final(self.lane, self.extra)


def _lane_results(lp: LaneProgram, S: list[int], slots: dict, new_views: dict[int, DeviceView],
                  owns: list[set[int]], failed: int, period: int, n_scans: int, opts: Options,
                  outcomes: list[list[ExpectOutcome]]) -> list[RunResult | None]:
    """Each passing lane's RunResult, as a single run reports it (the program's and watched
    devices and the scenario's own, sorted, by name), made lazily (RunResult.lazy): the order
    of the union of all lanes' devices is worked out once here, a lane's values and names
    only when its devices are read. A lane view is a bit of X/Y/M/A, so its (kind, number),
    its slot, says which view it is: the program's slots are its own devices, a scenario's
    other slots are views of `new_views`."""
    n = len(owns)
    names = program_devices(lp.prog) | set(opts.watch)
    order = sorted(names.union(new_views.values()), key=DeviceView.sort_key)
    rank = {v: k for k, v in enumerate(order)}
    base_set = {rank[v] for v in names}
    rank_of = {slot: rank[v] for slot, v in new_views.items() if rank[v] not in base_set}  # extra devices
    all_lanes = (1 << n) - 1
    words = []
    for v in order:
        slot = slots.get((v.kind, v.number))
        words.append(0 if slot is None else S[slot] & all_lanes)
    table = _LaneTable(order, words, sorted(base_set), n)
    extra_slots = rank_of.keys()
    out: list[RunResult | None] = []
    for lane, (own, expected) in enumerate(zip(owns, outcomes)):
        if failed >> lane & 1:
            out.append(None)
            continue
        mine = extra_slots & own
        extra = tuple(rank_of[slot] for slot in mine) if mine else ()
        out.append(RunResult.lazy(period, n_scans, expected, _LaneFinal(table, lane, extra)))
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
    scenarios run there in chunks (mlctool/sim/campaign/cluster.py; ClusterError when it cannot)."""
    stats = BatchStats()
    results: dict[str, Scenario] = {}
    paused = gc.isenabled()
    gc.disable()  # see _run_batch_lanes
    gc.unfreeze()  # (what an earlier block froze: as mlctool.cli.common.collector_paused)
    try:
        if loaded is None:
            names = NameCache(target)
            loaded = {p: load_stimulus(p, target, names) for p in paths}
        if cluster is None:
            rest = _run_batch_lanes(image, target, paths, opts, lanes, loaded, results, stats)
    finally:
        if paused:
            gc.freeze()
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
    third of a 1024-scenario batch. The scenarios run one by one are outside the pause.
    Afterwards the objects alive are frozen (gc.freeze: still freed by reference counting,
    skipped by the collector), else the first collection after resuming walks them all as
    young objects (~40 k of them, 7-20 ms of a 1024-scenario batch); the next batch or
    program load thaws them first."""
    rest: list[str] = []
    lp = wp = None
    # lanes are the compiled engine's batch form: a run that asks for another engine runs one by one
    if lanes and (opts.engine or "compiled") == "compiled" and lanes_target(target) and not opts.preload:
        prog = load_program(image, target)
        if prog.steps and sum(s.steps for s in prog.steps) <= opts.watchdog:
            lp = LaneProgram(prog)
            lp = lp if lp.ok else None
            wp = LazyWordLanes(image, target)
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
        elif wp is not None and wp.program() is not None and word_lane_ready(st, period, opts.watch, n_scans, scratch):
            wgroups.setdefault((period, n_scans), []).append((p, st))
        else:
            rest.append(p)
    for (period, n_scans), group in wgroups.items():
        if len(group) < 2:  # one scenario: the compiled engine is faster than numpy lanes
            rest += [p for p, _ in group]
            continue
        start = time.perf_counter()
        outcomes = run_word_lanes(wp.program(), group, period, n_scans, opts.watch, target)
        stats.word_lanes += _take_lanes(group, outcomes, results, rest, stats, time.perf_counter() - start)
    for (period, n_scans), group in groups.items():
        start = time.perf_counter()
        outcomes = run_lanes(lp, group, period, n_scans, opts)
        _take_lanes(group, outcomes, results, rest, stats, time.perf_counter() - start)
    return rest



def _run_on_cluster(address: str, image: Image, target: Target, paths: list[str], opts: Options,
                    lanes: bool, loaded: dict) -> tuple[list[Scenario], BatchStats]:
    from mlctool.sim.campaign.cluster import map_chunks

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
