"""Checked means runs (issue 30, defect 5 and "what to build" 3): a program `mlc check` accepts
never crashes the simulator (exit 3) on any engine. An operand that runs past its device's
end is an E2xx from the checker where it is written as a device; where an index register or
a register's value decides, the run faults or raises the operation error (E604, exit 1).

- the repros of the issue, each on its own (the checker's code) or on every engine (E604);
- the walk (tests/edgewalk.py): every instruction form of nc5, vs and fbs with its operands
  at the edges, checked, the accepted lines run on the reference interpreter and the compiled
  engine, and a sample of the forms the compiled engine writes out inline on the native
  engine (a build takes seconds): each runs or faults, none raises. In CI the walk is fixed
  (the rank-0 edges); `make fuzz` (MLC_FUZZ_EXAMPLES) walks every edge and adds random
  combinations drawn afresh.
"""

from __future__ import annotations

import os
import random

import edgewalk
import pytest

from conftest import run_mlc
from mlctool.sim.engines import native
from mlctool.sim.engines.codegen import _ARITH, _CMP, _FLOAT
from mlctool.targetapi import load_target

BUDGET = int(os.environ.get("MLC_FUZZ_EXAMPLES", "0"))

# ------------------------------------------------------------------ the repros

STATIC = [  # (target, line, code): the operand as written runs past its device, or the form is not allowed
    ("nc5", "ENCO X510 D0 K2", "E208"),  # 2^2 bits from X510: X510-X513 (4.5 API-27)
    ("nc5", "DECO K3 Y510 K3", "E208"),  # 2^3 bits from Y510 (4.5 API-26)
    ("nc5", "DMUL K0 D1 C79", "E208"),  # a 64-bit product: C79 and C80 (32 bits each)
    ("nc5", "DDIV K70000 K3 C79", "E208"),
    ("vs", "MUL D0 D0 Z7", "E208"),  # a 32-bit product: Z7, Z8
    ("vs", "DMUL D0 D0 V6", "E208"),  # V6-V9
    ("vs", "DDIV D0 K3 Z6", "E208"),
    ("vs", "ENCO X377 D0 K2", "E208"),
    ("vs", "DECO K3 Y376 K3", "E208"),
    ("vs", "ENCO S4095 D0 K3", "E208"),
    ("vs", "FLT R8 Z7", "E204"),  # a float result is a pair of D or R (5-1)
    ("vs", "DFLT D0 Z7", "E204"),
    ("vs", "FLT K1M0 R23999", "E208"),  # the float pair R23999, R24000
    ("vs", "INT R23999 R2", "E208"),
    ("vs", "SPD X2 K16 Z7", "E208"),  # D, D+1, D+2 (6-7 FNC 56)
    ("vs", "SFRD D9510 D0 K3", "E208"),  # the file of n = 3 from D9510 (6-5 FNC 39)
]


def _write(tmp_path, text: str):
    path = tmp_path / "p.il"
    path.write_text(text, "utf-8")
    return str(path)


@pytest.mark.parametrize("target, line, code", STATIC, ids=[f"{t}:{line}" for t, line, _ in STATIC])
def test_an_operand_past_its_device_is_a_check_error(tmp_path, target, line, code):
    r = run_mlc("check", "--target", target, "--no-lint", _write(tmp_path, f"LD M0\n{line}\nEND\n"))
    assert r.code == 1 and f"error[{code}]" in r.out + r.err, (r.code, r.out, r.err)


