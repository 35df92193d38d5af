"""Model-owned signals (mlctool/sim/signals.py): `XC1.pos`, `XC1.torque` ... read directly by
stimulus expectations, --watch, JSON and the VCD; names checked against the models; read-only.
The XC100 values quote the manual 004 sentences they show."""

from __future__ import annotations

import json

import pytest

from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.controller import Point
from mlctool.devices.xc100.simmodel import signal_values

PROGRAM = "LD X0\nOUT Y1\nEND\n"  # Y1 -> IN2 SERVO
WIRED = "model xc100 in1=Y0 in2=Y1 out1=X1"


def run(mlc, tmp_path, stim: str, *args):
    (tmp_path / "p.il").write_text(PROGRAM)
    (tmp_path / "s.stim").write_text(stim)
    return mlc("sim", "p.il", "--stimulus", "s.stim", *args, cwd=tmp_path)


def test_expect_watch_json_and_vcd_read_the_signals(mlc, tmp_path):
    stim = (f"{WIRED} start=50 name=Cyl\n0ms X0=1\n"
            "100ms expect Cyl.pos=0 Cyl.servo=1 Cyl.homed=0 Cyl.alarm=0 Cyl.step=-1\nrun 200ms\n")
    r = run(mlc, tmp_path, stim, "--watch", "CYL.torque", "--json", "--vcd", "o.vcd")
    assert r.code == 0, r.err
    data = json.loads(r.out)
    assert data["devices"]["CYL.pos"] == 0 and data["devices"]["CYL.torque"] == 50  # 2.1: the
    # incremental encoder counts from 0 at power-up; the servo holds with 5 % [P]
    vcd = (tmp_path / "o.vcd").read_text()
    assert "CYL.pos" in vcd and "CYL.limit" in vcd  # every signal of the model is a waveform
    r = run(mlc, tmp_path, stim.replace("Cyl.pos=0", "Cyl.pos=1"))
    assert r.code == 1 and "CYL.pos" in r.out + r.err


def test_unnamed_models_are_xc1_xc2_in_order(mlc, tmp_path):
    stim = (f"{WIRED}\nmodel xc100 in3=Y2 out1=X2 r0515=1\n0ms X0=1\n"
            "50ms expect XC1.servo=1 XC2.servo=0\nrun 60ms\n")  # 5.3 0515H = 1: servo OFF at power-up
    r = run(mlc, tmp_path, stim)
    assert r.code == 0, r.out + r.err


@pytest.mark.parametrize("stim,code,words", [
    (f"{WIRED}\n10ms expect XC9.pos=0\n", "E602", "no model named XC9"),
    (f"{WIRED}\n10ms expect XC1.bogus=0\n", "E602", "no model signal"),
    (f"{WIRED}\n10ms XC1.pos=5\n", "E602", "cannot be set"),
    (f"{WIRED}\n10ms force XC1.alarm=1\n", "E602", "cannot be set"),
    (f"{WIRED} name=A\nmodel xc100 in2=Y1 out1=X2 name=a\n", "E601", "two models are named A"),
    (f"{WIRED} name=1x\n", "E601", "name takes"),
    ("10ms expect XC1.pos=0\n", "E602", "no model named XC1"),
])
def test_signal_names_are_checked(mlc, tmp_path, stim, code, words):
    r = run(mlc, tmp_path, stim + "run 20ms\n")
    assert r.code == 2 and code in r.err and words in r.err, r.err


def test_watch_of_a_missing_model_is_refused(mlc, tmp_path):
    r = run(mlc, tmp_path, f"{WIRED}\nrun 20ms\n", "--watch", "XC2.pos")
    assert r.code == 2 and "E602" in r.err and "<--watch>" in r.err, r.err


def test_mirror_still_writes_the_registers(mlc, tmp_path):
    stim = (f"{WIRED} mirror=D200\n0ms X0=1 Y0=1\n"
            "500ms expect D200:d=-681 XC1.pos=-681 D203=0 XC1.alarm=0\nrun 600ms\n")
    r = run(mlc, tmp_path, stim)
    assert r.code == 0, r.out + r.err


def homed(**kw) -> c.Xc100:
    dev = c.new_xc100(**kw)
    c.set_inputs(dev, 0b11)  # IN1 ORG, IN2 SERVO (3.8 defaults)
    for _ in range(2000):
        if dev.homed and dev.motion is None:
            break
        c.advance(dev, 10_000)
    c.set_inputs(dev, 0b10)
    assert dev.homed
    return dev


def test_torque_while_homing_pushes_against_the_end():
    """5.7 0907H OrgTrqLimit: "原點復歸時的扭力設定 (×0.1%) ... 當原點覆歸時撞到硬體極限需達到的
    扭力值" (the torque homing must reach at the hard end) and 090AH OrgTrqLmtTime "執行扭力原點
    復歸時，扭力到達設定時間則判定條件成立": while homing pushes against the end, XC1.torque
    shows that torque and XC1.limit the limit in force (no register or pin shows either)."""
    dev = c.new_xc100(params={0x0907: 450})
    c.set_inputs(dev, 0b11)
    seen = []
    for _ in range(600):
        c.advance(dev, 10_000)
        v = signal_values(dev)
        if dev.motion is not None and v["speed"] == 0 and v["pos"] < 0:
            seen.append((v["torque"], v["limit"], v["homed"]))
    assert seen and all(s == (450, 450, 0) for s in seen)  # pushing at the end, not homed yet
    assert dev.homed and signal_values(dev)["limit"] == 0  # at rest: no limit in force


def test_torque_of_a_push_move_at_the_workpiece():
    """4.2 +TSL and 9014H 扭力限制 "除了信號搜尋模式外，其他移動模式都受其影響"; 1004H TrqLmtStatus:
    after a torque search meets the workpiece the motor keeps pushing with the point's torque
    limit: XC1.pushing = 1, XC1.torque = XC1.limit = the point's 33.5 %."""
    dev = homed(work_mm=120.0, points={3: Point(mode=c.MODE_TSL_PLUS, speed=20, torque=335)})
    c.start_point(dev, 3)
    for _ in range(2000):
        if dev.motion is None:
            break
        c.advance(dev, 10_000)
    v = signal_values(dev)
    assert v["pushing"] == 1 and v["torque"] == 335 and v["limit"] == 335
    assert v["pos"] == 12000 and v["speed"] == 0
