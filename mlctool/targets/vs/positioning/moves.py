"""Positioning on the pulse axes Y0-Y3 (8-3 FNC 301/302 JOGF/R, 303/304 DRVR/A,
305/306 DV2R/A, 307 DVIT, 308 DV2I, 309/310 DVSR/A, 311 PLSV; on the same moves: 312 DTBL in
targets/vs/positioning/table.py, 313 DABS in targets/vs/positioning/absolute.py, 314 MPG in targets/vs/positioning/mpg.py, 315/316 LIR/A in
targets/vs/positioning/lines.py), on virtual time: each instruction plans one speed
profile (mlctool/sim/hardware/motion.py, solved analytically) from the axis parameters and replans it when the page lets a value
change; every execution reads the profile at the scan's time and writes the axis registers,
the flags and the Y pin's level (On in the first half of each pulse period, as PLSY).

Axis k (Y0 ... Y3) shares the relays and registers of the pulse outputs (target.toml
`[pulse_outputs]`: M9340+20k busy, +1 outputting, +2 done, +3 abnormal end, +5/+6 stop
relays; D9351:D9350+20k speed) plus target.toml `[positioning]`: the parameter registers
(max speed, bias, accel/decel ms, origin, override, current position D9355:D9354) and the
parts of the editor's positioning parameter form the program cannot see (home mode, DOG,
interrupt and CLR signals, limit switches LSF/LSR, home and rotation direction). ZRN (FNC
300) and its DOG search are in targets/vs/positioning/homing.py, on the moves and limits of this module.
"""

from __future__ import annotations

import math

from mlctool.sim.hardware import motion
from mlctool.sim.state import Machine
from mlctool.targets.vs.common import op_error, read_block, state
from mlctool.targets.vs.pulse_out import (
    ABNORMAL,
    DECEL_STOP,
    DONE,
    OUTPUT,
    STOP,
    _acquire,
    _max_hz,
    _relay,
    _release,
    _set,
    _set_pair,
)

MICRO = 1_000_000


def _cfg(m: Machine) -> dict:
    return m.target.settings.get("positioning", {})


def _register(m: Machine, axis: int, key: str) -> int:
    c = _cfg(m)
    return c["registers"] + c["step"] * axis + c[key]


def _word(m: Machine, axis: int, key: str) -> int:
    v = m.words["D"][_register(m, axis, key)]
    return v - 0x10000 if v & 0x8000 else v


def _pair(m: Machine, axis: int, key: str) -> int:
    n = _register(m, axis, key)
    v = m.words["D"][n] | (m.words["D"][n + 1] << 16)
    return v - (1 << 32) if v & 0x80000000 else v


def _set_position(m: Machine, axis: int, value: int) -> None:
    n, v = _register(m, axis, "position"), value & 0xFFFFFFFF
    m.words["D"][n], m.words["D"][n + 1] = v & 0xFFFF, v >> 16


def _pin(m: Machine, key: str, axis: int) -> tuple[str, int] | None:
    """A signal of the parameter form (`X10`, `M5`; "" = none), numbered in its radix."""
    names = _cfg(m).get(key, [])
    name = names[axis] if axis < len(names) else ""
    if not name:
        return None
    kind = name[0]
    return kind, int(name[1:], m.target.devices[kind].radix)


def _level(m: Machine, pin: tuple[str, int] | None) -> int:
    return m.bits[pin[0]][pin[1]] if pin else 0


# The form's input polarity word (target.toml `input_polarity`, one per axis), in the bit
# layout of the positioning parameter table 2-17-9 BFM#115 "參數設定": b9 STR, b10 DOG, b11
# PG0, b12 INT; 0 = N/O contact, 1 = N/C contact. The built-in axes have no STR input.
POLARITY_BITS = {"str": 9, "dog": 10, "pg0": 11, "interrupt": 12}


def normally_closed(m: Machine, key: str, axis: int) -> bool:
    """The form's signal `key` of the axis is wired to an N/C contact."""
    words = _cfg(m).get("input_polarity", [])
    bit = POLARITY_BITS.get(key)
    return bit is not None and axis < len(words) and bool(int(words[axis]) >> bit & 1)


