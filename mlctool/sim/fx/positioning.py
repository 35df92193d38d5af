"""Positioning on the pulse axes Y0-Y3 (8-3 FNC 301/302 JOGF/R, 303/304 DRVR/A,
305/306 DV2R/A, 307 DVIT, 308 DV2I, 309/310 DVSR/A, 311 PLSV, 312 DTBL, 313 DABS, 314 MPG, 315/316 LIR/A), on virtual time: each instruction plans one speed
profile (mlctool/sim/motion.py, solved analytically) from the axis parameters and replans it when the page lets a value
change; every execution reads the profile at the scan's time and writes the axis registers,
the flags and the Y pin's level (On in the first half of each pulse period, as PLSY).

Axis k (Y0 ... Y3) shares the relays and registers of the pulse outputs (target.toml
`[pulse_outputs]`: M9340+20k busy, +1 outputting, +2 done, +3 abnormal end, +5/+6 stop
relays; D9351:D9350+20k speed) plus target.toml `[positioning]`: the parameter registers
(max speed, bias, accel/decel ms, origin, override, current position D9355:D9354) and the
parts of the editor's positioning parameter form the program cannot see (home mode, DOG,
interrupt and CLR signals, limit switches LSF/LSR, home and rotation direction). ZRN (FNC
300) and its DOG search are in fx/homing.py, on the moves and limits of this module.
"""

from __future__ import annotations

import math
from fractions import Fraction
from types import SimpleNamespace

from mlctool.sim import fx_mbus, motion, pulses
from mlctool.sim.fx.common import op_error, read_block, set_relay, state, write_block
from mlctool.sim.fx.pulse_out import (
    ABNORMAL,
    DECEL_STOP,
    DONE,
    OUTPUT,
    STOP,
    _acquire,
    _max_hz,
    _owners,
    _relay,
    _release,
    _set,
    _set_pair,
)
from mlctool.sim.state import Machine, s16, s32

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


def _start(m: Machine, s, memo: dict, axis: int, direction: int) -> dict | None:
    """Common start (condition OFF -> ON): take the axis, read the parameters, set the
    direction pin. None when the axis is held by another instruction (not executed)."""
    if not _acquire(m, s, axis):
        return None
    p = _params(m, axis)
    for offset in (DONE, ABNORMAL):
        _set(m, axis, offset, False)
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
        if not begin(m, s, memo, axis):
            memo.setdefault("refused", True)
            return
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


# ------------------------------------------------------------ CLR signal (ZRN, fx/homing.py)

def _clr_tick(m: Machine, memo: dict, axis: int) -> None:
    if memo.get("clr_until") is not None and m.now_us >= memo["clr_until"]:
        _clr_off(m, memo, axis)


def _clr_off(m: Machine, memo: dict, axis: int) -> None:
    pin = _pin(m, "clr", axis)
    if pin and memo.get("clr_until") is not None:
        m.bits[pin[0]][pin[1]] = 0
        memo["clr_until"] = None


# ------------------------------------------------------------ DTBL (FNC 312)

# operation commands of a table row (8-3 DTBL "運轉資料")
END, SINGLE_REL, SINGLE_ABS, CHAIN_REL, CHAIN_ABS, JMP = range(6)
MOVES = (SINGLE_REL, SINGLE_ABS, CHAIN_REL, CHAIN_ABS)
NO_MCODE = -1
WITH_MCODE = 10_000  # m codes 10000-32767 come with the step's start, 0-9999 after its end


def _field(m: Machine, row, name: str) -> int:
    """A row's field now: a constant, or the register(s) it names (32-bit: the pair), as the
    field's width in target.toml [tables.DTBL] says."""
    op = row.fields[name]
    if op.is_const:
        return int(op.value)
    width = next(f.get("width", 16) for f in m.target.settings["tables"][row.kind]["fields"]
                 if f["name"] == name)
    words = m.words[op.kind]
    v = words[op.number] | ((words[op.number + 1] << 16) if width == 32 else 0)
    return v - (1 << width) if v >> (width - 1) & 1 else v


