"""The XC100 controller: state, IO signals, point execution, homing, alarms (manual 004).

A pure state machine on virtual time: `set_inputs` (CN-4 pins), `advance` (a time step) and
the Modbus command functions change an `Xc100`; nothing here reads the wall clock. The
decisions where the manual is silent are listed in docs/xc100.md and beside the data.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from mlctool.devices.xc100.axis import Motion, ramp_rate, step_target, step_velocity
from mlctool.devices.xc100.tables import tables

SUBSTEP_US = 1000  # the axis integrates in fixed 1 ms steps, whatever the caller's step
ENCODER_PPR = 10000  # 2.1
TEACH_MIN_US = 20_000  # 7.3: TEACH ON at least 20 ms
Z_WINDOW = 5  # pulses either side of each revolution mark where the Z phase is ON [P]
IDLE_CURRENT, MOVE_CURRENT, ACCEL_CURRENT = 50, 150, 400  # x0.1 % of rated [P]

# 201EH MovType codes (8.2)
CMD_INC, CMD_ABS, CMD_TSL, CMD_ORG, CMD_SETPOS = 0, 1, 2, 3, 4
CMD_RESET, CMD_CLEAR, CMD_STOP, CMD_ESTOP, CMD_JOG_PLUS, CMD_JOG_MINUS = 6, 7, 8, 9, 11, 12

MODE_INC, MODE_ABS, MODE_ORG, MODE_TSL_PLUS, MODE_TSL_MINUS = 0, 1, 2, 3, 4
MODE_INC_R, MODE_ABS_R, MODE_INC_T, MODE_ABS_T = 12, 13, 15, 16

ALARM_FULL_COUNT, ALARM_EMG = 2, 11
ERR_BUSY, ERR_SERVO, ERR_LOCK, ERR_SOFT_LIMIT, ERR_NOT_HOMED = 1, 8, 9, 10, 12
ERR_REBOOT = 6
ERR_RANGE = 2  # 10.3 上下限錯誤: a parameter value outside its range


@dataclass
class Point:
    mode: int = 0
    position: int = 0
    speed: int = 100
    torque: int = 1000
    reserved: int = 0
    zone_low: int = 0
    zone_high: int = 0
    accel: int = 300
    decel: int = 300
    wait: int = 0
    next: int = -1


@dataclass
class Xc100:
    """One controller with its cylinder. Positions in command pulses (float while moving)."""

    params: dict[int, int]  # parameter address -> value (32-bit values at the first address)
    saved: dict[int, int]  # what power-up loads (9999H = 0 saves into it)
    points: list[Point]  # P0-P127
    lead_mm: float = 10.0  # cylinder lead: mm per motor revolution (model data, not a register)
    stroke: float = 0.0  # mechanical travel, pulses; the ends are at phys 0 and phys stroke
    work: float | None = None  # phys position of a workpiece the rod meets moving + (None: none)
    kp: float = 5000.0  # position loop gain, 1/s: actual lags command by velocity / kp [P]
    boot: dict[int, int] = field(default_factory=dict)  # parameters as of the last power-up
    origin: float = 0.0  # phys position of coordinate 0
    cmd: float = 0.0
    vel: float = 0.0
    act: float = 0.0
    current: int = 0
    servo: bool = False
    homed: bool = False
    alarm: int = 0
    history: list[int] = field(default_factory=list)  # newest first (1060H = AlarmList01) [A]
    error: int = 0
    action: int = 0  # 1000H: 0 stopped, 1 moving, 2 abnormal stop
    step_no: int = -1
    motion: Motion | None = None
    torque_reached: bool = False
    push_current: int = 0  # after a torque stop the motor keeps pushing with this current
    near_target: float | None = None
    zone: tuple[int, int] = (0, 0)
    pins: int = 0  # CN-4 IN1-IN14 as wired (bit 0 = IN1)
    sim_pins: int = 0  # 2040H simulated inputs, ORed with the pins (8.2)
    last_in: dict[str, bool] = field(default_factory=dict)
    teach_since: int | None = None
    emg_closed: bool = True
    unlocked: bool = False
    needs_reboot: bool = False
    time_us: int = 0
    pending_us: int = 0
    regs: dict[int, int] = field(default_factory=dict)  # last values of the action registers
    requests: list[str] = field(default_factory=list)  # recent Modbus requests (status view)
    refused: str = ""  # the last parameter write refused as out of range, and why (status view)


# -- construction and parameters

def default_params() -> dict[int, int]:
    return {p.addr: p.default for p in tables().params}


def new_xc100(lead_mm: float = 10.0, stroke_mm: float = 300.0, start_mm: float = 50.0,
              work_mm: float | None = None, params: dict[int, int] | None = None,
              points: dict[int, Point] | None = None) -> Xc100:
    """A powered-up controller; `params` and `points` as if stored before power-up."""
    stored = default_params()
    stored.update(params or {})
    dev = Xc100(params=dict(stored), saved=dict(stored), points=[Point() for _ in range(128)],
                lead_mm=lead_mm)
    for n, p in (points or {}).items():
        dev.points[n] = p
    dev.stroke = stroke_mm * pulses_per_mm(dev)
    dev.work = None if work_mm is None else work_mm * pulses_per_mm(dev)
    power_up(dev, start_phys=start_mm * pulses_per_mm(dev))
    return dev


def power_up(dev: Xc100, start_phys: float | None = None) -> None:
    """Power on: stored parameters load, the incremental encoder counts from 0 (2.1)."""
    phys = dev.origin + dev.act if start_phys is None else start_phys
    dev.params = dict(dev.saved)
    dev.boot = dict(dev.params)
    dev.origin, dev.cmd, dev.act, dev.vel = phys, 0.0, 0.0, 0.0
    dev.homed, dev.alarm, dev.error, dev.action = False, 0, 0, 0
    dev.motion, dev.step_no, dev.torque_reached, dev.near_target = None, -1, False, None
    dev.unlocked, dev.needs_reboot, dev.sim_pins, dev.teach_since = False, False, 0, None
    dev.regs = {}
    dev.last_in = {p.name: False for p in tables().inputs()}
    # 5.3 0515H and 10.5: ON after power-up if the parameter says so or the SERVO input is ON
    dev.servo = dev.params[0x0515] == 0 or _raw_input(dev, "SERVO")
    dev.last_in = {p.name: _raw_input(dev, p.name) for p in tables().inputs()}
    dev.current = IDLE_CURRENT if dev.servo else 0
    if not dev.emg_closed:
        raise_alarm(dev, ALARM_EMG)


def param(dev: Xc100, name: str) -> int:
    return dev.params[tables().by_name[name].addr]


def pulses_per_rev(dev: Xc100) -> float:
    """5.1: encoder pulses per revolution / (gear numerator / denominator), as of power-up."""
    return ENCODER_PPR * dev.boot[0x010C] / dev.boot[0x010B]


def pulses_per_mm(dev: Xc100) -> float:
    gear = dev.boot or dev.params
    return ENCODER_PPR * gear[0x010C] / gear[0x010B] / dev.lead_mm


def speed_pps(dev: Xc100, percent: int) -> float:
    """8.2: 1-100 % of HighSpeed (0802H); 0 % = LowSpeed (0800H)."""
    if percent <= 0:
        return float(param(dev, "LowSpeed"))
    return param(dev, "HighSpeed") * percent / 100.0


def hundredths_to_pulses(dev: Xc100, value: int) -> float:
    return value / 100.0 * pulses_per_mm(dev)


# -- IO (3.8, 5.4, 5.5, 6.2)

def _raw_input(dev: Xc100, name: str) -> bool:
    pin = dev.boot.get(tables().by_name[name].addr, 0) if dev.boot else 0
    return bool(pin) and bool((dev.pins | dev.sim_pins) >> (pin - 1) & 1)


def effective_pins(dev: Xc100) -> int:
    return (dev.pins | dev.sim_pins) & 0x3FFF


def set_inputs(dev: Xc100, pins: int) -> None:
    """The CN-4 inputs IN1-IN14 (bit 0 = IN1) as wired; acts on their edges at once."""
    dev.pins = pins & 0x3FFF
    _process_inputs(dev)


def set_simulated_inputs(dev: Xc100, bits: int) -> None:
    dev.sim_pins = bits & 0x3FFF
    _process_inputs(dev)


def _process_inputs(dev: Xc100) -> None:
    now = {p.name: _raw_input(dev, p.name) for p in tables().inputs()}
    prev = dev.last_in
    dev.last_in = now

    def rose(name: str) -> bool:
        return now[name] and not prev.get(name, False)

    # 10.5: a rising edge of the SERVO input turns the servo ON, a falling edge OFF
    if rose("SERVO"):
        servo_on(dev)
    elif prev.get("SERVO") and not now["SERVO"]:
        servo_off(dev)
    if rose("ALM_RESET"):
        alarm_reset(dev)
    if now["LOCK"] and dev.motion is not None and not dev.motion.stopping:
        dev.error = ERR_LOCK  # 10.3: LOCK during a motion stops it
        _stop(dev, status=2)
    manual = now["MANUAL"]
    selected = sum(1 << i for i in range(7) if now[f"PRGSEL{i}"])
    if not manual:  # 7.1, 7.4: ORG and START only with MANUAL OFF
        if rose("ORG"):
            start_homing(dev)
        if rose("START"):
            start_point(dev, selected)
        dev.teach_since = None
    else:  # 7.2, 7.3: JOG and TEACH only with MANUAL ON
        for name, direction in (("JOG+", 1), ("JOG-", -1)):
            if rose(name):
                start_jog(dev, direction, inching=True)
            elif prev.get(name) and not now[name]:
                m = dev.motion
                if m is not None and m.kind == "jog" and m.direction == direction:
                    _stop(dev, status=0)
        if rose("TEACH"):
            dev.teach_since = dev.time_us
        elif not now["TEACH"]:
            dev.teach_since = None
    check_sensor_homing(dev)


def output_signals(dev: Xc100) -> dict[str, bool]:
    """Each output function's state (3.8 ② DO list)."""
    m = dev.motion
    cmd_done = m is None or m.arrived
    dev_err = abs(dev.cmd - dev.act)
    low, high = dev.zone
    plus, minus = param(dev, "PlusSoftLimit"), param(dev, "MinusSoftLimit")
    pos_mm100 = dev.act / pulses_per_mm(dev) * 100.0
    code = max(dev.step_no, 0)
    out = {
        "INP": dev.servo and cmd_done and dev_err < param(dev, "InPositionZone"),
        "ALARM": dev.alarm != 0,
        "READY": dev.servo and dev.alarm == 0 and m is None and dev.emg_closed,
        "MOVE": m is not None,
        "ORG-S": dev.homed and not (m is not None and m.kind == "home"),
        "SERVO-S": dev.servo,
        "TRQ_LMT": dev.torque_reached,
        "INRANGE": (low, high) != (0, 0) and low <= dev.act <= high,
        "NEAR": dev.near_target is not None and abs(dev.near_target - dev.act) < param(dev, "NearZone"),
        "SOFTLMT": (plus != 0 and pos_mm100 >= plus) or (minus != 0 and pos_mm100 <= minus),
    }
    for i in range(7):
        out[f"PRGSEL{i}-S"] = bool(code >> i & 1)
    for i in range(4):
        out[f"ERR{i}"] = bool(dev.alarm >> i & 1)
    return out