def _signal(m: Machine, key: str, axis: int) -> int:
    """The form's signal `key` as the positioning sees it: the input's level, inverted for an
    N/C contact (On = the switch is actuated, its contact open); 0 without a signal."""
    pin = _pin(m, key, axis)
    if pin is None:
        return 0
    level = m.bits[pin[0]][pin[1]]
    return level ^ 1 if normally_closed(m, key, axis) else level


def _params(m: Machine, axis: int) -> dict:
    """The axis parameters as the instruction reads them at its start, clamped as 8-1-1
    says: max 1 .. the model's maximum, bias 0-20 kHz, ramps 0-32000 ms, override 1-30000
    (else 1000). The ramp rates are (max - bias) / time."""
    top = min(max(_pair(m, axis, "max_speed"), 1), _max_hz(m))
    bias = min(max(_word(m, axis, "bias"), 0), 20_000, top)
    rates = []
    for key in ("accel_ms", "decel_ms"):
        ms = min(max(_word(m, axis, key), 0), 32_000)
        rates.append((top - bias) * 1000 / ms if ms and top > bias else math.inf)
    return {"max": top, "bias": bias, "up": rates[0], "down": rates[1]}


def _override(m: Machine, axis: int) -> int:
    v = _word(m, axis, "override")
    return v if 1 <= v <= 30_000 else 1000


def _speed(m: Machine, axis: int, raw: int, p: dict, top: float | None = None) -> float:
    """Run speed = |S| x override (D9348, 0.1 %), then clamped to bias .. max (DECISION:
    the override applies before the clamp, so the axis never passes its maximum)."""
    v = abs(raw) * _override(m, axis) / 1000
    return float(min(max(v, p["bias"]), top if top is not None else p["max"]))


def _direction_pin(m: Machine, s, direction: int) -> None:
    """D2 On = motor forward; forward is the increasing direction unless the form says
    "position increasing: motor reverse" (`reverse_rotation`)."""
    forward = direction > 0
    if _cfg(m).get("reverse_rotation", False):
        forward = not forward
    s.ops[-1].setbit(m, 1 if forward else 0)


def _now(m: Machine, memo: dict) -> float:
    return (m.now_us - memo["t0"]) / MICRO


def limit_pin(m: Machine, axis: int, direction: int) -> tuple[str, int] | None:
    """The travel-limit switch a move toward `direction` (+1: increasing position) runs into
    (8-1-2): LSF limits the motor's forward rotation, LSR its reverse; which way the position
    counts for "forward" is the form's rotation direction. None: not in the form."""
    forward = direction > 0
    if _cfg(m).get("reverse_rotation", False):
        forward = not forward
    return _pin(m, "lsf" if forward else "lsr", axis)


def _at_limit(m: Machine, memo: dict, axis: int) -> bool:
    """The limit switch ahead is On (any X or M: its level, 8-1-2 "Level"); a ZRN searching
    for the DOG handles the one in the home direction itself (`own_limit`)."""
    return memo.get("own_limit") != memo["dir"] and bool(_level(m, limit_pin(m, axis, memo["dir"])))


def _new_leg(m: Machine, s, memo: dict, t: float, direction: int) -> None:
    """Start a new leg of the move at t s (from the present leg's start): the travel so far
    goes into the start position, the time origin moves to t and the direction may turn
    (ZRN's DOG search). The caller plans the leg's profile from 0."""
    x, _ = motion.at(memo["prof"], t)
    memo["pos0"] += memo["dir"] * int(x + motion.EPS)
    memo["t0"] += round(t * MICRO)
    memo["dir"] = direction
    _direction_pin(m, s, direction)


def _claim(m: Machine, s, axis: int) -> bool:
    """Take the axis for this instruction, its done and abnormal-end relays cleared; False
    when another instruction holds it (not executed)."""
    if not _acquire(m, s, axis):
        return False
    for offset in (DONE, ABNORMAL):
        _set(m, axis, offset, False)
    return True


