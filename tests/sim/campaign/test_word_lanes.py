"""Numpy word lanes (mlctool/sim/campaign/word_lanes.py) against one run per scenario: random
straight-line programs of the instructions the lanes take, random stimuli (lanes that agree
and lanes that differ, values at the 16/32-bit limits, negative values, forced words, timer
and counter words written by the stimulus), several scan periods against the timer bases (a
tick every few scans, every scan, several per scan), expectations that hold and that fail."""

from __future__ import annotations

import random

import pytest

from mlctool.sim.campaign.batch import Options, run_batch
from mlctool.sim.campaign.word_lanes import WordLaneProgram
from mlctool.sim.scan import load_program
from simkit import NC5, image_of

BITS = ["X0", "X1", "X2", "X3", "M0", "M1", "M2", "M3", "M1000", "T0", "T200", "C0", "C1"]
WORDS16 = ["D0", "D1", "D2", "D3", "D4", "D5", "D21"]  # D21 overlaps the pair D20/D21
WORDS32 = ["D20", "D30", "D40"]  # D30: only ever a pair in the program; D40 too, with MUL
SOURCES16 = WORDS16 + ["T0", "T200", "C0"]
EDGE_VALUES = [0, 1, -1, 2, 7, 100, 255, 32767, -32768, 30000, -30000, 12345]
EDGE_VALUES32 = [0, 1, -1, 70000, -70000, 2**31 - 1, -2**31, 65535, 65536, 2**31 - 70000]


def const16(rnd) -> str:
    return f"K{rnd.choice(EDGE_VALUES)}"


def src16(rnd) -> str:
    return rnd.choice(SOURCES16) if rnd.random() < 0.7 else const16(rnd)


def src32(rnd) -> str:
    return rnd.choice(WORDS32) if rnd.random() < 0.7 else f"K{rnd.choice(EDGE_VALUES32)}"


def contact(rnd, cls: str) -> str:
    """A contact: LD/AND/OR with an optional I/P/F, or a 16/32-bit compare."""
    if rnd.random() < 0.3:
        cmp = rnd.choice(["=", "<>", ">", "<", ">=", "<="])
        if rnd.random() < 0.3:
            return f"D{cls}{cmp} {src32(rnd)} {src32(rnd)}"
        return f"{cls}{cmp} {src16(rnd)} {src16(rnd)}"
    suffix = rnd.choice(["", "", "I", "P", "F"])
    name = {"ANDI": "ANI"}.get(cls + suffix, cls + suffix)
    return f"{name} {rnd.choice(BITS)}"


def output(rnd, timers: set, counters: set) -> list[str]:
    k = rnd.randrange(12)
    if k == 0:
        return [f"{rnd.choice(['OUT', 'SET', 'RST', 'PLS', 'PLF'])} {rnd.choice(['M0', 'M1', 'M2', 'M3', 'Y0', 'Y1'])}"]
    if k == 1:
        t = rnd.choice([t for t in ("T0", "T1", "T200") if t not in timers] or ["M0"])
        if t == "M0":
            return ["OUT M0"]
        timers.add(t)  # each timer once: a TMR runs every scan
        return [f"TMR {t} K{rnd.choice([0, 1, 2, 3, 5, 20])}"]
    if k == 2:
        c = rnd.choice([c for c in ("C0", "C1") if c not in counters] or ["C0"])
        counters.add(c)
        return [f"CNT {c} K{rnd.choice([0, 1, 2, 5])}"]
    if k == 3:
        return [f"MOV {src16(rnd)} {rnd.choice(WORDS16)}"]
    if k == 4:
        return [f"DMOV {src32(rnd)} {rnd.choice(WORDS32)}"]
    if k == 5:
        op = rnd.choice(["ADD", "SUB", "WAND", "WOR", "WXOR"])
        if op.startswith("W"):
            return [f"{op} {rnd.choice(WORDS16)} {const16(rnd)} {rnd.choice(WORDS16)}"]
        return [f"{op} {src16(rnd)} {src16(rnd)} {rnd.choice(WORDS16)}"]
    if k == 6:
        op = rnd.choice(["DADD", "DSUB", "DWAND", "DWOR", "DWXOR"])
        return [f"{op} {src32(rnd)} {src32(rnd)} {rnd.choice(WORDS32)}"]
    if k == 7:
        return [f"MUL {src16(rnd)} {src16(rnd)} {rnd.choice(['D40', 'D2', 'D20'])}"]
    if k == 8:
        return [f"{rnd.choice(['INC', 'DEC'])} {rnd.choice(WORDS16)}"]
    if k == 9:
        return [f"{rnd.choice(['DINC', 'DDEC'])} {rnd.choice(WORDS32)}"]
    if k == 10:
        return [f"CML {rnd.choice(WORDS16)} {rnd.choice(WORDS16)}"]
    return [f"DCML {rnd.choice(WORDS32)} {rnd.choice(WORDS32)}"]