def output_pins(dev: Xc100) -> int:
    """OUT1-OUT10 (bit 0 = OUT1) through the output assignment of the last power-up."""
    sig = output_signals(dev)
    bits = 0
    for p in tables().outputs():
        pin = dev.boot.get(p.addr, 0)
        if pin and sig[p.name]:
            bits |= 1 << (pin - 1)
    return bits


def z_phase(dev: Xc100) -> bool:
    ppr = pulses_per_rev(dev)
    r = (dev.origin + dev.act) % ppr
    return r <= Z_WINDOW or ppr - r <= Z_WINDOW


def led_blinks(dev: Xc100) -> int:
    """ERR LED blinks per group (10.1, 10.2): alarm code + 1; 0 = off."""
    return tables().alarms[dev.alarm][1] if dev.alarm else 0


# -- servo, alarms

def servo_on(dev: Xc100) -> None:
    if dev.alarm:
        dev.error = ERR_SERVO
        return
    dev.servo = True
    dev.cmd = dev.act
    dev.current = IDLE_CURRENT


def servo_off(dev: Xc100) -> None:
    if dev.motion is not None:
        _abort(dev, status=2)
    dev.servo = False
    dev.current = 0


def servo_command(dev: Xc100, value: int) -> None:
    """2011H: 0 = ON, 1 = OFF; 10.5: a command OFF is ignored while the SERVO input is ON."""
    if value == 0:
        servo_on(dev)
    elif not dev.last_in.get("SERVO"):
        servo_off(dev)


