"""Simulator speed: mlc (compiled engine, native engine, reference interpreter) against awlsim, pyrung's
PLC.step and pyrung's CompiledPLC, with two C lower bounds (issues 5 and 19; docs/bench.md).

Method (issue 19 §1):
- Every system runs the same logic, and the bench proves it before it prints a ratio: from the
  same start state, each runs VERIFY_SCANS scans, then the compared devices (bool1000: M0-M999;
  mixed: 133 words, double words, floats and bits) must equal mlc's compiled engine's, or the
  bench exits 1 naming the differences.
- Every system is timed in this process with the same clock, time.process_time (CPU time),
  awlsim through its Python API (AwlSim.runCycle, one OB1 cycle a scan). ROUNDS interleaved
  rounds (each system in turn, so all see the same stretches of a busy machine) of BUDGET CPU
  seconds each; the table prints the median and range of scans/s, ns per mlc instruction, and
  the ratio of medians. On a shared machine the ratios of one run are the figure.
- "Instructions" are the mlc program's instructions executed per scan, for every system (the
  equivalent work; awlsim executes ~3x as many AWL statements for mixed).
- mlc's native engine (--engine native: the compiled engine's code built into a C extension by
  Cython; sim/engines/native.py) is a row of its own where Cython and a C compiler are present, built
  before the rounds (its build time printed: once per program, then kept in the user cache).
- When a C compiler (cc/gcc) is present, bool1000 is also generated as straight-line C and as a
  C switch-dispatch interpreter over (opcode, device) pairs, compiled with -O2 into a temp dir,
  verified the same way, and timed by clock() in their own process in the same rounds.

Benchmarks:
- bool1000: 200 rungs of LD Ma / ANI Mb / OR Mc / AND Md / OUT Me (1000 basic instructions,
  device numbers from a fixed seed) from random M0-M999. awlsim runs the same logic as S7 AWL
  (U( U UN O ) U =), pyrung as rungs And(Or(And(a, ~b), c), d) -> out(e).
- mixed: timers, counters, MOV/ADD/MUL, compare contacts, 32-bit and float arithmetic, Kn
  groups, V/Z indexing, FOR/NEXT, CALL and CJ; the same work in AWL and pyrung. The run bit
  M1000 (M 125.0) is on, so every system runs all of it; timer and counter inputs stay off
  (awlsim's timers run on wall time).
- batch: 1024 scenarios of bool1000 (`mlc sim --stimulus 'dir/*.stim'` as lanes), and the
  same scenarios one by one in 2 processes; 1024 scenarios of mixed-words (the straight-line
  word part of mixed) as numpy word lanes, and some of them one by one.
- compile cost: a 64k-step program (bench/gen.py) from linked image to its first scan.

Run: make bench (installs awlsim and pyrung into .venv-bench first), or
.venv-bench/bin/python bench/sim_speed.py [bool1000 mixed ...]; BENCH_ROUNDS, BENCH_BUDGET.
"""

from __future__ import annotations

import os
import random
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(__file__))

from mlctool.asm import program_from_paths  # noqa: E402
from mlctool.sim.engines.compile import compile_program  # noqa: E402
from mlctool.sim.engines.engine import Scanner, scanner  # noqa: E402
from mlctool.sim.scan import load_program  # noqa: E402
from mlctool.sim.state import Machine  # noqa: E402
from mlctool.targetapi import load_target  # noqa: E402

NC5 = load_target("nc5")
SEED = 1
UNITS = 16  # repeated units of the mixed benchmark


# ---------------------------------------------------------------------------- programs

def bool1000_rungs() -> list[tuple[int, int, int, int, int]]:
    rnd = random.Random(SEED)
    return [tuple(rnd.randrange(1000) for _ in range(5)) for _ in range(200)]


def bool1000_il() -> str:
    out = []
    for a, b, c, d, e in bool1000_rungs():
        out += [f"LD M{a}", f"ANI M{b}", f"OR M{c}", f"AND M{d}", f"OUT M{e}"]
    return "\n".join(out + ["END"]) + "\n"


def _m(k: int) -> str:
    return f"M {k // 8}.{k % 8}"


