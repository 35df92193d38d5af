"""The explicit search of a bit-logic program, bit-sliced: a whole breadth-first layer (every
frontier state with every input vector) runs as one call of the simulator's bit-sliced lane
code (sim/campaign/batch.py LaneProgram: contacts, edges, blocks, the MPS stack, OUT/SET/RST/PLS/PLF on
X/Y/M/A), each device one Python integer whose bit l is lane l. States are packed into 64-bit
words (the devices' bits and the edge memory the code reads), deduplicated with numpy.

Taken by `explicit.search` when the program is such (LaneProgram.ok on a lanes target), its
state fits 64 bits, the properties have no history (always, never, reachable) and no input is
constant or held; otherwise the search runs scan by scan on the compiled engine. Both are
exact: the same verdicts, the same shortest counterexamples (the cross-check compares them).
"""

from __future__ import annotations

import re
import time

import numpy as np

from mlctool.program import Image
from mlctool.sim.campaign.batch import LaneProgram
from mlctool.sim.campaign.lane_codegen import lanes_target
from mlctool.sim.scan import load_program
from mlctool.targetapi.model import Target
from mlctool.verify.props import And, Atom, Const, Not, Or, Property, atoms
from mlctool.verify.results import PROVEN, UNKNOWN, VIOLATED, Stats, Verdict
from mlctool.verify.space import Space

MAX_LANES = 1 << 16  # lanes of one scan call (a layer runs in chunks of this many)


class Bitsliced:
    """A program's scan over packed states, or `ok` False (the compiled engine searches)."""

    def __init__(self, image: Image, target: Target, space: Space, props: list[Property]):
        self.ok = False
        if not lanes_target(target) or space.constant or space.holds:
            return
        if any(p.kind not in ("always", "never", "reachable") for p in props):
            return
        if any(v.view != "bit" for v in space.views) or any(v.view != "bit" for v, _ in space.initial):
            return
        lp = LaneProgram(load_program(image, target))
        if not lp.ok:
            return
        names = []
        for p in props:
            for a in atoms(p.expr):
                v = a.view
                if v.view != "bit" or v.kind not in ("X", "Y", "M", "A") or a.op not in ("bit", "=", "!="):
                    return
                names.append((v.kind, v.number))
        self.lp = lp
        for key in names:  # a device only a property names: a slot of its own (never written: its start)
            lp.slot(*key)
        self.inputs = {(v.kind, v.number): k for k, v in enumerate(space.views)}
        for key in self.inputs:
            lp.slot(*key)
        self.slots = dict(lp.slots)
        self.state_slots = [s for key, s in sorted(self.slots.items(), key=lambda kv: kv[1]) if key not in self.inputs]
        self.edges = sorted({int(x) for x in re.findall(r"E\[(\d+)\]", lp.source)})
        if len(self.state_slots) + len(self.edges) > 64:
            return
        self.space = space
        self.props = props
        self.ok = True


def _column(bits: np.ndarray) -> int:
    """A boolean lane array as a lane word (bit l: lane l)."""
    return int.from_bytes(np.packbits(bits, bitorder="little").tobytes(), "little")


