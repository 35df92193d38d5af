"""The native engine (sim/engines/native.py) against the compiled engine: one program per target that
holds every kind of rung the compiled engine's random programs draw (test_compiled_engine.py),
run on generated stimuli (power cycles, index registers out of range, float patterns), must
give identical traces, devices, memory, faults, alarms, expectations and writers. A build
takes seconds, so the program is fixed and the stimuli vary."""

from __future__ import annotations

import functools

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_compiled_engine import _image, engines_agree, stimulus, vs_dialect

from mlctool.sim.engines import native
from mlctool.sim.engines.engine import NativeScanner, Scanner, scanner
from mlctool.sim.run.run import Simulation, build_models, plan_scans
from mlctool.sim.scan import Fault, load_program
from mlctool.sim.state import Machine
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from simkit import NC5, image_of
from vskit import VS

pytestmark = pytest.mark.skipif(native.unavailable() is not None, reason=f"native engine: {native.unavailable()}")

RUNGS = """
LD M16
FADD D0 F1.5 D12
FMUL D0 D12 D14
LD X0
ANI X1
OR M0
OUT Y0
LDP X2
OUT M1
LDF X3
SET M2
LD X4
RST M2
LD X5
PLS M3
LDI X0
PLF M4
LD X1
MPS
AND X2
OUT M5
MRD
ANI X3
OUT M6
MPP
OUT M7
LD X1
INV
TMR T0 K3
LD X2
CNT C0 K2
LD> D0 K3
AND<> D1 D2
OR< D3 K5
MOV K7 D1
LD= D0 K0
LD X3
ORB
ADD D0 D1 D2
SUB D2 K5 D3
WAND D0 K255 D4
WOR D1 D2 D5
WXOR D3 D4 D6
INC D7
DEC D6
DADD D0 K70000 D2
DSUB D3 D5 D1
DWAND D0 K99999 D2
DWOR D1 D3 D5
DWXOR D2 D0 D3
LDI X4
LD<> D6 K-2810
ANB
OR<= D0 K387
ORF X2
OUT Y3
OUT M24
LD X4
MOV D1V0 D5
RST T0
RST C1
DIV D0 D1 D2
MUL D0 K-300 D4
CML D1 D7
FADD D0 F1.5 D2
FSUB D2 D4 D6
FMUL D0V0 D0 D2
FDIV F2.5 D0 D4
FADD D2V0 D4 D6
MOV K4M0 D3
MOV D5 K2Y0
DMOV K8M8 D2
MOV K2X0 D7
CNT C1 D1
DMUL D0 K123 D4
LD X5
MOV K2 V0
MOV K-1 Z0
MOV D0Z0 D3V0
INC D1Z0
ADD D0V0 K2 D1Z0
DMOV D0V0 D2
DMOV K65537 V1
DMOV V1 D4
LD M0
TMR T1 D1
MOV T1 D3
MOV K2 T1
MOV K2M1 D4
FOR K3
LD X1
INC D6
NEXT
FOR D0
LD M1
ADD D5 K1 D5
NEXT
LD X2
CJ P10
LD X3
OUT Y1
MOV K1 D0
P10:
P0:
LD M15
CJ P0
LD X4
CALL P2
OUT Y2
FEND
P2:
LD X1
INC D7
MOV D7 D0V0
SRET
END
"""


@functools.cache
def program_image(target_name: str):
    il = RUNGS.strip()
    image = _image(il if target_name == "nc5" else vs_dialect(il), NC5 if target_name == "nc5" else VS)
    assert image is not None, f"the native test program does not assemble for {target_name}"
    return image


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(stimulus(), st.sampled_from(["nc5", "vs"]))
def test_native_engine_matches_the_compiled_engine(stim, target_name):
    """(The rung of LDI X4 ... OUT Y3, OUT M24 keeps its result: `bY[3] = a = e and not c or
    <compare> or k and <compare>`, which Cython 3.3 built into a segmentation fault: native._KEPT_RESULT.)"""
    engines_agree("", stim, target_name, engines=("native", "compiled"), image=program_image(target_name))


@pytest.mark.parametrize("target_name", ["nc5", "vs"])
def test_float_pairs_in_the_infinity_rows(target_name):
    """A D pair whose high word is 7F80H/FF80H reads as +-inf with a zero low word and NaN
    otherwise (engine._InfRow); the extension writes that rule out (native._float_pairs)."""
    # (the first rung reads D0:D1 as the stimulus left it: later rungs write D1)
    stim = ("#0 M16=1 D1=32640 D0=0\n#1 D1=32640 D0=1\n#2 D1=-128 D0=0\n#3 D1=-128 D0=-3\n"
            "#4 D1=16320 D0=0\nrun #6\n")
    engines_agree("", stim, target_name, engines=("native", "compiled"), image=program_image(target_name))


