"""XC100 model (manual 004): the IO sequences of ch. 7, point modes of 4.2, interlocks of
10.3, alarms and LED blinks of 10.2, the servo priority of 10.5, and virtual-time purity."""

from __future__ import annotations

import pytest

from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.controller import Point

# default assignment (3.8): IN1 ORG, IN2 SERVO, IN3 ALM_RESET, IN4 START, IN5-11 PRGSEL0-6
ORG, SERVO, RESET, START = 1, 2, 4, 8
MANUAL, JOG_PLUS, TEACH = 1 << 11, 1 << 12, 1 << 13  # IN12-14, assigned below
IO_PARAMS = {0x0603: 12, 0x0601: 13, 0x0604: 14, 0x0703: 5, 0x0706: 0}  # + MOVE on OUT5


def sel(n: int) -> int:
    return n << 4


def run_until(dev, cond, limit_s=20.0, step_us=10_000) -> float:
    t = 0
    while not cond(dev):
        c.advance(dev, step_us)
        t += step_us
        assert t < limit_s * 1e6, "condition never held"
    return t / 1e6


def homed(**kw) -> c.Xc100:
    dev = c.new_xc100(params={**IO_PARAMS, **kw.pop("params", {})}, **kw)
    c.set_inputs(dev, SERVO | ORG)
    run_until(dev, lambda d: d.motion is None)
    c.set_inputs(dev, SERVO)
    assert dev.homed
    return dev


def sig(dev, name):
    return c.output_signals(dev)[name]


def test_7_1_homing_sequence():
    dev = c.new_xc100(params=IO_PARAMS)
    assert sig(dev, "SERVO-S") and sig(dev, "READY") and not sig(dev, "ORG-S")  # 1. servo ON
    c.set_inputs(dev, SERVO | ORG)  # 2. ORG ON
    assert sig(dev, "MOVE") and not sig(dev, "READY")  # 3. MOVE ON ...
    c.advance(dev, 50_000)
    c.set_inputs(dev, SERVO)  # ... then ORG may go OFF
    assert sig(dev, "MOVE") and not sig(dev, "ORG-S")
    t = run_until(dev, lambda d: not sig(d, "MOVE"))
    assert sig(dev, "ORG-S") and sig(dev, "READY") and round(dev.act) == 0  # 4.
    assert 2.5 < t < 3.0  # 50 mm at 20 mm/s (OrgSpeed 10 %) + ramp + 100 ms torque time
    assert c.output_pins(dev) & 0b1  # ORG-S on OUT1
    assert c.output_pins(dev) >> 4 & 1 == 0  # MOVE (OUT5) off


def test_7_4_point_select_and_start_and_order_of_outputs():
    dev = homed(points={5: Point(mode=1, position=30000, speed=50, wait=100)})
    c.set_inputs(dev, SERVO | sel(5))
    c.advance(dev, 10_000)
    c.set_inputs(dev, SERVO | sel(5) | START)
    assert sig(dev, "MOVE") and not sig(dev, "READY") and dev.step_no == 5
    c.set_inputs(dev, SERVO | sel(5))
    assert [sig(dev, f"PRGSEL{i}-S") for i in range(3)] == [True, False, True]
    t_inp = run_until(dev, lambda d: sig(d, "INP"))
    assert sig(dev, "MOVE") and not sig(dev, "READY")  # 4.7: the wait is part of the move
    t_done = t_inp + run_until(dev, lambda d: not sig(d, "MOVE"))
    assert sig(dev, "READY") and round(dev.act) == 30000
    assert t_done - t_inp == pytest.approx(0.1, abs=0.011)


def test_start_and_org_ignored_in_manual_mode_and_jog_only_in_manual():
    dev = homed()
    c.set_inputs(dev, SERVO | MANUAL | START)
    assert dev.motion is None
    c.set_inputs(dev, SERVO | JOG_PLUS)  # MANUAL off: JOG ignored
    assert dev.motion is None


def test_7_2_jog_moves_while_held():
    dev = homed()
    c.set_inputs(dev, SERVO | MANUAL)
    c.set_inputs(dev, SERVO | MANUAL | JOG_PLUS)
    assert sig(dev, "MOVE")
    c.advance(dev, 2_000_000)
    assert dev.act > 1000  # inching step, pause, then continuous travel
    c.set_inputs(dev, SERVO | MANUAL)
    run_until(dev, lambda d: not sig(d, "MOVE"), limit_s=2)
    assert sig(dev, "READY")


def test_7_3_teach_needs_20ms():
    dev = homed()
    c.command(dev, c.CMD_SETPOS)  # position stays 0
    dev.act = dev.cmd = 12345.0
    c.set_inputs(dev, SERVO | MANUAL | sel(7))
    c.set_inputs(dev, SERVO | MANUAL | sel(7) | TEACH)
    c.advance(dev, 10_000)
    c.set_inputs(dev, SERVO | MANUAL | sel(7))  # 10 ms: too short
    assert dev.points[7].position == 0
    c.set_inputs(dev, SERVO | MANUAL | sel(7) | TEACH)
    c.advance(dev, 20_000)
    assert dev.points[7].position == 12345 and dev.points[7].mode == c.MODE_ABS