def _start(m: Machine, s, memo: dict, axis: int, direction: int) -> dict | None:
    """Common start (condition OFF -> ON): take the axis, read the parameters, set the
    direction pin. None when the axis is held by another instruction (not executed)."""
    if not _claim(m, s, axis):
        return None
    p = _params(m, axis)
    memo.update(t0=m.now_us, dir=direction, pos0=_pair(m, axis, "position"), p=p,
                ended=False, stopping=False, moved=0)
    _direction_pin(m, s, direction)
    return p


def _finish(m: Machine, memo: dict, axis: int, y, done: bool) -> None:
    memo["ended"] = True
    _set_pair(m, axis, 0, 0)
    _set(m, axis, OUTPUT, False)
    _set(m, axis, DONE if done else ABNORMAL, True)
    y.setbit(m, 0)


def _advance(m: Machine, s, memo: dict, axis: int, replan=None) -> None:
    """One execution of a running move: stop relays and the condition, the kind's own
    replanning (`replan(t, x, v)`), then the registers, flags and pin at this instant."""
    y = s.ops[-2]
    p = memo["p"]
    t = _now(m, memo)
    x, v = motion.at(memo["prof"], t)
    waiting = memo.get("wait_until") is not None  # JOGF/JOGR inside their buffer time
    legs = memo.get("legs", False)  # ZRN's DOG search: a stop that turns back is no end
    if not memo["stopping"]:
        if _relay(m, axis, STOP):
            memo["prof"], memo["stopping"], memo["abnormal"] = motion.halt(t, x), True, True
        elif not m.acc and waiting:  # a short press: the one pulse's move runs to its end
            memo["stopping"], memo["abnormal"] = True, False
        elif _relay(m, axis, DECEL_STOP) or not m.acc:
            memo["prof"], memo["stopping"] = motion.stop(t, x, v, p["bias"], p["down"]), True
            memo["abnormal"] = bool(m.acc)  # a stop relay, not the condition, ended it
        elif _at_limit(m, memo, axis) and (legs or not motion.ended(memo["prof"], t)):
            # 8-1-2 LSF/LSR: a decelerating stop, abnormal end (DECISION: M9343, as a stop relay)
            memo["prof"], memo["stopping"] = motion.stop(t, x, v, p["bias"], p["down"]), True
            memo["abnormal"] = True
        elif replan is not None and (waiting or legs or not motion.ended(memo["prof"], t)):
            replan(t, x, v)
            t = _now(m, memo)  # a replan may have started a new leg (_new_leg)
        if memo["stopping"]:
            memo["wait_until"], memo["legs"] = None, False
        x, v = motion.at(memo["prof"], t)
    elif _relay(m, axis, STOP) and not motion.ended(memo["prof"], t):
        # M9346 ("會立即停止輸出脈衝") also cuts a decelerating stop under way (condition Off,
        # M9345, a limit; JOGF/R's one pulse): the pulses up to this scan went out. M9343 as
        # that stop set it (DECISION: after the condition's Off it stays Off, as the pages:
        # "當指令條件接點變為OFF時，M9343也會變為OFF"; MPG and PLSR do the same)
        memo["prof"] = motion.halt(t, x)
        x, v = motion.at(memo["prof"], t)
    pulses = int(x + motion.EPS)
    memo["moved"] = pulses
    if memo.get("home_at") is None:
        _set_position(m, axis, memo["pos0"] + memo["dir"] * pulses)
    prof = memo["prof"]
    if motion.ended(prof, t) and memo.get("wait_until") is None and not memo.get("legs"):
        reached = memo.get("done_on_end") or (prof.stop_at is not None
                                               and pulses >= int(prof.stop_at + motion.EPS))
        _finish(m, memo, axis, y, reached and not memo["stopping"])
        if memo["stopping"] and not memo.get("abnormal"):
            _set(m, axis, ABNORMAL, False)  # condition Off: neither done nor abnormal
        return
    _set_pair(m, axis, 0, int(v + 1e-6))  # whole Hz; float sums land just below
    _set(m, axis, OUTPUT, True)  # the move is under way (at its start the speed is still 0)
    y.setbit(m, 1 if v > 0 and (x - pulses) < 0.5 else 0)


