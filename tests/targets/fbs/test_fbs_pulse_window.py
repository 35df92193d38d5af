"""`mlc sim --pulse-window FROM..TO`: the pulse pins as real pulse trains inside the window,
read back with vcdvcd; edges counted = pulses output in the window (DR4088 moved by as many)."""

from __future__ import annotations

import dataclasses
import os
import tempfile
from pathlib import Path

import vcdvcd
from test_fbs_cli import mlc
from test_fbs_sim import AXIS, FBS, SAMPLES

from mlctool.asm import program_from_paths
from mlctool.sim.run.run import Simulation
from mlctool.sim.run.vcd import to_vcd
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targets.fbs.files import table_preload


def rising(tv, lo_ns: int, hi_ns: int) -> int:
    n, prev = 0, "0"
    for t, v in tv:
        if lo_ns <= t < hi_ns and v == "1" and prev == "0":
            n += 1
        prev = v
    return n


def value_at(tv, t_ns: int) -> int:
    v = [val for t, val in tv if t <= t_ns][-1]
    x = int(v, 2)
    return x - (1 << 32) if x >> 31 and len(v) == 32 else x


def test_cli_window_edges_are_the_pulses_of_the_window(tmp_path):
    vcd = tmp_path / "axis.vcd"
    r = mlc("sim", "--target", "fbs", str(SAMPLES / "home_and_run.il"),
            "--table", f"R5000={SAMPLES / 'home.pos'}", "--table", f"R5100={SAMPLES / 'run.pos'}",
            "--stimulus", str(SAMPLES / "home_and_run.stim"), "--vcd", str(vcd),
            "--pulse-window", "1s..1.05s")
    assert r.returncode == 0, r.stdout + r.stderr
    v = vcdvcd.VCDVCD(str(vcd))
    lo, hi = 1_000_000_000, 1_050_000_000  # 1 ns time unit with a window
    moved = value_at(v["mlc.R4088_d"].tv, hi) - value_at(v["mlc.R4088_d"].tv, lo)
    assert moved > 500  # the table's step 1 runs forward at speed in the window
    assert rising(v["mlc.Y0"].tv, lo, hi) == moved
    assert rising(v["mlc.Y1"].tv, lo, hi) == 0
    # outside the window: per-scan levels (Y0 On while pulsing, changes only at scan times)
    assert all(t % 10_000_000 == 0 for t, _ in v["mlc.Y0"].tv if not lo <= t <= hi)


def test_cli_window_usage_errors(tmp_path):
    il = str(SAMPLES / "home_and_run.il")
    vcd = str(tmp_path / "a.vcd")
    for args in (("--pulse-window", "1s..1s", "--vcd", vcd), ("--pulse-window", "1s", "--vcd", vcd),
                 ("--pulse-window", "x..2s", "--vcd", vcd), ("--pulse-window", "0ms..1s")):
        r = mlc("sim", "--target", "fbs", il, "--scans", "2", *args)
        assert r.returncode == 2 and "--pulse-window" in r.stderr and "Traceback" not in r.stderr, r.stderr
    r = mlc("sim", str(SAMPLES.parent / "nc5" / "conveyor.il"), "--scans", "2", "--vcd", vcd,
            "--pulse-window", "0ms..1s")
    assert r.returncode == 2 and "no pulse outputs" in r.stderr and "Traceback" not in r.stderr
    assert not os.path.exists(vcd)


def simulate(mode: str, window, limit: int | None = None):
    """2000 forward pulses at 10 kHz, then 1000 reverse, on Ps0 in output mode `mode`."""
    target = dataclasses.replace(FBS, settings={**FBS.settings, "pulse_modes": [mode] * 4})
    table = "001 SPD 10000\n DRV ADR,+,2000,Ps\n GOTO NEXT\n002 SPD 10000\n DRV ADR,-,1000,Ps\n MEND\n"
    with tempfile.TemporaryDirectory() as tmp:
        il = os.path.join(tmp, "t.il")
        Path(il).write_text(AXIS, "utf-8")
        pos = os.path.join(tmp, "t.pos")
        Path(pos).write_text(table, "utf-8")
        image, diags, _ = program_from_paths([il], target)
        preload = [table_preload(f"R5000={pos}")[0]]
        st, _ = parse_stimulus_text("t.stim", "scan 10ms\n0ms M0=1\nrun 600ms\n", target)
        sim = Simulation(image, target, st, [], 10_000, [], True, preload=preload, pulse_window=window)
        if limit:
            sim.m.pin_window.limit = limit
        r = sim.run(60)
        vcd = os.path.join(tmp, "t.vcd")
        Path(vcd).write_text(to_vcd(r, image, target), "utf-8")
        return r, vcdvcd.VCDVCD(vcd)


def test_whole_run_window_in_pr_and_ab_modes():
    lo, hi = 0, 600_000_000
    r, v = simulate("PR", (0, 600_000))
    assert r.devices["R4088:d"] == 1000
    assert rising(v["mlc.Y0"].tv, lo, hi) == 3000  # every pulse on the pulse pin
    assert rising(v["mlc.Y1"].tv, lo, hi) == 1  # direction: up, then down once
    r, v = simulate("AB", (0, 600_000))
    assert rising(v["mlc.Y0"].tv, lo, hi) == rising(v["mlc.Y1"].tv, lo, hi) == 3000
    # quadrature: forward A leads B, reverse B leads A
    first_a = next(t for t, x in v["mlc.Y0"].tv if x == "1")
    first_b = next(t for t, x in v["mlc.Y1"].tv if x == "1")
    assert first_a < first_b


def test_edge_limit_stops_recording_and_flags_the_window():
    r, _ = simulate("UD", (0, 600_000), limit=100)
    assert r.pin_window.overflow and len(r.pin_window.edges) == 100
