"""The step ladder's flows as the VS manual draws them (issue 33): 4-1-3 (a transfer and
the scan after it), 4-1-4 / 4-3-1 .. 4-3-3 (single flow, selective and parallel branch and
merge, jump, repeat), the points 4-3-4 says need care (dummy steps between a merge and a
branch, shared transition contacts), and 4-4 items 17 and 19, on every engine. A program
holding STL runs the reference routines whatever the engine (docs/simulator.md: the rail is
the interpreter's), but the native engine's machine keeps its registers in C arrays, so each
case runs on all three. Rules of the checker for merges are at the end."""

from __future__ import annotations

import pytest

import vskit
from conftest import SAMPLES

ENGINES = ("interp", "compiled", "native")

# the issue's program: 4-3-3's parallel branch and merge as 4-6-2 writes it in step ladder
PARALLEL = """LD M9002
SET S20
STL S20
LD X0
SET S21
SET S23
STL S21
OUT Y0
LD X1
SET S22
STL S23
OUT Y1
LD X2
SET S24
STL S22
STL S24
LD X3
SET S25
STL S25
OUT Y2
LD X4
OUT S20
RET"""


def pulses(*names_at: tuple[str, int]) -> str:
    """Stimulus lines: each input On for the one 10 ms scan at its time."""
    return "".join(f"{ms}ms {n}=1\n{ms + 10}ms {n}=0\n" for n, ms in names_at)


def in_time_order(stim: str) -> str:
    """The lines sorted by their time (stable: a setting before an expectation at one time)."""
    lines = [line for line in stim.splitlines() if line.strip()]
    return "\n".join(sorted(lines, key=lambda line: int(line.split("ms", 1)[0]))) + "\n"


def repeat_stim() -> str:
    # X1, X2, X3 pulsed in turn: the loop S21 -> S22 -> S23 -> S21 runs three times (C0
    # counts each entry into S21), then X3 leaves for S24
    out = "10ms X0=1\n20ms X0=0\n"
    t = 30
    for k in range(3):
        out += pulses(("X1", t), ("X2", t + 20), ("X3", t + 40))
        out += f"{t + 10}ms expect S22=1 S21=0 Y2=1\n"
        out += f"{t + 40}ms expect {'S21=1 S23=0 S24=0' if k < 2 else 'S24=1 S21=0 S23=0 Y4=1'}\n"
        t += 60
    return out