def test_faults_and_watchdog_name_the_same_step():
    """X5's rung reads D0Z0 with Z0 = -1 (an address fault); M15 jumps back to itself until
    the watchdog stops the scan: both engines stop at the same step with the same memory."""
    image = program_image("nc5")
    for setup, text in (({"X5": 1}, "D-1"), ({"M15": 1}, "watchdog")):
        found = []
        for engine in ("native", "compiled"):
            prog = load_program(image, NC5)
            m = Machine(NC5, len(prog.steps))
            sc = scanner(prog, m, engine)
            assert sc.engine == engine
            for name, v in setup.items():
                m.bits[name[0]][int(name[1:])] = v
            with pytest.raises(Fault) as caught:
                sc(1000)
            f = caught.value
            found.append((f.message, f.step.index, list(m.words["D"][:8]), bytes(m.edge), dict(m.writer)))
        assert found[0] == found[1] and text in found[0][0]


def test_two_machines_of_one_program_share_the_extension():
    """The extension of a program loads once per process; each Scanner binds its own
    machine's containers before it runs: two machines' scans interleaved end as each one
    run alone on the compiled engine."""
    image = program_image("nc5")

    def machine(engine: str, x1: int):
        prog = load_program(image, NC5)
        m = Machine(NC5, len(prog.steps))
        m.bits["X"][1] = x1
        m.bits["X"][4] = 1
        return m, scanner(prog, m, engine)

    pairs = [machine("native", x1) for x1 in (0, 1)]
    assert pairs[0][1].native is pairs[1][1].native is not None
    for _ in range(5):
        for _m, sc in pairs:
            sc()
    for (m, _), x1 in zip(pairs, (0, 1), strict=True):
        alone, sc = machine("compiled", x1)
        for _ in range(5):
            sc()
        assert list(m.words["D"][:8]) == list(alone.words["D"][:8]) and m.bits == alone.bits
    assert pairs[0][0].words["D"][:8] != pairs[1][0].words["D"][:8]


def test_without_a_build_the_compiled_engine_runs_and_says_why(monkeypatch):
    monkeypatch.setattr(native, "unavailable", lambda: "no C compiler (cc) found")
    monkeypatch.setattr(native, "_LOADED", {})
    monkeypatch.setenv("MLC_CACHE", "off")
    builds = []
    monkeypatch.setattr(native, "on_build", lambda: builds.append(1))  # (the CLI's note)
    image = image_of("LD X0\nOUT Y7\nEND")
    prog = load_program(image, NC5)
    m = Machine(NC5, len(prog.steps))
    sc = scanner(prog, m, "native")
    assert builds == [1]
    assert isinstance(sc, NativeScanner) and sc.engine == "compiled" and sc.native is None
    assert sc.native_error == "no C compiler (cc) found"
    m.bits["X"][0] = 1
    sc()
    assert m.bits["Y"][7] == 1
    # the stamps of the writer records are bound again as an array: the records are right
    plain = Machine(NC5, len(prog.steps))
    plain.bits["X"][0] = 1
    Scanner(load_program(image, NC5), plain, "compiled")()
    assert dict(m.writer) == dict(plain.writer) and dict(m.writer)


def test_machine_arrays_survive_a_power_cycle():
    prog = load_program(image_of("LD X0\nMOV K5 D0\nEND"), NC5)
    m = Machine(NC5, len(prog.steps))
    Scanner(prog, m, "compiled")
    assert m.use_arrays() and not m.use_arrays()  # the second call changes nothing
    m.words["D"][3] = 7
    m.power_cycle()
    assert type(m.words["D"]).__name__ == "array" and type(m.cval).__name__ == "array"
    assert m.words["D"][3] == 0


def test_the_debugger_travels_in_time_on_the_native_engine(tmp_path):
    """mlc debug --engine native: checkpoints copy the machine's arrays and a restore rebinds
    the extension; going back and forth ends where the compiled engine's session does."""
    from mlctool.debug.load import load_session
    from mlctool.debug.session import BOUNDARY

    il, stim = tmp_path / "p.il", tmp_path / "p.stim"
    il.write_text(RUNGS.strip() + "\n")
    stim.write_text("#0 X1=1\n#3 X4=1\n#6 X2=1 V0=2\n#9 X1=0\n")
    states = []
    for engine in ("native", "compiled"):
        s = load_session([str(il)], str(stim), NC5, engine=engine, checkpoint_every=4)
        assert s.sim.scan.engine == engine
        s.goto((14, BOUNDARY))
        s.goto((5, BOUNDARY))
        s.back_scan()
        s.goto((14, BOUNDARY))
        m = s.sim.m
        states.append(({k: list(v) for k, v in m.words.items()}, m.bits, list(m.cval), dict(m.writer)))
    assert states[0] == states[1]