def _mcode(m: Machine, axis: int, code: int) -> None:
    """D9349 = the m code; M9348 On while there is one (-1: none)."""
    m.words["D"][_register(m, axis, "mcode")] = code & 0xFFFF
    _set(m, axis, _cfg(m)["mcode_on"], code != NO_MCODE)


def _table_step(m: Machine, s, memo: dict, step: int) -> None:
    memo["step"] = step
    kind, n = s.ins.operands[1].kind, s.ops[1].addr(m)
    m.words[kind][n] = step & 0xFFFF  # S2: the step in progress


def _table_flow(m: Machine, s, memo: dict) -> None:
    """Run the rows that need no start signal from the present step: END turns M9029 On for
    one scan and the table is finished, JMP goes to the row its position names. DECISION
    (the page draws END right after the last move): END and JMP run when reached."""
    rows = memo["rows"]
    for _ in range(len(rows) + 1):
        step = memo["step"]
        if not 0 <= step < len(rows):
            memo["phase"] = "stopped"
            return op_error(m, s, f"table step {step} does not exist (rows 0-{len(rows) - 1})")
        cmd = _field(m, rows[step], "command")
        if cmd == END:
            memo["phase"], memo["m9029"] = "end", True
            set_relay(m, "done", True)
            return
        if cmd != JMP:
            memo["phase"] = "wait"
            return
        _table_step(m, s, memo, _field(m, rows[step], "position"))
    memo["phase"] = "stopped"
    op_error(m, s, "the table's JMP rows loop without a move or END")


def _table_parts(m: Machine, memo: dict, axis: int) -> list[tuple[int, int]]:
    """(row, signed travel) of the move that starts at the present step: one row for the
    single commands; for the continuous ones the following continuous rows too, while they
    run the same way (DECISION: a continuous row that turns back ends the run there; the
    page: the run "stops first, then goes on with the next step" when it must break off)."""
    rows, step = memo["rows"], memo["step"]
    at, parts, way = _pair(m, axis, "position"), [], 0
    while step < len(rows):
        cmd = _field(m, rows[step], "command")
        if cmd not in MOVES or (parts and (cmd in (SINGLE_REL, SINGLE_ABS)
                                           or _field(m, rows[parts[0][0]], "command") < CHAIN_REL)):
            break
        pos = _field(m, rows[step], "position")
        travel = pos - at if cmd in (SINGLE_ABS, CHAIN_ABS) else pos
        if parts and travel * way < 0:
            break
        way = way or (1 if travel > 0 else -1 if travel < 0 else 0)
        parts.append((step, travel))
        at += travel
        step += 1
    return parts


def _table_speed(m: Machine, memo: dict, axis: int) -> float:
    row = memo["rows"][memo["parts"][memo["part"]][0]]
    return _speed(m, axis, _field(m, row, "speed"), memo["p"])


def _table_move(m: Machine, s, memo: dict, axis: int) -> None:
    """A start signal M9347 OFF -> ON with no m code pending: the move of the present step."""
    parts = _table_parts(m, memo, axis)
    way = next((1 if d > 0 else -1 for _, d in parts if d), 1)
    p = _params(m, axis)
    for offset in (DONE, ABNORMAL):
        _set(m, axis, offset, False)
    memo.update(t0=m.now_us, dir=way, pos0=_pair(m, axis, "position"), p=p, ended=False,
                stopping=False, moved=0, parts=parts, part=0, phase="move",
                bounds=[sum(abs(d) for _, d in parts[:k + 1]) for k in range(len(parts))])
    _direction_pin(m, s, way)
    _table_part(m, s, memo, axis, 0.0, 0.0, 0.0)


