"""The virtual NC's cost: `mlc sim` of an NC5 machine program with `model nc5` against the same
program with the NC's flags played by a stimulus (issue 27: at least half the scans per second).

Method (as bench/sim_speed.py), for two machine programs:
- "bench machine": a small machine: the cycle restarts at every M30, the M/S/T handshake with
  coolant and spindle, a tool change that turns the magazine until D3x039 is 0, a part
  counter, and PANEL rungs of operator-panel logic (the rest of a real machine's program).
- "nc5-mill": the flagship project samples/nc5-mill (its mlc.toml's sources and [symbols],
  built as `mlc test` builds them) on its scenario tests/slot_setup.stim (its longest: the
  slot with rapids at 25 %, a tool change), its `expect` lines dropped and the cycle started
  again after every M30 (a part every MILL_CYCLE_MS) until SCANS scans.
- Run A has the virtual NC (the `model nc5 ... program=...` line). Run B has no model: its
  stimulus is A's without the model line, plus, at the scans A's NC wrote them, every NC -> MLC
  relay and register the program reads (taken from A's trace). Before any timing, the bench
  checks that A and B give every device the program writes (and its inputs) the same value at
  every one of SCANS scans (their traces equal), or exits 1 naming the differences.
- All run through mlctool.sim.run.run.Simulation (what `mlc sim` runs) on the compiled engine,
  timed with time.process_time (CPU time) in ROUNDS interleaved rounds (every run of both
  machines in turn); the table prints the median scans/s of each, the ratio of the medians and
  whether it meets the goal (a miss exits 0, as bench/sim_speed.py's goals do; unequal work
  exits 1).

Run: python bench/nc5_speed.py; BENCH_ROUNDS (default 5), BENCH_SCANS (default 6000).
"""

from __future__ import annotations

import os
import platform
import random
import re
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass

from mlctool.asm import program_from_paths
from mlctool.asm.project import project_tables
from mlctool.config import load_config
from mlctool.program import Image
from mlctool.sim.decode import program_devices
from mlctool.sim.run.run import Simulation, build_models
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targetapi import load_target

NC5 = load_target("nc5")
ROUNDS = int(os.environ.get("BENCH_ROUNDS", "5"))
SCANS = int(os.environ.get("BENCH_SCANS", "6000"))
PERIOD_US = 10_000
PANEL = 60  # rungs of 5 instructions: the operator panel and interlocks
SEED = 1
MILL = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "samples", "nc5-mill")
MILL_SCENARIO = "tests/slot_setup.stim"
# the scenario's part ends (M3x016 falls) at 13 630 ms; a part without the tool change (T11 is
# in the spindle by then) takes 9 310 ms from cycle start: start again at these times
MILL_FIRST_START_MS = 13_700
MILL_CYCLE_MS = 9_400


@dataclass
class Case:
    """One machine program: run A's stimulus (with the model) and where its files are."""

    name: str
    image: Image
    stim_path: str  # a model's program= is relative to it
    with_model: str
    part_end: tuple[str, int]  # the NC signal and value that mark a part's end, for the report
    played: str = ""
    parts: int = 0


PART = """O0001 (a pocket, then a tool change)
G90 G00 X0 Y0 Z5.
S2000 M03
M08
G01 Z-1. F1200
X20.
Y10.
X0
Y0
G00 Z5.
M09
T5
M30
"""