def raise_alarm(dev: Xc100, code: int) -> None:
    """An alarm stops the axis at once and turns the servo OFF (2.1 SON LED off on error)."""
    if dev.motion is not None:
        _abort(dev, status=2)
    dev.alarm = code
    dev.history = ([code] + dev.history)[:50]
    dev.servo = False
    dev.current = 0
    dev.action = 2


def alarm_reset(dev: Xc100) -> None:
    """10.3: alarm reset with the servo ON is error 8; EMG open keeps alarm 11."""
    if dev.servo:
        dev.error = ERR_SERVO
        return
    if dev.alarm == ALARM_EMG and not dev.emg_closed:
        return
    dev.alarm, dev.error, dev.action = 0, 0, 0


def set_emergency(dev: Xc100, closed: bool) -> None:
    """EMG+/EMG- (3.5), a normally closed contact: opening it is alarm 11."""
    if dev.emg_closed and not closed:
        dev.emg_closed = False
        raise_alarm(dev, ALARM_EMG)
    dev.emg_closed = closed


# -- starting motions

def _may_move(dev: Xc100, homing: bool = False) -> bool:
    """10.3 interlocks; on refusal ErrorStatus says why."""
    if dev.motion is not None:
        dev.error = ERR_BUSY
    elif not dev.servo or dev.alarm:
        dev.error = ERR_SERVO
    elif dev.last_in.get("LOCK"):
        dev.error = ERR_LOCK
    elif not homing and not dev.homed and param(dev, "OrgRetRestrict") == 1:
        dev.error = ERR_NOT_HOMED
    else:
        dev.error = 0
        return True
    return False