def _drive(m: Machine, s, begin, replan=None) -> None:
    """The life of a positioning instruction: start at the condition's OFF -> ON (`begin`
    plans the profile or refuses), run, and release the axis once the condition is Off and
    the axis has stopped (a decelerating stop runs on with the condition Off)."""
    y = s.ops[-2]
    axis = y.addr(m)
    memo = state(m, s, {})
    if not memo:
        if not m.acc:
            return
        # the start fills a memo of its own, kept only once it has started: a start that
        # faults half-way (an operand out of range) leaves no half-made move behind
        started: dict = {}
        if not begin(m, s, started, axis):
            memo.update(started)
            memo.setdefault("refused", True)
            return
        memo.update(started)
    if memo.get("refused"):
        if not m.acc:
            memo.clear()
        return
    if not memo["ended"]:
        _advance(m, s, memo, axis, None if replan is None else
                 lambda t, x, v: replan(m, s, memo, axis, t, x, v))
    _clr_tick(m, memo, axis)
    if not m.acc and memo["ended"]:
        _clr_off(m, memo, axis)
        _release(m, s, axis, y)
        memo.clear()


# ------------------------------------------------------------ speed changes (DRVR ... PLSV)

def _speed_ref(s):
    return s.ops[1] if len(s.ops) == 4 else s.ops[0]