# One program of the run-time repros, each behind its own input so that one native build
# serves them all: the stimulus turns one input On.
RUNTIME_PROGRAM = """\
LD X0
MOV K-1 D1
BON D0 Y0 D1
LD X1
MOV K1 D10
MOV K32767 D11
DEBIN D10 R0
LD X6
MOV K32767 D51
DEBIN D50 R10
LD X2
SFRD D20 D30 D9510
LD X3
MOV K7 Z0
DJOGF K100 K1Y3 Y1Z0 S1
LD X4
MOV H4241 D40
PR C2 Y20
LD X5
DIV K7 K2 K4Y40
END
"""
RUNTIME = [  # (input, exit, what the output says)
    ("X0", 1, "BON: n = -1 is outside 0-15"),  # a register count out of the table's range: operation error
    ("X1", 1, "1 x 10^32767 is beyond the float range"),  # DEBIN: an operation error
    ("X6", 0, ""),  # DEBIN 0 x 10^32767 is 0 (10.0 ** 32767 overflowed)
    ("X2", 1, "SFRD: n = 0 is outside 2-512"),
    ("X3", 1, "Y1Z0 with Z0=7 addresses Y8; the instruction takes Y0-Y3 here"),
    ("X4", 0, ""),  # PR reads a counter's value (C is in its table): it runs
    ("X5", 0, ""),  # DIV into K4Y40: the quotient in Y40-Y57, the remainder in Y60-Y77
]


@pytest.mark.parametrize("engine", ["interp", "compiled", "native"])
@pytest.mark.parametrize("pin, code, says", RUNTIME, ids=[r[0] for r in RUNTIME])
def test_a_register_or_index_out_of_range_is_e604_on_every_engine(tmp_path, engine, pin, code, says):
    if engine == "native" and native.unavailable() is not None:
        pytest.skip(f"native engine: {native.unavailable()}")
    src = _write(tmp_path, RUNTIME_PROGRAM)
    expect = {"X5": "expect K4Y40=3 K4Y60=1"}.get(pin, "")
    stim = tmp_path / "s.stim"
    stim.write_text(f"scan 10ms\n0ms {pin}=1\n30ms {expect}\nrun 40ms\n" if expect else
                    f"scan 10ms\n0ms {pin}=1\nrun 40ms\n", "utf-8")
    r = run_mlc("sim", "--target", "vs", src, "--stimulus", str(stim), "--engine", engine)
    out = r.out + r.err
    assert "internal error" not in out and "Traceback" not in out, out
    assert r.code == code, (r.code, out)
    if code:
        assert "error[E604]" in out and says in out, out


# ------------------------------------------------------------------ the walk

# the ops the compiled engine writes out inline (compile.py, compile_ops.py): the native engine
# builds those into C; every other op calls the reference routine on both
INLINE_OPS = frozenset(_ARITH) | frozenset(_CMP) | frozenset(_FLOAT) | {
    "contact", "contact_not", "contact_rise", "contact_fall", "out", "set", "rst", "pls", "plf",
    "tmr", "cnt", "mov", "inc", "dec", "cml", "mul"}
NATIVE_SNIPPETS = 48  # per target: a build of about 10 s