CASES = [
    # 4-1-3: the transfer scan: the destination (later in the program) runs at once, the
    # source is still On for the rest of the scan (A); the next scan the source's block runs
    # once more with its step Off: its OUT coil goes Off, its SET coil stays (B)
    pytest.param("LD M9002\nSET S21\nSTL S20\nOUT Y7\nSTL S21\nOUT Y0\nLD X1\nSET Y1\nLD X0\nSET S22\n"
                 "STL S22\nOUT Y2\nLD S21\nOUT M0\nRET",
                 "0ms X1=1\n0ms expect S21=1 Y0=1 Y1=1 Y7=0 Y2=0\n10ms X0=1\n"
                 "10ms expect S22=1 Y2=1 M0=1 Y0=1 S21=0\n20ms expect Y0=0 Y1=1 Y2=1 M0=0 S21=0 Y7=0",
                 id="4-1-3-transfer-scans"),
    # 4-3-1 jump: SET to a step further down the same flow skips the steps between
    pytest.param("LD M9002\nSET S20\nSTL S20\nOUT Y0\nLD X0\nSET S21\nLD X3\nSET S23\nSTL S21\nOUT Y1\n"
                 "LD X1\nSET S22\nSTL S22\nOUT Y2\nLD X2\nSET S23\nSTL S23\nOUT Y3\nRET",
                 "0ms expect S20=1\n10ms X3=1\n10ms expect S23=1 Y3=1 S20=0 S21=0 S22=0 Y1=0 Y2=0\n"
                 "20ms expect Y0=0 Y3=1", id="4-3-1-jump-same-flow"),
    # 4-3-1 / 4-6-1 jump: OUT to a step of another flow (its own initial step S2 never ran)
    pytest.param("LD M9002\nSET S1\nSTL S1\nOUT Y0\nLD X0\nSET S10\nSTL S10\nOUT Y1\nLD X1\nOUT S22\nRET\n"
                 "STL S2\nLD X2\nSET S20\nSTL S20\nLD X3\nSET S21\nSTL S21\nLD X4\nSET S22\nSTL S22\nOUT Y2\n"
                 "LD X5\nSET S2\nRET",
                 "10ms X0=1\n20ms X0=0\n20ms expect S10=1 Y1=1\n30ms X1=1\n"
                 "30ms expect S22=1 Y2=1 S10=0 S1=0 S2=0 S20=0 S21=0\n40ms expect Y1=0 Y2=1\n"
                 "50ms X5=1\n50ms expect S2=1 S22=0", id="4-3-1-jump-other-flow"),
    # 4-3-1 jump written with OUT inside its own flow: the same transfer as SET (4-6-1)
    pytest.param("LD M9002\nSET S20\nSTL S20\nOUT Y0\nLD X3\nOUT S23\nSTL S21\nOUT Y1\nSTL S23\nOUT Y3\nRET",
                 "10ms X3=1\n10ms expect S23=1 Y3=1 S20=0\n20ms expect Y0=0", id="4-3-1-jump-out-same-flow"),
    # 4-3-1 repeat: a transfer back to an earlier step of the flow; the loop runs until C0
    # has counted three entries into S21
    pytest.param("LD M9002\nSET S20\nSTL S20\nLD X0\nSET S21\nSTL S21\nOUT Y1\nOUT C0 K3\nLD X1\nSET S22\n"
                 "STL S22\nOUT Y2\nLD X2\nSET S23\nSTL S23\nLD X3\nANI C0\nSET S21\nLD X3\nAND C0\nSET S24\n"
                 "STL S24\nOUT Y4\nRST C0\nRET", repeat_stim(), id="4-3-1-repeat"),
    # 4-3-2 selective branch and merge: one path of three by its condition, back to one step
    pytest.param("LD M9002\nSET S10\nSTL S10\nOUT Y0\nLD X0\nSET S20\nLD X1\nSET S30\nLD X2\nSET S40\n"
                 "STL S20\nOUT Y1\nLD X3\nSET S11\nSTL S30\nOUT Y2\nLD X3\nSET S11\nSTL S40\nOUT Y3\nLD X3\n"
                 "SET S11\nSTL S11\nOUT Y4\nLD X4\nSET S10\nRET",
                 pulses(("X1", 10), ("X3", 30), ("X4", 50), ("X2", 70), ("X3", 90))
                 + "10ms expect S30=1 Y2=1 S20=0 S40=0 S10=0\n30ms expect S11=1 S30=0 Y4=1\n"
                 "40ms expect Y2=0 Y4=1\n50ms expect S10=1 S11=0\n70ms expect S40=1 S20=0 S30=0\n"
                 "90ms expect S11=1 S40=0 Y3=1\n100ms expect Y3=0 S11=1", id="4-3-2-selective"),
    # 4-3-3 parallel branch: every first step of the branch becomes active at once
    pytest.param(PARALLEL, "0ms X0=1\n0ms expect S21=1 S23=1 S20=0 Y0=1 Y1=1", id="4-3-3-parallel-branch"),
    # 4-3-3 parallel merge (the issue's program): the transfer to S25 waits for both last
    # steps, then resets every step of the merge (S22 stayed On before the fix)
    pytest.param(PARALLEL, "0ms X0=1\n20ms X1=1 X2=1\n20ms expect S22=1 S24=1 S21=0 S23=0\n"
                 "40ms expect S25=0 S22=1 S24=1\n50ms X3=1\n"
                 "50ms expect S25=1 Y2=1 S20=0 S21=0 S22=0 S23=0 S24=0\n60ms expect Y0=0 Y1=0 Y2=1 S22=0",
                 id="4-3-3-parallel-merge"),
    # 4-3-3: one path done is not enough; the merge's transfer condition alone neither
    # (S23's block comes before the merge's: its transfer to S24 and the merge happen in one scan)
    pytest.param(PARALLEL, "0ms X0=1\n20ms X1=1 X3=1\n40ms expect S22=1 S23=1 S24=0 S25=0\n"
                 "50ms X2=1\n50ms expect S25=1 S22=0 S23=0 S24=0",
                 id="4-3-3-merge-waits"),
    # 4-3-3 then 4-3-1: the merged flow repeats from S20 (OUT S20) and the branch runs again
    pytest.param(PARALLEL, "0ms X0=1\n20ms X1=1 X2=1\n50ms X3=1\n60ms X0=0 X1=0 X2=0 X3=0\n70ms X4=1\n"
                 "70ms expect S20=1 S25=0\n80ms X4=0 X0=1\n80ms expect S21=1 S23=1 S20=0 S22=0 S24=0",
                 id="4-3-3-merge-then-repeat"),
    # 4-6-2: the steps of a merge with blocks of their own (their outputs), the merge after them
    pytest.param("LD M9002\nSET S20\nSTL S20\nLD X0\nSET S22\nSET S24\nSTL S22\nOUT Y20\nSTL S24\nOUT Y22\n"
                 "STL S22\nSTL S24\nOUT M5\nLD X3\nSET S25\nSTL S25\nOUT Y2\nRET",
                 "10ms X0=1\n10ms expect S22=1 S24=1 Y20=1 Y22=1 M5=1\n40ms X3=1\n"
                 "40ms expect S25=1 Y2=1 S22=0 S24=0 Y20=1 Y22=1\n50ms expect Y20=0 Y22=0 M5=0 S25=1",
                 id="4-6-2-merge-with-own-blocks"),
    # 4-3-4: transitions that share contacts (a branch decided by X0, then X1 or X2; a merge
    # whose conditions share X6 or X7) are each written with their whole condition, so exactly
    # one path is taken (X10 starts the branch)
    pytest.param("LD M9002\nSET S10\nSTL S10\nLD X10\nAND X0\nAND X1\nSET S20\nLD X10\nAND X0\nANI X1\n"
                 "SET S30\nLD X10\nANI X0\nAND X2\nSET S40\nLD X10\nANI X0\nANI X2\nSET S50\n"
                 "STL S20\nOUT M0\nOUT T0 K1\nLD X6\nAND T0\nSET S11\nSTL S30\nOUT M1\nOUT T1 K1\nLD X6\n"
                 "AND T1\nSET S11\nSTL S40\nOUT M2\nOUT T2 K1\nLD X7\nAND T2\nSET S11\nSTL S50\nOUT M3\n"
                 "OUT T3 K1\nLD X7\nAND T3\nSET S11\nSTL S11\nOUT Y0\nRET",
                 "10ms X2=1 X10=1\n10ms expect S40=1 M2=1 S20=0 S30=0 S50=0 S10=0\n20ms X10=0\n30ms X6=1 X7=1\n"
                 "60ms expect S40=1 S11=0\n150ms expect S11=1 Y0=1 S40=0\n160ms expect M2=0",
                 id="4-3-4-shared-contact"),
    # 4-3-4: a parallel merge straight into a parallel branch goes through a dummy step S100
    pytest.param("LD M9002\nSET S20\nSET S30\nSTL S20\nSTL S30\nLD X0\nSET S100\nSTL S100\nLD M9000\n"
                 "SET S40\nSET S50\nSTL S40\nOUT Y0\nSTL S50\nOUT Y1\nRET",
                 "10ms X0=1\n10ms expect S40=1 S50=1 Y0=1 Y1=1 S20=0 S30=0 S100=0",
                 id="4-3-4-dummy-parallel-to-parallel"),
    # 4-3-4: a selective merge into a selective branch through dummy step S100
    pytest.param("LD M9002\nSET S30\nSTL S20\nLD X0\nSET S100\nSTL S30\nLD X1\nSET S100\nSTL S100\nLD X3\n"
                 "SET S40\nLD X4\nSET S50\nSTL S40\nOUT Y0\nSTL S50\nOUT Y1\nRET",
                 "10ms X0=1\n10ms expect S30=1 S100=0\n20ms X1=1\n20ms expect S100=1 S30=0\n"
                 "30ms X4=1\n30ms expect S50=1 Y1=1 S40=0 S100=0", id="4-3-4-dummy-selective-to-selective"),
    # 4-3-4: a selective merge into a parallel branch through dummy step S101
    pytest.param("LD M9002\nSET S20\nSTL S20\nLD X0\nSET S101\nSTL S30\nLD X1\nSET S101\nSTL S101\nLD M9000\n"
                 "SET S40\nSET S50\nSTL S40\nOUT Y0\nSTL S50\nOUT Y1\nRET",
                 "10ms X0=1\n10ms expect S40=1 S50=1 S20=0 S101=0 S30=0", id="4-3-4-dummy-selective-to-parallel"),
    # 4-3-4: a parallel merge (condition X0) into a selective branch through dummy step S200
    pytest.param("LD M9002\nSET S20\nSET S30\nSTL S20\nSTL S30\nLD X0\nSET S200\nSTL S200\nLD X1\nSET S40\n"
                 "LD X2\nSET S50\nSTL S40\nOUT Y0\nSTL S50\nOUT Y1\nRET",
                 "10ms X2=1\n10ms expect S20=1 S30=1 S200=0\n20ms X0=1\n20ms expect S50=1 S40=0 S20=0 S30=0 "
                 "S200=0", id="4-3-4-dummy-parallel-to-selective"),
    # 4-4 item 17: RST of the step itself resets it (no transfer); RST of another step
    # resets that one and the running step stays On
    pytest.param("LD M9002\nSET S20\nSET S30\nSTL S20\nLD X0\nRST S30\nLD X1\nRST S20\nSTL S30\nOUT Y1\nRET",
                 "0ms expect S20=1 S30=1 Y1=1\n10ms X0=1\n10ms expect S30=0 S20=1\n20ms expect Y1=0\n"
                 "30ms X1=1\n30ms expect S20=0", id="4-4-rst-step"),
    # 4-4 item 19: one held signal as the transition of two steps in a row passes both in one
    # scan (the step after is active at once, 4-1-3)...
    pytest.param("LD M9002\nSET S100\nSTL S100\nLD X0\nSET S101\nSTL S101\nLD X0\nSET S102\nSTL S102\n"
                 "OUT Y2\nRET", "10ms X0=1\n10ms expect S102=1 Y2=1 S101=0 S100=0", id="4-4-same-signal-twice"),
    # ... so each step takes the button's pulse (M0) only while its own entry pulse (PLS on the
    # step's bus) is Off, the construction of item 20: one press, one step
    pytest.param("LD X0\nPLS M0\nLD M9002\nSET S100\nSTL S100\nPLS M1\nLD M0\nANI M1\nSET S101\n"
                 "STL S101\nPLS M2\nLD M0\nANI M2\nSET S102\nSTL S102\nOUT Y2\nRET",
                 "10ms X0=1\n10ms expect S101=1 S102=0 S100=0\n20ms X0=0\n40ms expect S101=1\n50ms X0=1\n"
                 "50ms expect S102=1 Y2=1 S101=0", id="4-4-pulse-transition"),
]


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("il, stim", CASES)
def test_flow(il, stim, engine):
    vskit.run(il, in_time_order(stim), engine=engine)


