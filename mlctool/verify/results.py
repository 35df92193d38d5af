"""What `mlc verify` finds, engine-independent: a verdict per property (PROVEN, VIOLATED,
UNKNOWN) with its method, bound and statistics, and the scan sequence of a counterexample or
witness, written as a stimulus file that `mlc sim` replays to the same expectation."""

from __future__ import annotations

from dataclasses import dataclass, field

from mlctool.sim.state import DeviceView
from mlctool.verify.props import Atom, Property

PROVEN, VIOLATED, UNKNOWN = "PROVEN", "VIOLATED", "UNKNOWN"
# kinds proven by a witness (a run that shows it), violated when the reachable set has none;
# `left` is the built-in stl-exit check's (verify/builtin.py)
WITNESSED = ("reachable", "left")


@dataclass
class Stats:
    states: int = 0  # distinct states reached (explicit) / unrolled depth (symbolic)
    transitions: int = 0  # scans simulated
    depth: int = 0  # scans from power-on to the deepest state explored
    seconds: float = 0.0


@dataclass
class Trace:
    """A scan sequence from power-on: the input vector before each scan, the failing (or
    witnessing) scan last, and the checks of its expect line."""

    views: list[DeviceView]  # the inputs, in vector order
    vectors: list[tuple]  # vectors[k]: the inputs before scan k
    initial: list[tuple[DeviceView, int | float]]
    checks: list[tuple[Atom, bool]]  # the expect line: atom, the truth it expects
    trigger: int | None = None  # response: the scan whose trigger went unanswered
    trigger_checks: list[tuple[Atom, bool]] = field(default_factory=list)
    note: str = ""

    @property
    def scan(self) -> int:
        return len(self.vectors) - 1


@dataclass
class Verdict:
    prop: Property
    status: str
    method: str  # "explicit: reachable set exhausted", "k-induction (k=2)", ...
    stats: Stats
    trace: Trace | None = None  # a violation's counterexample or a reachability witness
    reason: str = ""  # UNKNOWN: why the search stopped

    @property
    def ok(self) -> bool:
        return self.status == PROVEN


# ------------------------------------------------------------------ stimulus text

def check_text(atom: Atom, truth: bool, actual_of) -> str:
    """One expect check meaning `atom` is `truth` (actual_of(view): the device's value in the
    trace's last state, for forms a check cannot write: a compare of two devices, a value
    outside a range)."""
    view, op, v = atom.view, atom.op, atom.value
    name = view.name
    if op == "bit":
        if view.view == "bit":
            return f"{name}={1 if truth else 0}"
        return f"{name}!=0" if truth else f"{name}=0"
    if isinstance(v, DeviceView):
        v = actual_of(v)
    lo, hi = _span(view)
    if op in ("=", "!="):
        return f"{name}{'=' if (op == '=') == truth else '!='}{_num(v)}"
    if op in ("<", "<=", ">", ">="):
        if not truth:
            op = {"<": ">=", "<=": ">", ">": "<=", ">=": "<"}[op]
        a, b = {"<": (lo, v - 1), "<=": (lo, v), ">": (v + 1, hi), ">=": (v, hi)}[op]
        return f"{name}={_num(a)}..{_num(b)}"
    if op == "range" and truth:
        return f"{name}={_num(v[0])}..{_num(v[1])}"
    if op == "set" and truth and len(v) == 1:
        return f"{name}={_num(next(iter(v)))}"
    actual = actual_of(view)  # outside a range, in or out of a set: the value itself
    return f"{name}={_num(actual)}" if truth else f"{name}!={_num(actual)}"


def _num(x) -> str:
    return repr(x) if isinstance(x, float) else str(x)


def _span(view: DeviceView) -> tuple[int, int]:
    from mlctool.sim.stimulus.stimulus import _range

    return _range(view)


def stim_text(verdict: Verdict, period_us: int, source: str, actual_of) -> str:
    """The trace as a stimulus file: inputs per scan (`#k X0=1`), the property as an expect
    line at its scan: for a violation every check but the last as the state has it and the
    last as the property needs it (that one fails); for a witness every check holds."""
    t = verdict.trace
    prop = verdict.prop
    what = {VIOLATED: "counterexample", UNKNOWN: "the program's fault"}.get(verdict.status, "witness")
    out = [f"# {what} on the way to {source}:{prop.line}: {prop.text}" if verdict.status == UNKNOWN
           else f"# {what} of {source}:{prop.line}: {prop.text}",
           "# written by mlc verify; replay: mlc sim PROGRAM --stimulus THIS_FILE",
           f"scan {period_us}us" if period_us % 1000 else f"scan {period_us // 1000}ms"]
    if t.note:
        out.append(f"# {t.note}")
    prev: tuple | None = None
    for k, vec in enumerate(t.vectors):
        items = [f"{v.name}={_num(x)}" for j, (v, x) in enumerate(zip(t.views, vec, strict=True))
                 if prev is None or prev[j] != x]
        if k == 0:
            items = [f"{v.name}={_num(x)}" for v, x in t.initial] + items
        if items:
            out.append(f"#{k} " + " ".join(items))
        prev = vec
        if t.trigger == k and t.trigger_checks:
            out.append(f"#{k} expect " + " ".join(check_text(a, b, actual_of) for a, b in t.trigger_checks)
                       + "   # the trigger")
    checks = list(t.checks)
    if verdict.status == VIOLATED and checks:
        atom, truth = checks[-1]
        checks[-1] = (atom, not truth)
    what = "the property fails here" if verdict.status == VIOLATED else "the state the property asks for"
    if checks:  # (none when the program faults in the last scan: the replay stops there, E604)
        out.append(f"#{t.scan} expect " + " ".join(check_text(a, b, actual_of) for a, b in checks) + f"   # {what}")
    out.append(f"run #{t.scan + 1}")
    return "\n".join(out) + "\n"


# ------------------------------------------------------------------ reports

def describe(v: Verdict) -> str:
    p = v.prop
    head = f"{v.status:<8} {p.name}: {p.text}"
    s = v.stats
    if v.method.startswith("symbolic"):
        figures = f"{s.depth} scans unrolled, {s.seconds:.2f} s"
    else:
        figures = f"{s.states:,} states, {s.transitions:,} scans simulated, depth {s.depth}, {s.seconds:.2f} s"
    lines = [head, f"         {v.method}; {figures}"]
    if v.reason:
        lines.append(f"         {v.reason}")
    return "\n".join(lines)


def to_dict(v: Verdict, stim_path: str | None) -> dict:
    p = v.prop
    s = v.stats
    out = {"property": p.name, "kind": p.kind, "text": p.text, "line": p.line, "column": p.col,
           "status": v.status, "method": v.method,
           "stats": {"states": s.states, "transitions": s.transitions, "depth": s.depth,
                     "seconds": round(s.seconds, 6)}}
    if v.reason:
        out["reason"] = v.reason
    if v.trace is not None:
        out["trace"] = {"scans": v.trace.scan + 1, "stimulus": stim_path,
                        "inputs": [dict(zip([x.name for x in v.trace.views], vec, strict=True))
                                   for vec in v.trace.vectors]}
    return out

