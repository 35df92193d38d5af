"""The symbolic engine: bounded model checking and k-induction over the z3 SMT solver
(z3-solver, the `verify` extra; docs/verify.md "Engines" says why z3 over python-sat).

The scan is translated by the simulator's own bit-sliced lane code generator (sim/campaign/batch.py
LaneProgram: contacts, edges, ANB/ORB, MPS/MRD/MPP, INV, OUT/SET/RST/PLS/PLF): the code it
generates runs unchanged on z3 terms, whose `&`, `|` and `^ True` are conjunction,
disjunction and negation. Added here: timer contacts and TMR with a constant preset on a
timer that is not retentive, exact as a count of scans (the contact turns On in the first
scan at or after start + preset x base: after ceil(preset x base / scan) scans of its rung
On, docs/stimulus.md "When a timer contact turns on"). Anything else is `Unmodelled`, named,
never skipped. Its counterexamples are replayed on the simulator before they are reported.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from mlctool.program import Image
from mlctool.sim.campaign.batch import LaneProgram
from mlctool.sim.campaign.lane_codegen import lanes_target
from mlctool.sim.operands import BitRef, ConstRef
from mlctool.sim.scan import load_program
from mlctool.sim.state import DeviceView
from mlctool.targetapi.model import Target
from mlctool.verify.explicit import Budget, replay_trace
from mlctool.verify.props import And, Atom, Const, Not, Or, Property
from mlctool.verify.results import PROVEN, UNKNOWN, VIOLATED, Stats, Verdict
from mlctool.verify.space import Space

DEFAULT_DEPTH = 60  # scans the bounded check unrolls
QUICK_DEPTH = 8  # --engine auto's first try, before the explicit search
MAX_INDUCTION = 12  # the largest k of k-induction tried


class Unmodelled(ValueError):
    """Something of the program or its assumptions the symbolic engine does not model."""


def _z3():
    try:
        import z3
    except ImportError:  # pragma: no cover - the extra is installed with the tests
        raise Unmodelled("the symbolic engine needs z3-solver (pip install 'mlctool[verify]')") from None
    return z3


class _SymbolicProgram(LaneProgram):
    """The lane program with timer contacts and TMR (see the module's doc)."""

    def __init__(self, prog, target: Target, period_us: int):
        self.target = target
        self.period = period_us
        self.timers: dict[int, tuple[int, int]] = {}  # timer -> (step index of its TMR, scans to its contact)
        self.refused = ""
        super().__init__(prog)

    def _name(self, ref):
        if type(ref) is BitRef and ref.ix is None and ref.kind == "T":
            self.slot("T", ref.num)
            return f"T{ref.num}"
        return super()._name(ref)

    def _instr(self, s):
        spec = s.ins.spec
        if spec.op == "tmr":
            return self._tmr(s)
        out = super()._instr(s)
        if out is None and not self.refused:
            self.refused = f"{s.ins.file}:{s.ins.line}: {s.ins.mnemonic} {' '.join(s.ins.texts)}"
        return out

    def _tmr(self, s):
        timer, preset = s.ops[0], s.ops[1] if len(s.ops) > 1 else None
        where = f"{s.ins.file}:{s.ins.line}: {s.ins.mnemonic} {' '.join(s.ins.texts)}"
        if timer.ix is not None or type(preset) is not ConstRef:
            self.refused = f"{where} (an indexed timer or a preset in a register)"
            return None
        n = timer.num
        base = self.target.timer_base(n)
        if base.get("retentive") or n in self.timers:
            self.refused = f"{where} (a retentive timer, or a timer with two TMR)"
            return None
        k = preset.get(None) & 0xFFFF
        rng = self.target.settings.get("timer_preset_range")
        if rng is not None and not rng[0] <= k <= rng[1]:
            k = 0
        scans = -(-k * base["ms"] * 1000 // self.period)
        self.timers[n] = (s.index, scans)
        self.slot("T", n)
        self.written.add(f"T{n}")
        return [f"    T{n} = TMR(a, E, {s.index}, {scans})"]


@dataclass
class Model:
    """A program's transition relation: slots (bit devices), edge memories, timers."""

    image: Image
    target: Target
    space: Space
    period: int
    lanes: _SymbolicProgram
    scan: object  # the generated scan run on z3 terms
    slots: dict[tuple[str, int], int]
    edges: list[int]  # step indexes whose edge memory the code reads


def model_of(image: Image, target: Target, space: Space, period_us: int) -> Model:
    """The program's transition relation, or Unmodelled naming what is not modelled."""
    z3 = _z3()
    if not lanes_target(target):
        raise Unmodelled(f"the symbolic engine does not model target {target.name}'s system relays, outputs-off "
                         "relay or hardware between scans")
    prog = load_program(image, target)
    lp = _SymbolicProgram(prog, target, period_us)
    if not lp.ok:
        raise Unmodelled("the symbolic engine does not model " + (lp.refused or "this program's flow (no END last)"))
    for view in space.views:
        if view.view != "bit":
            raise Unmodelled(f"the symbolic engine does not model the word input {view.name}")
    for view, _ in space.initial:
        if view.view != "bit":
            raise Unmodelled(f"the symbolic engine does not model the initial word {view.name}")
    g = {"TMR": _tmr(z3)}
    exec(compile(lp.source, "<mlc-verify-symbolic>", "exec"), g)  # noqa: S102 - the lane generator's code
    edges = sorted({int(x) for x in _edge_refs(lp.source)})
    return Model(image, target, space, period_us, lp, g["scan"], lp.slots, edges)


def _edge_refs(source: str) -> list[str]:
    import re

    return re.findall(r"E\[(\d+)\]", source)


def _tmr(z3):
    def tmr(a, E, i, scans):
        """A timer's (running, scans counted) in E[i]; its contact, after this execution."""
        running, count = E[i]
        nxt = z3.If(running, z3.If(count < scans, count + 1, count), 0)
        count2 = z3.If(a, nxt, 0)
        E[i] = (a, count2)
        return z3.And(a, count2 >= scans)
    return tmr


class _Unrolling:
    """States 0..k of the scans, each a list of slot terms, with the inputs chosen per scan."""

    def __init__(self, model: Model, solver, free_start: bool):
        self.z3 = _z3()
        self.model = model
        self.solver = solver
        self.states: list[dict] = []  # per scan: {"S": [...], "E": {...}, "in": [...]}
        self.free_start = free_start
        self.start = self._start()

    def _start(self) -> dict:
        z3, m = self.z3, self.model
        n = len(m.slots)
        if self.free_start:  # k-induction: any state (timers within their bounds)
            S = [z3.Bool(f"s0_{k}") for k in range(n)]
            E = {i: z3.Bool(f"e0_{i}") for i in m.edges}
            for t, (i, scans) in m.lanes.timers.items():
                r, c = z3.Bool(f"r0_{t}"), z3.Int(f"c0_{t}")
                self.solver.add(c >= 0, c <= scans, z3.Implies(z3.Not(r), c == 0),
                                S[m.slots[("T", t)]] == z3.And(r, c >= scans))
                E[i] = (r, c)
            return {"S": S, "E": E}
        given = {(v.kind, v.number): bool(x) for v, x in m.space.initial}
        S = [z3.BoolVal(given.get(key, False)) for key in m.slots]
        E = {i: z3.BoolVal(False) for i in m.edges}
        for _t, (i, _) in m.lanes.timers.items():
            E[i] = (z3.BoolVal(False), z3.IntVal(0))
        return {"S": S, "E": E}

    def state(self, k: int) -> dict:
        while len(self.states) <= k:
            self.states.append(self._next(self.states[-1] if self.states else self.start, len(self.states)))
        return self.states[k]

    def _next(self, prev: dict, k: int) -> dict:
        z3, m = self.z3, self.model
        S = list(prev["S"])
        E_list: list = [None] * len(m.lanes.prog.steps)
        for i, x in prev["E"].items():
            E_list[i] = x
        ins = [z3.Bool(f"in{k}_{j}") for j in range(len(m.space.inputs))]
        for j, inp in enumerate(m.space.inputs):
            slot = m.slots.get((inp.view.kind, inp.view.number))
            if slot is not None:
                S[slot] = ins[j]
        space = m.space
        if len(space.vectors) < 2 ** len(space.inputs):
            self.solver.add(z3.Or([z3.And([x if v else z3.Not(x) for x, v in zip(ins, vec, strict=True)])
                                   for vec in space.vectors]))
        if k > 0 and space.constant:
            before = self.states[k - 1]["in"]
            self.solver.add(*[ins[j] == before[j] for j in space.constant])
        ages = []
        if space.holds:  # a held input changes only when it has kept its value long enough
            last, before_ages = prev.get("in"), prev.get("ages")
            for h, (j, n) in enumerate(space.holds):
                if last is None:  # before the first scan: power-on, or (induction) anything
                    if self.free_start:
                        old, age = z3.Bool(f"h0_{j}"), z3.Int(f"a0_{j}")
                        self.solver.add(age >= 1, age <= n)
                    else:
                        old, age = z3.BoolVal(bool(space.start[j])), z3.IntVal(n)
                else:
                    old, age = last[j], before_ages[h]
                changed = ins[j] != old
                self.solver.add(z3.Implies(changed, age >= n))
                ages.append(z3.If(changed, 1, z3.If(age < n, age + 1, age)))
        m.scan(S, E_list, z3.BoolVal(True))
        E = {i: E_list[i] for i in prev["E"]}
        return {"S": S, "E": E, "in": ins, "ages": ages}

    def value(self, view: DeviceView, k: int):
        """A bit device's term after scan k (its power-on value where the program has no slot)."""
        z3, m = self.z3, self.model
        key = (view.kind, view.number)
        if view.view != "bit":
            raise Unmodelled(f"the symbolic engine does not model {view.name} in a property (bits only)")
        slot = m.slots.get(key)
        if slot is None:
            given = {(v.kind, v.number): bool(x) for v, x in m.space.initial}
            inputs = {(i.view.kind, i.view.number): j for j, i in enumerate(m.space.inputs)}
            if key in inputs:
                return self.state(k)["in"][inputs[key]]
            return z3.BoolVal(given.get(key, False))
        return self.state(k)["S"][slot]

    def expr(self, e, k: int):
        z3 = self.z3
        if isinstance(e, Atom):
            if e.op == "bit":
                return self.value(e.view, k)
            if e.op in ("=", "!=") and isinstance(e.value, int) and e.view.view == "bit":
                x = self.value(e.view, k)
                return x if (e.value == 1) == (e.op == "=") else z3.Not(x)
            raise Unmodelled(f"the symbolic engine does not model the compare {e.text} (bits only)")
        if isinstance(e, Not):
            return z3.Not(self.expr(e.arg, k))
        if isinstance(e, And):
            return z3.And([self.expr(x, k) for x in e.args])
        if isinstance(e, Or):
            return z3.Or([self.expr(x, k) for x in e.args])
        if isinstance(e, Const):
            return z3.BoolVal(e.value)
        raise TypeError(e)  # pragma: no cover


def check_property(model: Model, prop: Property) -> None:
    """Raise Unmodelled when the property names what the engine does not model."""
    if prop.kind == "left":
        raise Unmodelled("the symbolic engine does not model the stl-exit check")
    z3 = _z3()
    u = _Unrolling(model, z3.Solver(), False)
    u.expr(prop.expr, 0)
    if prop.response is not None:
        u.expr(prop.response, 0)


class _Monitor:
    """The property over an unrolling: bad(k), whether it fails at scan k (for reachable:
    holds there), with the history a response or stability property needs as terms of the
    state (so that induction ranges over it too: `free` starts from any history)."""

    def __init__(self, u: _Unrolling, prop: Property, free: bool):
        self.u, self.prop, self.z3 = u, prop, u.z3
        z3 = self.z3
        self.limit = prop.scans if prop.time_us is None else prop.time_us // u.model.period
        self.hist: list = []  # per scan: the history after it
        if prop.kind == "response":  # scans since the oldest unanswered trigger (0: none)
            if free:
                p0 = z3.Int(f"p_{id(self)}")
                u.solver.add(p0 >= 0, p0 <= self.limit)
                self.start = p0
            else:
                self.start = z3.IntVal(0)
        elif prop.kind == "stable":  # (the value, scans since it last changed, capped)
            if free:
                v0, a0 = z3.Bool(f"v_{id(self)}"), z3.Int(f"a_{id(self)}")
                u.solver.add(a0 >= 1, a0 <= self.limit)
                self.start = (v0, a0)
            else:
                self.start = (_start_value(u, prop.expr), z3.IntVal(self.limit))
        else:
            self.start = None
        self.bads: list = []

    def bad(self, k: int):
        while len(self.bads) <= k:
            self._step(len(self.bads))
        return self.bads[k]

    def history(self, k: int):
        self.bad(k)
        return self.hist[k]

    def _step(self, k: int) -> None:
        z3, u, prop = self.z3, self.u, self.prop
        before = self.hist[k - 1] if k else self.start
        if prop.kind in ("always", "never"):
            self.hist.append(None)
            self.bads.append(u.expr(prop.bad_expr(), k))
        elif prop.kind == "reachable":
            self.hist.append(None)
            self.bads.append(u.expr(prop.expr, k))
        elif prop.kind == "response":
            r, t = u.expr(prop.response, k), u.expr(prop.expr, k)
            p = z3.If(r, 0, z3.If(before > 0, before + 1, z3.If(t, 1, 0)))
            self.hist.append(p)
            self.bads.append(p > self.limit)
        else:
            v = u.expr(prop.expr, k)
            prev, age = before
            changed = v != prev
            self.hist.append((v, z3.If(changed, 1, z3.If(age < self.limit, age + 1, age))))
            self.bads.append(z3.And(changed, age < self.limit))


def _start_value(u: _Unrolling, e):
    """The expression at power-on (before the first scan)."""
    z3 = u.z3
    given = {(v.kind, v.number): bool(x) for v, x in u.model.space.initial}

    def value(x):
        if isinstance(x, Atom):
            v = given.get((x.view.kind, x.view.number), False)
            return z3.BoolVal(v if x.op == "bit" or (x.value == 1) == (x.op == "=") else not v)
        if isinstance(x, Not):
            return z3.Not(value(x.arg))
        if isinstance(x, And):
            return z3.And([value(a) for a in x.args])
        if isinstance(x, Or):
            return z3.Or([value(a) for a in x.args])
        return z3.BoolVal(x.value)
    return value(e)


def _distinct(u: _Unrolling, mon: _Monitor, i: int, j: int):
    """States i and j (after those scans) differ somewhere: the simple-path constraint that
    makes k-induction complete on a finite system."""
    z3 = u.z3
    a, b = u.state(i), u.state(j)
    diffs = [x != y for x, y in zip(a["S"], b["S"], strict=True)]
    for key in a["E"]:
        x, y = a["E"][key], b["E"][key]
        diffs += [p != q for p, q in zip(x, y, strict=True)] if isinstance(x, tuple) else [x != y]
    space = u.model.space
    kept = sorted(set(space.constant) | {k for k, _ in space.holds})  # inputs that carry state
    diffs += [a["in"][k] != b["in"][k] for k in kept]
    diffs += [x != y for x, y in zip(a["ages"], b["ages"], strict=True)]
    h1, h2 = mon.history(i), mon.history(j)
    if isinstance(h1, tuple):
        diffs += [h1[0] != h2[0], h1[1] != h2[1]]
    elif h1 is not None:
        diffs.append(h1 != h2)
    return z3.Or(diffs) if diffs else z3.BoolVal(False)


def prove(model: Model, prop: Property, budget: Budget, depth: int = DEFAULT_DEPTH,
          induction: int = MAX_INDUCTION) -> Verdict:
    """Bounded model checking to `depth` scans (a counterexample or witness: the shortest),
    with k-induction (with simple paths) tried at each depth up to `induction`."""
    z3 = _z3()
    started = time.perf_counter()
    check_property(model, prop)
    base = z3.Solver()
    u = _Unrolling(model, base, False)
    mon = _Monitor(u, prop, False)
    step_solver = z3.Solver()
    w = _Unrolling(model, step_solver, True)
    wmon = _Monitor(w, prop, True)
    reach = prop.kind == "reachable"
    for k in range(depth):
        if budget.out_of_time():
            break
        if base.check(mon.bad(k)) == z3.sat:
            vecs = _vectors(u, base.model(), k)
            trace = replay_trace(model.image, model.target, prop, model.space, model.period, vecs)
            stats = Stats(k + 1, k + 1, k + 1, time.perf_counter() - started)
            if reach:
                return Verdict(prop, PROVEN, f"symbolic: bounded model checking found a witness at depth {k + 1}",
                               stats, trace)
            return Verdict(prop, VIOLATED, f"symbolic: bounded model checking, shortest counterexample "
                           f"(depth {k + 1})", stats, trace)
        base.add(z3.Not(mon.bad(k)))  # holds at k from here on (the next depths build on it)
        if k < induction:
            # k-induction: from any state, k+1 scans on a simple path where the property holds, then
            # one where it fails: none (unsat) proves it for every reachable state
            step_solver.add(z3.Not(wmon.bad(k)))
            for i in range(k + 1):
                step_solver.add(_distinct(w, wmon, i, k + 1))
            if step_solver.check(wmon.bad(k + 1)) == z3.unsat:
                stats = Stats(k + 1, 0, k + 1, time.perf_counter() - started)
                if reach:
                    return Verdict(prop, VIOLATED, f"symbolic: k-induction (k={k + 1}): no reachable state "
                                   "satisfies it", stats)
                return Verdict(prop, PROVEN, f"symbolic: k-induction (k={k + 1}) with its base checked", stats)
    stats = Stats(depth, 0, depth, time.perf_counter() - started)
    why = "--max-wall reached" if budget.out_of_time() else f"no counterexample in {depth} scans from power-on"
    if reach:
        return Verdict(prop, UNKNOWN, "symbolic: bounded model checking", stats,
                       reason=f"{why}; no witness within the bound (--engine explicit decides it)")
    return Verdict(prop, UNKNOWN, "symbolic: bounded model checking", stats,
                   reason=f"{why}; induction did not close up to k={min(induction, depth)} (--engine explicit may prove it)")


def _vectors(u: _Unrolling, model, k: int) -> list[tuple]:
    z3 = u.z3
    out = []
    for t in range(k + 1):
        ins = u.state(t)["in"]
        vec = tuple(1 if z3.is_true(model.eval(x, model_completion=True)) else 0 for x in ins)
        out.append(vec)
    return out
