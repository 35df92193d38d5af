"""Simulator speed: mlc (compiled engine and reference interpreter) against awlsim and pyrung.

Benchmarks (issue 5; figures in docs/bench.md):
- bool1000: 200 rungs of LD Ma / ANI Mb / OR Mc / AND Md / OUT Me (1000 basic instructions,
  device numbers from a fixed seed). awlsim runs the same logic as S7 AWL (U( U UN O ) U =),
  pyrung as rungs And(Or(And(a, ~b), c), d) -> out(e).
- mixed: timers, counters, MOV/ADD/MUL, compare contacts, 32-bit and float arithmetic, Kn
  groups, V/Z indexing, FOR/NEXT, CALL and CJ; the same work in AWL and pyrung.
- batch: 1024 scenarios of bool1000 (`mlc sim --stimulus 'dir/*.stim'` as lanes), and the
  same scenarios one by one in 2 processes; 1024 scenarios of mixed-words (the straight-line
  word part of mixed) as numpy word lanes, and some of them one by one.
- compile cost: a 64k-step program (bench/gen.py) from linked image to its first scan.

"Basic instructions/s" counts the mlc program's executed instructions per scan for every
system (the equivalent work), times its scans/s; awlsim's own statements/s is printed too.
Times are CPU seconds of the measuring process (steadier than wall time on a shared machine);
awlsim reports its own figures (wall time, in its process).

Run: make bench (installs awlsim and pyrung into .venv first), or python bench/sim_speed.py.
"""

from __future__ import annotations

import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(__file__))

from mlctool.asm import program_from_paths  # noqa: E402
from mlctool.sim.batch import Options, run_batch  # noqa: E402
from mlctool.sim.compile import compile_program  # noqa: E402
from mlctool.sim.engine import Scanner  # noqa: E402
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
    """The mixed program in S7 AWL: D words are DB1 words (DBW 2n), Kn groups are MW."""
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
            f"\tL MW {2 + 2 * u}", f"\tT {w(600 + u)}",
            # D(100+u)V0 -> D(700+u)Z0: pointer arithmetic on the index registers
            "\tL MW 200", f"\tL {100 + u}", "\t+I", "\tSLD 4", "\tT MD 210",
            "\tL MW 202", f"\tL {700 + u}", "\t+I", "\tSLD 4", "\tT MD 214",
            "\tL DBW [MD 210]", "\tT DBW [MD 214]",
            f"b{u}:\tNOP 0",
        ]
    out += ["\tU M 125.0", "\tSPBN f0", "\tL 5", "f1:\tT MW 220", f"\tL {'DBW 1800'}", "\t+ 1",
            "\tT DBW 1800", "\tL MW 220", "\tLOOP f1", "f0:\tNOP 0",
            "\tU M 125.0", "\tSPBN c0", "\tUC FC 1", "c0:\tNOP 0",
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


# ---------------------------------------------------------------------------- peers

def awlsim_figures(awl: str) -> tuple[float, float] | None:
    """(awlsim statements/s, OB1 cycles/s) from awlsim-test's own CPU dumps (the best one)."""
    exe = shutil.which("awlsim-test", path=os.path.dirname(sys.executable)) or shutil.which("awlsim-test")
    if exe is None:
        return None
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "bench.awl")
        with open(path, "w") as f:
            f.write(awl)
        r = subprocess.run([exe, "-L", "3", "-M", "4", path], capture_output=True, timeout=120)
    text = r.stdout.decode("utf-8", "replace").replace("\r", "\n")
    speeds = re.findall(r"Speed:\s+([0-9.]+) ([kM]?) ?stmt/s", text)
    cycles = re.findall(r"OB1:\s+avg:\s+([0-9.]+) ms", text)
    if r.returncode != 0 or not speeds or not cycles:
        print(f"  awlsim-test failed (exit {r.returncode}): {text[-400:]}")
        return None
    # awlsim warms up over its run: its best dump, as mlc reports its best timing window
    stmts = max(float(value) * {"": 1, "k": 1e3, "M": 1e6}[unit] for value, unit in speeds)
    return stmts, 1000.0 / min(float(c) for c in cycles)


