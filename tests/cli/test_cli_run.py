"""`mlc run` (mlctool/cli/run.py): real time, the acceptance run of issue 32 (a pymodbus
client reads Y and D and writes M of a sample while its scans run), Ctrl-C, options."""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import subprocess
import time

from pymodbus.client import ModbusTcpClient

from tests.conftest import MLC_COMMAND, ROOT, SAMPLES, run_mlc

CONVEYOR = str(SAMPLES / "nc5" / "conveyor.il")


def start(*args: str) -> tuple[subprocess.Popen, int]:
    """`mlc run ... --serve modbus-tcp://127.0.0.1:0`: the process and the port it serves."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([*MLC_COMMAND, "run", *args, "--serve", "modbus-tcp://127.0.0.1:0"],
                            stderr=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env, cwd=ROOT)
    line = proc.stderr.readline()
    mt = re.search(r"on port ([0-9]+)", line)
    assert mt, line + proc.stderr.read()
    return proc, int(mt[1])


def test_an_hmi_reads_y_and_d_and_writes_m_while_scans_run():
    proc, port = start(CONVEYOR, "--duration", "20s", "--json")
    try:
        c = ModbusTcpClient("127.0.0.1", port=port, timeout=3)
        assert c.connect()
        # nc5 map: M n = coil n, Y n = discrete input 1000 + n, D n = holding register n
        assert c.read_discrete_inputs(1000, count=2, device_id=1).bits[:2] == [False, False]
        assert c.write_coil(0, True, device_id=1).bits == [True]  # M0 RUNNING: the belt runs
        deadline = time.monotonic() + 3
        while not c.read_discrete_inputs(1000, count=1, device_id=1).bits[0] and time.monotonic() < deadline:
            pass
        assert c.read_discrete_inputs(1000, count=1, device_id=1).bits[0] is True  # Y0 MOTOR
        assert c.read_holding_registers(0, count=4, device_id=1).registers == [0, 0, 0, 0]  # D0 = C0
        c.close()
    finally:
        proc.send_signal(signal.SIGINT)  # Ctrl-C: a clean stop, the figures
        out, err = proc.communicate(timeout=10)
    assert proc.returncode == 0, err
    figures = json.loads(out)
    assert figures["stats"]["scans"] > 0 and figures["servers"][0]["requests"] >= 5
    assert "stopped: scan" in err and "jitter mean" in err


def test_duration_is_plc_time_and_speed_runs_it_faster():
    started = time.monotonic()
    r = run_mlc("run", CONVEYOR, "--duration", "2s", "--speed", "20x", "--scan-time", "5ms", "--json")
    assert r.code == 0, r.err
    stats = json.loads(r.out)["stats"]
    assert stats["scans"] == 400 and stats["plc_time_s"] == 2.0
    assert 0.05 < stats["wall_s"] < 1.0 and time.monotonic() - started < 3


def test_the_stimulus_plays_and_its_expectations_decide_the_exit_code(tmp_path):
    stim = tmp_path / "s.stim"
    stim.write_text("scan 5ms\n0ms X0=1\n20ms X0=0\n50ms expect Y0=1\n60ms expect D0=7\nrun 100ms\n")
    r = run_mlc("run", CONVEYOR, "--stimulus", str(stim), "--speed", "10x")
    assert r.code == 1 and "D0" in r.err and "stopped: scan 20 " in r.err, r.err


def test_bad_options_are_e750_and_a_busy_port_e751():
    for args, words in ((["--serve", "modbus-tcp://10.0.0.1:502"], "--listen"),
                        (["--serve", "http://127.0.0.1:80"], "expected one of"),
                        (["--speed", "0x"], "--speed"), (["--speed", "fast"], "--speed"),
                        (["--allow", "Q7"], "--allow"), (["--read-only", "--allow", "M0"], "not both"),
                        (["--map", "plc5"], "maps are")):
        r = run_mlc("run", CONVEYOR, "--duration", "10ms", *args)
        assert r.code == 2 and "E750" in r.err and words in r.err, (args, r.err)
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        r = run_mlc("run", CONVEYOR, "--duration", "10ms", "--serve", f"modbus-tcp://127.0.0.1:{s.getsockname()[1]}")
    assert r.code == 2 and "E751" in r.err, r.err


def test_listen_serves_beyond_loopback_with_a_warning():
    r = run_mlc("run", CONVEYOR, "--duration", "20ms", "--listen", "0.0.0.0", "--serve", "modbus-tcp://0.0.0.0:0")
    assert r.code == 0 and "W750" in r.err, r.err


def test_alarms_are_reported_as_mlc_sim_reports_them(tmp_path):
    """mlc run said nothing of an operation error and exited 0 where mlc sim gives E604, exit 1;
    named in the stimulus (`expect alarm`), the run passes as the simulation does."""
    (tmp_path / "p.il").write_text("LD M9000\nDIV K1 D1 D0\nEND\n")
    for command in (["sim", "--scans", "3"], ["run", "--duration", "30ms", "--speed", "10x"]):
        r = run_mlc(*command, "--target", "vs", "p.il", cwd=tmp_path)
        assert r.code == 1 and "error[E604]: alarm MLC_ARITH_ERROR at 0 ms (scan 0)" in r.err, (command, r.err)
    (tmp_path / "p.stim").write_text("scan 10ms\n0ms expect alarm MLC_ARITH_ERROR\nrun 30ms\n")
    r = run_mlc("run", "--target", "vs", "p.il", "--stimulus", "p.stim", "--speed", "10x", cwd=tmp_path)
    assert r.code == 0 and "E604" not in r.err, r.err