def test_the_merge_resets_every_step_on_the_issue_timing():
    """The issue's exact figures: X0 at 0 ms, X1 and X2 at 20 ms, X3 at 50 ms; after the
    merge S21-S24 are all Off (S22 stayed On, its Y0 step running, before the fix)."""
    stim = "0ms X0=1\n20ms X1=1 X2=1\n50ms X3=1\n100ms expect S25=1 S21=0 S22=0 S23=0 S24=0 Y0=0 Y1=0 Y2=1"
    for engine in ENGINES:
        vskit.run(PARALLEL, stim, engine=engine)


def test_the_reduced_merge_of_the_issue():
    """`STL S20 / STL S30 / LD X0 / SET S40` with S20, S30, X0 On: S40 On, both sources Off
    (before the fix S30 alone went Off); with S30 Off the merge does not transfer."""
    il = "STL S20\nSTL S30\nLD X0\nSET S40\nRET"
    vskit.run(il, "0ms S20=1 S30=1 X0=1\n0ms expect S40=1 S20=0 S30=0")
    vskit.run(il, "0ms S20=0 S30=1 X0=1\n0ms expect S40=0 S30=1")


MERGE_OF = "LD M9002\nSET S20\nSTL S20\nLD X0\n{sets}\n{blocks}\n{merge}\nLD X3\nSET S99\nSTL S99\nOUT Y0\nRET\nEND"