def pyrung_bool1000():
    try:
        from pyrung import PLC, And, Bool, Or, Program, out, rung
    except ImportError:
        return None
    m = [Bool(f"M{k}") for k in range(1000)]
    with Program(strict=False) as logic:
        for a, b, c, d, e in bool1000_rungs():
            with rung(And(Or(And(m[a], ~m[b]), m[c]), m[d])):
                out(m[e])
    return PLC(logic), None


def pyrung_mixed():
    try:
        from pyrung import (
            PLC,
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
    bits = BoolBlock(0, 4095, name="MB")
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
    def setup():
        run_bit.value = True
    return PLC(logic), setup


def pyrung_scans_per_s(built, min_cpu: float = 1.0) -> float:
    plc, setup = built
    with plc:
        if setup is not None:
            setup()
        plc.step()
        n, t0 = 0, time.process_time()
        while time.process_time() - t0 < min_cpu:
            for _ in range(5):
                plc.step()
            n += 5
        return n / (time.process_time() - t0)


# ---------------------------------------------------------------------------- report

def table(name: str, instrs: int, mlc_c: float, mlc_i: float, awl, pyr) -> None:
    print(f"\n{name}: {instrs} basic instructions executed per scan (mlc program)")
    print(f"  {'system':<28}{'scans/s':>12}{'basic instr/s':>16}{'mlc compiled / this':>22}")
    rows = [("mlc (compiled engine)", mlc_c), ("mlc (reference interpreter)", mlc_i)]
    if awl is not None:
        rows.append((f"awlsim ({awl[0] / 1e6:.2f} M stmt/s own)", awl[1]))
    else:
        rows.append(("awlsim (not installed)", None))
    rows.append(("pyrung" if pyr is not None else "pyrung (not installed)", pyr))
    for label, sps in rows:
        if sps is None:
            print(f"  {label:<28}{'-':>12}{'-':>16}{'-':>22}")
            continue
        print(f"  {label:<28}{sps:>12,.0f}{sps * instrs / 1e6:>13.2f} M{mlc_c / sps:>21.1f}x")


def mlc_and_awlsim(image, setup, awl: str, rounds: int = 5) -> tuple[float, tuple[float, float] | None]:
    """The compiled engine and awlsim measured in turns, each system's best round: on a machine
    whose speed drifts, both see the same stretches of it."""
    best_mlc, best_awl = 0.0, None
    for _ in range(rounds):
        c, engine = mlc_scans_per_s(image, "compiled", setup)
        assert engine == "compiled"
        best_mlc = max(best_mlc, c)
        a = awlsim_figures(awl)
        if a is not None and (best_awl is None or a[1] > best_awl[1]):
            best_awl = a
    return best_mlc, best_awl


def bench_bool1000() -> None:
    image = build(bool1000_il())
    instrs = executed_per_scan(image, lambda m: None)
    c, awl = mlc_and_awlsim(image, lambda m: None, bool1000_awl())
    i, _ = mlc_scans_per_s(image, "interp", lambda m: None)
    plc = pyrung_bool1000()
    table("bool1000", instrs, c, i, awl, pyrung_scans_per_s(plc) if plc is not None else None)
    print(f"  goal: >= 30 M basic instr/s (FX3U 0.065 us/instr = 15.4 M/s): "
          f"{c * instrs / 1e6:.1f} M/s = {c * instrs * 0.065e-6:.2f}x FX3U")


def bench_mixed() -> None:
    image = build(mixed_il())

    def setup(m):
        m.bits["M"][1000] = 1
    instrs = executed_per_scan(image, setup)
    c, awl = mlc_and_awlsim(image, setup, mixed_awl())
    i, _ = mlc_scans_per_s(image, "interp", setup)
    plc = None
    try:
        plc = pyrung_mixed()
    except Exception as e:  # noqa: BLE001 - a peer's API changing must not stop the bench
        print(f"  pyrung mixed program failed to build: {e}")
    table("mixed", instrs, c, i, awl, pyrung_scans_per_s(plc) if plc is not None else None)


def bench_batch(n: int = 1024, scans: int = 1000) -> None:
    image = build(bool1000_il())
    rnd = random.Random(SEED)
    with tempfile.TemporaryDirectory() as d:
        paths = []
        for k in range(n):
            lines = [f"#{rnd.randrange(scans)} M{rnd.randrange(1000)}={rnd.randrange(2)}" for _ in range(20)]
            path = os.path.join(d, f"s{k:04}.stim")
            with open(path, "w") as f:
                f.write("\n".join(lines) + f"\nrun #{scans}\n")
            paths.append(path)
        t0 = time.perf_counter()
        c0 = time.process_time()
        scenarios, stats = run_batch(image, NC5, paths, Options())
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        work = n * scans * 1000
        print(f"\nbatch: {n} scenarios x {scans} scans of bool1000 as lanes ({stats.lanes} lanes): "
              f"{work / wall / 1e6:,.0f} M scenario-instr/s wall ({wall:.2f} s), "
              f"{work / cpu / 1e6:,.0f} M/s CPU; goal >= 300 M/s")
        few = paths[:64]
        t0 = time.perf_counter()
        run_batch(image, NC5, few, Options(), jobs=2, lanes=False)
        wall = time.perf_counter() - t0
        print(f"  same scenarios one by one, compiled engine, --jobs 2: "
              f"{len(few) * scans * 1000 / wall / 1e6:,.1f} M scenario-instr/s wall "
              f"({len(few)} scenarios in {wall:.2f} s, process start-up included)")
        assert all(s.ok for s in scenarios)


def bench_batch_words(n: int = 1024, scans: int = 1000) -> None:
    image = build(mixed_words_il())
    instrs = executed_per_scan(image, lambda m: None)
    rnd = random.Random(SEED)
    with tempfile.TemporaryDirectory() as d:
        paths = []
        for k in range(n):
            lines = [f"#{rnd.randrange(scans)} X{rnd.randrange(8)}={rnd.randrange(2)}" for _ in range(10)]
            lines += [f"#{rnd.randrange(scans)} M{rnd.randrange(17)}={rnd.randrange(2)}" for _ in range(10)]
            lines += [f"#{rnd.randrange(scans)} M1000={rnd.randrange(2)}" for _ in range(3)]
            lines += [f"#{rnd.randrange(scans)} D{800 + rnd.randrange(16)}={rnd.randrange(-30, 30)}" for _ in range(5)]
            path = os.path.join(d, f"w{k:04}.stim")
            with open(path, "w") as f:
                f.write("\n".join(lines) + f"\nrun #{scans}\n")
            paths.append(path)
        t0, c0 = time.perf_counter(), time.process_time()
        scenarios, stats = run_batch(image, NC5, paths, Options())
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        work = n * scans * instrs
        print(f"\nbatch words: {n} scenarios x {scans} scans of mixed-words ({instrs} instructions/scan: TMR, "
              f"CNT, MOV, ADD, SUB, MUL, LD>, DADD) as numpy lanes ({stats.word_lanes} lanes): "
              f"{work / wall / 1e6:,.0f} M scenario-instr/s wall ({wall:.2f} s), {work / cpu / 1e6:,.0f} M/s CPU")
        few = paths[:32]
        t0 = time.perf_counter()
        c0 = time.process_time()
        run_batch(image, NC5, few, Options(), lanes=False)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        print(f"  same scenarios one by one, compiled engine, 1 process: "
              f"{len(few) * scans * instrs / cpu / 1e6:,.1f} M scenario-instr/s CPU ({len(few)} scenarios in {wall:.2f} s)")
        assert all(s.ok for s in scenarios) and stats.word_lanes == n


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
    which = sys.argv[1:] or ["bool1000", "mixed", "batch", "words", "compile", "vs"]
    for name in which:
        {"bool1000": bench_bool1000, "mixed": bench_mixed, "batch": bench_batch,
         "words": bench_batch_words, "compile": bench_compile, "vs": bench_vs}[name]()


if __name__ == "__main__":
    main()