def _begin(dev: Xc100, m: Motion) -> None:
    dev.motion = m
    dev.action = 1
    dev.torque_reached = False
    dev.near_target = m.near_target


def _soft_clip(dev: Xc100, target: float, m: Motion) -> float:
    plus, minus = param(dev, "PlusSoftLimit"), param(dev, "MinusSoftLimit")
    if plus and target > hundredths_to_pulses(dev, plus):
        m.soft_limited = True
        return hundredths_to_pulses(dev, plus)
    if minus and target < hundredths_to_pulses(dev, minus):
        m.soft_limited = True
        return hundredths_to_pulses(dev, minus)
    return target


def start_point(dev: Xc100, n: int, chained: bool = False) -> bool:
    """Run point n (7.4 START, or "next step" chaining) -> False when refused."""
    p = dev.points[n]
    if p.mode == MODE_ORG:
        return start_homing(dev, point=n, chained=chained)
    if not chained and not _may_move(dev):
        return False
    speed = speed_pps(dev, p.speed)
    m = Motion("point", None, 1, speed, ramp_rate(speed, p.accel), ramp_rate(speed, p.decel),
               torque=p.torque, point=n)
    if p.mode in (MODE_TSL_PLUS, MODE_TSL_MINUS):
        m.direction = 1 if p.mode == MODE_TSL_PLUS else -1
        m.torque_stop = True
    else:
        base = dev.cmd if p.mode in (MODE_INC, MODE_INC_R, MODE_INC_T) else 0.0
        m.target = _soft_clip(dev, base + p.position, m)
        m.torque_stop = p.mode in (MODE_INC_T, MODE_ABS_T)
        if p.mode in (MODE_INC, MODE_ABS):
            m.near_target = m.target
        m.end_speed = _chain_speed(dev, p, m)
    dev.step_no = n
    dev.zone = (p.zone_low, p.zone_high)
    _begin(dev, m)
    return True


def _chain_speed(dev: Xc100, p: Point, m: Motion) -> float:
    """4.2: an -R point hands over to its next point without stopping, at its own speed, if
    the next point goes on the same way and no wait intervenes (4.7 wait forces a stop) [A]."""
    if p.mode not in (MODE_INC_R, MODE_ABS_R) or p.next < 0 or p.wait > 0:
        return 0.0
    q = dev.points[p.next]
    way = m.target - dev.cmd
    if q.mode in (MODE_INC_R, MODE_INC, MODE_INC_T):
        follow = q.position
    elif q.mode in (MODE_ABS_R, MODE_ABS, MODE_ABS_T):
        follow = q.position - m.target
    else:
        return 0.0
    return m.speed if way * follow > 0 else 0.0