def machine_il() -> str:
    rnd = random.Random(SEED)
    panel = []
    for _ in range(PANEL):
        a, b, c, d, e = (rnd.randrange(1000) for _ in range(5))
        panel += [f"LD M{a}", f"ANI M{b}", f"OR M{c}", f"AND M{d}", f"OUT M{e + 1000}"]
    return "\n".join([
        "LDI M0", "OUT M21012", "MOV K100 D21002", "MOV K100 D21004", "MOV K50 D21006",
        "MOV K100 D21026",
        "LD M31023", "OR X0", "OUT M21000",  # the cycle again at each M30
        "LD M31064", "AND= D31048 K3", "SET M2000",
        "LD M31064", "AND= D31048 K5", "RST M2000",
        "LD M2000", "OUT M21704",
        "LD M31064", "AND= D31048 K8", "SET Y0",
        "LD M31064", "AND= D31048 K9", "RST Y0",
        "LD M31066", "AND<> D31039 K0", "ANI M21064", "OUT M21064",  # count pots
        "LD M31066", "AND= D31039 K0", "OUT M21066",  # exchange
        "LD M31064", "AND M31704", "OR M31065", "LD M31066", "AND= D31039 K0", "ORB", "OUT M21016",
        "LD M31023", "CNT C0 K9999",
        "LD M31704", "MOV D31026 D100",
        *panel,
        "END",
    ]) + "\n"


def machine_case(tmp: str) -> Case:
    path = os.path.join(tmp, "machine.il")
    with open(path, "w", encoding="utf-8") as f:
        f.write(machine_il())
    image, diags, _ = program_from_paths([path], NC5)
    assert image is not None, [d.message for d in diags]
    with open(os.path.join(tmp, "part.nc"), "w", encoding="utf-8") as f:
        f.write(PART)
    return Case("bench machine", image, os.path.join(tmp, "a.stim"),
                "model nc5 program=part.nc\n0ms X0=1\n10ms X0=0\n", ("M31023", 1))