def bool1000_awl() -> str:
    out = ["ORGANIZATION_BLOCK OB 1", "BEGIN"]
    for a, b, c, d, e in bool1000_rungs():
        out += ["\tU(", f"\tU {_m(a)}", f"\tUN {_m(b)}", f"\tO {_m(c)}", "\t)", f"\tU {_m(d)}",
                f"\t= {_m(e)}"]
    return "\n".join(out + ["END_ORGANIZATION_BLOCK", ""])


def mixed_il() -> str:
    out = ["LD M1000", "MOV K3 V0", "MOV K1 Z0"]
    for u in range(UNITS):
        out += [
            f"LD M{u}", f"TMR T{u} K50",
            f"LD X{u % 8}", f"CNT C{u} K100",
            "LD M1000", f"MOV K{u} D{100 + u}", f"ADD D{100 + u} K3 D{200 + u}",
            f"MUL D{200 + u} K2 D{300 + 2 * u}",
            f"LD> D{200 + u} K10", f"OUT M{100 + u}",
            "LD M1000", f"DADD D{400 + 2 * u} K70000 D{400 + 2 * u}",
            f"FADD D{500 + 2 * u} F1.5 D{500 + 2 * u}",
            f"MOV K4M{2000 + 16 * u} D{600 + u}",
            f"MOV D{100 + u}V0 D{700 + u}Z0",
        ]
    out += ["FOR K5", "LD M1000", "INC D900", "NEXT",
            "LD M1000", "CALL P1",
            "LD M1001", "CJ P2", "LD M1000", "INC D901", "P2:",
            "FEND", "P1:", "LD M1000", "INC D902", "SRET", "END"]
    return "\n".join(out) + "\n"


def mixed_words_il() -> str:
    """The straight-line word part of mixed (no float, Kn, index or flow): numpy word lanes."""
    out = []
    for u in range(UNITS):
        out += [
            f"LD M{u}", f"TMR T{u} K50",
            f"LD X{u % 8}", f"CNT C{u} K100",
            "LD M1000", f"MOV K{u} D{100 + u}", f"ADD D{100 + u} D{800 + u} D{200 + u}",
            f"MUL D{200 + u} K2 D{300 + 2 * u}",
            f"LD> D{200 + u} K10", f"OUT M{100 + u}",
            "LD M1000", f"DADD D{400 + 2 * u} K70000 D{400 + 2 * u}", f"SUB D{200 + u} D{100 + u} D{600 + u}",
        ]
    return "\n".join(out + ["END"]) + "\n"


def mixed_awl() -> str:
    """The mixed program in S7 AWL: D words are DB1 words (DBW 2n), 32-bit pairs DBD 2n (the
    verify step compares them as values: S7 stores the high word first), K4M(2000+16u) is
    MW(250+2u), the run bit M1000 is M 125.0, V0/Z0 are MW 200/202."""
    out = ["ORGANIZATION_BLOCK OB 1", "BEGIN", "\tAUF DB 1",
           "\tU M 125.0", "\tSPBN nx0", "\tL 3", "\tT MW 200", "\tL 1", "\tT MW 202", "nx0:\tNOP 0"]
    for u in range(UNITS):
        w = lambda n: f"DBW {2 * n}"  # noqa: E731
        d = lambda n: f"DBD {2 * n}"  # noqa: E731
        out += [
            f"\tU {_m(u)}", "\tL S5T#5S", f"\tSE T {u}",
            f"\tU E 0.{u % 8}", f"\tZV Z {u}",
            "\tU M 125.0", f"\tSPBN a{u}",
            f"\tL {u}", f"\tT {w(100 + u)}",
            f"\tL {w(100 + u)}", "\tL 3", "\t+I", f"\tT {w(200 + u)}",
            f"\tL {w(200 + u)}", "\tL 2", "\t*D", f"\tT {d(300 + 2 * u)}",
            f"a{u}:\tL {w(200 + u)}", "\tL 10", "\t>I", f"\t= {_m(100 + u)}",
            "\tU M 125.0", f"\tSPBN b{u}",
            f"\tL {d(400 + 2 * u)}", "\tL L#70000", "\t+D", f"\tT {d(400 + 2 * u)}",
            f"\tL {d(500 + 2 * u)}", "\tL 1.5", "\t+R", f"\tT {d(500 + 2 * u)}",
            f"\tL MW {250 + 2 * u}", f"\tT {w(600 + u)}",
            # D(100+u)V0 -> D(700+u)Z0: pointer arithmetic on the index registers
            "\tL MW 200", f"\tL {100 + u}", "\t+I", "\tSLD 4", "\tT MD 210",
            "\tL MW 202", f"\tL {700 + u}", "\t+I", "\tSLD 4", "\tT MD 214",
            "\tL DBW [MD 210]", "\tT DBW [MD 214]",
            f"b{u}:\tNOP 0",
        ]
    out += ["\tU M 125.0", "\tSPBN f0", "\tL 5", "f1:\tT MW 220", f"\tL {'DBW 1800'}", "\t+ 1",
            "\tT DBW 1800", "\tL MW 220", "\tLOOP f1", "f0:\tNOP 0",
            "\tU M 125.0", "\tSPBN c0", "\tCALL FC 1", "c0:\tNOP 0",
            "\tU M 125.1", "\tSPB p2", "\tU M 125.0", "\tSPBN p2", "\tL DBW 1802", "\t+ 1",
            "\tT DBW 1802", "p2:\tNOP 0",
            "END_ORGANIZATION_BLOCK", "",
            "FUNCTION FC 1 : VOID", "BEGIN", "\tAUF DB 1", "\tU M 125.0", "\tSPBN s0",
            "\tL DBW 1804", "\t+ 1", "\tT DBW 1804", "s0:\tNOP 0", "END_FUNCTION", "",
            "DATA_BLOCK DB 1", "STRUCT", "\tw : ARRAY [0..999] OF INT;", "END_STRUCT;", "BEGIN",
            "END_DATA_BLOCK", ""]
    return "\n".join(out)