def start_homing(dev: Xc100, point: int = -1, chained: bool = False) -> bool:
    """7.1 / 5.7: search the end (torque modes 0-3) or ORG_SIG (4-7), optionally Z, offset."""
    if not chained and not _may_move(dev, homing=True):
        return False
    mode = param(dev, "OrgMode")
    speed = speed_pps(dev, param(dev, "OrgSpeed"))
    acc = ramp_rate(speed, param(dev, "AccelTim"))
    m = Motion("home", None, 1 if mode % 2 == 0 else -1, speed, acc,
               ramp_rate(speed, param(dev, "DecelTime")), torque=param(dev, "OrgTrqLimit"),
               point=point, phase="seek")
    dev.homed = False
    if point >= 0:
        dev.step_no = point
    _begin(dev, m)
    return True


def start_jog(dev: Xc100, direction: int, inching: bool) -> bool:
    """7.2: JOG+/- moves while held: one inching step (0810H) at 080FH, then after 0812H
    continuous travel until release [A: the manual names the three parameters only]."""
    if not _may_move(dev):
        return False
    speed = param(dev, "HighSpeed") * param(dev, "JogInchingSpd") / 1000.0
    if not inching:
        speed = speed_pps(dev, dev.regs.get(0x2014, 100))
    acc = ramp_rate(speed, param(dev, "AccelTim"))
    m = Motion("jog", None, direction, speed, acc, ramp_rate(speed, param(dev, "DecelTime")),
               phase="run")
    if inching:
        m.phase = "inch"
        m.target = _soft_clip(dev, dev.cmd + direction * param(dev, "JogInchingData"), m)
    _begin(dev, m)
    return True


def command(dev: Xc100, code: int) -> None:
    """201EH MovType (8.2); refusals land in ErrorStatus (100DH), not in exceptions."""
    regs = dev.regs
    if code == CMD_STOP:
        if dev.motion is not None:
            _stop(dev, status=0)
        return
    if code == CMD_ESTOP:
        if dev.motion is not None:
            _abort(dev, status=2)
        return
    if code == CMD_RESET:
        alarm_reset(dev)
        return
    if code == CMD_CLEAR:
        dev.cmd = dev.act
        return
    if code == CMD_SETPOS:
        if dev.motion is not None:
            dev.error = ERR_BUSY
            return
        shift = _s32(regs.get(0x2006, 0)) - dev.act
        dev.origin -= shift
        dev.act += shift
        dev.cmd = dev.act
        return
    if code == CMD_ORG:
        start_homing(dev)
        return
    if code in (CMD_JOG_PLUS, CMD_JOG_MINUS):
        start_jog(dev, 1 if code == CMD_JOG_PLUS else -1, inching=False)
        return
    if not _may_move(dev):
        return
    speed = speed_pps(dev, regs.get(0x2014, 100))
    m = Motion("cmd", None, 1, speed, ramp_rate(speed, param(dev, "AccelTim")),
               ramp_rate(speed, param(dev, "DecelTime")))
    if code == CMD_TSL:  # 5.2: the push torques apply to torque searches by command
        m.direction = -1 if regs.get(0x2005, 0) else 1
        m.torque = param(dev, "PushTrqRateCcw" if m.direction < 0 else "PushTrqRateCw")
        m.torque_stop = True
    else:
        target = dev.cmd + _s32(regs.get(0x2000, 0)) if code == CMD_INC else _s32(regs.get(0x2002, 0))
        m.target = _soft_clip(dev, float(target), m)
        m.near_target = m.target
    _begin(dev, m)


def teach(dev: Xc100, n: int) -> None:
    """7.3: store the current position into point n; the point becomes ABS (as 9.4 does)."""
    p = dev.points[n]
    p.position = round(dev.act)
    p.mode = MODE_ABS


def _s32(v: int) -> int:
    v &= 0xFFFFFFFF
    return v - (1 << 32) if v >> 31 else v


# -- stopping

def _stop(dev: Xc100, status: int) -> None:
    """Decelerate to a stop (STOP command, LOCK, JOG release); the motion ends there."""
    m = dev.motion
    m.stopping = True
    m.stop_status = status
    m.arrived = False
    m.target = None
    m.direction = 1 if dev.vel >= 0 else -1
    m.kind = "stop"


