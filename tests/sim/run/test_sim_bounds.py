"""Virtual time is bounded, one bound for every way to ask for it, and --max-wall bounds real
time (docs/simulator.md "Bounds"; issue 21 item 12)."""

from __future__ import annotations

import pytest

from conftest import SAMPLES, run_mlc
from mlctool.sim.stimulus.stimulus import MAX_SCANS, MAX_TIME_US

CONVEYOR = (SAMPLES / "nc5" / "conveyor.il").read_text()


@pytest.fixture
def work(tmp_path):
    (tmp_path / "c.il").write_text(CONVEYOR)
    return tmp_path


@pytest.mark.parametrize("stimulus, where", [
    ("run 1000000000s\n", "run 1000000000s"),            # 10^15 us was accepted
    ("run #999999999999999\n", "run #9999"),              # scans past the --scans cap were accepted
    ("#1000000001 X0=1\n", "#1000000001"),
    ("0ms X0=1\n+500000s X0=0\n+500000s X0=1\n+1us X0=0\n", "+1us"),  # relative times added past the check
    ("scan 1us\nrun 100000s\n", "run"),                   # within the time bound, 10^11 scans
    ("scan 1us\n1000001s X0=1\n", "1000001s"),
])
def test_stimulus_past_a_bound_is_e601_before_running(work, stimulus, where):
    (work / "s.stim").write_text(stimulus)
    r = run_mlc("sim", "c.il", "--stimulus", "s.stim", cwd=work)
    assert r.code == 2 and "E601" in r.err, r.err
    assert "bound" in r.err or "at most" in r.err
    assert where.split()[0] in r.err


def test_the_bounds_themselves_are_accepted(work):
    (work / "s.stim").write_text(f"0ms X0=1\n{MAX_TIME_US}us X0=0\n")
    from mlctool.sim.stimulus.stimulus import load_stimulus
    from mlctool.targetapi import load_target

    st, diags = load_stimulus(str(work / "s.stim"), load_target("nc5"))
    assert not diags and st.events[-1].time_us == MAX_TIME_US
    (work / "s.stim").write_text(f"#{MAX_SCANS} X0=1\n")
    st, diags = load_stimulus(str(work / "s.stim"), load_target("nc5"))
    assert not diags and st.events[-1].scan == MAX_SCANS


@pytest.mark.parametrize("args", [
    ["--until", "1000000001s"],
    ["--scans", str(MAX_SCANS + 1)],
    ["--until", "100000s", "--scan-time", "1us"],
    ["--scan-time", "1000000001s"],
])
def test_options_past_a_bound_are_refused(work, args):
    r = run_mlc("sim", "c.il", *args, cwd=work)
    assert r.code == 2, r.err
    assert "bound" in r.err or "at most" in r.err or "not in the range" in r.err or "range" in r.err


def test_max_wall_stops_a_long_run_with_e607(work):
    (work / "w.vcd").write_text("older\n")
    r = run_mlc("sim", "c.il", "--scans", str(MAX_SCANS), "--max-wall", "300ms", "--vcd", "w.vcd", cwd=work)
    assert r.code == 1 and "E607" in r.err and "--max-wall 300ms" in r.err, r.err
    assert (work / "w.vcd").read_text() == "older\n"
    assert not [p for p in work.iterdir() if p.name.startswith(".mlc-")]


def test_max_wall_stops_mlc_test(work):
    (work / "t.stim").write_text(f"run #{MAX_SCANS}\n")
    (work / "mlc.toml").write_text('sources = ["c.il"]\ntests = ["*.stim"]\n')
    r = run_mlc("test", "--max-wall", "300ms", "--junit", "j.xml", cwd=work)
    assert r.code == 1 and "E607" in r.err, r.err
    assert not (work / "j.xml").exists()


def test_max_wall_unused_when_the_run_ends_first(work):
    r = run_mlc("sim", "c.il", "--scans", "10", "--max-wall", "10min", cwd=work)
    assert r.code == 0 and "E607" not in r.err
    assert run_mlc("sim", "c.il", "--max-wall", "0s", cwd=work).code == 2
    assert run_mlc("sim", "c.il", "--max-wall", "soon", cwd=work).code == 2