# ---------------------------------------------------------------------------- mlc

def build(il: str, target=NC5):
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "bench.il")
        with open(path, "w") as f:
            f.write(il)
        image, diags, _ = program_from_paths([path], target)
    errors = [d.message for d in diags if d.severity == "error"]
    if image is None or errors:
        raise SystemExit(f"benchmark program does not check: {errors[:3]}")
    return image


def executed_per_scan(image, setup) -> int:
    """Instructions the reference interpreter executes in one scan."""
    prog = load_program(image, NC5)
    m = Machine(NC5, len(prog.steps))
    setup(m)
    count = [0]
    for s in prog.steps:
        run = s.run
        s.run = (lambda r: lambda m_, s_: (count.__setitem__(0, count[0] + 1), r(m_, s_))[1])(run)
    Scanner(prog, m, "interp")()
    return count[0]


def mlc_scans_per_s(image, engine: str, setup, min_cpu: float = 1.0, target=NC5) -> tuple[float, str]:
    prog = load_program(image, target)
    m = Machine(target, len(prog.steps))
    setup(m)
    sc = Scanner(prog, m, engine)
    best = 0.0
    for _ in range(3):
        n, t0 = 0, time.process_time()
        while True:
            for _ in range(50):
                m.now_us = n * 10_000
                sc()
                n += 1
            dt = time.process_time() - t0
            if dt >= min_cpu / 3:
                break
        best = max(best, n / dt)
    return best, sc.engine



# ---------------------------------------------------------------------------- peers' programs

def pyrung_bool1000():
    try:
        from pyrung import And, Bool, Or, Program, out, rung
    except ImportError:
        return None
    m = [Bool(f"M{k}") for k in range(1000)]
    with Program(strict=False) as logic:
        for a, b, c, d, e in bool1000_rungs():
            with rung(And(Or(And(m[a], ~m[b]), m[c]), m[d])):
                out(m[e])
    return logic