def mill_case() -> Case:
    """The flagship project, built as `mlc test` builds it (sources and [symbols] of mlc.toml)."""
    here = os.getcwd()
    os.chdir(MILL)
    try:
        config = load_config(explicit="mlc.toml")
        assert not project_tables(config), "the bench preloads no register tables"
        image, diags, _ = program_from_paths(config.data["sources"], NC5, config)
    finally:
        os.chdir(here)
    assert image is not None, [d.message for d in diags if d.severity == "error"]
    stim_path = os.path.join(MILL, MILL_SCENARIO)
    with open(stim_path, encoding="utf-8") as f:
        scenario = f.read()
    assert f"scan {PERIOD_US // 1000}ms" in scenario
    keep = [ln for ln in scenario.splitlines() if not re.match(r"\s*(\S+\s+expect\b|run\b)", ln)]
    for t in range(MILL_FIRST_START_MS, SCANS * PERIOD_US // 1000, MILL_CYCLE_MS):
        keep += [f"{t}ms X1=1", f"{t + 10}ms X1=0"]  # cycle start again after M30
    return Case("nc5-mill", image, stim_path, "\n".join(keep) + "\n", ("M31016", 0))


def nc_side(view) -> bool:
    """A relay or register the NC writes: M3c..., D3c..., D49c.. (5.1)."""
    return view.kind in "MD" and (30000 <= view.number <= 38999 or 49000 <= view.number <= 49899)


def simulation(case: Case, stim: str, trace: bool = False, watch=()) -> Simulation:
    st, diags = parse_stimulus_text(case.stim_path, stim, NC5)
    assert not diags, [d.message for d in diags]
    models, mdiags = build_models(st, NC5)
    assert not mdiags, [d.message for d in mdiags]
    return Simulation(case.image, NC5, st, models, PERIOD_US, list(watch), trace, engine="compiled")


def play(case: Case) -> None:
    """Run A once with its NC-side devices traced: run B's stimulus is A's without the model line,
    plus those devices set at the scans A's NC wrote them."""
    nc = sorted((v for v in simulation(case, case.with_model).views if nc_side(v)), key=lambda v: v.sort_key())
    r = simulation(case, case.with_model, trace=True, watch=nc).run(SCANS)
    index = {i: v for i, v in enumerate(r.views) if nc_side(v)}
    lines = [ln for ln in case.with_model.splitlines() if not ln.lstrip().startswith("model ")]
    flag, end_value = case.part_end
    last = None
    for t, changes in r.trace:
        sets = [(index[i].name, int(v)) for i, v in changes if i in index]
        if sets:
            lines.append(f"#{t // PERIOD_US} " + " ".join(f"{n}={v}" for n, v in sets))
        for n, v in sets:
            if n == flag:
                case.parts += last is not None and last != end_value and v == end_value
                last = v
    case.played = "\n".join(lines) + "\n"


def outcome(case: Case, stim: str) -> tuple[dict[str, int], list[tuple[int, str, int]]]:
    """The devices the program writes (and its inputs) after SCANS scans, and every change of
    them on the way: (scan, device, value)."""
    mine = [v for v in simulation(case, stim).views if not nc_side(v) and not v.kind.startswith("@")]
    r = simulation(case, stim, trace=True, watch=mine).run(SCANS)
    names = {i: v.name for i, v in enumerate(r.views) if not nc_side(v) and not v.kind.startswith("@")}
    history = [(t // PERIOD_US, names[i], int(v)) for t, changes in r.trace for i, v in sorted(changes) if i in names]
    return {n: r.devices[n] for n in names.values()}, history


def same_work(case: Case) -> bool:
    """A and B give every device the program writes the same value at every scan: say so (or
    what differs)."""
    play(case)
    (a, a_history), (b, b_history) = outcome(case, case.with_model), outcome(case, case.played)
    differ = sorted(k for k in a.keys() | b.keys() if a.get(k) != b.get(k))
    if differ:
        print(f"{case.name}: the two runs differ after {SCANS} scans: " +
              ", ".join(f"{k} {a.get(k)} / {b.get(k)}" for k in differ[:10]))
        return False
    if a_history != b_history:
        at = next(i for i, (x, y) in enumerate(zip(a_history + [None], b_history + [None])) if x != y)
        print(f"{case.name}: the two runs part at change {at}: {a_history[at:at + 1]} / {b_history[at:at + 1]}")
        return False
    steps = len(simulation(case, case.played).prog.steps)
    devices = len(program_devices(simulation(case, case.played).prog))
    played_scans = len(re.findall(r"^#\d", case.played, re.M))
    print(f"{case.name}: same work: {SCANS} scans of {PERIOD_US // 1000} ms, {len(a)} program devices "
          f"equal at every scan ({len(a_history)} changes), "
          f"{case.parts} parts machined; the NC's writes played at {played_scans} scans; "
          f"{steps} program steps, {devices} devices")
    return True


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        cases = [machine_case(tmp), mill_case()]
        if not all([same_work(c) for c in cases]):
            return 1
        runs = [(c, label, stim) for c in cases
                for label, stim in (("virtual NC", c.with_model), ("flags by stimulus", c.played))]
        rates: dict[tuple[str, str], list[float]] = {(c.name, label): [] for c, label, _ in runs}
        for _ in range(ROUNDS):
            for case, label, stim in runs:
                sim = simulation(case, stim)
                t0 = time.process_time()
                sim.run(SCANS)
                rates[case.name, label].append(SCANS / (time.process_time() - t0))
        med = {k: statistics.median(v) for k, v in rates.items()}
        print(f"python {platform.python_version()}, {os.cpu_count()} cores, load average "
              f"{os.getloadavg()[0]:.2f}; CPU time, {ROUNDS} interleaved rounds of {SCANS} scans; median (min-max)")
        print(f"{'program':<14} {'run':<18} {'scans/s':>9}  {'range':>17}  virtual NC / flags by stimulus")
        for case in cases:
            ratio = med[case.name, "virtual NC"] / med[case.name, "flags by stimulus"]
            for label in ("virtual NC", "flags by stimulus"):
                v = rates[case.name, label]
                verdict = "met" if ratio >= 0.5 else "missed"
                shown = f"{ratio:.2f} (goal >= 0.50: {verdict})" if label == "flags by stimulus" else ""
                print(f"{case.name:<14} {label:<18} {med[case.name, label]:9,.0f}  "
                      f"{f'{min(v):,.0f}-{max(v):,.0f}':>17}  {shown}")
        return 0


if __name__ == "__main__":
    sys.exit(main())
