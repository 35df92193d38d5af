"""`mlc debug`'s core (mlctool/debug/session.py) and its console: stepping, breakpoints,
watches, forces, time travel by checkpoints and replay, `save` as a stimulus file.

The replay-equivalence property: after any sequence of step/scan/back/run/goto/force, the
machine at a scan boundary equals a plain simulation of the same inputs (the stimulus plus
the forces, as `save` writes them) run for the same number of scans.
"""

from __future__ import annotations

import subprocess

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mlctool.debug.console import Console
from mlctool.debug.load import load_session
from mlctool.debug.session import BOUNDARY, DebugError, machine_state
from mlctool.debug.stimfile import stimulus_text
from mlctool.sim.run import Simulation, build_models
from mlctool.sim.stimulus import parse_stimulus_text
from mlctool.targets import load_target
from tests.conftest import MLC_COMMAND, SAMPLES

NC5 = load_target("nc5")
CONVEYOR = str(SAMPLES / "nc5" / "conveyor.il")
CONVEYOR_STIM = str(SAMPLES / "nc5" / "conveyor.stim")


def session(checkpoint_every: int = 4, stim: str | None = CONVEYOR_STIM):
    return load_session([CONVEYOR], stim, NC5, checkpoint_every=checkpoint_every)


def plain_state(s, stim_text: str, scans: int) -> dict:
    """The machine after `scans` scans of a plain simulation of the session's program."""
    st, diags = parse_stimulus_text("saved.stim", stim_text, NC5)
    assert not [d for d in diags if d.severity == "error"], [(d.span.line, d.message) for d in diags]
    models, _ = build_models(st, NC5)
    sim = Simulation(s.image, NC5, st, models, s.period, [], False)
    sim.run(scans)
    return machine_state(sim.m)


def test_step_walks_instructions_and_the_end_ends_the_scan():
    s = session()
    assert s.position == (0, BOUNDARY)
    s.step()
    assert s.position == (0, 1) and s.current_step().ins.mnemonic == "OR"
    n = s.scan_length(0)
    s.goto((0, BOUNDARY))
    for _ in range(n):
        s.step()
    assert s.position == (1, BOUNDARY)


def test_back_from_a_boundary_lands_on_the_scans_last_instruction():
    s = session()
    length = s.scan_length(1)
    s.goto((2, BOUNDARY))
    s.back()
    assert s.scan == 1 and s.n == length - 1 and s.current_step().ins.mnemonic == "END"


def test_line_breakpoint_hit_count_condition_and_logpoint():
    s = session()
    out: list[str] = []
    s.output = out.append
    s.add_line("conveyor.il:22", hit="3")
    stop = s.run()
    assert stop.reason == "breakpoint" and s.scan == 2 and s.current_step().ins.line == 22
    s.breakpoints.clear()
    s.add_line("27", log="C0={C0:w} X2={X2}")
    s.run(scans=2)
    assert out == ["C0=0 X2=0"] * 2  # once per scan, the line's first instruction
    s.breakpoints.clear()
    s.add_line("conveyor.il:22", condition="X2")
    stop = s.run()
    assert stop.reason == "breakpoint" and s.m.bits["X"][2] == 1


def test_condition_and_watch_stop_at_scan_ends():
    s = session()
    s.add_condition("D0 >= 2 && !Y0")
    stop = s.run()
    assert stop.reason == "condition" and s.m.words["D"][0] >= 2 and not s.m.bits["Y"][0]
    s.breakpoints.clear()
    w = s.add_watch("M1")
    before = s.m.bits["M"][1]
    stop = s.run()
    assert stop.reason == "watch" and s.m.bits["M"][1] != before and stop.breakpoints == [w.id]


def test_continue_stops_where_the_stimulus_ends():
    s = session()
    stop = s.run()
    assert stop.reason == "end" and s.scan == 1300  # `run 13s` at 10 ms


def test_force_holds_write_does_not_and_release():
    s = session(stim=None)
    s.force(s.view("X1"), 1)
    s.step_scan()
    s.step_scan()
    assert s.m.bits["X"][1] == 1
    s.release(s.view("X1"))
    s.write(s.view("D5"), 7)
    assert s.m.words["D"][5] == 7
    try:
        s.release(s.view("X1"))
    except DebugError as e:
        assert "not forced" in str(e)
    else:
        raise AssertionError("released twice")