def pyrung_mixed():
    try:
        from pyrung import (
            Bool,
            BoolBlock,
            Counter,
            Dint,
            Int,
            IntBlock,
            Program,
            Real,
            Timer,
            calc,
            call,
            copy,
            count_up,
            forloop,
            on_delay,
            out,
            pack_bits,
            rung,
            subroutine,
        )
    except ImportError:
        return None
    mb = [Bool(f"M{k}") for k in range(UNITS + 1)]
    x = [Bool(f"X{k}") for k in range(8)]
    run_bit, skip = Bool("M1000"), Bool("M1001")
    d = IntBlock(0, 999, name="D")
    bits = BoolBlock(0, 4095, name="MB")  # the Kn groups' bits: MB2000..
    groups = [bits.select(2000 + 16 * u, 2015 + 16 * u) for u in range(UNITS)]
    words = [Int(f"W{u}") for u in range(UNITS)]
    dints = [Dint(f"DD{u}") for u in range(UNITS)]
    prods = [Dint(f"P{u}") for u in range(UNITS)]
    reals = [Real(f"R{u}") for u in range(UNITS)]
    cmp_out = [Bool(f"M{100 + u}") for u in range(UNITS)]
    v0, z0 = Int("V0"), Int("Z0")
    timers = Timer.clone("T", count=UNITS)
    counters = Counter.clone("C", count=UNITS)
    d900, d901, d902 = Int("D900"), Int("D901"), Int("D902")
    with Program(strict=False) as logic:
        with rung(run_bit):
            copy(3, v0)
            copy(1, z0)
        for u in range(UNITS):
            with rung(mb[u]):
                on_delay(timers[u + 1], 5000)
            with rung(x[u % 8]):
                count_up(counters[u + 1], 100).reset(skip)
            with rung(run_bit):
                copy(u, d[100 + u])
                calc(d[100 + u] + 3, d[200 + u])
                calc(d[200 + u] * 2, prods[u])
            with rung(d[200 + u] > 10):
                out(cmp_out[u])
            with rung(run_bit):
                calc(dints[u] + 70000, dints[u])
                calc(reals[u] + 1.5, reals[u])
                pack_bits(groups[u], words[u])
                copy(d[v0 + (100 + u)], d[z0 + (700 + u)])
        with rung(run_bit):
            with forloop(5):
                calc(d900 + 1, d900)
        with rung(run_bit):
            call("sub")
        with rung(~skip, run_bit):  # CJ P2 over this rung: pyrung has no jump
            calc(d901 + 1, d901)
        with subroutine("sub"):
            with rung(run_bit):
                calc(d902 + 1, d902)
    return logic


# ---------------------------------------------------------------------------- start states

def bool1000_start() -> list[int]:
    """M0-M999 at the start of every system's run: random bits from a fixed seed (from all
    zeros the program's coils stay off, and the verify step would compare nothing)."""
    rnd = random.Random(SEED + 1)
    return [rnd.randrange(2) for _ in range(1000)]


def mixed_start() -> dict[int, int]:
    """The mixed program's bits set at the start: the run bit M1000 (M 125.0 in AWL) and
    random bits in the Kn groups K4M2000.. (MW 250.. in AWL)."""
    rnd = random.Random(SEED + 2)
    bits = {1000: 1}
    for k in range(2000, 2000 + 16 * UNITS):
        bits[k] = rnd.randrange(2)
    return bits


def mixed_names() -> list[str]:
    """The devices the verify step compares for mixed, in mlc's names."""
    names = ["V0", "Z0", "D900", "D901", "D902"]
    for u in range(UNITS):
        names += [f"D{100 + u}", f"D{200 + u}", f"D{300 + 2 * u}:d", f"M{100 + u}",
                  f"D{400 + 2 * u}:d", f"D{500 + 2 * u}:f", f"D{600 + u}", f"D{701 + u}"]
    return names


# ---------------------------------------------------------------------------- systems
#
# A system is built from the program and its start state and offers step() (one scan) and
# state() (the compared devices, by mlc name). The C bounds run in their own process and
# offer verify(n) and rate(cpu_budget) instead.

class Mlc:
    def __init__(self, image, engine: str, start: dict[int, int], names: list[str]):
        from mlctool.sim.state import parse_device_name

        self.label = {"compiled": "mlc (compiled engine)", "interp": "mlc (reference interpreter)",
                      "native": "mlc (native engine)"}[engine]
        prog = load_program(image, NC5)
        self.m = Machine(NC5, len(prog.steps))
        for k, v in start.items():
            self.m.bits["M"][k] = v
        self.scanner = scanner(prog, self.m, engine)
        if self.scanner.engine != engine:
            raise NativeMissing(getattr(self.scanner, "native_error", None) or f"{engine} engine not used")
        self.views = [(n, parse_device_name(n, NC5)) for n in names]
        self.n = 0

    def step(self) -> None:
        self.m.now_us = self.n * 10_000
        self.scanner()
        self.n += 1

    def state(self) -> dict:
        return {n: v.read(self.m) for n, v in self.views}


