"""The compiled engine's function layout (compile._Layout, _Gen.split): blocks laid out into
few functions (fall-through, jumps and loops inside a function, one-block subroutines inlined
at their CALL), long blocks split into chained functions. Whatever the layout, every scan must
give the interpreter's devices, faults (message and step), watchdog step, loop and call
stacks, and writer records."""

from __future__ import annotations

from collections import OrderedDict

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_compiled_engine import engines_agree, program, stimulus

from mlctool.sim.engines import compile as compile_mod
from mlctool.sim.engines import compile_layout
from mlctool.sim.engines.engine import Scanner
from mlctool.sim.scan import Fault, load_program
from mlctool.sim.state import Machine
from simkit import NC5, image_of

# FOR bodies of one and of several blocks (a CALL inside), a CJ over a block, a one-block
# subroutine called from two places, a subroutine of two blocks, index-modified stores; the
# one-block loop and P1 are several rungs (split with tiny thresholds)
FLOW = """LD X0
MOV K3 D0
FOR K3
LD X1
INC D1
LD X0
MOV D1 D10V0
LDI X3
OUT M5
NEXT
LD X2
CALL P1
LD X3
CJ P2
LD X0
INC D2
P2:
FOR D0
LD X1
INC D3
CALL P1
NEXT
LD X4
CALL P3
FEND
P1:
LD X1
INC D4
LD X2
MOV K7 D20Z0
LD X3
ADD D4 K1 D6
SRET
P3:
LD X0
CALL P1
INC D5
SRET
END"""


def _scan_all(il: str, setups: list[dict], watchdogs, scans: int = 3):
    """Per engine: for each setup and watchdog, `scans` scans (continuing after faults),
    and after each the fault, devices, loop and call stacks and writer records."""
    image = image_of(il)
    found = []
    for engine in ("compiled", "interp"):
        out = []
        for setup in setups:
            for watchdog in watchdogs:
                prog = load_program(image, NC5)
                m = Machine(NC5, len(prog.steps))
                sc = Scanner(prog, m, engine)
                assert sc.engine == engine
                for name, v in setup.items():
                    (m.bits["X"] if name[0] == "X" else m.words[name[0]])[int(name[1:])] = v
                for _ in range(scans):
                    try:
                        sc(watchdog)
                        out.append(None)
                    except Fault as f:
                        out.append((f.message, f.step.index))
                    out.append((m.words["D"][:40], m.fors, m.calls, dict(m.writer)))
        found.append(out)
    return found


SETUPS = [{"X0": 1, "X1": 1, "X2": 1, "X4": 1}, {"X1": 1, "X3": 1, "X4": 1, "V0": 1},
          {"X0": 1, "X1": 1, "X2": 1, "Z0": 30000}, {"X0": 1, "X2": 1, "X3": 1}]


def test_merged_flow_matches_the_interpreter_at_every_watchdog_limit():
    """Each limit from 1 step to past the scan stops a different block (in a FOR body, a
    jumped-over block, an inlined subroutine, a called function) at the interpreter's step."""
    code = compile_mod.compile_program(load_program(image_of(FLOW), NC5))
    assert len(set(code.funcs)) < len(code.starts) // 2  # few functions for the blocks
    assert "m.calls.pop()\n" in code.source  # P1 inlined at its CALLs
    a, b = _scan_all(FLOW, SETUPS, range(1, 120))
    assert a == b


@pytest.fixture
def tiny_layout(monkeypatch):
    """Thresholds so small that every block is split and laid out in many functions."""
    monkeypatch.setattr(compile_mod, "_CACHE", OrderedDict())
    monkeypatch.setattr(compile_mod, "PIECE_LINES", 3)
    monkeypatch.setattr(compile_layout, "REGION_LINES", 12)
    monkeypatch.setattr(compile_layout, "REGION_BLOCKS", 2)


def test_split_blocks_and_small_functions_match_the_interpreter(tiny_layout):
    code = compile_mod.compile_program(load_program(image_of(FLOW), NC5))
    assert "def piece3(m, ws" in code.source and len(set(code.funcs)) > 4
    a, b = _scan_all(FLOW, SETUPS, [1000, 17, 40, 77])
    assert a == b


def test_a_huge_block_is_split_into_functions_of_bounded_size():
    """A long straight program (one block) is compiled as a chain of functions of about
    PIECE_LINES lines each (compile()'s memory grows with a function), with the results,
    the fault step and the writers of the interpreter."""
    rungs = []
    for k in range(1500):
        rungs += [f"LD X{k % 8}", f"AND M{k % 50}", f"OUT M{100 + k % 400}",
                  "LD M1000", f"ADD D{k % 90} K{k} D{(k * 7) % 90}", f"MOV D{k % 90}V0 D{100 + k % 90}"]
    il = "\n".join(rungs + ["END"])
    code = compile_mod.compile_program(load_program(image_of(il), NC5))
    assert len(code.starts) == 1
    starts = [k for k, line in enumerate(code.source.split("\n")) if line.startswith("def ")]
    sizes = [b - a for a, b in zip(starts, starts[1:])]
    assert len(starts) > 3 and max(sizes) < compile_mod.PIECE_LINES + 100
    setups = [{"X1": 1, "X3": 1}, {"X0": 1, "X5": 1, "V0": 5}, {"X2": 1, "V0": 65000}]
    a, b = _scan_all(il.replace("LD M1000", "LD X1"), setups, [100_000, 4000], scans=2)
    assert a == b


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                   HealthCheck.function_scoped_fixture])
@given(program(), stimulus(), st.sampled_from(["nc5", "vs"]))
def test_random_programs_split_into_tiny_functions_match_the_interpreter(tiny_layout, il, stim, target_name):
    engines_agree(il, stim, target_name)


def test_functions_take_the_new_containers_after_a_power_cycle():
    """A generated function's containers are its parameters' defaults: a power cycle (new
    device lists) and another Scanner on the same machine (a new writer dict) set them again."""
    image = image_of(FLOW)
    found = []
    for engine in ("compiled", "interp"):
        prog = load_program(image, NC5)
        m = Machine(NC5, len(prog.steps))
        sc = Scanner(prog, m, engine)
        out = []
        for k in range(6):
            if k == 2:
                m.power_cycle()
            if k == 4:
                Scanner(prog, m, engine)()
            m.bits["X"][0:5] = bytes([1, 1, k & 1, 1, 1])
            sc()
            out.append((m.words["D"][:40], dict(m.writer)))
        found.append(out)
    assert found[0] == found[1]
    assert found[0][1][0] != found[0][2][0]  # the power cycle cleared D (the code wrote the new lists)
