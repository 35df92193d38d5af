"""Deterministic generator of large, valid, warning-free NC5 programs for the benchmarks."""

from __future__ import annotations

import itertools
import os
import random
import shutil
import subprocess
import sys
import time

# (template, steps); {o} is a fresh coil, {t} a fresh timer, {p} a fresh 32-bit pair, {w} a fresh word
RUNGS = [
    ("LD X{a}\nANI M{b}\nOR M{c}\nAND M{d}\nOUT M{o}\n", 5),
    ("LD M{a}\nTMR T{t} K{k}\n", 4),
    ("LD= D{w} K{k}\nMOV K{k} D{w2}\n", 8),
    ("LDP X{a}\nADD D{w} K1 D{w2}\n", 8),
    ("LD M{a}\nMPS\nAND M{b}\nOUT M{o}\nMPP\nANI M{d}\nOUT M{o2}\n", 7),
    ("LD X{a}\nOR M{b}\nLD M{c}\nORI M{d}\nANB\nDMOV K70000 D{p}\n", 11),
]


def program(steps: int, seed: int = 1) -> str:
    """A main program of about `steps` steps, ending with END, that `mlc check` passes cleanly."""
    rnd = random.Random(seed)
    coils = itertools.count(1000)
    timers = itertools.count(0)
    pairs = itertools.count(0, 2)  # D0, D2, ... : pairs never overlap
    words = itertools.count(3000)  # 16-bit words, apart from the pairs below D3000
    out = ["; generated benchmark program\n"]
    total = 0
    while total < steps - 1:
        k = rnd.randrange(len(RUNGS))
        if k == 1 and total > steps // 2:
            k = 0  # 256 timers only
        template, n = RUNGS[k]
        t = next(timers) if k == 1 else 0
        if t > 255:
            template, n = RUNGS[0]
        vals = {c: rnd.randrange(0, 32) if c == "a" else rnd.randrange(0, 999) for c in "abcd"}
        fresh = {"o": coils, "o2": coils, "p": pairs, "w": words, "w2": words}
        vals.update({name: next(it) for name, it in fresh.items() if "{" + name + "}" in template})
        vals.update(t=t, k=rnd.randrange(1, 1000))
        out.append(template.format(**vals))
        total += n
    out.append("END\n")
    return "".join(out)


# lines that each give one or more diagnostics of different checks (syntax, operands, structure, lint)
BAD_LINES = ["FOO X0", "OUT Y99999", "LD", "MOV K1", "P1:", "LD X0 X1", "@@", "MPS", "ANB", "OUT M0",
             "LD X0", "AND D0", "CALL P7", "CJ P9", "SET M5", "DMOV K1 D1", "FOR K3", "NEXT", "SRET",
             "FEND", ".define A", ".export P1", "ADD K1 K2 K3", "RST Y99999"]


def bad_program(lines: int, seed: int = 1) -> str:
    """`lines` lines drawn from BAD_LINES, then END."""
    rnd = random.Random(seed)
    return "".join(rnd.choice(BAD_LINES) + "\n" for _ in range(lines)) + "END\n"


def mlc_command() -> str:
    """The mlc of the running interpreter's environment (the project's .venv under make), its
    package byte-compiled first."""
    byte_compiled()
    return shutil.which("mlc", path=os.path.dirname(sys.executable)) or shutil.which("mlc") or "mlc"


def byte_compiled() -> None:
    """Compile the package's modules as pip does at install. Where PYTHONDONTWRITEBYTECODE is
    set (this machine's shells set it) and the checkout was never compiled, every run would
    compile them from source (~60 ms of CPU): a cost no installed mlc pays, and one that grows
    with the package, so a whole-process figure would drift for no reason of its own."""
    import compileall

    import mlctool

    compileall.compile_dir(os.path.dirname(mlctool.__file__), quiet=1)


def timed(cmd, cwd=None) -> tuple[float, float, int]:
    """Run a whole process: (wall s, CPU s of the child, exit code). CPU time is steadier
    than wall time on a busy machine."""
    before = os.times()
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, cwd=cwd)
    wall = time.perf_counter() - t
    after = os.times()
    cpu = (after.children_user - before.children_user) + (after.children_system - before.children_system)
    return wall, cpu, r.returncode