class NativeMissing(Exception):
    """The native engine does not run here (no Cython or C compiler): its row is left out."""


def native_system(image, start: dict[int, int], names: list[str]) -> list:
    """mlc's native engine (sim/engines/native.py) as a system, built now (the build's wall time is
    printed: it is paid once per program and kept in the user cache), or [] saying why not."""
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        system = Mlc(image, "native", start, names)
    except NativeMissing as e:
        print(f"  not measured: mlc's native engine ({e})")
        return []
    print(f"  mlc's native engine: built or loaded in {time.perf_counter() - t0:.1f} s wall, "
          f"{time.process_time() - c0:.1f} s CPU in this process (Cython; cc runs as a child process)")
    return [system]


def awlsim_modules():
    """awlsim's packages, imported in the order awlsim-test does (another order leaves names
    of its star imports undefined)."""
    import importlib

    try:
        return tuple(importlib.import_module(f"awlsim_loader.{name}") for name in ("common", "core", "awlcompiler"))
    except ImportError:
        return None


class Awlsim:
    """awlsim in this process through its Python API (what awlsim-test does, without the
    console): OB1 cycles by AwlSim.runCycle, timed with the same CPU clock as the rest."""

    label = "awlsim (in-process API)"

    def __init__(self, awl: str, start: dict[int, int], reader):
        common, core, awlcompiler = awlsim_modules()
        project = common.Project.fromProjectOrRawAwlData(awl.encode())
        parser = awlcompiler.AwlParser()
        for src in project.getAwlSources():
            parser.parseSource(src)
        self.sim = core.AwlSim()
        self.sim.reset()
        self.sim.load(parser.getParseTree())
        self.sim.build()
        self.sim.startup()
        self.cpu = self.sim.getCPU()
        flags = self.cpu.flags.getDataBytes()  # the live M memory (pure-Python core)
        for k, v in start.items():
            if 2000 <= k < 2000 + 16 * UNITS:  # Kn bit i of a group -> S7 word, high byte first
                g, i = divmod(k - 2000, 16)
                byte, bit = 250 + 2 * g + (0 if i >= 8 else 1), i % 8
            else:
                byte, bit = divmod(k, 8)
            if v:
                flags[byte] |= 1 << bit
        self.reader = reader

    def step(self) -> None:
        self.sim.runCycle()

    def state(self) -> dict:
        return self.reader(self.cpu)