def random_program(rnd) -> str:
    lines: list[str] = []
    timers: set = set()
    counters: set = set()
    for _ in range(rnd.randrange(8, 16)):
        lines.append(contact(rnd, "LD"))
        for _ in range(rnd.randrange(3)):
            lines.append(contact(rnd, rnd.choice(["AND", "OR"])))
        if rnd.random() < 0.2:  # a block joined by ANB/ORB
            lines += [contact(rnd, "LD"), contact(rnd, "AND"), rnd.choice(["ANB", "ORB"])]
        if rnd.random() < 0.2:
            lines += ["MPS", contact(rnd, "AND")] + output(rnd, timers, counters) + ["MPP"]
        for _ in range(rnd.randrange(1, 4)):
            lines += output(rnd, timers, counters)
    return "\n".join(lines + ["END"]) + "\n"


def random_stimulus(rnd, k: int, period_ms: int, uniform: bool) -> str:
    """`uniform`: every scenario of the batch drives the same inputs (only its D0 value and
    expectations differ), so lanes agree on most words and bits."""
    r = random.Random(5) if uniform else rnd
    when = lambda: f"{r.randrange(0, 300, period_ms)}ms"  # noqa: E731
    lines = [f"scan {period_ms}ms"]
    lines += [f"{when()} {r.choice(BITS[:9])}={r.randrange(2)}" for _ in range(8)]
    lines += [f"{when()} {r.choice(WORDS16)}={r.choice(EDGE_VALUES)}" for _ in range(3)]
    lines += [f"{when()} {r.choice(WORDS32)}:d={r.choice(EDGE_VALUES32)}" for _ in range(2)]
    lines.append(f"{when()} {r.choice(['D30', 'D31', 'D41'])}={r.choice(EDGE_VALUES)}")  # a word of a pair
    if r.random() < 0.3:
        lines.append(f"{when()} T0:w={r.choice([0, 1, 4, 65535])} C0:w={r.choice([0, 3, 65535])}")
    if r.random() < 0.3:
        lines += [f"{r.randrange(0, 100, period_ms)}ms force D{r.randrange(4)}={r.choice(EDGE_VALUES)}",
                  f"{r.randrange(100, 200, period_ms)}ms release D0 D1 D2 D3",
                  f"{r.randrange(0, 100, period_ms)}ms force M1=1", f"{r.randrange(100, 300, period_ms)}ms release M1"]
    if r.random() < 0.3:
        lines += [f"{r.randrange(0, 100, period_ms)}ms force D31={r.choice(EDGE_VALUES)}",
                  f"{r.randrange(0, 100, period_ms)}ms force D40:d={r.choice(EDGE_VALUES32)}",
                  f"{r.randrange(100, 300, period_ms)}ms release D31 D40:d"]
    if uniform and k % 3 == 0:
        lines.append(f"{rnd.randrange(0, 300, period_ms)}ms D0={rnd.choice(EDGE_VALUES)}")
    if k % 4 == 1:  # an expectation that mostly fails: the lane runs again on its own
        lines.append(f"{rnd.randrange(0, 300, period_ms)}ms expect D1={rnd.choice(EDGE_VALUES)} D31=0 Y0=1")
    return "\n".join(lines) + "\nrun 300ms\n"


