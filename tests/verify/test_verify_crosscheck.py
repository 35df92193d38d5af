"""The two engines of `mlc verify` against each other and against the simulator, over random
small ladder programs (issue 31's acceptance: 200 programs, two properties each, of every
kind): bit logic with edges, blocks, the MPS stack, SET/RST/PLS/PLF and 10 ms timers on three
free inputs.

For every program and property: the explicit search bit-sliced (lanes.py) and scan by scan
on the compiled engine agree; a violation found by one engine is found by the other at the
same (shortest) depth; a property the explicit search proves is never violated symbolically
(the symbolic engine may leave it UNKNOWN where induction does not close in its bound); and
every counterexample, replayed on the simulator as its stimulus file, fails exactly at its
last expect line."""

from __future__ import annotations

import random

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mlctool.sim.run.run import Simulation, plan_scans
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targetapi import load_target
from mlctool.verify.explicit import Budget, search
from mlctool.verify.props import parse_props_text
from mlctool.verify.results import UNKNOWN, VIOLATED, stim_text
from mlctool.verify.run import prepare
from mlctool.verify.symbolic import model_of, prove
from simkit import image_of

NC5 = load_target("nc5")
INPUTS = ["X0", "X1", "X2"]
BITS = ["Y0", "Y1", "M0", "M1", "M2"]
CONTACTS = INPUTS + BITS + ["T200", "T201"]
DEPTH = 10  # scans the symbolic engine unrolls here
COUNTS = {"programs": 0, "violated": 0, "witnessed": 0, "proven": 0, "symbolic_unknown": 0, "bitsliced": 0}


def random_rung(rnd: random.Random) -> list[str]:
    def block() -> list[str]:
        out = [f"{rnd.choice(['LD', 'LDI', 'LD', 'LDP', 'LDF'])} {rnd.choice(CONTACTS)}"]
        for _ in range(rnd.randint(0, 2)):
            out.append(f"{rnd.choice(['AND', 'ANI', 'OR', 'ORI'])} {rnd.choice(CONTACTS)}")
        return out

    lines = block()
    if rnd.random() < 0.3:
        lines += block() + [rnd.choice(["ANB", "ORB"])]

    def coil() -> str:
        r = rnd.random()
        if r < 0.12:
            return f"TMR T{rnd.choice([200, 201])} K{rnd.randint(1, 4)}"
        if r < 0.25:
            return f"{rnd.choice(['PLS', 'PLF'])} {rnd.choice(['M0', 'M1', 'M2'])}"
        return f"{rnd.choice(['OUT', 'OUT', 'SET', 'RST'])} {rnd.choice(BITS)}"

    if rnd.random() < 0.25:
        return lines + ["MPS", "AND " + rnd.choice(CONTACTS), coil(), "MRD", coil(), "MPP",
                        "ANI " + rnd.choice(CONTACTS), coil()]
    return lines + [coil()]


def random_program(rnd: random.Random) -> str:
    lines: list[str] = []
    timers: set[str] = set()
    for _ in range(rnd.randint(2, 6)):
        rung = random_rung(rnd)
        # one TMR per timer (a second would be another timer's rung in the symbolic model)
        for k, line in enumerate(rung):
            if line.startswith("TMR"):
                t = line.split()[1]
                if t in timers:
                    rung[k] = "OUT M2"
                timers.add(t)
        lines += rung
    return "\n".join(lines + ["END"]) + "\n"


def random_props(rnd: random.Random) -> str:
    a, b = rnd.sample(BITS, 2)
    neg = rnd.choice(["", "not "])
    kinds = [f"never {a} and {neg}{b}",
             f"always {rnd.choice(BITS)} or not {rnd.choice(CONTACTS)}",
             f"reachable {rnd.choice(BITS)} and {rnd.choice(['', 'not '])}{rnd.choice(BITS)}",
             f"response {rnd.choice(INPUTS)} -> {rnd.choice(['', 'not '])}{rnd.choice(BITS)} within "
             f"{rnd.randint(0, 2)} scans",
             f"stable {rnd.choice(BITS)} for {rnd.randint(2, 3)} scans"]
    return "".join(f"p{k}: {text}\n" for k, text in enumerate(rnd.sample(kinds, 2)))


def replays(image, verdict, period: int) -> bool:
    """The counterexample's stimulus fails on the simulator at its last expect line only (a
    witness's holds everywhere)."""
    text = stim_text(verdict, period, "p.props", lambda v: 0)
    st, diags = parse_stimulus_text("cx.stim", text, NC5)
    assert not diags, (text, diags)
    sim = Simulation(image, NC5, st, [], period, [], trace=False)
    result = sim.run(plan_scans(st, period, None, None))
    last = max(e.line for e in st.events if e.kind == "expect")
    failed = [f.line for f in result.failed]
    return failed == ([last] if verdict.status == VIOLATED else [])


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32 - 1))
def test_engines_agree_and_counterexamples_replay(seed):
    rnd = random.Random(seed)
    il = random_program(rnd)
    image = image_of(il)
    assert image is not None, il
    props, diags = parse_props_text("p.props", random_props(rnd), NC5)
    assert not diags
    space, period = prepare(image, NC5, props)
    explicit = search(image, NC5, props.properties, space, period, Budget(200_000))
    # the bit-sliced search (a timer-free program, properties without history) and the scan-by-scan
    # one on the compiled engine: the same verdicts, counterexamples of the same length
    scanned = search(image, NC5, props.properties, space, period, Budget(200_000), bitsliced=False)
    for a, b in zip(explicit, scanned, strict=True):
        assert (a.status, a.trace and a.trace.scan) == (b.status, b.trace and b.trace.scan), (il, a, b)
        COUNTS["bitsliced"] += "bit-sliced" in a.method
    model = model_of(image, NC5, space, period)
    COUNTS["programs"] += 1
    for ev in explicit:
        sv = prove(model, ev.prop, Budget(), depth=DEPTH, induction=DEPTH)
        assert ev.status != UNKNOWN, (il, ev)
        if ev.trace is not None:  # a counterexample, or a reachability witness
            if ev.trace.scan < DEPTH:  # within the symbolic bound: the same verdict at the same depth
                assert sv.status == ev.status and sv.trace.scan == ev.trace.scan, (il, ev.prop.text, ev, sv)
            else:
                assert sv.status == UNKNOWN, (il, ev.prop.text, ev, sv)
            for v in (ev, sv):
                if v.trace is not None:
                    assert replays(image, v, period), (il, v.prop.text, v.method)
            COUNTS["violated" if ev.status == VIOLATED else "witnessed"] += 1
        else:  # proven by exhaustion (or no witness anywhere): never contradicted by the solver
            assert sv.status in (ev.status, UNKNOWN) and sv.trace is None, (il, ev.prop.text, ev, sv)
            COUNTS["proven"] += 1
            COUNTS["symbolic_unknown"] += sv.status == UNKNOWN


def test_the_cross_check_saw_every_verdict():
    """(Runs after the property test in file order: it met violations, witnesses and proofs.)"""
    if COUNTS["programs"]:
        assert min(COUNTS["violated"], COUNTS["proven"]) > 15 and COUNTS["witnessed"] > 5, COUNTS
        assert COUNTS["symbolic_unknown"] < COUNTS["proven"] // 5, COUNTS
        assert COUNTS["bitsliced"] > 10, COUNTS
        print("cross-check:", COUNTS)
