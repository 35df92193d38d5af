"""What a search ranges over, shared by the engines: the inputs it chooses each scan (from the
property file's assumptions and the inputs the program reads), the input vectors one scan may
take, and the property monitors (the history a response or stability property needs).

A vector is a tuple of values, one per input in `Space.inputs` order. A property is decided
on the state after each scan (as an `expect` line checks it).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.sim.state import DeviceView
from mlctool.verify.props import And, Atom, Input, Not, Or, Property, Props, evaluate

MAX_VECTORS = 1 << 16  # input vectors of one scan the explicit search enumerates


class SpaceError(ValueError):
    """Assumptions that leave no input vector (E702) or too many to enumerate (E703)."""

    def __init__(self, diagnostic: Diagnostic):
        super().__init__(diagnostic.message)
        self.diagnostic = diagnostic


@dataclass
class Space:
    inputs: list[Input]  # in device order
    vectors: list[tuple]  # every vector one scan may take
    initial: list[tuple[DeviceView, int | float]]  # written before the first scan
    constant: tuple[int, ...]  # indexes of constant inputs
    holds: tuple[tuple[int, int], ...]  # (index, scans) of inputs held once changed
    start: tuple = ()  # the inputs' values at power-on (0, or `assume initial`)

    @property
    def views(self) -> list[DeviceView]:
        return [i.view for i in self.inputs]

    def allowed(self, prev: tuple | None, ages: tuple) -> list[int]:
        """Indexes of the vectors allowed after `prev` (None: the first scan) with the hold
        ages `ages` (scans since each held input last changed, capped at its hold)."""
        if prev is None or (not self.constant and not self.holds):
            return list(range(len(self.vectors)))
        fixed = [k for k in self.constant]
        fixed += [k for (k, n), age in zip(self.holds, ages, strict=True) if age < n]
        if not fixed:
            return list(range(len(self.vectors)))
        return [j for j, v in enumerate(self.vectors) if all(v[k] == prev[k] for k in fixed)]

    def first_ages(self) -> tuple:
        return tuple(n for _, n in self.holds)

    def next_ages(self, prev: tuple | None, vector: tuple, ages: tuple) -> tuple:
        """Before the first scan an input holds its power-on value (`start`): setting it
        then is a change too."""
        if not self.holds:
            return ()
        prev = self.start if prev is None else prev
        return tuple(1 if vector[k] != prev[k] else min(age + 1, n)
                     for (k, n), age in zip(self.holds, ages, strict=True))


def input_space(props: Props, program_inputs: list[DeviceView]) -> Space:
    """The inputs and their vectors. Without `assume free`, every input bit the program reads
    is free, with the words given a range or set; with it, only those named (others stay 0)."""
    declared = dict(props.inputs)
    if not props.free_declared:
        for view in program_inputs:
            declared.setdefault(view, Input(view, (0, 1)))
    inputs = sorted(declared.values(), key=lambda i: i.view.sort_key())
    index = {i.view: k for k, i in enumerate(inputs)}
    total = 1
    for i in inputs:
        total *= len(i.values)
    path = props.path
    initial = [(v, x) for v, x, _, _ in props.initial]
    for view, value, line, col in props.initial:
        if view in index and value not in inputs[index[view]].values:
            raise SpaceError(diag(path, Span.at(line, col, len(view.name)), "E702",
                                  f"{view.name}: initial {value} is not a value the input may take"))
    if total > MAX_VECTORS:
        raise SpaceError(diag(path, Span.at(1), "E703",
                              f"the inputs give {total:,} combinations a scan ({len(inputs)} inputs); the explicit "
                              f"search takes at most {MAX_VECTORS:,}: fix some (assume X0=0), declare the free ones "
                              "(assume free X0 X1) or constrain them (assume onehot, assume D0 in 0..3)"))
    vectors = list(itertools.product(*(i.values for i in inputs)))
    rules: list[tuple[int, int, object]] = []  # (line, col, test of a vector)
    for views, line, col in props.onehot:
        ks = [index[v] for v in views]
        rules.append((line, col, lambda vec, ks=ks: sum(1 for k in ks if vec[k]) == 1))
    for expr, line, col in props.constraints:
        def test(vec, expr=expr):
            return evaluate(expr, lambda v: vec[index[v]])
        rules.append((line, col, test))
    for line, col, test in sorted(rules, key=lambda r: (r[0], r[1])):
        vectors = [v for v in vectors if test(v)]
        if not vectors:
            raise SpaceError(diag(path, Span.at(line, col), "E702",
                                  "no input vector satisfies the assumptions up to this line: they contradict "
                                  "each other"))
    constant = tuple(k for k, i in enumerate(inputs) if i.constant)
    holds = tuple((k, i.hold) for k, i in enumerate(inputs) if i.hold > 1 and not i.constant)
    given = {v: x for v, x in initial}
    start = tuple(given.get(i.view, 0) for i in inputs)
    return Space(inputs, vectors, initial, constant, holds, start)


# ------------------------------------------------------------------ monitors

class Monitor:
    """A property's history over the scans, read on the machine `m`: `start()` its state
    before the first scan, `step(state)` the state after a scan and whether the property
    failed there. A reachability monitor's failure is its witness."""

    def __init__(self, prop: Property, period_us: int, m):
        self.kind = prop.kind
        self.limit = prop.scans if prop.time_us is None else prop.time_us // period_us
        # the expressions compiled against the machine
        self.first = compiled(prop.bad_expr() if self.kind in ("always", "never") else prop.expr, m)
        self.second = compiled(prop.response, m) if prop.response is not None else None

    def start(self):
        """The state at power-on (a stability property's value then counts as settled)."""
        if self.kind == "left":  # whether the expression has held yet
            return False
        if self.kind == "stable":
            return (self.first(), self.limit)
        return 0 if self.kind == "response" else None

    def step(self, state):
        kind = self.kind
        if kind in ("always", "never", "reachable"):
            return None, self.first()
        if kind == "left":  # the witness: On after some scan, Off after a later one
            now = self.first()
            return (state or now), bool(state and not now)
        if kind == "response":
            if self.second():
                return 0, False
            p = min(state + 1, self.limit + 1) if state else (1 if self.first() else 0)
            return p, p > self.limit
        value = self.first()
        prev, age = state
        if value != prev:
            return (value, 1), age < self.limit
        return (value, min(age + 1, self.limit)), False


