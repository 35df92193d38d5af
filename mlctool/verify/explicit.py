"""The explicit engine: breadth-first search over the program's reachable states, each scan a
run of the simulator's own engine (the compiled engine on a Machine; `Stepper`), states
hashed, timers and counters exact on virtual time. It proves a property when the reachable
set is exhausted; it stops with UNKNOWN and its statistics at the state or time budget.

A state is what the next scan depends on: the devices the program (and the property) names,
the timers' and counters' bookkeeping (a timer's last update kept relative to the scan, so
states a second apart that will behave alike are one), the instructions' edge memory, the
clock relays' phase when the program reads one, whether the first scan has run. Writes to
devices outside that set are caught after every layer (the machine's writer records), and
the search starts again with them added.
"""

from __future__ import annotations

import math
import time

from mlctool.program import Image
from mlctool.sim.decode import program_devices
from mlctool.sim.run.run import Simulation
from mlctool.sim.scan import Fault
from mlctool.sim.state import DeviceView
from mlctool.sim.stimulus.stimulus import Stimulus
from mlctool.targetapi.model import Target
from mlctool.verify.props import Property, views_of
from mlctool.verify.results import PROVEN, UNKNOWN, VIOLATED, WITNESSED, Stats, Trace, Verdict
from mlctool.verify.space import Monitor, Space, explain

DEFAULT_MAX_STATES = 2_000_000


class Unsupported(ValueError):
    """The program has something the engine cannot take (E703)."""


class Budget:
    """--max-states and --max-wall of one command: every search draws on the same clock."""

    def __init__(self, max_states: int = DEFAULT_MAX_STATES, max_seconds: float | None = None):
        self.max_states = max_states
        self.deadline = None if max_seconds is None else time.monotonic() + max_seconds

    def out_of_time(self) -> bool:
        return self.deadline is not None and time.monotonic() > self.deadline


def index_modified(image: Image) -> list[str]:
    """`file:line: INSTR` of instructions with index-modified operands (D0Z0): they reach any
    device, so no set of devices is the program's state."""
    return [f"{i.file}:{i.line}: {i.mnemonic} {' '.join(i.texts)}" for i in image.instrs
            if any(op.index for op in i.operands if not op.is_const)]