def awlsim_bool1000_state(cpu) -> dict:
    flags = cpu.flags.getDataBytes()
    return {f"M{k}": (flags[k // 8] >> (k % 8)) & 1 for k in range(1000)}


def awlsim_mixed_state(cpu) -> dict:
    flags = cpu.flags.getDataBytes()
    db = cpu.getDB(1).structInstance.memory.getDataBytes()

    def w(n, signed=True):
        return int.from_bytes(db[2 * n:2 * n + 2], "big", signed=signed)

    def d(n):
        return int.from_bytes(db[2 * n:2 * n + 4], "big", signed=True)

    out = {"V0": int.from_bytes(flags[200:202], "big", signed=True),
           "Z0": int.from_bytes(flags[202:204], "big", signed=True),
           "D900": w(900), "D901": w(901), "D902": w(902)}
    for u in range(UNITS):
        out.update({
            f"D{100 + u}": w(100 + u), f"D{200 + u}": w(200 + u), f"D{300 + 2 * u}:d": d(300 + 2 * u),
            f"M{100 + u}": (flags[(100 + u) // 8] >> ((100 + u) % 8)) & 1,
            f"D{400 + 2 * u}:d": d(400 + 2 * u),
            f"D{500 + 2 * u}:f": struct.unpack(">f", bytes(db[1000 + 4 * u:1004 + 4 * u]))[0],
            f"D{600 + u}": w(600 + u), f"D{701 + u}": w(701 + u)})
    return out


class Pyrung:
    """pyrung's PLC.step (its interpreter) or CompiledPLC.step (its compiled kernel)."""

    def __init__(self, logic, compiled: bool, start: dict[str, object], reader):
        from pyrung import PLC
        from pyrung.core.compiled_plc import CompiledPLC

        self.label = "pyrung CompiledPLC" if compiled else "pyrung PLC"
        self.plc = CompiledPLC(logic) if compiled else PLC(logic)
        self.plc.patch(start)
        self.reader = reader

    def step(self) -> None:
        self.plc.step()

    def state(self) -> dict:
        return self.reader(self.plc.current_state.tags)


def pyrung_mixed_state(tags) -> dict:
    out = {"V0": tags.get("V0", 0), "Z0": tags.get("Z0", 0)}
    for n in (900, 901, 902):
        out[f"D{n}"] = tags.get(f"D{n}", 0)
    for u in range(UNITS):
        out.update({
            f"D{100 + u}": tags.get(f"D{100 + u}", 0), f"D{200 + u}": tags.get(f"D{200 + u}", 0),
            f"D{300 + 2 * u}:d": tags.get(f"P{u}", 0), f"M{100 + u}": int(tags.get(f"M{100 + u}", 0)),
            f"D{400 + 2 * u}:d": tags.get(f"DD{u}", 0), f"D{500 + 2 * u}:f": tags.get(f"R{u}", 0.0),
            f"D{600 + u}": tags.get(f"W{u}", 0), f"D{701 + u}": tags.get(f"D{701 + u}", 0)})
    return out


# ---------------------------------------------------------------------------- C bounds

C_MAIN = r"""
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
static unsigned char m[1000];
static const unsigned char start[1000] = {%(start)s};
%(body)s
int main(int argc, char **argv) {
    memcpy(m, start, sizeof m);
    if (argc > 2) {  /* verify: N scans, then the bits */
        long n = atol(argv[2]);
        for (long i = 0; i < n; i++) scan();
        for (int k = 0; k < 1000; k++) putchar('0' + m[k]);
        putchar('\n');
        return 0;
    }
    double budget = atof(argv[1]);
    long n = 0;
    clock_t t0 = clock();
    double dt;
    do {
        for (int i = 0; i < 1000; i++) scan();
        n += 1000;
        dt = (double)(clock() - t0) / CLOCKS_PER_SEC;
    } while (dt < budget);
    unsigned sum = 0;  /* the result is used, so the scans are not optimised away */
    for (int k = 0; k < 1000; k++) sum += m[k];
    printf("%%ld %%.9f %%u\n", n, dt, sum);
    return 0;
}
"""


def c_straight_line() -> str:
    lines = ["static void scan(void) {"]
    for a, b, c, d, e in bool1000_rungs():
        lines.append(f"    m[{e}] = ((m[{a}] & !m[{b}]) | m[{c}]) & m[{d}];")
    return "\n".join(lines + ["}"])


def c_switch_interpreter() -> str:
    """The program as (opcode, device) pairs and a switch over the opcode, the least an
    interpreter of it does per instruction."""
    ops = []
    for a, b, c, d, e in bool1000_rungs():
        ops += [(0, a), (1, b), (2, c), (3, d), (4, e)]
    table = ", ".join(f"{{{o}, {n}}}" for o, n in ops)
    return f"""
struct insn {{ unsigned char op; unsigned short dev; }};
static const struct insn prog[{len(ops)}] = {{{table}}};
static void scan(void) {{
    unsigned char acc = 0;
    for (const struct insn *p = prog, *end = prog + {len(ops)}; p < end; p++) {{
        switch (p->op) {{
        case 0: acc = m[p->dev]; break;
        case 1: acc &= !m[p->dev]; break;
        case 2: acc |= m[p->dev]; break;
        case 3: acc &= m[p->dev]; break;
        case 4: m[p->dev] = acc; break;
        }}
    }}
}}
"""


class CBound:
    def __init__(self, label: str, body: str, start: list[int], tmp: str, cc: str):
        self.label = label
        src = os.path.join(tmp, label.split()[0] + ".c")
        self.exe = src[:-2]
        with open(src, "w") as f:
            f.write(C_MAIN % {"start": ",".join(map(str, start)), "body": body})
        subprocess.run([cc, "-O2", "-o", self.exe, src], check=True, capture_output=True)

    def verify(self, n: int) -> dict:
        out = subprocess.run([self.exe, "v", str(n)], check=True, capture_output=True, text=True).stdout
        return {f"M{k}": int(ch) for k, ch in enumerate(out.strip())}

    def rate(self, budget: float) -> float:
        n, dt, _ = subprocess.run([self.exe, str(budget)], check=True, capture_output=True,
                                  text=True).stdout.split()
        return int(n) / float(dt)


def c_compiler() -> str | None:
    return shutil.which("cc") or shutil.which("gcc")


# ---------------------------------------------------------------------------- verify and time

VERIFY_SCANS = 50


def same(a, b) -> bool:
    if isinstance(a, float) or isinstance(b, float):
        return a == b or (a != a and b != b)
    return int(a) == int(b)


def verify(name: str, systems: list, reference, scans: int = VERIFY_SCANS) -> None:
    """Every system runs `scans` scans from the same start; any device that differs from mlc's
    compiled engine fails the bench before a ratio is printed."""
    for s in [reference, *systems]:
        if not hasattr(s, "verify"):
            for _ in range(scans):
                s.step()
    want = reference.state()
    for s in systems:
        got = s.verify(scans) if hasattr(s, "verify") else s.state()
        diff = [(k, want[k], got.get(k)) for k in want if not same(want[k], got.get(k))]
        if diff:
            print(f"\n{name}: VERIFY FAILED: {s.label} differs from {reference.label} after {scans} scans "
                  f"in {len(diff)} of {len(want)} devices, e.g. "
                  + ", ".join(f"{k}: {a} vs {b}" for k, a, b in diff[:8]))
            raise SystemExit(1)
    print(f"\n{name}: verified: {len(systems) + 1} systems agree on {len(want)} devices after {scans} "
          f"scans from the same start")


def scans_per_s(system, budget: float) -> float:
    if hasattr(system, "rate"):
        return system.rate(budget)
    step = system.step
    n, t0 = 0, time.process_time()
    while True:
        for _ in range(10):
            step()
        n += 10
        dt = time.process_time() - t0
        if dt >= budget:
            return n / dt


ROUNDS = int(os.environ.get("BENCH_ROUNDS", "5"))
BUDGET = float(os.environ.get("BENCH_BUDGET", "0.3"))  # CPU s per system per round


def timed_table(name: str, instrs: int, systems: list) -> dict[str, float]:
    """Interleaved rounds (each system in turn, ROUNDS times, so all see the same stretches of
    a busy machine); the median and range of each system's scans/s, ratios of medians."""
    rates: dict[str, list[float]] = {s.label: [] for s in systems}
    for _ in range(ROUNDS):
        for s in systems:
            rates[s.label].append(scans_per_s(s, BUDGET))
    med = {k: statistics.median(v) for k, v in rates.items()}
    ref = med[systems[0].label]
    print(f"  {instrs} mlc instructions executed per scan; CPU time, {ROUNDS} interleaved rounds of "
          f"{BUDGET} s per system; median (min-max)")
    print(f"  {'system':<30}{'scans/s':>12}{'range':>22}{'ns/instr':>10}{'mlc compiled / this':>21}")
    for s in systems:
        v = rates[s.label]
        print(f"  {s.label:<30}{med[s.label]:>12,.0f}{f'{min(v):,.0f}-{max(v):,.0f}':>22}"
              f"{1e9 / (med[s.label] * instrs):>10.2f}{ref / med[s.label]:>20.2f}x")
    return med


def goals(med: dict[str, float], ref: str, wanted) -> None:
    """Issue 19's goals for mlc's engines (compiled, and native where it ran), as ratios of
    this run's medians."""
    for engine in (ref, "mlc (native engine)"):
        parts = [f"{med[engine] / med[peer]:.1f}x {peer} (goal >= {g}x)"
                 for peer, g in wanted if peer in med and engine in med]
        if parts:
            print(f"  goals: {engine} is " + "; ".join(parts))


def bench_bool1000() -> None:
    image = build(bool1000_il())
    instrs = executed_per_scan(image, lambda m: None)
    bits = bool1000_start()
    start = dict(enumerate(bits))
    names = [f"M{k}" for k in range(1000)]

    def make():
        systems = [Mlc(image, "compiled", start, names), Mlc(image, "interp", start, names),
                   *native_system(image, start, names)]
        if awlsim_modules() is not None:
            systems.append(Awlsim(bool1000_awl(), start, awlsim_bool1000_state))
        logic = pyrung_bool1000()
        if logic is not None:
            named = {f"M{k}": bool(v) for k, v in start.items()}
            systems += [Pyrung(logic, False, named, lambda t: {n: int(t.get(n, 0)) for n in names}),
                        Pyrung(logic, True, named, lambda t: {n: int(t.get(n, 0)) for n in names})]
        return systems

    with tempfile.TemporaryDirectory() as tmp:
        systems = make()
        cc = c_compiler()
        if cc is not None:
            systems += [CBound("C straight-line (lower bound)", c_straight_line(), bits, tmp, cc),
                        CBound("C switch interpreter (bound)", c_switch_interpreter(), bits, tmp, cc)]
        verify("bool1000", systems[1:], systems[0])
        missing = [p for p, ok in (("awlsim", awlsim_modules()), ("pyrung", pyrung_bool1000()), ("cc", cc))
                   if ok is None]
        if missing:
            print(f"  not measured (not installed): {', '.join(missing)}")
        med = timed_table("bool1000", instrs, systems)
        goals(med, systems[0].label, (("pyrung CompiledPLC", 10), ("awlsim (in-process API)", 100)))


def bench_mixed() -> None:
    image = build(mixed_il())
    start = mixed_start()

    def setup(m):
        for k, v in start.items():
            m.bits["M"][k] = v
    instrs = executed_per_scan(image, setup)
    names = mixed_names()
    systems = [Mlc(image, "compiled", start, names), Mlc(image, "interp", start, names),
               *native_system(image, start, names)]
    if awlsim_modules() is not None:
        systems.append(Awlsim(mixed_awl(), start, awlsim_mixed_state))
    logic = pyrung_mixed()
    if logic is not None:
        named = {("M1000" if k == 1000 else f"MB{k}"): bool(v) for k, v in start.items()}
        systems += [Pyrung(logic, False, named, pyrung_mixed_state),
                    Pyrung(logic, True, named, pyrung_mixed_state)]
    verify("mixed", systems[1:], systems[0])
    med = timed_table("mixed", instrs, systems)
    goals(med, systems[0].label, (("pyrung CompiledPLC", 50),))


def bench_compile() -> None:
    from gen import program

    image = build(program(64000))
    t0 = time.perf_counter()
    prog = load_program(image, NC5)
    t1 = time.perf_counter()
    compile_program(prog)
    t2 = time.perf_counter()
    m = Machine(NC5, len(prog.steps))
    sc = Scanner(prog, m)
    sc()
    t3 = time.perf_counter()
    assert sc.engine == "compiled"
    n, c0 = 0, time.process_time()
    while time.process_time() - c0 < 1.0:
        m.now_us = (n + 1) * 10_000
        sc()
        n += 1
    rate = n / (time.process_time() - c0)
    print(f"\ncompile cost, 64k-step program ({len(prog.steps)} instructions, {image.total_steps} steps): "
          f"decode {t1 - t0:.2f} s, compile {t2 - t1:.2f} s, bind + first scan {t3 - t2:.3f} s; "
          f"image to first scan {t3 - t0:.2f} s (goal: 1-2 s); then {rate:,.0f} scans/s")


def bench_vs() -> None:
    """The Vigor VS target on both engines: bool1000's rungs, and the same with a 100 ms timer
    and a counter per rung (OUT T / OUT C with the VS preset rules)."""
    vs = load_target("vs")
    timed = []
    for k, (a, b, c, *_) in enumerate(bool1000_rungs()[:100]):
        timed += [f"LD M{a}", f"ANI M{b}", f"OUT T{k} K50", f"LD M{c}", f"OUT C{k} K10"]
    for name, il in (("bool1000", bool1000_il()), ("timers+counters", "\n".join(timed) + "\nEND\n")):
        image = build(il, vs)
        c, engine = mlc_scans_per_s(image, "compiled", lambda m: None, target=vs)
        i, _ = mlc_scans_per_s(image, "interp", lambda m: None, target=vs)
        print(f"\nvs {name}: compiled engine ({engine}) {c:,.0f} scans/s, reference interpreter "
              f"{i:,.0f} scans/s: {c / i:.1f}x")


def main() -> None:
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} cores; CPU-time figures")
    # (the batch figures are bench/batch_speed.py's, which verifies its ratios)
    which = sys.argv[1:] or ["bool1000", "mixed", "compile", "vs"]
    for name in which:
        {"bool1000": bench_bool1000, "mixed": bench_mixed, "compile": bench_compile,
         "vs": bench_vs}[name]()


if __name__ == "__main__":
    main()