def check_lanes_equal_single(tmp_path, program: str, rnd, periods, uniform: bool, per_period: int = 6):
    image = image_of(program)
    assert WordLaneProgram(load_program(image, NC5)).ok, program
    paths, last = [], []
    for period in periods:
        for k in range(per_period):
            p = tmp_path / f"p{period}_{k}.stim"
            p.write_text(random_stimulus(rnd, k, period, uniform))
            paths.append(str(p))
            last.append((300 // period - 1) * period)  # the run's last scan
    first, _ = run_batch(image, NC5, paths, Options(), lanes=False)
    for k, sc in enumerate(first):  # expectations that hold: the single run's values
        if k % 4 == 2 and sc.result is not None:
            d = sc.result.devices
            with open(paths[k], "a") as f:
                checks = [f"{v}={d[v]}" for v in ("D2", "D20:d", "T0:w", "C0:w", "D30:d", "D31", "D40") if v in d]
                f.write(f"{last[k]}ms expect {' '.join(checks)}\n")
    lanes, stats = run_batch(image, NC5, paths, Options())
    single, _ = run_batch(image, NC5, paths, Options(), lanes=False)
    assert stats.word_lanes + stats.reruns == len(paths), program
    for a, b in zip(lanes, single):
        assert a.result == b.result, (a.stim, program)
        assert list(a.result.devices.items()) == list(b.result.devices.items()), (a.stim, program)
        assert [(d.code, d.message) for d in a.diagnostics] == [(d.code, d.message) for d in b.diagnostics]


@pytest.mark.parametrize("seed", range(6))
def test_random_programs_lanes_equal_single_runs(tmp_path, seed):
    """Lanes that differ: every scenario its own random inputs, at scan periods below, at
    and above the 100 ms and 10 ms timer bases."""
    rnd = random.Random(seed)
    check_lanes_equal_single(tmp_path, random_program(rnd), rnd, [10, 30, 100, 250] if seed % 2 else [3, 10, 40],
                             uniform=False)


@pytest.mark.parametrize("seed", range(4))
def test_random_programs_uniform_lanes_equal_single_runs(tmp_path, seed):
    """Lanes that agree: the same inputs in every scenario, only D0 and the expectations
    differ (the paths where all lanes hold the same value or the same rung result)."""
    rnd = random.Random(100 + seed)
    check_lanes_equal_single(tmp_path, random_program(rnd), rnd, [10, 20], uniform=True, per_period=8)


TIMER_PROGRAM = """
LD X0
TMR T0 K3
LD X1
TMR T1 K0
LD X2
TMR T200 K7
LD X3
ANI T0
TMR T201 K65535
LD T0
OUT Y0
LD T200
OUT Y1
LDP X1
CNT C0 K3
LD X2
CNT C1 K0
LD C0
OUT Y2
LD T0
MOV T0 D0
ADD T200 C0 D1
LD> T0 K1
OUT M0
END
"""


@pytest.mark.parametrize("periods", [[3, 7, 10], [30, 100, 130, 250]])
def test_timers_reach_presets_at_different_scans(tmp_path, periods):
    """Timers on for different spans in each lane reach their presets at different scans
    (a 100 ms and a 10 ms base against scans of 3-250 ms: a tick every some scans, one or
    more per scan, with and without a remainder), written by the stimulus meanwhile."""
    rnd = random.Random(sum(periods))
    image = image_of(TIMER_PROGRAM)
    assert WordLaneProgram(load_program(image, NC5)).ok
    paths = []
    for period in periods:
        for k in range(12):  # runs of three lengths: the states in between are compared too
            lines = [f"scan {period}ms"]
            lines += [f"{rnd.randrange(0, 1000, period)}ms X{rnd.randrange(4)}={rnd.randrange(2)}" for _ in range(8)]
            if k % 3 == 0:
                lines.append(f"{rnd.randrange(0, 1000, period)}ms T0:w={rnd.choice([0, 2, 5, 65535])}")
            if k % 4 == 0:
                lines.append(f"{rnd.randrange(0, 1000, period)}ms C0:w={rnd.choice([0, 2, 9, 65535])}")
            (tmp_path / f"t{period}_{k}.stim").write_text("\n".join(lines) + f"\nrun {[230, 470, 1000][k % 3]}ms\n")
            paths.append(str(tmp_path / f"t{period}_{k}.stim"))
    lanes, stats = run_batch(image, NC5, paths, Options())
    single, _ = run_batch(image, NC5, paths, Options(), lanes=False)
    assert stats.word_lanes == len(paths)
    assert len({s.result.devices["T0:w"] for s in single}) > 2  # the lanes' timers differ
    for a, b in zip(lanes, single):
        assert list(a.result.devices.items()) == list(b.result.devices.items()), a.stim