def test_reverse_continue_goes_to_the_previous_hit():
    s = session()
    s.add_line("conveyor.il:22")
    s.run()
    s.run()
    s.run()
    assert s.scan == 2
    stop = s.reverse_continue()
    assert stop.reason == "breakpoint" and s.scan == 1 and s.current_step().ins.line == 22


def test_checkpoints_stay_bounded():
    s = session(checkpoint_every=1)
    s.max_checkpoints = 8
    s.run(scans=200)
    assert len(s.checkpoints) <= 8 + 1 and 0 in s.checkpoints
    s.goto_scan(3)
    assert s.position == (3, BOUNDARY)


def test_diff_lists_changed_devices():
    s = session()
    names = {name for name, _, _ in s.changed_between(0, 5)}
    assert {"X0", "M0", "Y0"} <= names


def test_save_writes_a_stimulus_that_replays(tmp_path):
    s = session()
    out: list[str] = []
    c = Console(s, out.append)
    for line in ("run #3", "force X1=1", "watch Y0", "continue", "release X1", "scan", f"save {tmp_path}/t.stim"):
        c.execute(line)
    text = (tmp_path / "t.stim").read_text()
    assert "#3 force X1=1" in text and "expect Y0=0" in text and f"run #{s.scan}" in text
    r = subprocess.run([*MLC_COMMAND, "sim", CONVEYOR, "--stimulus", str(tmp_path / "t.stim")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr


def test_console_pipe_script(tmp_path):
    script = "\n".join([
        "step", "print M0 T0 C0", "break 22", "continue", "rung", "back", "where",
        "break if D0 > 100 &&", "frobnicate", "print Q9", "force X0", "watch Y0", "continue",
        "back scan", "goto 3", "diff 0 20", "log conveyor.il:27 \"count={C0:w}\"", "scan",
        "breakpoints", "delete 99", "run 50ms", "reverse-continue", "help", "quit", "step",
    ]) + "\n"
    r = subprocess.run([*MLC_COMMAND, "debug", "conveyor.il", "--stimulus", "conveyor.stim"], input=script,
                       capture_output=True, text=True, timeout=60, cwd=SAMPLES / "nc5")
    assert r.returncode == 0, r.stderr
    assert "Traceback" not in r.stdout + r.stderr
    out = r.stdout
    assert "stepped to scan 0 (t=0ms), conveyor.il:17: step 2 OR RUNNING" in out
    assert "T0: contact Off, value 0 (0ms elapsed), preset 10 (1s)" in out
    assert "breakpoint #1 conveyor.il:22 at scan 0" in out
    assert " ▶    22  LDP SENSOR" in out  # the rung marks the next instruction with values
    assert "error: unknown command 'frobnicate'" in out
    assert "error: 'Q9': no device Q on target nc5" in out
    assert "error: give DEV=VALUE" in out
    assert "error: no breakpoint #99" in out
    assert "watch #2 watch Y0 (0 hits) = 0" in out  # ids go to breakpoints made, not to errors
    assert "at scan 3 (t=30ms), before the scan" in out
    assert "count=0" in out
    assert out.count("\n") > 30


def test_the_console_warns_of_unmodelled_specials_as_mlc_sim_does(tmp_path):
    """W608 (VS M9039 constant scan written) at the start of a debug session, as mlc sim says
    it; a program without such writes starts without it."""
    (tmp_path / "p.il").write_text("LD X0\nOUT M9039\nOUT Y0\nEND\n")
    (tmp_path / "q.il").write_text("LD X0\nOUT Y0\nEND\n")
    for name, warned in (("p.il", True), ("q.il", False)):
        r = subprocess.run([*MLC_COMMAND, "debug", "--target", "vs", name], input="quit\n",
                           capture_output=True, text=True, timeout=60, cwd=tmp_path)
        assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
        assert ("p.il:2:1: warning[W608]: M9039 (constant scan" in r.stderr) is warned, r.stderr


def test_bad_program_exits_2():
    r = subprocess.run([*MLC_COMMAND, "debug", "no/such.il"], capture_output=True, text=True, timeout=60,
                       input="")
    assert r.returncode == 2 and "Traceback" not in r.stderr


COMMANDS = st.one_of(
    st.tuples(st.just("step"), st.integers(1, 40)),
    st.tuples(st.just("scan"), st.integers(1, 3)),
    st.tuples(st.just("back"), st.integers(1, 30)),
    st.tuples(st.just("back scan"), st.integers(1, 2)),
    st.tuples(st.just("run"), st.integers(1, 12)),
    st.tuples(st.just("goto"), st.integers(0, 30)),
    st.tuples(st.just("force"), st.integers(0, 1)),
)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(COMMANDS, min_size=1, max_size=12))
def test_replay_equivalence(commands):
    s = session(checkpoint_every=3)
    for cmd, n in commands:
        try:
            if cmd == "step":
                for _ in range(n):
                    s.step()
            elif cmd == "scan":
                for _ in range(n):
                    s.step_scan()
            elif cmd == "back":
                for _ in range(n):
                    s.back()
            elif cmd == "back scan":
                for _ in range(n):
                    s.back_scan()
            elif cmd == "run":
                s.run(scans=n)
            elif cmd == "goto":
                s.goto_scan(min(n, s.scan + 5))
            elif cmd == "force" and s.n == BOUNDARY:  # inputs a stimulus file can say
                s.force(s.view("X1"), n)
        except DebugError:
            pass  # before scan 0
    s.step_scan()  # to a boundary, with the actions logged at the last one inside the run
    while (s.scan, BOUNDARY) in s.actions:  # (replayed on arrival: a stimulus says them at the next scan)
        s.step_scan()
    got = machine_state(s.m)
    assert got == plain_state(s, stimulus_text(s), s.scan)


def test_rung_view_says_when_the_rail_is_off(tmp_path):
    """VS 3-6: stopped inside an Off MC block, the rung view says the rail is Off (its closed
    contacts still show `conducts`: the contact is closed, the rung has no power)."""
    from mlctool.debug.rung import rung_text
    vs = load_target("vs")
    il = tmp_path / "mc.il"
    il.write_text("LD M100\nMC N0\nLD X0\nOR X1\nOUT Y0\nMCR N0\nEND\n", encoding="utf-8")
    stim = tmp_path / "mc.stim"
    stim.write_text("0ms X1=1\n", encoding="utf-8")
    s = load_session([str(il)], str(stim), vs, checkpoint_every=4)
    for _ in range(4):  # LD M100, MC N0, LD X0, OR X1: stopped before OUT Y0
        s.step()
    text = rung_text(s)
    assert "OUT Y0" in s.where() and "rail Off" in text and "conducts" in text
    s.m.bits["M"][100] = 1
    s.step_scan()
    for _ in range(4):
        s.step()
    assert "OUT Y0" in s.where() and "rail Off" not in rung_text(s)


def test_ctrl_c_ends_a_long_console_move_and_the_console_goes_on():
    """As gdb's Ctrl-C: `step 99999999` or `run #N` ends where it is, the debugger lives on."""
    import os
    import signal
    import threading

    s = session(stim=None)
    out: list[str] = []
    console = Console(s, out.append)
    for line in ("step 99999999", "scan 99999999", "run #99999999"):
        out.clear()
        timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        try:
            assert console.execute_interruptible(line)
        finally:
            timer.cancel()
        assert len(out) == 1 and out[0].startswith("interrupted at scan "), out
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # put back
    console.execute("where")
    assert out[-1] == s.where() and s.scan > 0


def test_scan_n_stops_where_a_breakpoint_fires_on_the_way(tmp_path):
    path = tmp_path / "p.il"
    path.write_text("LD X0\nADD D0 K1 D0\nEND\n")
    s = load_session([str(path)], None, NC5)
    out: list[str] = []
    console = Console(s, out.append)
    for line in ("force X0=1", "break if D0 == 2", "scan 5"):
        console.execute(line)
    assert out[-1] == "condition #1 (D0 == 2) holds at scan 2 (t=20ms), before the scan" and s.scan == 2