def _table_part(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    """Plan the present part from (t, x, v): the last part ends on the total travel, the
    others run on at their speed to their boundary; a WITH m code shows at the part's start."""
    row = memo["parts"][memo["part"]][0]
    _table_step(m, s, memo, row)
    code = _field(m, memo["rows"][row], "mcode")
    if code >= WITH_MCODE:
        _mcode(m, axis, code)
    p, memo["cruise"] = memo["p"], _table_speed(m, memo, axis)
    if memo["part"] == len(memo["parts"]) - 1:
        memo["prof"] = motion.move_to(t, x, v, memo["bounds"][-1], memo["cruise"], p["bias"],
                                      p["up"], p["down"])
    else:
        memo["prof"] = motion.run_on(t, x, v, memo["cruise"], p["bias"], p["up"], p["down"])


def _table_replan(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    """Parts whose boundary was passed since the last execution hand over at that instant;
    then the speed data and the override may change the present part's speed."""
    while memo["part"] < len(memo["parts"]) - 1 and x >= memo["bounds"][memo["part"]] - motion.EPS:
        at = motion.time_at(memo["prof"], memo["bounds"][memo["part"]])
        _, speed = motion.at(memo["prof"], at)
        memo["part"] += 1
        _table_part(m, s, memo, axis, at, memo["bounds"][memo["part"] - 1], speed)
        x, v = motion.at(memo["prof"], t)
    _cruise_to(memo, _table_speed(m, memo, axis), t, x, v)


def _table_moved(m: Machine, s, memo: dict, axis: int) -> None:
    """A move has ended: done (M9342 On): an AFTER m code, then the next step; a stop relay
    (M9343 On): the table stays stopped until the condition goes Off (8-3: restart)."""
    if not _relay(m, axis, DONE):
        memo["phase"] = "stopped"
        return
    row = memo["parts"][-1][0]
    code = _field(m, memo["rows"][row], "mcode")
    if 0 <= code < WITH_MCODE:
        _mcode(m, axis, code)
    _table_step(m, s, memo, row + 1)
    _table_flow(m, s, memo)


def _table_begin(m: Machine, s, memo: dict, axis: int) -> bool:
    q = s.ins.operands[0].number + s.ops[0].index_value(m)
    rows = fx_mbus.tables(m, "DTBL").get(q)
    if not rows:
        op_error(m, s, f"table Q{q} has no DTBL rows (.table Q{q} DTBL ...)")
        return False
    if not _acquire(m, s, axis):
        return False
    for offset in (DONE, ABNORMAL):
        _set(m, axis, offset, False)
    _mcode(m, axis, NO_MCODE)  # the page: DTBL's start sets the m code to -1
    memo.update(rows=rows, ended=True, start_level=_relay(m, axis, _cfg(m)["table_start"]),
                off_level=_relay(m, axis, _cfg(m)["mcode_off"]), m9029=False)
    kind, n = s.ins.operands[1].kind, s.ops[1].addr(m)
    _table_step(m, s, memo, s16(m.words[kind][n + 1]))  # S2+1: the start step
    _table_flow(m, s, memo)
    return True


def _table_signals(m: Machine, s, memo: dict, axis: int) -> None:
    """M9349 OFF -> ON clears the m code; M9347 OFF -> ON turns M9342 Off and starts the step
    waiting for it, unless an m code is pending (DECISION: that edge is then ignored)."""
    off = _relay(m, axis, _cfg(m)["mcode_off"])
    if off and not memo["off_level"]:
        _mcode(m, axis, NO_MCODE)
    start = _relay(m, axis, _cfg(m)["table_start"])
    rise = start and not memo["start_level"]
    memo["off_level"], memo["start_level"] = off, start
    if not rise:
        return
    _set(m, axis, DONE, False)
    pending = s16(m.words["D"][_register(m, axis, "mcode")]) != NO_MCODE
    if memo["phase"] == "wait" and not pending and m.acc:
        _table_move(m, s, memo, axis)


def dtbl(m: Machine, s) -> None:
    """DTBL S1 S2 D1 D2 (FNC 312): runs positioning table S1 (`.table Qn DTBL position speed
    mcode command` rows, docs/vs.md) on axis D1 from step S2+1; S2 shows the step. Each move
    starts on M9347 OFF -> ON; m codes in D9349/M9348, cleared by M9349; M9029 at END."""
    y = s.ops[-2]
    axis = y.addr(m)
    memo = state(m, s, {})
    if memo.get("m9029"):  # On for one scan: the next execution turns it Off
        memo["m9029"] = False
        set_relay(m, "done", False)
    if not memo:
        if not m.acc:
            return
        if not _table_begin(m, s, memo, axis):
            memo.clear()
            memo["refused"] = True  # not executed until the condition goes Off and On again
            return
    if memo.get("refused"):
        if not m.acc:
            memo.clear()
        return
    _table_signals(m, s, memo, axis)
    if memo["phase"] == "move":
        _advance(m, s, memo, axis, lambda t, x, v: _table_replan(m, s, memo, axis, t, x, v))
        if memo["ended"]:
            if m.acc:
                _table_moved(m, s, memo, axis)
            else:
                memo["phase"] = "stopped"
    if not m.acc and memo["phase"] != "move":
        _release(m, s, axis, y)
        memo.clear()


# ------------------------------------------------------------ DABS (FNC 313)

ABS_DATA, ABS_SUM = 16, 3  # transfers of 2 bits: the 32-bit position, then a 6-bit checksum


def _abs_outputs(m: Machine, s, servo_on: int, mode: int, request: int) -> None:
    d1 = s.ops[1]
    for k, v in enumerate((servo_on, mode, request)):  # D1 SERVO ON, D1+1 ABSM, D1+2 ABSR
        d1.setbit(m, v, k)


def _abs_take(m: Machine, s, memo: dict) -> None:
    """ABST (S+2) On: the 2 bits on S (bit 0) and S+1 (bit 1) are the next transfer; the
    last one checks the sum and, when it holds, writes the position to D2."""
    bits = s.ops[0].bit(m, 0) | s.ops[0].bit(m, 1) << 1
    k = memo["k"]
    if k < ABS_DATA:
        memo["data"] |= bits << (2 * k)
        memo["sum"] += bits
    else:
        memo["check"] |= bits << (2 * (k - ABS_DATA))
    memo["k"] = k + 1
    if memo["k"] < ABS_DATA + ABS_SUM:
        return
    memo["done"] = True
    _abs_outputs(m, s, 1, 0, 0)
    if memo["check"] != memo["sum"] & 0x3F:
        return op_error(m, s, f"ABS checksum {memo['check']} != {memo['sum'] & 0x3F}")
    s.ops[2].set(m, s32(memo["data"]))
    memo["m9029"] = True
    set_relay(m, "done", True)


def dabs(m: Machine, s) -> None:
    """DABS S D1 D2 (FNC 313): reads a Mitsubishi absolute-encoder servo's position into D2
    (usually D9353:D9352). The page gives only the wiring (S ABS bit 0, bit 1, ready; D1 SERVO
    ON, ABS mode, ABS request) and "M9029 On one scan when read; the condition Off interrupts".
    DECISION: the handshake of the servo's ABS transfer (MR-J2S): SERVO ON and ABS mode On;
    per transfer the request On, the ready signal On = 2 bits valid, the request Off, ready
    Off; 16 transfers of the position (low bits first), 3 of the checksum (the low 6 bits of
    the sum of the 16 transfers); a wrong checksum is an operation error (D2 unchanged)."""
    memo = state(m, s, {})
    if memo.get("m9029"):  # On for one scan: the next execution turns it Off
        memo["m9029"] = False
        set_relay(m, "done", False)
    if not m.acc:
        if memo:
            _abs_outputs(m, s, 0, 0, 0)
            memo.clear()
        return
    if not memo:
        for ref in s.ops[:2]:  # S and D1 take 3 points each (the page)
            if ref.addr(m) + 2 > m.target.devices[ref.kind].hi:
                return op_error(m, s, f"{ref.text} takes 3 points, past the device range")
        memo.update(k=0, data=0, sum=0, check=0, done=False, m9029=False, ready=s.ops[0].bit(m, 2))
    if memo["done"]:
        return
    ready = s.ops[0].bit(m, 2)
    if ready and not memo["ready"]:
        _abs_take(m, s, memo)
    memo["ready"] = ready
    if not memo["done"]:
        _abs_outputs(m, s, 1, 1, 0 if ready else 1)


# ------------------------------------------------------------ MPG (FNC 314)

def _mpg_setting(m: Machine, ref, k: int, lo: int, hi: int, default: int) -> int:
    v = s16(m.words[ref.kind][ref.addr(m, 3) + k])
    return v if lo <= v <= hi else default


def _mpg_count(m: Machine, s, memo: dict) -> None:
    """Input cycles of the A/B pair up to now - response time (the output lags the input by
    it, DECISION), at the gear ratio S2+1 / S2+2 in force (each 1-32767, else 1); kept as an
    exact fraction so a ratio change never loses a part pulse."""
    work = s.ops[1]
    delay = _mpg_setting(m, work, 0, 1, 500, 5) * 1000
    upto = max(memo["in_t"], m.now_us - delay)
    n = pulses.quadrature_count(m, memo["a"], memo["b"], 1, memo["in_t"], upto)
    gear = Fraction(_mpg_setting(m, work, 1, 1, 32767, 1), _mpg_setting(m, work, 2, 1, 32767, 1))
    memo["out"] += n * gear
    memo["in_t"] = upto


def _mpg_begin(m: Machine, s, memo: dict, axis: int) -> bool:
    pairs = _cfg(m)["mpg_inputs"]
    k = s.ops[0].get(m)
    if not 0 <= k < len(pairs):
        op_error(m, s, f"S1 = {k}: the handwheel inputs are 0-{len(pairs) - 1}")
        return False
    if not _acquire(m, s, axis):
        return False
    for offset in (DONE, ABNORMAL):
        _set(m, axis, offset, False)
    a, b = (_pin_named(m, name) for name in pairs[k])
    memo.update(a=a, b=b, in_t=m.now_us, out=Fraction(0), sent=0, moved=0, at=m.now_us,
                pos0=_pair(m, axis, "position"), axis=axis, limits=_mpg_limits(m, axis),
                p=_params(m, axis), forward=True, phase="follow")
    return True


def _mpg_limits(m: Machine, axis: int) -> tuple[int, int]:
    """8-3 MPG: "脈衝輸出中，若碰到正/反轉極限開關，則會立即停止 ... 此時僅能接受相反方向的脈衝
    輸出要求": the levels of the limit switches of the motor's forward (LSF) and reverse
    (LSR) rotation, as this scan shows them; they hold back the pulses put out after it."""
    return _level(m, _pin(m, "lsf", axis)), _level(m, _pin(m, "lsr", axis))


def _pin_named(m: Machine, name: str) -> tuple[str, int]:
    return name[0], int(name[1:], m.target.devices[name[0]].radix)


def mpg(m: Machine, s) -> None:
    """MPG S1 S2 D1 D2 (FNC 314): a handwheel's A/B pulses on input pair S1 (target.toml
    [positioning] mpg_inputs) put out on D1 as input x S2+1 / S2+2, after the response time
    S2 (1-500 ms, else 5); D2 On while A leads. The override does not apply (the page). A
    travel limit ahead (LSF/LSR of the form) stops the output at once; pulses the other way
    still go out (the page). The condition Off or M9345 ramps the output down from the speed
    it has (a decelerating stop), M9346 stops it at once; after a stop relay the wheel is not
    followed again until the condition's next OFF -> ON (M9343 On, the axis held)."""
    y = s.ops[-2]
    memo = state(m, s, {})
    if not memo:
        if not m.acc:
            return
        if not _mpg_begin(m, s, memo, y.addr(m)):
            memo["refused"] = True
            return
    if memo.get("refused"):
        if not m.acc:
            memo.clear()
        return
    axis = memo["axis"]
    hz = 0.0
    if memo["phase"] == "follow":
        hz = _mpg_follow(m, s, memo, axis)
        if _relay(m, axis, STOP):
            memo.update(phase="stopped", abnormal=True)
            hz = 0.0
        elif _relay(m, axis, DECEL_STOP) or not m.acc:
            # DECISION: the ramp starts from the speed this execution shows (its interval's
            # output rate) at the axis's deceleration rate (max - bias) / decel time
            p = memo["p"]
            memo.update(phase="ramp", abnormal=bool(m.acc), t0=m.now_us, ramp_sent=0,
                        prof=motion.stop(0.0, 0.0, hz, p["bias"], p["down"]))
    if memo["phase"] == "ramp":
        hz = _mpg_ramp(m, memo, axis)
    # the position counts the motor's way: up forward unless the form says "position
    # increasing: motor reverse" (8-1-1 rotation direction)
    way = -1 if _cfg(m).get("reverse_rotation", False) else 1
    _set_position(m, axis, memo["pos0"] + way * memo["moved"])
    _set_pair(m, axis, 0, int(hz + 1e-6))
    _set(m, axis, OUTPUT, hz > 0)
    y.setbit(m, 1 if hz > 0 else 0)  # DECISION: On while pulses go out (no pulse phase)
    if memo["phase"] == "stopped":
        _set(m, axis, ABNORMAL, memo["abnormal"])
        if not m.acc:
            _release(m, s, axis, y)
            memo.clear()


def _mpg_follow(m: Machine, s, memo: dict, axis: int) -> float:
    """Follow the handwheel up to this execution; the output rate of its interval (Hz)."""
    _mpg_count(m, s, memo)
    sent = int(memo["out"])  # whole pulses, toward zero
    step, forward = sent - memo["sent"], sent > memo["sent"]  # A leads: the motor forward
    if step and memo["limits"][0 if forward else 1]:
        # the pulses since the previous execution, toward a limit switch that execution saw
        # On: stopped at once, dropped (DECISION: not owed when the wheel turns back)
        step = 0
    memo["limits"] = _mpg_limits(m, axis)
    dt = (m.now_us - memo["at"]) / MICRO
    if step:
        s.ops[-1].setbit(m, 1 if forward else 0)  # the page: A leads, D2 On, motor forward
        memo["forward"] = forward
    memo.update(sent=sent, at=m.now_us, moved=memo["moved"] + step)
    return abs(step) / dt if dt > 0 else 0.0


def _mpg_ramp(m: Machine, memo: dict, axis: int) -> float:
    """A decelerating stop under way: its pulses (the area under its speed line up to now, in
    whole pulses) go the way the output last went; M9346 ends it at once, and so does a limit
    ahead (as while following: the level the previous execution saw holds back the pulses
    since). Its speed now; 0 once it has ended (phase "stopped")."""
    t = (m.now_us - memo["t0"]) / MICRO
    x, v = motion.at(memo["prof"], t)
    n = int(x + motion.EPS)
    forward = memo["forward"]
    if memo["limits"][0 if forward else 1]:
        n = memo["ramp_sent"]
        memo["phase"] = "stopped"
    elif _relay(m, axis, STOP) or motion.ended(memo["prof"], t):
        memo["phase"] = "stopped"
    memo["limits"] = _mpg_limits(m, axis)
    step, memo["ramp_sent"] = n - memo["ramp_sent"], n
    memo["moved"] += step if forward else -step
    return 0.0 if memo["phase"] == "stopped" else v


# ------------------------------------------------------------ LIR, LIA (FNC 315, 316)

class _Pin:
    """An output pin of a two-axis instruction, in the shape _advance and _finish drive."""

    def __init__(self, kind: str, number: int):
        self.kind, self.number = kind, number

    def addr(self, m: Machine) -> int:
        return self.number

    def setbit(self, m: Machine, v: int) -> None:
        m.bits[self.kind][self.number] = 1 if v else 0


def _lin_axes(m: Machine, s) -> list:
    """D = 0: Y0/Y1 with the direction pins Y4/Y5; D = 1: Y2/Y3 with Y6/Y7 (the page's
    table), each as a stand-in step for the one-axis helpers (same owner index)."""
    first = 2 * s.ops[1].get(m)
    return [SimpleNamespace(ops=[_Pin("Y", first + k), _Pin("Y", first + k + 4)], index=s.index,
                            ins=s.ins, axis=first + k) for k in (0, 1)]


def _lin_begin(m: Machine, s, memos: list, absolute: bool) -> bool:
    """The vector speeds split by each axis's share of the path (written to S+5 ... S+8);
    both axes ramp in the same time, so they arrive together. The page: the axis parameters
    and the override do not apply; both travels 0: not executed."""
    width = s.ops[0].width
    block = read_block(m, s.ops[0], 9, width)
    axes = _lin_axes(m, s)
    travel = [block[3 + k] - (_pair(m, a.axis, "position") if absolute else 0)
              for k, a in enumerate(axes)]
    bias = min(max(block[0], 0), 20_000)
    run = min(max(block[1], 10), _max_hz(m))
    if bias > run:
        op_error(m, s, f"the bias vector speed {bias} passes the run vector speed {run}")
        return False
    if not any(travel) or any(_owners(m).get(a.axis, s.index) != s.index for a in axes):
        return False
    ms = min(max(block[2], 0), 32_000)
    length = math.hypot(*travel)
    for k, (a, memo) in enumerate(zip(axes, memos, strict=True)):
        share = abs(travel[k]) / length
        b, r = bias * share, run * share
        block[5 + 2 * k], block[6 + 2 * k] = int(b), int(r)
        _start(m, a, memo, a.axis, 1 if travel[k] >= 0 else -1)
        rate = (r - b) * 1000 / ms if ms and r > b else math.inf
        memo.update(p={"max": r, "bias": b, "up": rate, "down": rate}, shim=a, cruise=r)
        # the page: an axis below 1 Hz puts out no pulses (DECISION: it stays; done with the other)
        memo["prof"] = motion.move_to(0.0, 0.0, 0.0, abs(travel[k]) if r >= 1 else 0, r, b, rate, rate)
    write_block(m, s.ops[0], block, width)
    return True


def _lin_stops(m: Machine, memos: list) -> None:
    """A stop relay of either axis stops both (M9346 at once, M9345 ramped), abnormal end; so
    does (ramped) a travel limit ahead of either (8-1-2 LSF/LSR)."""
    limit = any(not memo["ended"] and _at_limit(m, memo, memo["shim"].axis) for memo in memos)
    for relay, ramped in ((STOP, False), (DECEL_STOP, True)):
        if not any(_relay(m, memo["shim"].axis, relay) for memo in memos) and not (ramped and limit):
            continue
        for memo in memos:
            if memo["ended"]:
                continue
            t = _now(m, memo)
            if memo["stopping"] and (ramped or motion.ended(memo["prof"], t)):
                continue  # M9346 also cuts a ramp under way (as _advance), M9343 as it was
            x, v = motion.at(memo["prof"], t)
            memo["prof"] = (motion.stop(t, x, v, memo["p"]["bias"], memo["p"]["down"]) if ramped
                            else motion.halt(t, x))
            if not memo["stopping"]:
                memo["stopping"], memo["abnormal"] = True, True


def _linear(m: Machine, s, absolute: bool) -> None:
    memos = state(m, s, [])
    if not memos:
        if not m.acc:
            return
        memos.extend(({}, {}))
        if not _lin_begin(m, s, memos, absolute):
            memos[:] = [{"refused": True}]
            return
    if memos[0].get("refused"):
        if not m.acc:
            memos.clear()
        return
    _lin_stops(m, memos)
    for memo in memos:
        if not memo["ended"]:
            _advance(m, memo["shim"], memo, memo["shim"].axis)
    if not m.acc and all(memo["ended"] for memo in memos):
        for memo in memos:
            _release(m, memo["shim"], memo["shim"].axis, memo["shim"].ops[0])
        memos.clear()


def lir(m: Machine, s) -> None:
    """LIR S D (FNC 315): two axes (D = 0: Y0/Y1, 1: Y2/Y3) move S+3 / S+4 pulses on a straight
    line: bias and run vector speeds S, S+1, ramp time S+2 ms (the 32-bit form: pairs)."""
    _linear(m, s, False)


def lia(m: Machine, s) -> None:
    """LIA S D (FNC 316): as LIR to the absolute position (S+3, S+4)."""
    _linear(m, s, True)


POSITIONING_ACTIONS = {"jogf": jogf, "jogr": jogr, "drvr": drvr, "drva": drva,
                       "dv2r": dv2r, "dv2a": dv2a, "dvit": dvit, "dv2i": dv2i, "dvsr": dvsr,
                       "dvsa": dvsa, "plsv": plsv, "tbl": dtbl,
                       "dabs": dabs, "mpg": mpg,
                       "lir": lir, "lia": lia}