def _lanes(word: int, n: int) -> np.ndarray:
    """A lane word as n booleans."""
    raw = np.frombuffer(word.to_bytes((n + 7) // 8, "little"), dtype=np.uint8)
    return np.unpackbits(raw, bitorder="little")[:n].astype(bool)


def search(b: Bitsliced, budget, started: float, trace_of) -> list[Verdict]:
    """Breadth-first search, a layer at a time; `trace_of(prop, vectors)` builds a trace (the
    compiled engine's replay, for the expect lines)."""
    lp, space, props = b.lp, b.space, b.props
    vectors = np.array(space.vectors, dtype=bool).reshape(len(space.vectors), len(space.inputs))
    nv = len(space.vectors)
    n_slots = len(b.slots)
    state_bits = b.state_slots  # bit j of a packed state: slot state_bits[j]; then the edges
    ns = len(state_bits)
    given = {(v.kind, v.number): bool(x) for v, x in space.initial}
    first = 0
    for j, slot in enumerate(state_bits):
        key = next(k for k, s in b.slots.items() if s == slot)
        if given.get(key):
            first |= 1 << j
    layers_states = [np.array([first], dtype=np.uint64)]
    layers_parent = [np.array([-1], dtype=np.int64)]
    layers_vector = [np.array([-1], dtype=np.int64)]
    visited = layers_states[0].copy()
    total = 1
    transitions = 0
    depth = 0
    decided: dict[int, Verdict] = {}
    bad_exprs = [p.bad_expr() if p.kind in ("always", "never") else p.expr for p in props]
    scan = lp.scan

    def path_to(layer: int, index: int, vec: int) -> list[tuple]:
        vecs = [space.vectors[vec]]
        while layer > 0:
            vecs.append(space.vectors[int(layers_vector[layer][index])])
            index = int(layers_parent[layer][index])
            layer -= 1
        return vecs[::-1]

    def finish(status_left: str, reason: str = "") -> list[Verdict]:
        for k, p in enumerate(props):
            if k in decided:
                continue
            stats = Stats(total, transitions, depth, time.perf_counter() - started)
            if status_left == UNKNOWN:
                decided[k] = Verdict(p, UNKNOWN, "explicit search (bit-sliced)", stats, reason=reason)
            elif p.kind == "reachable":
                decided[k] = Verdict(p, VIOLATED, "explicit search (bit-sliced): reachable set exhausted, no state "
                                     "satisfies it", stats)
            else:
                decided[k] = Verdict(p, PROVEN, "explicit search (bit-sliced): reachable set exhausted", stats)
        return [decided[k] for k in range(len(props))]

    while True:
        frontier = layers_states[-1]
        if len(frontier) == 0:
            return finish(PROVEN)
        nxt_states, nxt_parent, nxt_vector = [], [], []
        chunk = max(1, MAX_LANES // nv)
        for lo in range(0, len(frontier), chunk):
            part = frontier[lo:lo + chunk]
            n = len(part) * nv
            ALL = (1 << n) - 1
            S = [0] * n_slots
            for j, slot in enumerate(state_bits):
                S[slot] = _column(np.repeat(((part >> np.uint64(j)) & np.uint64(1)).astype(bool), nv))
            for (kind, num), k in b.inputs.items():
                S[b.slots[(kind, num)]] = _column(np.tile(vectors[:, k], len(part)))
            E = [0] * len(lp.prog.steps)
            for j, i in enumerate(b.edges):
                E[i] = _column(np.repeat(((part >> np.uint64(ns + j)) & np.uint64(1)).astype(bool), nv))
            scan(S, E, ALL)
            transitions += n
            cols = {slot: _lanes(S[slot], n) for slot in range(n_slots)}
            after = np.zeros(n, dtype=np.uint64)
            for j, slot in enumerate(state_bits):
                after |= cols[slot].astype(np.uint64) << np.uint64(j)
            for j, i in enumerate(b.edges):
                after |= _lanes(E[i], n).astype(np.uint64) << np.uint64(ns + j)
            for k, e in enumerate(bad_exprs):
                if k in decided:
                    continue
                hits = _evaluate(e, cols, b.slots, n)
                if hits.any():
                    lane = int(np.argmax(hits))
                    vecs = path_to(len(layers_states) - 1, lo + lane // nv, lane % nv)
                    trace = trace_of(props[k], vecs)
                    stats = Stats(total, transitions, len(vecs), time.perf_counter() - started)
                    if props[k].kind == "reachable":
                        decided[k] = Verdict(props[k], PROVEN, "explicit search (bit-sliced): witness found", stats,
                                             trace)
                    else:
                        decided[k] = Verdict(props[k], VIOLATED, "explicit search (bit-sliced): shortest "
                                             "counterexample", stats, trace)
            if len(decided) == len(props):
                return finish(PROVEN)
            uniq, first_at = np.unique(after, return_index=True)
            new = ~_member(uniq, visited)
            uniq, first_at = uniq[new], first_at[new]
            if len(nxt_states):  # (earlier chunks of this layer found some already)
                seen = np.concatenate(nxt_states)
                keep = ~np.isin(uniq, seen)
                uniq, first_at = uniq[keep], first_at[keep]
            nxt_states.append(uniq)
            nxt_parent.append(lo + first_at // nv)
            nxt_vector.append(first_at % nv)
            total += len(uniq)
            if total > budget.max_states or budget.out_of_time():
                why = f"--max-states {budget.max_states:,} reached" if total > budget.max_states else "--max-wall reached"
                return finish(UNKNOWN, f"{why} after {depth} scans from power-on: constrain the inputs (assume ...) "
                              "or try --engine symbolic")
        layer = np.concatenate(nxt_states) if nxt_states else np.zeros(0, dtype=np.uint64)
        layers_states.append(layer)
        layers_parent.append(np.concatenate(nxt_parent) if nxt_parent else np.zeros(0, dtype=np.int64))
        layers_vector.append(np.concatenate(nxt_vector) if nxt_vector else np.zeros(0, dtype=np.int64))
        # (disjoint sorted runs: the stable sort merges them in linear time)
        visited = np.sort(np.concatenate((visited, layer)), kind="stable")
        if len(layer):
            depth += 1


def _member(values: np.ndarray, sorted_set: np.ndarray) -> np.ndarray:
    """values[i] in sorted_set, by binary search (np.isin sorts both sides again)."""
    if len(sorted_set) == 0:
        return np.zeros(len(values), dtype=bool)
    at = np.minimum(np.searchsorted(sorted_set, values), len(sorted_set) - 1)
    return sorted_set[at] == values


def _evaluate(e, cols: dict[int, np.ndarray], slots: dict, n: int) -> np.ndarray:
    if isinstance(e, Atom):
        x = cols[slots[(e.view.kind, e.view.number)]]
        if e.op == "bit":
            return x
        want = bool(e.value)
        return x == want if e.op == "=" else x != want
    if isinstance(e, Not):
        return ~_evaluate(e.arg, cols, slots, n)
    if isinstance(e, And):
        out = np.ones(n, dtype=bool)
        for a in e.args:
            out &= _evaluate(a, cols, slots, n)
        return out
    if isinstance(e, Or):
        out = np.zeros(n, dtype=bool)
        for a in e.args:
            out |= _evaluate(a, cols, slots, n)
        return out
    return np.full(n, bool(e.value) if isinstance(e, Const) else False)