def _walk_snippets(target):
    if BUDGET:  # make fuzz: every edge, and random combinations drawn afresh
        rnd = random.Random()
        return edgewalk.snippets(target, rnd, draws=max(1, BUDGET // 200), full=True)
    return edgewalk.snippets(target)


def _sink(target) -> str:
    """A relay the contact snippets drive: the last ordinary M (none of the edges)."""
    dev = target.devices["M"]
    area = next((a for a in dev.areas if a.write == "ok"), None)
    return f"M{(area.hi if area else dev.hi) - 1}"


@pytest.mark.parametrize("name", ["nc5", "vs", "fbs"])
def test_every_form_with_edge_operands_runs_or_faults(tmp_path, name, capsys):
    target = load_target(name)
    snips = _walk_snippets(target)
    checked = edgewalk.check_and_pack(target, snips, _sink(target), tmp_path)
    assert checked.accepted > len(snips) // 2, checked.rejected  # the walk must mostly run, not be refused
    # every form reaches the engines, or its twin does (a P-suffix form: the same routine and operands)
    ran = {(s.form.op, s.form.width, s.form.operands) for p in checked.programs for s in p.snippets}
    walked = [f for f in edgewalk.forms(target) if edgewalk.walked(f)]
    missing = [f.mnemonic for f in walked if (f.op, f.width, f.operands) not in ran]
    assert not missing, f"forms the checker refused at every edge, even at the base: {missing}"
    crashes, faults = [], 0
    for p in checked.programs:
        first = edgewalk.run_program(p, "interp")
        failing = set(first.faults) | set(first.crashes)
        # the compiled engine: the snippets that ran on the interpreter, then the ones that did not
        second = edgewalk.run_program(p, "compiled", [set(range(len(p.snippets))) - failing, failing])
        for o in (first, second):
            faults += len(o.faults)
            crashes += [f"{o.engine}: {p.snippets[i].line} after {p.snippets[i].setup}: {msg}"
                        for i, msg in o.crashes.items()]
    with capsys.disabled():
        print(f"\n{name}: {len(walked)} forms walked, {len(snips)} snippets, {checked.accepted} accepted in "
              f"{len(checked.programs)} programs, {faults} faults (E604)")
    assert not crashes, "\n".join(crashes[:40])


@pytest.mark.skipif(native.unavailable() is not None, reason=f"native engine: {native.unavailable()}")
@pytest.mark.parametrize("name", ["nc5", "vs"])
def test_the_native_engine_runs_or_faults_at_the_edges(tmp_path, name):
    """The forms the native engine builds into C (fbs has none beyond the contacts and coils
    the others cover), a fixed sample across the walk's edges, in one program per target."""
    target = load_target(name)
    inline = [s for s in _walk_snippets(target) if s.form.op in INLINE_OPS]
    step = max(1, len(inline) // NATIVE_SNIPPETS)
    checked = edgewalk.check_and_pack(target, inline[::step][:NATIVE_SNIPPETS], _sink(target), tmp_path)
    crashes = []
    for p in checked.programs:
        ran = edgewalk.run_program(p, "native")
        assert ran.ran == "native", "the native engine fell back to the compiled one"
        crashes += [f"{p.snippets[i].line} after {p.snippets[i].setup}: {msg}" for i, msg in ran.crashes.items()]
        failing = set(ran.faults) | set(ran.crashes)
        ran = edgewalk.run_program(p, "native", [set(range(len(p.snippets))) - failing, failing])
        crashes += [f"{p.snippets[i].line} after {p.snippets[i].setup}: {msg}" for i, msg in ran.crashes.items()]
    assert not crashes, "\n".join(crashes)


@pytest.mark.parametrize("name", ["nc5", "vs", "fbs"])
def test_program_flow_at_the_edges_runs_or_faults(tmp_path, name):
    """The forms the line walk leaves out (labels, jumps, calls, loops, stack and block
    operators, master control, step ladder, interrupts), in small whole programs: every such
    form is in one the checker accepts, and each of those runs or faults on both engines."""
    from mlctool.asm import program_from_paths
    from mlctool.sim.run.run import Simulation
    from mlctool.sim.scan import Fault
    from mlctool.sim.stimulus.stimulus import parse_stimulus_text

    target = load_target(name)
    covered, crashes = set(), []
    for k, text in enumerate(edgewalk.flow_programs(target)):
        path = tmp_path / f"flow{k}.il"
        path.write_text(text, "utf-8")
        image, diags, _ = program_from_paths([str(path)], target)
        if image is None or any(d.severity == "error" for d in diags):
            continue
        covered |= edgewalk.flow_forms(target, text)
        st, _ = parse_stimulus_text("s.stim", "0ms X0=1 X1=1\n", target)
        for engine in ("interp", "compiled"):
            try:
                Simulation(image, target, st, [], 10_000, [], False, engine=engine).run(3)
            except Fault:
                pass
            except Exception as e:  # noqa: BLE001 - what the walk looks for
                crashes.append(f"{engine}: {text!r}: {type(e).__name__}: {e}")
    left = {f.mnemonic for f in edgewalk.forms(target) if not edgewalk.walked(f)}
    assert left - covered - edgewalk.NOT_WALKED.get(name, set()) == set()
    assert not crashes, "\n".join(crashes)