class Stepper:
    """One scan from a saved state with given inputs, on the simulator's engine."""

    def __init__(self, image: Image, target: Target, period_us: int, space: Space, extra: list[DeviceView],
                 engine: str | None = None, more: set[tuple[str, int]] = frozenset()):
        self.sim = Simulation(image, target, Stimulus("<verify>", []), [], period_us, [], trace=False, engine=engine)
        self.m = m = self.sim.m
        self.period = period_us
        self.space = space
        bits: dict[str, set[int]] = {}
        words: dict[str, set[int]] = {}
        timers: set[int] = set()
        counters: set[int] = set()
        views = set(program_devices(self.sim.prog)) | set(extra) | set(space.views)
        for kind, n in more:
            if kind in m.bits and kind not in "TC":
                bits.setdefault(kind, set()).add(n)
            elif kind in m.words and kind != "T":
                words.setdefault(kind, set()).add(n)
            elif kind == "T":
                timers.add(n)
            elif kind == "C":
                counters.add(n)
        for v in views:
            k = v.gdev if v.view == "group" else v.kind
            if v.view == "group":
                bits.setdefault(k, set()).update(range(v.number, v.number + 4 * v.digits))
            elif k == "T":
                timers.add(v.number)
            elif k == "C":
                counters.add(v.number)
            elif v.view == "bit" and k in m.bits:
                bits.setdefault(k, set()).add(v.number)
            elif k in m.words:
                words.setdefault(k, set()).add(v.number)
                if v.view in ("d", "f"):
                    if k == "V":
                        words.setdefault("Z", set()).add(v.number)
                    else:
                        words[k].add(v.number + 1)
        self.tracked = {(k, n) for k, ns in bits.items() for n in ns} | {(k, n) for k, ns in words.items() for n in ns}
        self.tracked |= {("T", n) for n in timers} | {("C", n) for n in counters}
        self.bit_slots = [(k, sorted(ns)) for k, ns in sorted(bits.items())]
        self.word_slots = [(k, sorted(ns)) for k, ns in sorted(words.items()) if k in m.words]
        self.timers = sorted(timers)
        self.counters = sorted(counters)
        self.input_views = space.views
        # clock relays the program reads: their phase is part of the state
        clocks = (target.settings.get("system_relays") or {}).get("clocks", {})
        periods = [int(ms) * 1000 for n, ms in clocks.items() if int(n) in bits.get("M", ())]
        self.cycle = math.lcm(*periods) if periods else 0
        self._generate()
        for view, value in space.initial:
            view.write(m, value)
        m.now_us = -period_us if self.cycle == 0 else -period_us % self.cycle
        self.first = self.save()

    def _generate(self) -> None:
        """save() -> the state tuple, and load(state, inputs), written out for this program's
        devices (a tuple display and one unpacking assignment: loops over slots cost 3x)."""
        m = self.m
        g: dict = {"m": m, "E": m.edge, "INPUTS": self.input_views}
        items: list[str] = []
        for k, ns in self.bit_slots:
            g[f"b{k}"] = m.bits[k]
            items += [f"b{k}[{n}]" for n in ns]
        for k, ns in self.word_slots:
            g[f"w{k}"] = m.words[k]
            items += [f"w{k}[{n}]" for n in ns]
        g.update(wT=m.words["T"], bT=m.bits["T"], tr=m.t_running, tf=m.t_frac, tl=m.t_last, tp=m.t_preset,
                 cv=m.cval, bC=m.bits["C"])
        save_items, load_items, rel = list(items), list(items), []
        for n in self.timers:
            save_items += [f"wT[{n}]", f"bT[{n}]", f"tr[{n}]", f"tf[{n}]", f"(now - tl[{n}] if tr[{n}] else 0)",
                           f"tp[{n}]"]
            load_items += [f"wT[{n}]", f"bT[{n}]", f"tr[{n}]", f"tf[{n}]", f"r{n}", f"tp[{n}]"]
            rel.append(f"    tl[{n}] = now - {self.period} - r{n}\n")
        for n in self.counters:
            save_items += [f"cv[{n}]", f"bC[{n}]"]
            load_items += [f"cv[{n}]", f"bC[{n}]"]
        inputs = []
        for k, view in enumerate(self.input_views):
            if view.view == "bit" and view.kind in m.bits:
                g.setdefault(f"b{view.kind}", m.bits[view.kind])
                inputs.append(f"    b{view.kind}[{view.number}] = v[{k}]\n")
            else:
                inputs.append(f"    INPUTS[{k}].write(m, v[{k}])\n")
        phase = f"now % {self.cycle}" if self.cycle else "0"
        nxt = f"(phase + {self.period}) % {self.cycle}" if self.cycle else str(self.period)
        src = ("def save():\n    now = m.now_us\n"
               f"    return ({''.join(x + ', ' for x in save_items)}bytes(E), {phase}, m.scans_done > 0)\n"
               "def load(s, v):\n"
               f"    {''.join(x + ', ' for x in load_items)}e, phase, started = s\n"
               f"    now = m.now_us = {nxt}\n" + "".join(rel) + "".join(inputs)
               + "    E[:] = e\n    m.scans_done = 1 if started else 0\n")
        exec(compile(src, "<mlc-verify-state>", "exec"), g)  # noqa: S102 - our own generated code
        self.save, self.load = g["save"], g["load"]

    def power_on(self) -> tuple:
        """The state before the first scan, with the property file's `assume initial`."""
        return self.first

    def step(self, state: tuple, vector: tuple) -> tuple:
        """The state after one scan from `state` with the inputs `vector`. Raises Fault."""
        self.load(state, vector)
        m = self.m
        if self.sim.before_scan:
            self.sim.before_scan(m)
        self.sim.scan(self.sim.watchdog)
        if m.alarms:
            m.alarms.clear()
        if m.warnings:
            m.warnings.clear()
        return self.save()

    def read(self, view: DeviceView):
        return view.read(self.m)

    def untracked(self) -> set[tuple[str, int]]:
        """Devices the program wrote that the state does not hold (grows the next search)."""
        keys = set(self.m.writer.keys())
        return {(k, n) for k, n in keys if isinstance(n, int) and (k, n) not in self.tracked
                and (k in self.m.bits or k in self.m.words or k in "TC")}