def _abort(dev: Xc100, status: int) -> None:
    """Stop at once (emergency stop, servo OFF, alarm)."""
    dev.motion = None
    dev.vel = 0.0
    dev.cmd = dev.act
    dev.action = status


def _finish(dev: Xc100, status: int = 0) -> None:
    dev.motion = None
    dev.vel = 0.0
    dev.action = status


# -- time

def advance(dev: Xc100, dt_us: int) -> None:
    """Let dt_us of virtual time pass, in fixed 1 ms steps (the result does not depend on
    how the caller slices time)."""
    dev.pending_us += dt_us
    while dev.pending_us >= SUBSTEP_US:
        dev.pending_us -= SUBSTEP_US
        dev.time_us += SUBSTEP_US
        _substep(dev, SUBSTEP_US / 1e6)


def _substep(dev: Xc100, h: float) -> None:
    if dev.teach_since is not None and dev.time_us - dev.teach_since >= TEACH_MIN_US:
        dev.teach_since = None
        if dev.motion is None:
            teach(dev, sum(1 << i for i in range(7) if dev.last_in[f"PRGSEL{i}"]))
    m = dev.motion
    if m is None or not dev.servo:
        dev.vel = 0.0
        dev.current = (dev.push_current if dev.torque_reached else IDLE_CURRENT) if dev.servo else 0
        _follow(dev)
        return
    if m.arrived:
        _after_arrival(dev, m, h)
        return
    old_vel = dev.vel
    if m.target is not None:
        dev.cmd, dev.vel, arrived = step_target(dev.cmd, dev.vel, m, h)
    else:
        dev.vel = step_velocity(dev.vel, m, h)
        dev.cmd += dev.vel * h
        arrived = m.stopping and dev.vel == 0.0
    dev.current = ACCEL_CURRENT if abs(dev.vel) != abs(old_vel) else MOVE_CURRENT
    contact = _follow(dev)
    if contact and dev.motion is m:
        _on_contact(dev, m, h)
        if dev.motion is not m or m.arrived:
            return
    if _soft_limit_hit(dev, m):
        return
    if arrived:
        m.arrived = True
        m.timer_us = 0
        _after_arrival(dev, m, 0.0)
    elif abs(dev.cmd - dev.act) > param(dev, "FullCountValue"):
        raise_alarm(dev, ALARM_FULL_COUNT)  # 10.2: the axis cannot follow its command


def _follow(dev: Xc100) -> bool:
    """Actual position = command - velocity/kp, kept inside the mechanical stops -> contact."""
    want = dev.cmd - dev.vel / dev.kp
    lo = -dev.origin
    hi = dev.stroke - dev.origin
    if dev.work is not None:
        hi = min(hi, dev.work - dev.origin)
    if want > hi or want < lo:
        dev.act = hi if want > hi else lo
        m = dev.motion
        if m is not None:
            dev.current = min(m.torque, 1000)
        return True
    dev.act = want
    return False


def _on_contact(dev: Xc100, m: Motion, h: float) -> None:
    """Pushing against a stop: torque moves end there (4.2 TSL / -T), homing counts its
    torque time (0907H, 090AH), position moves wind up until Full Count."""
    if m.kind == "home" and m.phase == "seek" and param(dev, "OrgMode") < 4:
        dev.cmd, dev.vel = dev.act, 0.0
        m.timer_us += int(h * 1e6)
        if m.timer_us >= param(dev, "OrgTrqLmtTime") * 1000:
            _home_next_phase(dev, m)
        return
    if m.torque_stop or m.kind in ("jog", "stop", "home"):
        dev.cmd, dev.vel = dev.act, 0.0
        dev.torque_reached = m.torque_stop
        dev.push_current = min(m.torque, 1000)
        if m.kind in ("jog", "stop", "home"):
            _finish(dev, 2 if m.kind != "stop" else m.stop_status)
            return
        m.arrived = True
        m.timer_us = 0


def _soft_limit_hit(dev: Xc100, m: Motion) -> bool:
    """Velocity-mode travel stops at a software limit (10.3 error 10)."""
    if m.target is not None or m.stopping:
        return False
    plus, minus = param(dev, "PlusSoftLimit"), param(dev, "MinusSoftLimit")
    for limit, sign in ((plus, 1), (minus, -1)):
        if limit and (dev.cmd - hundredths_to_pulses(dev, limit)) * sign >= 0:
            dev.cmd = dev.act = hundredths_to_pulses(dev, limit)
            dev.error = ERR_SOFT_LIMIT
            _finish(dev, 2)
            return True
    return False