def test_mlc_sim_engine_option_reaches_the_run(tmp_path, monkeypatch, mlc):
    """`mlc sim --engine X` runs engine X (a single run took MLC_SIM_ENGINE only); where the
    native engine cannot run, a note says so and the compiled engine gives the same result."""
    import mlctool.sim.run.run as run_module

    monkeypatch.delenv("MLC_SIM_ENGINE", raising=False)
    il, stim = tmp_path / "p.il", tmp_path / "p.stim"
    il.write_text(RUNGS.strip() + "\n")
    stim.write_text("#0 X1=1 X4=1\n#2 expect X1=1\nrun #5\n")
    used = []
    real = run_module.scanner

    def recording(prog, m, engine=None):
        sc = real(prog, m, engine)
        used.append(sc.engine)
        return sc

    monkeypatch.setattr(run_module, "scanner", recording)
    outs = []
    for engine in ("native", "interp", "compiled"):
        r = mlc("sim", "--json", "--engine", engine, str(il), "--stimulus", str(stim))
        assert r.code == 0, r.err
        outs.append(r.out)
    assert used == ["native", "interp", "compiled"] and outs[0] == outs[1] == outs[2]
    monkeypatch.setattr(native, "unavailable", lambda: "no C compiler (cc) found")
    r = mlc("sim", "--json", "--engine", "native", str(il), "--stimulus", str(stim))
    assert r.code == 0 and r.out == outs[0] and used[-1] == "native"  # (the module is loaded)
    assert "note: the native engine did not run (no C compiler (cc) found); the compiled engine did" in r.err


def test_a_program_over_the_line_limit_runs_on_the_compiled_engine(monkeypatch):
    monkeypatch.setenv(native.MAX_LINES_ENV, "10")
    builds = []
    monkeypatch.setattr(native, "on_build", lambda: builds.append(1))
    prog = load_program(program_image("nc5"), NC5)
    sc = scanner(prog, Machine(NC5, len(prog.steps)), "native")
    assert sc.engine == "compiled" and not builds
    assert "over the native engine's 10 " in sc.native_error and native.MAX_LINES_ENV in sc.native_error


def test_vs_block_copies_into_the_machine_arrays():
    """Reference routines that copy a block of registers into the machine's words: VS BMOV
    from module memory (UnG: kept in the buffer memory, not in an array) into D, and LINK
    reading a peer station's registers (CPUL shares its code). The native engine's words are
    arrays, whose slices take no list: both were an internal error of mlc sim (TypeError).
    Now the run is the compiled engine's and the values arrive."""
    il = (".table Q1 LINK K0 K1 D0 D0 K2\nLD X20\nLINK Q1 D100 K1\nLD M9000\nMOV K5 U1G0\nMOV K6 U1G1\n"
          "BMOV U1G0 D10 K2\nBMOV D10 U1G5 K2\nBMOV U1G5 D12 K2\nEND")
    stim = "model vsplc link=CP1 station=1\n0ms X20=1 CP1#1.D0=11 CP1#1.D1=12\n1s expect D0=11 D1=12 D10=5 D13=6\n"
    image = _image(il, VS)
    assert image is not None
    found = []
    for engine in ("native", "compiled"):
        st_, diags = parse_stimulus_text("t.stim", stim, VS)
        models, model_diags = build_models(st_, VS)
        assert not diags and not model_diags
        sim = Simulation(image, VS, st_, models, 10_000, [], True, engine=engine)
        r = sim.run(plan_scans(st_, 10_000, None, None))
        assert sim.scan.engine == engine
        found.append((repr(r.trace), repr(r.devices), r.fault, r.alarms, r.failed, list(sim.m.words["D"][:14]),
                      dict(sim.m.writer)))
    assert found[0] == found[1]
    assert found[0][2] is None and not found[0][3] and not found[0][4] and found[0][5][:2] == [11, 12]


def test_a_kept_rung_result_is_assigned_one_target_at_a_time():
    """native._KEPT_RESULT: `bY[3] = a = <rung>` goes into the Cython module as two statements of
    the same source line (Cython 3.3 miscompiles the chained form when the rung mixes C types)."""
    source = "def F0(m, ws, ex, jb, bY=G_bY):\n    bY[3] = a = e and not c or k and (w > 3)\n    return -1\n"
    text, origin = native.pyx_text(source, {"bY": "unsigned char[::1]"})
    lines = text.splitlines()
    k = lines.index("        a = e and not c or k and (w > 3)")
    assert lines[k + 1] == "        bY[3] = a" and origin[k] == origin[k + 1] == 1
    assert " = a = " not in text


def test_a_watchdog_past_64_bits_is_taken():
    """`mlc sim --watchdog` has no upper bound; the extension keeps the limit in a C variable
    (a limit past 2^63 was an OverflowError, an internal error of mlc sim): the scans run as
    on the compiled engine."""
    found = []
    for engine in ("native", "compiled"):
        prog = load_program(program_image("nc5"), NC5)
        m = Machine(NC5, len(prog.steps))
        sc = scanner(prog, m, engine)
        assert sc.engine == engine
        m.bits["X"][1] = m.bits["X"][4] = 1
        for _ in range(3):
            sc(10**20)
        found.append((list(m.words["D"][:8]), bytes(m.bits["Y"][:4])))
    assert found[0] == found[1]