def search(image: Image, target: Target, props: list[Property], space: Space, period_us: int, budget: Budget,
           engine: str | None = None, bitsliced: bool = True) -> list[Verdict]:
    """Breadth-first search for a violation of each property (a witness, for `reachable`),
    all properties in one search (bit-sliced for those without history where it applies)."""
    out: dict[int, Verdict] = {}
    plain = [p for p in props if p.kind in ("always", "never", "reachable")]
    rest = list(props)
    if bitsliced and plain:  # a bit-logic program: a layer a call (lanes.py)
        from mlctool.verify.lanes import Bitsliced
        from mlctool.verify.lanes import search as lane_search

        b = Bitsliced(image, target, space, plain)
        if b.ok:
            verdicts = lane_search(b, budget, time.perf_counter(), lambda p, vecs: replay_trace(
                image, target, p, space, period_us, vecs, engine))
            out.update({id(v.prop): v for v in verdicts})
            rest = [p for p in props if p not in plain]
    # the others in one search on the compiled engine: its state carries every monitor (a
    # response's pending count, a stability's value and age: small, so the product stays near
    # the program's own reachable set)
    for group in [rest] if rest else []:
        more: set[tuple[str, int]] = set()
        started = time.perf_counter()
        for _ in range(8):  # each round adds the devices written outside the state
            views = [v for p in group for v in _prop_views(p)]
            stepper = Stepper(image, target, period_us, space, views, engine, more)
            verdicts, extra = _bfs(stepper, group, space, budget, started)
            if not extra:
                break
            more |= extra
        out.update({id(v.prop): v for v in verdicts})
    return [out[id(p)] for p in props]


def _prop_views(prop: Property) -> list[DeviceView]:
    return views_of(prop.expr) + (views_of(prop.response) if prop.response is not None else [])