def _respeed(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    """The run speed and the override may change while running (8-3 DRVA ... PLSV): the
    profile is replanned from the present travel and speed when the result changes."""
    _cruise_to(memo, _speed(m, axis, _speed_ref(s).get(m), memo["p"]), t, x, v)


def _cruise_to(memo: dict, cruise: float, t: float, x: float, v: float) -> None:
    if cruise == memo["cruise"]:
        return
    memo["cruise"] = cruise
    p = memo["p"]
    if memo["prof"].stop_at is None:
        memo["prof"] = motion.run_on(t, x, v, cruise, p["bias"], p["up"], p["down"])
    else:
        memo["prof"] = motion.move_to(t, x, v, memo["prof"].stop_at, cruise, p["bias"],
                                      p["up"], p["down"])


def _move(m: Machine, s, memo: dict, axis: int, travel: int) -> bool:
    p = _start(m, s, memo, axis, 1 if travel >= 0 else -1)
    if p is None:
        return False
    memo["cruise"] = _speed(m, axis, s.ops[1].get(m), p)
    memo["prof"] = motion.move_to(0.0, 0.0, 0.0, abs(travel), memo["cruise"], p["bias"], p["up"],
                                  p["down"])
    return True


def _drvr_begin(m: Machine, s, memo: dict, axis: int) -> bool:
    return _move(m, s, memo, axis, s.ops[0].get(m))


def _drva_begin(m: Machine, s, memo: dict, axis: int) -> bool:
    return _move(m, s, memo, axis, s.ops[0].get(m) - _pair(m, axis, "position"))


def drvr(m: Machine, s) -> None:
    """DRVR S1 S2 D1 D2 (FNC 303, FX DRVI): S1 pulses relative to the present position
    (sign = direction) at S2 Hz with the axis's ramps; M9342 when all are out."""
    _drive(m, s, _drvr_begin, _respeed)


def drva(m: Machine, s) -> None:
    """DRVA S1 S2 D1 D2 (FNC 304): to the absolute position S1 (travel = S1 - D9355:D9354)."""
    _drive(m, s, _drva_begin, _respeed)


def _plsv_begin(m: Machine, s, memo: dict, axis: int) -> bool:
    raw = s.ops[0].get(m)
    p = _start(m, s, memo, axis, 1 if raw >= 0 else -1)
    if p is None:
        return False
    memo["cruise"] = _speed(m, axis, raw, p)
    memo["prof"] = motion.run_on(0.0, 0.0, 0.0, memo["cruise"], p["bias"], p["up"], p["down"])
    return True


def plsv(m: Machine, s) -> None:
    """PLSV S D1 D2 (FNC 311): pulses at |S| Hz, direction by S's sign, until the condition
    goes Off (decelerating stop). DECISION: the direction is fixed at the start; a later S
    of the other sign changes only the speed (the page names no reversal while running)."""
    _drive(m, s, _plsv_begin, _respeed)


# ------------------------------------------------------------ DV2R, DV2A (FNC 305, 306)

def _two_speed_begin(m: Machine, s, memo: dict, axis: int, absolute: bool) -> bool:
    """S1, S1+1 travels (DV2R) or target positions (DV2A); S2, S2+1 their speeds. DECISION:
    both parts run one way; a second part of the other sign is an operation error."""
    first, second = read_block(m, s.ops[0], 2, s.ops[0].width)
    if absolute:
        first, second = first - _pair(m, axis, "position"), second - first
    if first * second < 0:
        op_error(m, s, f"the second travel {second} runs against the first {first}")
        return False
    p = _start(m, s, memo, axis, -1 if first < 0 or second < 0 else 1)
    if p is None:
        return False
    speeds = [_speed(m, axis, v, p) for v in read_block(m, s.ops[1], 2, s.ops[1].width)]
    memo.update(stage=1, first=abs(first), total=abs(first) + abs(second), cruise=speeds[0])
    memo["prof"] = motion.run_on(0.0, 0.0, 0.0, speeds[0], p["bias"], p["up"], p["down"])
    if not first:
        _second_part(memo, 0.0, speeds[1])
    return True


def _second_part(memo: dict, t: float, cruise: float) -> None:
    """From the point the first travel ends (at whatever speed it has there) to the total at
    the second speed: the speed changes at that point, as the page's chart draws it."""
    p = memo["p"]
    x, v = motion.at(memo["prof"], t)
    memo.update(stage=2, cruise=cruise)
    memo["prof"] = motion.move_to(t, memo["first"], v, memo["total"], cruise, p["bias"], p["up"],
                                  p["down"])


def _two_speed_replan(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    speeds = [_speed(m, axis, v_, memo["p"]) for v_ in read_block(m, s.ops[1], 2, s.ops[1].width)]
    if memo["stage"] == 1 and x >= memo["first"] - motion.EPS:
        # the first travel ended between scans: replan from that instant
        _second_part(memo, motion.time_at(memo["prof"], memo["first"]), speeds[1])
        x, v = motion.at(memo["prof"], t)
    _cruise_to(memo, speeds[memo["stage"] - 1], t, x, v)


def dv2r(m: Machine, s) -> None:
    """DV2R S1 S2 D1 D2 (FNC 305): S1 pulses at S2, then S1+1 more at S2+1 (M9342 at the
    end); the speeds and the override may change while running."""
    _drive(m, s, lambda m_, s_, memo, axis: _two_speed_begin(m_, s_, memo, axis, False),
           _two_speed_replan)


def dv2a(m: Machine, s) -> None:
    """DV2A S1 S2 D1 D2 (FNC 306): to position S1 at S2, then to S1+1 at S2+1."""
    _drive(m, s, lambda m_, s_, memo, axis: _two_speed_begin(m_, s_, memo, axis, True),
           _two_speed_replan)


# ------------------------------------------------------------ JOGF, JOGR (FNC 301, 302)

def _jog_begin(m: Machine, s, memo: dict, axis: int, direction: int) -> bool:
    p = _start(m, s, memo, axis, direction)
    if p is None:
        return False
    buffer_ms = min(max(s.ops[0].get(m), 0), 5000)
    memo.update(cruise=_speed(m, axis, s.ops[1].get(m), p), wait_until=buffer_ms / 1000)
    memo["prof"] = motion.move_to(0.0, 0.0, 0.0, 1, memo["cruise"], p["bias"], p["up"], p["down"])
    return True


def _jog_replan(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    """Past the buffer time with the condition still On: run on at S2 from where the one
    pulse left the axis (S2 and the override may change from then on)."""
    if memo["wait_until"] is not None:
        if t < memo["wait_until"] - motion.EPS_T:
            return
        memo["wait_until"] = None
        p = memo["p"]
        memo["prof"] = motion.run_on(t, x, v, memo["cruise"], p["bias"], p["up"], p["down"])
    _respeed(m, s, memo, axis, t, x, v)


def jogf(m: Machine, s) -> None:
    """JOGF S1 S2 D1 D2 (FNC 301): inching forward. The condition On puts out one pulse
    (DECISION: the page's "1 position value" is 1 pulse; the PLC has no unit conversion); held
    past the buffer time S1 (0-5000 ms) it runs on at S2 until Off (decelerating stop). D2 On."""
    _drive(m, s, lambda m_, s_, memo, axis: _jog_begin(m_, s_, memo, axis, 1), _jog_replan)


def jogr(m: Machine, s) -> None:
    """JOGR S1 S2 D1 D2 (FNC 302): as JOGF toward the decreasing position, D2 Off."""
    _drive(m, s, lambda m_, s_, memo, axis: _jog_begin(m_, s_, memo, axis, -1), _jog_replan)


# ------------------------------------------------------------ DVIT (FNC 307)

def _dvit_begin(m: Machine, s, memo: dict, axis: int) -> bool:
    travel = s.ops[0].get(m)
    if _pin(m, "interrupt", axis) is None:
        op_error(m, s, f"axis Y{axis}: no interrupt signal in the positioning parameters")
        return False
    p = _start(m, s, memo, axis, 1 if travel >= 0 else -1)
    if p is None:
        return False
    memo.update(travel=abs(travel), cruise=_speed(m, axis, s.ops[1].get(m), p), after_int=None,
                int_level=_signal(m, "interrupt", axis))
    memo["prof"] = motion.run_on(0.0, 0.0, 0.0, memo["cruise"], p["bias"], p["up"], p["down"])
    return True


def _interrupted(m: Machine, memo: dict, axis: int) -> bool:
    """The interrupt signal's edge since the last execution (M9350 Off rising, On falling)."""
    level = _signal(m, "interrupt", axis)
    falling = _relay(m, axis, _cfg(m)["interrupt_edge"])
    edge = (memo["int_level"] and not level) if falling else (level and not memo["int_level"])
    memo["int_level"] = level
    return bool(edge)


def _dvit_replan(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    """Before the interrupt: run at the speed (changes allowed); at the edge M9350 selects
    (Off rising, On falling) the remaining travel S1 is planned from the present travel.
    DECISION: the edge is seen by the execution whose scan first shows the new level (the
    simulator's inputs change at scan starts)."""
    if _interrupted(m, memo, axis) and memo["after_int"] is None:
        memo["after_int"] = True
        p = memo["p"]
        memo["prof"] = motion.move_to(t, x, v, x + memo["travel"], memo["cruise"], p["bias"],
                                      p["up"], p["down"])
    _respeed(m, s, memo, axis, t, x, v)


def dvit(m: Machine, s) -> None:
    """DVIT S1 S2 D1 D2 (FNC 307): run at S2 until the interrupt signal, then S1 more
    pulses and stop (M9342)."""
    _drive(m, s, _dvit_begin, _dvit_replan)


# ------------------------------------------------------------ DV2I (FNC 308)

def _dv2i_begin(m: Machine, s, memo: dict, axis: int) -> bool:
    if not _dvit_begin(m, s, memo, axis):
        return False
    p = memo["p"]
    memo.update(stage=1, change_level=_level(m, _pin(m, "speed_change", axis)))
    memo["cruise"] = _speed(m, axis, read_block(m, s.ops[1], 2, s.ops[1].width)[0], p)
    memo["prof"] = motion.run_on(0.0, 0.0, 0.0, memo["cruise"], p["bias"], p["up"], p["down"])
    return True


def _dv2i_replan(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    """Speed 1 (S2) until the speed change signal rises, then speed 2 (S2+1); the interrupt's
    edge then plans the travel S1 at the speed in force (DECISION: an interrupt before the
    change signal is acted on at speed 1, and the change signal still switches to speed 2)."""
    level = _level(m, _pin(m, "speed_change", axis))
    if level and not memo["change_level"]:
        memo["stage"] = 2
    memo["change_level"] = level
    if _interrupted(m, memo, axis) and memo["after_int"] is None:
        memo["after_int"] = True
        p = memo["p"]
        memo["prof"] = motion.move_to(t, x, v, x + memo["travel"], memo["cruise"], p["bias"],
                                      p["up"], p["down"])
    speeds = read_block(m, s.ops[1], 2, s.ops[1].width)
    _cruise_to(memo, _speed(m, axis, speeds[memo["stage"] - 1], memo["p"]), t, x, v)


def dv2i(m: Machine, s) -> None:
    """DV2I S1 S2 D1 D2 (FNC 308): S2 Hz, S2+1 Hz from the speed change signal (form), then
    S1 more pulses from the interrupt signal; M9342 at the end."""
    _drive(m, s, _dv2i_begin, _dv2i_replan)


# ------------------------------------------------------------ DVSR, DVSA (FNC 309, 310)

def _stoppable_begin(m: Machine, s, memo: dict, axis: int, absolute: bool) -> bool:
    if _pin(m, "interrupt", axis) is None:
        op_error(m, s, f"axis Y{axis}: no interrupt signal in the positioning parameters")
        return False
    travel = s.ops[0].get(m) - (_pair(m, axis, "position") if absolute else 0)
    if not _move(m, s, memo, axis, travel):
        return False
    memo["int_level"] = _signal(m, "interrupt", axis)
    return True


def _stoppable_replan(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    """The interrupt's edge ramps the axis down at once and that stop completes the move
    (M9342 On, 8-3 DVSR); never past the travel. Same edge DECISION as DVIT."""
    if memo.get("done_on_end"):
        return  # stopping: no more speed changes
    if _interrupted(m, memo, axis):
        p, target = memo["p"], memo["prof"].stop_at
        memo["prof"] = motion.stop(t, x, v, p["bias"], p["down"])
        memo["prof"].stop_at = target
        memo["done_on_end"] = True
        return
    _respeed(m, s, memo, axis, t, x, v)


def dvsr(m: Machine, s) -> None:
    """DVSR S1 S2 D1 D2 (FNC 309): DRVR that the interrupt signal stops (ramped down)."""
    _drive(m, s, lambda m_, s_, memo, axis: _stoppable_begin(m_, s_, memo, axis, False),
           _stoppable_replan)


def dvsa(m: Machine, s) -> None:
    """DVSA S1 S2 D1 D2 (FNC 310): DRVA that the interrupt signal stops (ramped down)."""
    _drive(m, s, lambda m_, s_, memo, axis: _stoppable_begin(m_, s_, memo, axis, True),
           _stoppable_replan)


# ------------------------------------------------------------ CLR signal (ZRN, targets/vs/positioning/homing.py)

def _clr_tick(m: Machine, memo: dict, axis: int) -> None:
    if memo.get("clr_until") is not None and m.now_us >= memo["clr_until"]:
        _clr_off(m, memo, axis)


def _clr_off(m: Machine, memo: dict, axis: int) -> None:
    pin = _pin(m, "clr", axis)
    if pin and memo.get("clr_until") is not None:
        m.bits[pin[0]][pin[1]] = 0
        memo["clr_until"] = None


POSITIONING_ACTIONS = {"jogf": jogf, "jogr": jogr, "drvr": drvr, "drva": drva,
                       "dv2r": dv2r, "dv2a": dv2a, "dvit": dvit, "dv2i": dv2i, "dvsr": dvsr,
                       "dvsa": dvsa, "plsv": plsv}
