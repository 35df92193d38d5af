"""The virtual NC's cost: `mlc sim` of an NC5 machine program with `model nc5` against the same
program with the NC's flags played by a stimulus (issue 27: at least half the scans per second).

Method (as bench/sim_speed.py):
- The program is a small machine: the cycle restarts at every M30, the M/S/T handshake with
  coolant and spindle, a tool change that turns the magazine until D3x039 is 0, a part
  counter, and PANEL rungs of operator-panel logic (the rest of a real machine's program).
- Run A has the virtual NC (`model nc5 program=part.nc`). Run B has no model: its stimulus sets,
  at the scans A's NC wrote them, every NC -> MLC relay and register the program reads (taken
  from A's trace). Before any timing, the bench checks that A and B leave every device the
  program writes with the same value after SCANS scans, or exits 1 naming the differences.
- Both run through mlctool.sim.run.run.Simulation (what `mlc sim` runs) on the compiled engine, timed
  with time.process_time (CPU time) in ROUNDS interleaved rounds; the table prints the median
  scans/s of each and the ratio of the medians.

Run: python bench/nc5_speed.py; BENCH_ROUNDS (default 5), BENCH_SCANS (default 6000).
"""

from __future__ import annotations

import os
import random
import statistics
import sys
import tempfile
import time

from mlctool.asm import program_from_paths
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


def build(tmp: str):
    path = os.path.join(tmp, "machine.il")
    with open(path, "w", encoding="utf-8") as f:
        f.write(machine_il())
    image, diags, _ = program_from_paths([path], NC5)
    assert image is not None, [d.message for d in diags]
    with open(os.path.join(tmp, "part.nc"), "w", encoding="utf-8") as f:
        f.write(PART)
    return image


def nc_side(view) -> bool:
    """A relay or register the NC writes: M3c..., D3c..., D49c.. (5.1)."""
    return view.kind in "MD" and (30000 <= view.number <= 38999 or 49000 <= view.number <= 49899)


def simulation(image, stim_path: str, stim: str, trace: bool = False, watch=()) -> Simulation:
    st, diags = parse_stimulus_text(stim_path, stim, NC5)
    assert not diags, [d.message for d in diags]
    models, mdiags = build_models(st, NC5)
    assert not mdiags, [d.message for d in mdiags]
    return Simulation(image, NC5, st, models, PERIOD_US, list(watch), trace, engine="compiled")


def played_stimulus(image, tmp: str) -> str:
    """Run A once with its NC-side devices traced: the stimulus that plays them in run B."""
    sim = simulation(image, os.path.join(tmp, "a.stim"), "model nc5 program=part.nc\n0ms X0=1\n10ms X0=0\n")
    nc = sorted((v for v in sim.views if nc_side(v)), key=lambda v: v.sort_key())
    sim = simulation(image, os.path.join(tmp, "a.stim"), "model nc5 program=part.nc\n0ms X0=1\n10ms X0=0\n",
                     trace=True, watch=nc)
    r = sim.run(SCANS)
    index = {i: v for i, v in enumerate(r.views) if nc_side(v)}
    lines = ["0ms X0=1", "10ms X0=0"]
    for t, changes in r.trace:
        sets = [f"{index[i].name}={int(v)}" for i, v in changes if i in index]
        if sets:
            lines.append(f"#{t // PERIOD_US} " + " ".join(sets))
    return "\n".join(lines) + "\n"


def outcome(sim: Simulation) -> dict[str, int]:
    r = sim.run(SCANS)
    return {v.name: r.devices[v.name] for v in r.views if not nc_side(v) and not v.kind.startswith("@")}


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        image = build(tmp)
        played = played_stimulus(image, tmp)
        a_stim = "model nc5 program=part.nc\n0ms X0=1\n10ms X0=0\n"
        a = outcome(simulation(image, os.path.join(tmp, "a.stim"), a_stim))
        b = outcome(simulation(image, os.path.join(tmp, "b.stim"), played))
        differ = sorted(k for k in a.keys() | b.keys() if a.get(k) != b.get(k))
        if differ:
            print(f"the two runs differ after {SCANS} scans: " +
                  ", ".join(f"{k} {a.get(k)} / {b.get(k)}" for k in differ[:10]))
            return 1
        parts = a.get("C0:w", a.get("C0", 0))
        steps = len(program_devices(simulation(image, os.path.join(tmp, "b.stim"), played).prog))
        print(f"same work: {SCANS} scans of {PERIOD_US // 1000} ms, {len(a)} program devices equal, "
              f"{parts} parts machined; {played.count(chr(10))} stimulus lines play the NC; "
              f"{steps} devices in the program")
        rates: dict[str, list[float]] = {"virtual NC": [], "flags by stimulus": []}
        for _ in range(ROUNDS):
            for name, path, stim in (("virtual NC", "a.stim", a_stim), ("flags by stimulus", "b.stim", played)):
                sim = simulation(image, os.path.join(tmp, path), stim)
                t0 = time.process_time()
                sim.run(SCANS)
                rates[name].append(SCANS / (time.process_time() - t0))
        med = {k: statistics.median(v) for k, v in rates.items()}
        for k, v in rates.items():
            print(f"{k:>18}: {med[k]:9,.0f} scans/s (median of {ROUNDS}; {min(v):,.0f}-{max(v):,.0f})")
        ratio = med["virtual NC"] / med["flags by stimulus"]
        print(f"virtual NC / flags by stimulus = {ratio:.2f} (issue 27 asks at least 0.50)")
        return 0 if ratio >= 0.5 else 1


if __name__ == "__main__":
    sys.exit(main())