def _bfs(st: Stepper, props: list[Property], space: Space, budget: Budget, started: float):
    monitors = [Monitor(p, st.period, st.m) for p in props]
    stats = Stats()
    first = (st.power_on(), None, space.first_ages(), tuple(mon.start() for mon in monitors))
    parent: dict[tuple, tuple | None] = {first: None}
    frontier = [first]
    vectors = space.vectors
    tracked_inputs = bool(space.constant or space.holds)
    depth = 0
    decided: dict[int, Verdict] = {}

    def decide(k: int, status: str, method: str, key=None, reason: str = "", note: str = "") -> None:
        trace = _trace(st, parent, key, props[k], space, monitors[k], note) if key is not None else None
        s = Stats(len(parent), stats.transitions, trace.scan + 1 if trace else depth, time.perf_counter() - started)
        decided[k] = Verdict(props[k], status, method, s, trace, reason)

    def rest(status: str, method: str, reason: str = "", key=None, note: str = "") -> tuple[list[Verdict], set]:
        for k, p in enumerate(props):
            if k not in decided:
                if status == "exhausted":
                    if p.kind in WITNESSED:
                        decide(k, VIOLATED, "explicit search: reachable set exhausted, no state satisfies it")
                    else:
                        decide(k, PROVEN, "explicit search: reachable set exhausted")
                else:
                    decide(k, status, method, key, reason, note)
        return [decided[k] for k in range(len(props))], set()

    while frontier:
        nxt = []
        for key in frontier:
            mstate, prev, ages, mons = key
            for j in space.allowed(prev, ages):
                vec = vectors[j]
                try:
                    after = st.step(mstate, vec)
                except Fault as f:
                    node = ("fault", key, j)
                    parent[node] = (key, j)
                    depth += 1
                    return rest(UNKNOWN, "explicit search", f"the program faults in a reachable state: {f.message} "
                                "(the stimulus replays it)", node, f"the program faults in this scan: {f.message}")
                stats.transitions += 1
                # (a decided property's monitor stops: its history would only multiply the states)
                stepped = [(None, False) if k in decided else mon.step(state)
                           for k, (mon, state) in enumerate(zip(monitors, mons, strict=True))]
                node = (after, vec if tracked_inputs else None, space.next_ages(prev, vec, ages),
                        tuple(x[0] for x in stepped))
                for k, (_, bad) in enumerate(stepped):
                    if bad and k not in decided:
                        # a node of its own: `node` may be an ancestor reached without failing
                        end = ("bad", k, node)
                        parent[end] = (key, j)
                        if props[k].kind in WITNESSED:
                            decide(k, PROVEN, "explicit search: witness found", end)
                        else:
                            decide(k, VIOLATED, "explicit search: shortest counterexample", end)
                        if len(decided) == len(props):
                            return [decided[i] for i in range(len(props))], set()
                if node in parent:
                    continue
                parent[node] = (key, j)
                nxt.append(node)
            if len(parent) > budget.max_states or budget.out_of_time():
                why = (f"--max-states {budget.max_states:,} reached" if len(parent) > budget.max_states
                       else "--max-wall reached")
                return rest(UNKNOWN, "explicit search", f"{why} after {depth} scans from power-on: constrain the "
                            "inputs (assume ...) or try --engine symbolic")
        extra = st.untracked()
        if extra:
            return [], extra
        frontier = nxt
        depth += 1 if nxt else 0
    return rest("exhausted", "")


def _trace(st: Stepper, parent: dict, key, prop: Property, space: Space, monitor: Monitor, note: str) -> Trace:
    """The scan sequence to `key` (by the parent links)."""
    path = []
    node = key
    while parent[node] is not None:
        prev, j = parent[node]
        path.append(j)
        node = prev
    path.reverse()
    return _replayed(st, [space.vectors[j] for j in path], prop, space, monitor, note)


def replay_trace(image: Image, target: Target, prop: Property, space: Space, period_us: int,
                 vectors: list[tuple], engine: str | None = None) -> Trace:
    """A trace found by another engine, replayed here to read the states its expect lines need."""
    st = Stepper(image, target, period_us, space, _prop_views(prop), engine)
    return _replayed(st, vectors, prop, space, Monitor(prop, period_us, st.m), "")


def _replayed(st: Stepper, vecs: list[tuple], prop: Property, space: Space, monitor: Monitor, note: str) -> Trace:
    """The trace of `vecs`, replayed on the stepper to read the last state (and the trigger's
    state, for a response) for the expect lines."""
    state = st.power_on()
    st.load(state, space.start)  # (the machine at power-on, for the monitor's start)
    st.m.now_us -= st.period
    mon = monitor.start()
    trigger, trigger_checks = None, []
    checks: list = []
    for k, vec in enumerate(vecs):
        try:
            state = st.step(state, vec)
        except Fault:
            break
        before = mon
        mon, _ = monitor.step(mon)
        if prop.kind == "response" and mon == 1 and not before:
            trigger, trigger_checks = k, explain(prop.expr, st.read)
    if not note:
        if prop.kind in ("always", "never"):
            checks = explain(prop.bad_expr(), st.read)
        elif prop.kind in WITNESSED:  # (`left`: the step Off now, as the state has it)
            checks = explain(prop.expr, st.read)
        elif prop.kind == "response":  # the response is false; the expect line needs it true
            checks = explain(prop.response, st.read)
        else:  # stable: the expression changed back too soon; expect it kept its value
            checks = explain(prop.expr, st.read)
    return Trace(space.views, vecs, list(space.initial), checks, trigger, trigger_checks, note)