def compiled(e, m) -> Callable[[], bool]:
    """e as a function of the machine `m`'s present state: plain bits read from their
    bytearray (an output's terminal where the target has an outputs-off relay: its view),
    every other device through its view, as expectations read it."""
    g: dict = {"m": m}
    names: dict[DeviceView, str] = {}

    def ref(view: DeviceView) -> str:
        if view not in names:
            plain = view.view == "bit" and view.kind in m.bits and not (view.kind == "Y" and m.outputs_off is not None)
            if plain:
                g[f"b{view.kind}"] = m.bits[view.kind]
                names[view] = f"b{view.kind}[{view.number}]"
            else:
                g[f"V{len(names)}"] = view
                names[view] = f"V{len(names)}.read(m)"
        return names[view]

    def code(x) -> str:
        if isinstance(x, Atom):
            k = len(g)
            g[f"A{k}"] = x.value
            left = ref(x.view)
            right = ref(x.value) if isinstance(x.value, DeviceView) else f"A{k}"
            if x.op == "bit":
                return f"({left} != 0)"
            if x.op == "range":
                return f"({right}[0] <= {left} <= {right}[1])"
            if x.op == "set":
                return f"({left} in {right})"
            return f"({left} {'==' if x.op == '=' else x.op} {right})"
        if isinstance(x, Not):
            return f"(not {code(x.arg)})"
        if isinstance(x, And | Or):
            return "(" + (" and " if isinstance(x, And) else " or ").join(map(code, x.args)) + ")"
        return "True" if x.value else "False"

    body = code(e)
    return eval(compile(f"lambda: {body}", "<mlc-verify-expr>", "eval"), g)  # noqa: S307 - our own code


# ------------------------------------------------------------------ counterexample checks

def explain(e, read) -> list[tuple[Atom, bool]]:
    """Atoms with their truth that fix e's value in a state: an And true needs all of its
    arguments, false only its first false one (Or the reverse)."""
    if isinstance(e, Atom):
        return [(e, evaluate(e, read))]
    if isinstance(e, Not):
        return explain(e.arg, read)
    if isinstance(e, And | Or):
        value = evaluate(e, read)
        decisive = [x for x in e.args if evaluate(x, read) == value]
        if value == isinstance(e, And):  # And true / Or false: every argument
            return [a for x in e.args for a in explain(x, read)]
        return explain(decisive[0], read)
    return []