def test_r_modes_chain_without_stopping_and_wait_forces_a_stop():
    pts = {1: Point(mode=c.MODE_ABS_R, position=50000, speed=30, next=2),
           2: Point(mode=c.MODE_ABS_R, position=150000, speed=100)}
    dev = homed(points=pts)
    c.start_point(dev, 1)
    speeds = []
    while dev.motion is not None:
        c.advance(dev, 1000)
        if 45000 < dev.cmd < 55000:
            speeds.append(abs(dev.vel))
    assert min(speeds) > 0.25 * 200000  # never below P1's 30 %: no stop at P1
    assert round(dev.act) == 150000 and dev.step_no == 2
    dev.points[1].wait = 300  # 4.7: wait at P1, so the axis stops there
    c.start_point(dev, 1)
    stopped = False
    while dev.motion is not None:
        c.advance(dev, 1000)
        stopped |= dev.vel == 0 and round(dev.cmd) == 50000
    assert stopped


def test_inc_r_case_2_nets_260mm():  # 4.2 INC-R case 2 (the narrative copied from ABS-R is wrong)
    dev = homed()
    mm = c.pulses_per_mm(dev)
    dev.points[1] = Point(mode=c.MODE_INC_R, position=round(210 * mm), speed=100, torque=500, next=2)
    dev.points[2] = Point(mode=c.MODE_INC_R, position=round(50 * mm), speed=20, torque=200)
    c.start_point(dev, 1)
    run_until(dev, lambda d: d.motion is None)
    assert dev.act / mm == pytest.approx(260.0)


def test_tsl_stops_at_the_workpiece_with_torque_reached():
    dev = homed(work_mm=120.0, points={3: Point(mode=c.MODE_TSL_PLUS, speed=20, torque=335)})
    c.start_point(dev, 3)
    run_until(dev, lambda d: d.motion is None)
    assert dev.act / c.pulses_per_mm(dev) == pytest.approx(120.0)
    assert sig(dev, "TRQ_LMT") and dev.current == 335 and dev.alarm == 0


def test_position_move_into_an_obstacle_is_full_count_alarm_3_blinks():
    dev = homed(work_mm=120.0, points={1: Point(mode=c.MODE_ABS, position=200000)})
    c.start_point(dev, 1)
    run_until(dev, lambda d: d.alarm != 0)
    assert dev.alarm == 2 and c.led_blinks(dev) == 3 and not dev.servo
    assert sig(dev, "ALARM") and not sig(dev, "READY") and dev.history[0] == 2
    c.set_inputs(dev, SERVO | RESET)  # 10.3: reset with the servo ON (IO servo held) ...
    c.set_inputs(dev, 0)
    c.set_inputs(dev, RESET)  # ... is refused only while ON: now OFF, accepted
    assert dev.alarm == 0
    c.set_inputs(dev, SERVO)
    assert dev.servo


def test_interlocks_10_3():
    dev = c.new_xc100(params=IO_PARAMS)
    dev.points[1] = Point(mode=c.MODE_ABS, position=1000)
    assert not c.start_point(dev, 1) and dev.error == c.ERR_NOT_HOMED  # 051BH = 1
    dev = homed(params={0x0607: 12})  # LOCK on IN12
    dev.points[1] = Point(mode=c.MODE_ABS, position=100000)
    c.set_inputs(dev, SERVO | MANUAL)  # IN12 is LOCK now
    assert not c.start_point(dev, 1) and dev.error == c.ERR_LOCK
    c.set_inputs(dev, SERVO)
    assert c.start_point(dev, 1)
    assert not c.start_point(dev, 1) and dev.error == c.ERR_BUSY
    c.advance(dev, 300_000)
    c.set_inputs(dev, SERVO | MANUAL)  # LOCK during the move: decelerated stop, error 9
    run_until(dev, lambda d: d.motion is None)
    assert dev.error == c.ERR_LOCK and dev.action == 2 and 0 < dev.act < 100000


@pytest.mark.parametrize("cmd_seq,io_seq,expected", [
    # 10.5: command servo state, IO servo state -> actual servo state
    ((0, 0, 0), (0, 1, 0), (True, True, False)),
    ((1, 1, 1), (0, 1, 0), (False, True, False)),
    ((1, 0, 1), (1, 1, 1), (True, True, True)),
    ((1, 0, 1), (0, 0, 0), (False, True, False)),
])
def test_10_5_servo_priority(cmd_seq, io_seq, expected):
    dev = c.new_xc100(params={0x0515: 1})  # power up OFF unless a source says ON
    got = []
    for k, (cmd, io) in enumerate(zip(cmd_seq, io_seq)):
        if k == 0:
            c.set_inputs(dev, SERVO * io)
            if cmd == 0:
                c.servo_command(dev, 0)
        else:
            c.set_inputs(dev, SERVO * io)
            if cmd != cmd_seq[k - 1]:
                c.servo_command(dev, cmd)
        got.append(dev.servo)
    assert tuple(got) == expected


