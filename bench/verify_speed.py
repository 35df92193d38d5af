"""`mlc verify` speed (issue 31): the same properties on the same programs through mlctool's
engines (explicit, bit-sliced where the program allows; symbolic) and through pyrung's prover
(pyrung.core.analysis.prove: always/never), CPU time, verdicts compared before any ratio.

Method:
- Every program is written twice, as IL for mlc and with pyrung's rung builders for pyrung,
  the same logic; the bench asks both the same property and prints a ratio only when their
  verdicts agree (proven / violated); a disagreement is printed and the bench exits 1.
- CPU time (time.process_time) of deciding one property, best of ROUNDS, each engine built
  from the program inside the timed part (mlc: check, link, the search; pyrung: its prover's
  passes and search; the pyrung Program object is built once, outside).
- States/s of the explicit search: distinct states over the search's CPU time, on shift16
  and shift20 (bool-only shift registers: 65,536 and 1,048,576 reachable states).
- Start-up included: `mlc verify` as a process on each bundled property file (samples/), wall
  time per property, against the goal of 1 s.
- Properties pyrung cannot state (a response within N scans, stability) are decided by mlc
  and marked so.

Run: make bench (pyrung is installed into .venv-bench), or python bench/verify_speed.py.
BENCH_ROUNDS (default 3).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from mlctool.asm import program_from_paths  # noqa: E402
from mlctool.targetapi import load_target  # noqa: E402
from mlctool.verify.explicit import Budget, search  # noqa: E402
from mlctool.verify.props import parse_props_text  # noqa: E402
from mlctool.verify.run import prepare, verify  # noqa: E402
from mlctool.verify.symbolic import Unmodelled, model_of, prove  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROUNDS = int(os.environ.get("BENCH_ROUNDS", "3"))

PRESS = """LDP X0
OR  M0
ANI X1
AND X2
OUT M0
LD  M0
OUT Y0
LD  M0
TMR T200 K50
LD  T200
ANI X1
OUT Y1
LD  X1
OUT Y2
END
"""

INTERLOCK = """LDP X0
OR  M0
ANI X2
ANI M1
OUT M0
LDP X1
OR  M1
ANI X2
ANI M0
OUT M1
LD  M0
OUT Y0
LD  M1
OUT Y1
END
"""
INTERLOCK_BROKEN = INTERLOCK.replace("ANI M1\n", "").replace("ANI M0\n", "")


def shift(n: int) -> str:
    lines = []
    for k in range(n - 1, 0, -1):
        lines += [f"LD M{k - 1}", f"OUT M{k}"]
    return "\n".join(lines + ["LD X0", "OUT M0", f"LD M{n - 1}", "AND M0", "OUT Y0", "END"]) + "\n"


# --------------------------------------------------------------------------- pyrung's programs

def pyrung_press():
    from pyrung import Bool, Program, Timer, latch, on_delay, out, reset, rise, rung

    start, estop, guard = Bool("X0"), Bool("X1"), Bool("X2")
    ram, clamp, lamp, run = Bool("Y0"), Bool("Y1"), Bool("Y2"), Bool("M0")
    t = Timer.clone("T", count=1)[1]
    with Program(strict=False) as logic:
        with rung(rise(start)):
            latch(run)
        with rung(estop):
            reset(run)
        with rung(~guard):
            reset(run)
        with rung(run):
            out(ram)
        with rung(run):
            on_delay(t, 500)
        with rung(t.Done, ~estop):
            out(clamp)
        with rung(estop):
            out(lamp)
    return logic, {"Y0": ram, "Y1": clamp, "X2": guard, "T200": t.Done}


def pyrung_interlock(broken: bool):
    from pyrung import Bool, Program, latch, out, reset, rise, rung

    fwd_b, rev_b, stop = Bool("X0"), Bool("X1"), Bool("X2")
    fwd, rev, y0, y1 = Bool("M0"), Bool("M1"), Bool("Y0"), Bool("Y1")
    with Program(strict=False) as logic:
        with rung(rise(fwd_b), *(() if broken else (~rev,))):
            latch(fwd)
        with rung(stop):
            reset(fwd)
        with rung(rise(rev_b), *(() if broken else (~fwd,))):
            latch(rev)
        with rung(stop):
            reset(rev)
        with rung(fwd):
            out(y0)
        with rung(rev):
            out(y1)
    return logic, {"Y0": y0, "Y1": y1}


def pyrung_shift(n: int):
    from pyrung import Bool, Program, out, rung

    m = [Bool(f"M{k}") for k in range(n)]
    x0, y0 = Bool("X0"), Bool("Y0")
    with Program(strict=False) as logic:
        for k in range(n - 1, 0, -1):
            with rung(m[k - 1]):
                out(m[k])
        with rung(x0):
            out(m[0])
        with rung(m[n - 1], m[0]):
            out(y0)
    return logic, {"Y0": y0, f"M{n - 1}": m[n - 1]}


# (name, IL, property, pyrung builder, pyrung property as (never-terms)) ; None: pyrung cannot say it
CASES = [
    ("press", PRESS, "never Y0 and not X2", pyrung_press, lambda t: (t["Y0"], ~t["X2"])),
    ("press", PRESS, "never Y1 and not T200", pyrung_press, lambda t: (t["Y1"], ~t["T200"])),
    ("press", PRESS, "response X1 -> not Y0 and not Y1 within 1 scans", None, None),
    ("interlock", INTERLOCK, "never Y0 and Y1", lambda: pyrung_interlock(False), lambda t: (t["Y0"], t["Y1"])),
    ("interlock_broken", INTERLOCK_BROKEN, "never Y0 and Y1", lambda: pyrung_interlock(True),
     lambda t: (t["Y0"], t["Y1"])),
    ("shift16", shift(16), "never Y0 and not M15", lambda: pyrung_shift(16), lambda t: (t["Y0"], ~t["M15"])),
    ("shift20", shift(20), "never Y0 and not M19", lambda: pyrung_shift(20), lambda t: (t["Y0"], ~t["M19"])),
]


def mlc_decide(il: str, prop: str, engine: str):
    """(verdict, CPU seconds, states) of one property from the IL text (checked and linked inside)."""
    nc5 = load_target("nc5")
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "p.il")
        with open(path, "w", encoding="utf-8") as f:
            f.write(il)
        t0 = time.process_time()
        image, _, _ = program_from_paths([path], nc5)
        props, diags = parse_props_text("p.props", prop + "\n", nc5)
        assert not diags, diags
        space, period = prepare(image, nc5, props)
        if engine == "symbolic":
            try:
                model = model_of(image, nc5, space, period)
            except Unmodelled:
                return None
            v = prove(model, props.properties[0], Budget())
        elif engine == "auto":  # what `mlc verify` does by default
            v = verify(image, nc5, props, "auto", 5_000_000)[0][0]
        else:
            v = search(image, nc5, props.properties, space, period, Budget(5_000_000))[0]
        return v.status, time.process_time() - t0, v.stats


def pyrung_decide(build, terms):
    from pyrung.core.analysis.prove import never

    logic, tags = build()
    t0 = time.process_time()
    r = never(logic, *terms(tags), max_states=5_000_000, depth_budget=10_000)
    seconds = time.process_time() - t0
    name = type(r).__name__
    return {"Proven": "PROVEN", "Counterexample": "VIOLATED"}.get(name, "UNKNOWN"), seconds, r


def best(fn, *args):
    runs = [fn(*args) for _ in range(ROUNDS)]
    if runs[0] is None:
        return None
    return min(runs, key=lambda r: r[1])


def main() -> int:
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} cores; CPU time, best of {ROUNDS}")
    try:
        import pyrung  # noqa: F401

        have_pyrung = True
    except ImportError:
        have_pyrung = False
        print("  not measured: pyrung (not installed; make bench installs it into .venv-bench)")
    print(f"\n  {'program':<17}{'property':<48}{'mlc explicit':>16}{'mlc symbolic':>16}{'mlc auto':>16}"
          f"{'pyrung':>16}{'pyrung / auto':>14}")
    failed = False
    for name, il, prop, build, terms in CASES:
        ex = best(mlc_decide, il, prop, "explicit")
        sy = best(mlc_decide, il, prop, "symbolic")
        au = best(mlc_decide, il, prop, "auto")
        py = best(pyrung_decide, build, terms) if have_pyrung and build is not None else None
        cells = [f"{ex[0]} {ex[1] * 1000:.0f} ms", f"{sy[0]} {sy[1] * 1000:.0f} ms" if sy else "not modelled",
                 f"{au[0]} {au[1] * 1000:.0f} ms"]
        ratio = ""
        if py is not None:
            cells.append(f"{py[0]} {py[1] * 1000:.0f} ms")
            if py[0] != ex[0]:
                failed = True
                ratio = "DISAGREE"
            else:
                ratio = f"{py[1] / au[1]:.1f}x"
        else:
            cells.append("cannot say it" if build is None else "-")
        if (sy is not None and sy[0] not in (ex[0], "UNKNOWN")) or au[0] != ex[0]:
            failed = True
            ratio += " (engines disagree)"
        print(f"  {name:<17}{prop[:46]:<48}{cells[0]:>16}{cells[1]:>16}{cells[2]:>16}{cells[3]:>16}{ratio:>14}")
        if name.startswith("shift"):
            s = ex[2]
            rate = (f"explicit search: {s.states:,} states, {s.states / s.seconds:,.0f} states/s, "
                    f"{s.transitions / s.seconds:,.0f} scans/s (the search alone)")
            print(f"  {'':<17}{rate}")
    print("\n  start-up included: `mlc verify` as a process on the bundled property files")
    for program, props, target in (("samples/nc5/conveyor.il", "samples/nc5/conveyor.props", "nc5"),
                                   ("samples/vs/traffic_light.il", "samples/vs/traffic_light.props", "vs"),
                                   ("samples/verify/press.il", "samples/verify/press.props", "nc5")):
        with tempfile.TemporaryDirectory() as d:
            t0 = time.perf_counter()
            r = subprocess.run([sys.executable, "-m", "mlctool", "verify", program, "--props", props, "--target",
                                target, "--out", d, "-q"], cwd=ROOT, capture_output=True, text=True)
            wall = time.perf_counter() - t0
        n = r.stdout.count("\n") and int(r.stdout.strip().splitlines()[-1].split()[0])
        print(f"  {props:<36} {n} properties in {wall:.2f} s wall ({wall / max(n, 1):.2f} s a property), "
              f"exit {r.returncode}")
    if failed:
        print("\nVERIFY FAILED: the verdicts differ (no ratio is meaningful)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
