"""Exit codes are the same for the same kind of failure in every command (docs/reliability.md,
"Exit codes"; issue 21 item 16)."""

from __future__ import annotations

import os
import signal
import subprocess
import time

import pytest

from conftest import MLC_COMMAND, SAMPLES, run_mlc

COMMANDS = [["check"], ["fmt"], ["ladder"], ["build", "-o", "x.mlx"], ["sim"], ["import"]]
UNREADABLE = {
    "missing.il": None,                      # E100
    "binary.il": b"LD X0\n\x00\x01OUT Y0\n",  # E101
    "latin1.il": b"LD X0\nOUT Y0 ; \xe9\n",   # E102
}


@pytest.mark.parametrize("command", COMMANDS, ids=lambda c: c[0])
@pytest.mark.parametrize("name", sorted(UNREADABLE))
def test_unreadable_input_exits_2_from_every_command(tmp_path, command, name):
    """check/fmt/ladder/build gave 1 for a binary or non-UTF-8 source, sim and import 2."""
    if UNREADABLE[name] is not None:
        (tmp_path / name).write_bytes(UNREADABLE[name])
    r = run_mlc(*command, name, cwd=tmp_path)
    assert r.code == 2, (r.code, r.err)
    assert not (tmp_path / "x.mlx").exists()


@pytest.mark.parametrize("command", [["check"], ["fmt", "--check"], ["ladder"], ["build", "-o", "x.mlx"]],
                         ids=lambda c: c[0])
def test_errors_in_a_readable_source_exit_1(tmp_path, command):
    (tmp_path / "bad.il").write_text("LD X0\nFOO Y0\nEND\n")
    assert run_mlc(*command, "bad.il", cwd=tmp_path).code == 1


def test_ctrl_c_exits_130_and_leaves_no_partial_output(tmp_path):
    """SIGINT during a long simulation: exit 130 (128 + SIGINT), not 2; the VCD being
    streamed is removed, no older file is touched."""
    (tmp_path / "c.il").write_text((SAMPLES / "nc5" / "conveyor.il").read_text())
    (tmp_path / "w.vcd").write_text("older waveform\n")
    proc = subprocess.Popen([*MLC_COMMAND, "sim", "c.il", "--scans", "100000000", "--vcd", "w.vcd"],
                            cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + 60
        # the streamed VCD's temporary file appears when the run has started
        while not any(p.name.startswith(".mlc-") for p in tmp_path.iterdir()):
            assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
            time.sleep(0.05)
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, err
    assert "interrupted" in err and "Traceback" not in err
    assert (tmp_path / "w.vcd").read_text() == "older waveform\n"
    assert not [p for p in os.listdir(tmp_path) if p.startswith(".mlc-")]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
@pytest.mark.parametrize("command", [["check"], ["fmt"], ["ladder"], ["build", "-o", "x.mlx"], ["sim"],
                                     ["import"], ["objdump"], ["sim", "c.il", "--stimulus"]],
                         ids=lambda c: " ".join(c))
def test_a_fifo_is_refused_not_read_forever(tmp_path, command):
    """`mlc check` on a FIFO blocked forever (issue 21 item 14): anything but a regular file
    is E100, exit 2. A subprocess, so a regression fails by its timeout instead of hanging."""
    (tmp_path / "c.il").write_text("LD X0\nOUT Y0\nEND\n")
    os.mkfifo(tmp_path / "f.il")
    done = subprocess.run([*MLC_COMMAND, *command, "f.il"], cwd=tmp_path, capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 2, done.stderr
    assert "E100" in done.stderr and "not a regular file" in done.stderr


def test_mlc_toml_globs_stay_inside_the_project(tmp_path):
    """`tests = ["/**"]` walked the whole disk; patterns leaving the project are refused."""
    (tmp_path / "c.il").write_text("LD X0\nOUT Y0\nEND\n")
    (tmp_path / "t.stim").write_text("0ms X0=1\n10ms expect Y0=1\n")
    for pattern in ["/**", "/tmp/*.stim", "../*.stim", "tests/../../*.stim"]:
        (tmp_path / "mlc.toml").write_text(f'sources = ["c.il"]\ntests = [{pattern!r}]\n'.replace("'", '"'))
        r = run_mlc("test", cwd=tmp_path)
        assert r.code == 2 and "E105" in r.err and "leaves the project" in r.err, (pattern, r.err)
    (tmp_path / "mlc.toml").write_text('sources = ["c.il"]\ntests = ["**/*.stim"]\n')
    assert run_mlc("test", cwd=tmp_path).code == 0


@pytest.mark.parametrize("command, flag", [(["run"], "--scan-time"), (["run"], "--duration"),
                                           (["debug"], "--scan-time"), (["verify"], "--max-wall"),
                                           (["sim"], "--max-wall"), (["sim"], "--scan-time")], ids=lambda c: " ".join(c) if isinstance(c, list) else c)
@pytest.mark.parametrize("value, said", [("0ms", "must be positive"), ("soon", "")])
def test_a_duration_option_that_is_not_a_positive_time_is_a_usage_error(tmp_path, command, flag, value, said):
    """cli.common.positive_time, one rule for every command's duration option: exit 2 naming the
    option, before any input is read (p.il does not exist)."""
    r = run_mlc(*command, flag, value, "p.il", cwd=tmp_path)
    assert r.code == 2 and flag in r.err and said in r.err, (r.code, r.err)
    assert "E100" not in r.err