def test_time_slicing_does_not_change_the_result():
    def run(step_us):
        dev = homed(points={1: Point(mode=c.MODE_ABS, position=77777, speed=37, accel=123)})
        c.start_point(dev, 1)
        for _ in range(1_500_000 // step_us):
            c.advance(dev, step_us)
        return dev.cmd, dev.vel, dev.act
    assert run(1000) == run(10_000) == run(500_000)


def test_emergency_stop_is_alarm_11():
    dev = homed()
    c.set_emergency(dev, closed=False)
    assert dev.alarm == 11 and c.led_blinks(dev) == 12 and not dev.servo
    c.set_inputs(dev, RESET)
    assert dev.alarm == 11  # still open
    c.set_emergency(dev, closed=True)
    c.set_inputs(dev, 0)
    c.set_inputs(dev, RESET)
    assert dev.alarm == 0


def test_inrange_and_near_and_soft_limit():
    dev = homed(params={0x0813: 5000})  # + soft limit at 50.00 mm
    mm = c.pulses_per_mm(dev)
    dev.points[1] = Point(mode=c.MODE_ABS, position=round(40 * mm), zone_low=round(30 * mm),
                          zone_high=round(45 * mm))
    c.start_point(dev, 1)
    run_until(dev, lambda d: d.motion is None)
    assert sig(dev, "INRANGE") and sig(dev, "NEAR") and not sig(dev, "SOFTLMT")
    dev.points[2] = Point(mode=c.MODE_ABS, position=round(80 * mm))
    c.start_point(dev, 2)
    run_until(dev, lambda d: d.motion is None)
    assert dev.act / mm == pytest.approx(50.0) and dev.error == c.ERR_SOFT_LIMIT
    assert sig(dev, "SOFTLMT") and not sig(dev, "INRANGE") and dev.action == 2


# 4.1 item 4 座標點資料項目 (the point-table screen):
#   "2 移動座標 ... -9999.99~9999.99 mm", "3 移動速度 ... 1~100 %", "4 扭力極限 ... 1~1000 0.1%",
#   "10 下一步編號 ... 1~127 ... 初始值 -1"
# 8.2 步序指令說明 (the registers): 9011H "-2147483648~214748648 pulse", 9013H "0~100%"
#   ("當值為 0%，速度為 0800 H 起始速度"), 9014H "0~1000 x0.1%", 901DH "-1~127 -1 為結束步序"
@pytest.mark.parametrize("text,ok", [
    ("ABS:9999.99:1:1:1:1:0:127", True), ("ABS:-9999.99", True), ("INC:0.01:100:1000:30000:30000:30000:-1", True),
    ("ABS:10000", False), ("ABS:-10000.00", False), ("ABS:1.005", False), ("ABS:nan", False),
    ("ABS:100:0", False), ("ABS:100:101", False), ("ABS:100:50:0", False),
    ("ABS:100:50:1000:300:300:0:0", False), ("ABS:100:50:1000:0", False),
])
def test_point_key_takes_the_screen_ranges_of_4_1(text, ok):
    """The stimulus key pN= is entered as the point-table screen is: 4.1's ranges."""
    from mlctool.devices.xc100.simmodel import parse_point

    if ok:
        parse_point(text, 1000.0)
    else:
        with pytest.raises(ValueError, match="4.1|not a number"):
            parse_point(text, 1000.0)


def test_point_registers_take_the_wider_ranges_of_8_2():
    """Modbus writes to the point registers follow 8.2: speed 0 (= LowSpeed 0800H), torque 0,
    next step 0 and positions far past +-9999.99 mm are stored; 8.2's own bounds still hold."""
    from mlctool.devices.xc100.registers import write_words

    dev = c.new_xc100()
    assert write_words(dev, 0x9013, [0]) == 0 and dev.points[1].speed == 0
    assert write_words(dev, 0x9014, [0]) == 0 and dev.points[1].torque == 0
    assert write_words(dev, 0x901D, [0]) == 0 and dev.points[1].next == 0
    big = 2_000_000_000  # pulses: 200,000 mm at 10,000 pulses/mm
    assert write_words(dev, 0x9011, [big >> 16, big & 0xFFFF]) == 0 and dev.points[1].position == big
    assert write_words(dev, 0x9013, [101]) == 3 and write_words(dev, 0x9014, [1001]) == 3
    assert write_words(dev, 0x901D, [128]) == 3 and write_words(dev, 0x901D, [0xFFFE]) == 3  # -2
