"""`model stepper`: a stepper motor on an FBs pulse axis (mlctool/devices/stepper.py), the
conversions of FATEK FBs manual 11.5.1 and the stimulus key for the pulse output mode."""

from __future__ import annotations

import json

import pytest
from fbskit import AXIS

from conftest import run_mlc
from mlctool.devices.stepper import STEP_ANGLES, rpm_x100, travel_um

# Ps0 with the FUN141 table of tests/fbskit.py (motor unit, 1 Ut = 1 Ps): SPD 1000 Ps/s,
# 2000 pulses forward, so 2 s of travel at 1000 Hz after a short ramp.

TABLE = "001 SPD 1000\n DRV ADR,+,2000,Ps\n MEND\n"


def sim(tmp_path, stim: str, toml: str = "", *extra: str):
    (tmp_path / "mlc.toml").write_text('target = "fbs"\n' + toml, "utf-8")
    (tmp_path / "t.il").write_text(AXIS.strip() + "\n", "utf-8")
    (tmp_path / "t.pos").write_text(TABLE, "utf-8")
    (tmp_path / "t.stim").write_text(stim, "utf-8")
    return run_mlc("sim", "t.il", "--table", "R5000=t.pos", "--stimulus", "t.stim", *extra, cwd=tmp_path)


def test_rpm_is_60_f_over_n_with_n_from_the_step_angle_table():
    """11.5.1: "N（RPM） = 60 × f / n ... n：馬達轉一圈所需之脈波數（Ps/Rev）  n = 360 / θs";
    the table: 5 相 0.36° FULL 1000 HALF 2000, 0.72° 500 / 1000, 4 相 0.90° 400 / 800,
    2 相 1.80° 200 / 400."""
    assert {a: n for a, n in STEP_ANGLES.items() if "." in a and len(a) == 4} == {
        "0.36": 1000, "0.72": 500, "0.90": 400, "1.80": 200}
    for angle, n in STEP_ANGLES.items():
        assert n == round(360 / float(angle))  # n = 360 / θs
    assert rpm_x100(1000, 200) == 30000  # 1 kHz into a 2-phase 1.8° motor: 300 rpm
    assert rpm_x100(1000, 400) == 15000  # the same in HALF drive
    assert rpm_x100(7, 2000) == 21  # 0.21 rpm, truncated
    assert travel_um(2000, 200, 5000) == 50000  # 10 revolutions of a 5 mm lead: 50 mm
    assert travel_um(-3, 200, 5000) == -75


def test_signals_while_running_and_at_the_end(tmp_path):
    stim = ("scan 10ms\nmodel stepper axis=0 pulses_per_rev=200 um_per_rev=5000\n0ms M0=1\n"
            "1s expect MOT1.freq=1000 MOT1.rpm=30000\n"
            "3s expect MOT1.pulses=2000 MOT1.travel=50000 MOT1.angle=0 MOT1.rpm=0 R4088:d=2000\n")
    r = sim(tmp_path, stim)
    assert r.code == 0, r.out + r.err
    r = sim(tmp_path, stim.replace("MOT1.travel=50000", "MOT1.travel=5000"))
    assert r.code == 1 and "MOT1.travel" in r.out + r.err  # the expectation can fail


def test_half_drive_and_json_output(tmp_path):
    stim = ("scan 10ms\nmodel stepper axis=0 step_angle=0.72 drive=half name=Z\n0ms M0=1\n"
            "1s expect Z.rpm=6000\nrun 1250ms\n")
    r = sim(tmp_path, stim, "", "--json", "--watch", "Z.pulses", "--watch", "Z.angle")
    assert r.code == 0, r.out + r.err
    devices = json.loads(r.out)["devices"]
    pulses, angle = devices["Z.pulses"], devices["Z.angle"]
    assert 1000 < pulses < 2000  # mid-move, a quarter revolution and more past the first
    assert angle == pulses % 1000 * 36000 // 1000 > 0  # 0.72° HALF: 1000 Ps/Rev


def test_mode_key_overrides_the_project_pulse_mode(tmp_path):
    """11.6: "P/R 模式：Y0 送出脈波。Y1 送出方向信號；ON=上數，OFF=下數" and "U/D 模式：Y0 送出上數
    脈波。Y1 送出下數脈波": forward pulsing shows Y1 On in P/R, Off in U/D. The stimulus key
    sets the axis' mode for the run over mlc.toml `pulse_modes`."""
    run = "scan 10ms\n0ms M0=1\n500ms expect Y0=1 Y1={y1}\n"
    assert sim(tmp_path, "model stepper axis=0 mode=P/R\n" + run.format(y1=1)).code == 0
    assert sim(tmp_path, "model stepper axis=0\n" + run.format(y1=0)).code == 0  # U/D, packaged
    r = sim(tmp_path, "model stepper axis=0 mode=U/D\n" + run.format(y1=0), 'pulse_modes = ["P/R"]\n')
    assert r.code == 0, r.out + r.err
    assert sim(tmp_path, "model stepper axis=0 mode=P/R\n" + run.format(y1=0)).code == 1


@pytest.mark.parametrize("line, key", [
    ("model stepper axis=4", "axis"),
    ("model stepper axis=0 step_angle=1.5", "step_angle"),
    ("model stepper axis=0 drive=quarter", "drive"),
    ("model stepper axis=0 pulses_per_rev=200 step_angle=1.8", "step_angle"),
    ("model stepper axis=0 pulses_per_rev=0", "pulses_per_rev"),
    ("model stepper axis=0 mode=CW", "mode"),
    ("model stepper axis=0 name=9x", "name"),
    ("model stepper axis=0 lead=5", "lead"),
])
def test_bad_parameters_are_e601_at_the_key(tmp_path, line, key):
    r = sim(tmp_path, f"scan 10ms\n{line}\n0ms M0=1\n100ms expect M0=1\n")
    assert r.code == 2 and "E601" in r.err and "Traceback" not in r.err, r.err
    assert f"t.stim:2:{line.index(' ' + key + '=') + 2}" in r.err


def test_a_target_without_pulse_axes_says_so(tmp_path):
    (tmp_path / "t.il").write_text("LD X0\nOUT Y0\nEND\n", "utf-8")
    (tmp_path / "t.stim").write_text("model stepper axis=0\n10ms expect Y0=0\n", "utf-8")
    r = run_mlc("sim", "t.il", "--target", "nc5", "--stimulus", "t.stim", cwd=tmp_path)
    assert r.code == 2 and "E601" in r.err and "no pulse output axes" in r.err, r.err