def merge_program(n: int, own_blocks: bool = True) -> str:
    steps = [30 + k for k in range(n)]
    return MERGE_OF.format(sets="\n".join(f"SET S{s}" for s in steps),
                           blocks="\n".join(f"STL S{s}\nOUT M{s}" for s in steps) if own_blocks else "",
                           merge="\n".join(f"STL S{s}" for s in steps))


@pytest.mark.parametrize("il, expected", [
    # 4-6-2 writes a parallel merge's steps with blocks of their own and the merge after them
    pytest.param(merge_program(2), [], id="4-6-2-merge-steps-have-blocks"),
    pytest.param(merge_program(8, own_blocks=False), [], id="4-3-3-eight-path-merge"),
    # 4-3-3: 2-8 paths; the ninth STL in series is warned (W320, line 4 + 9 SETs + 9 blocks + 9),
    # as the branch into them is (W224 at the ninth SET)
    pytest.param(merge_program(9), [("W224", 13), ("W320", 4 + 9 + 18 + 9)], id="4-3-3-nine-path-merge"),
    # a step leaves through one merge; its own block is still one (E902, as before)
    pytest.param(merge_program(2).replace("LD X3\nSET S99", "LD X3\nSET S99\nSTL S30\nSTL S40\nLD X4\nSET S98"),
                 [("E902", 15)], id="4-3-3-step-in-two-merges"),
    pytest.param(merge_program(2).replace("STL S31\nOUT M31", "STL S30\nOUT M31"), [("E902", 9)],
                 id="4-4-merge-step-two-blocks"),
])
def test_merge_layout_is_checked(il, expected):
    assert vskit.check_codes(il, severities=("error", "warning")) == expected


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name", ["sfc_parallel", "traffic_light_parallel", "parking"])
def test_chapter_4_sample_on_every_engine(name, engine):
    """The chapter 4 exercises with a merge or a three-way branch (samples/vs; the CLI runs
    them on the default engine in test_vs_samples.py)."""
    image = vskit.image_of((SAMPLES / "vs" / f"{name}.il").read_text("utf-8"))
    assert image is not None
    r = vskit.simulate(image, (SAMPLES / "vs" / f"{name}.stim").read_text("utf-8"), engine=engine)
    assert r.fault is None and r.expectations and not r.failed, [(f.line, f.device, f.expected, f.actual) for f in r.failed]