def _after_arrival(dev: Xc100, m: Motion, h: float) -> None:
    """Command output done: settle (MoveSttSet = 1 waits for INP), wait, then chain (4.7)."""
    dev.vel = m.end_speed * (1 if dev.vel >= 0 else -1) if m.end_speed else 0.0
    _follow(dev)
    if m.kind == "stop":
        _finish(dev, m.stop_status)
        return
    if m.kind == "home":
        _home_next_phase(dev, m)
        return
    if m.kind == "jog":
        if m.phase == "inch":  # hold still for JogInchingWait, then run if JOG is still held
            m.phase, m.arrived, m.timer_us = "pause", True, 0
        if m.phase == "pause":
            m.timer_us += int(h * 1e6)
            held = dev.last_in.get("JOG+" if m.direction > 0 else "JOG-")
            if not held:
                _finish(dev)
            elif m.timer_us >= param(dev, "JogInchingWait") * 1000:
                m.phase, m.target, m.arrived = "run", None, False
        return
    if m.soft_limited:
        dev.error = ERR_SOFT_LIMIT
        _finish(dev, 2)
        return
    if m.end_speed:  # -R: straight on to the next point
        _start_next(dev, dev.points[m.point].next)
        return
    if param(dev, "MoveSttSet") == 1 and abs(dev.cmd - dev.act) >= param(dev, "InPositionZone"):
        return
    wait = dev.points[m.point].wait if m.kind == "point" else 0
    m.timer_us += int(h * 1e6)
    if m.timer_us < wait * 1000:
        return
    nxt = dev.points[m.point].next if m.kind == "point" else -1
    if nxt >= 0:
        _start_next(dev, nxt)
    else:
        _finish(dev)


def _start_next(dev: Xc100, n: int) -> None:
    dev.motion = None
    start_point(dev, n, chained=True)


def _home_next_phase(dev: Xc100, m: Motion) -> None:
    mode = param(dev, "OrgMode")
    back = -m.direction if m.phase == "seek" else m.direction
    if m.phase == "seek" and mode in (2, 3, 6, 7):
        m.phase = "zseek"
        speed = param(dev, "HighSpeed") * param(dev, "OrgSpeed_Z1") / 100.0
        ppr = pulses_per_rev(dev)
        start = dev.origin + dev.act + back * param(dev, "OrgOffset_Z")
        # the next revolution mark beyond the Z offset, going back from the end found
        k = (start // ppr + 1) if back > 0 else -(-start // ppr) - 1
        _retarget(dev, m, k * ppr - dev.origin, speed, back)
        return
    if m.phase in ("seek", "zseek") and param(dev, "OrgOffset"):
        m.phase = "offset"
        speed = speed_pps(dev, param(dev, "OrgOffsetSpeed"))
        away = 1 if mode % 2 == 1 else -1  # away from the end (or sensor) searched for
        _retarget(dev, m, dev.act + away * param(dev, "OrgOffset"), speed, away)
        return
    # 5.7 0905H: the position becomes OrgData; 7.1: MOVE OFF, ORG-S ON
    data = hundredths_to_pulses(dev, param(dev, "OrgData"))
    dev.origin += dev.act - data
    dev.act = dev.cmd = data
    dev.homed = True
    _finish(dev)


def _retarget(dev: Xc100, m: Motion, target: float, speed: float, direction: int) -> None:
    m.target, m.direction, m.speed, m.arrived, m.timer_us = target, direction, speed, False, 0
    m.acc = ramp_rate(speed, param(dev, "AccelTim"))
    m.dec = ramp_rate(speed, param(dev, "DecelTime"))


def homing_sensor(dev: Xc100) -> bool:
    return bool(dev.last_in.get("ORG_SIG"))


def check_sensor_homing(dev: Xc100) -> None:
    """Modes 4-7 end their search when ORG_SIG turns ON (called after input changes)."""
    m = dev.motion
    if m is not None and m.kind == "home" and m.phase == "seek" and param(dev, "OrgMode") >= 4 \
            and homing_sensor(dev):
        dev.vel = 0.0
        dev.cmd = dev.act
        _home_next_phase(dev, m)
