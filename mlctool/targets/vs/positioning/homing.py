"""ZRN (8-3 FNC 300) homing on the pulse axes Y0-Y3, with the home modes and the automatic
DOG search of 8-1-2, on the moves of targets/vs/positioning/moves.py (one speed profile per leg, read at
each scan's time).

Home modes (target.toml `[positioning] home_mode`, the editor's form): "dog_rear" (DOG rear
edge), "dog_front" (DOG front edge: back out of the DOG at the creep speed), "dog_rear_pg0"
and "dog_front_pg0" (count the PG0 zero signal from the DOG's rear / front edge),
"data_set" (no motion). With a limit switch in the home direction in the form (`lsf`/`lsr`)
ZRN searches for the DOG from wherever it starts (8-1-2 "自動尋點功能", cases 1-4).
"""

from __future__ import annotations

from mlctool.sim.hardware import motion, pulses
from mlctool.sim.state import Machine, SimFault
from mlctool.targets.vs.common import op_error
from mlctool.targets.vs.positioning.moves import (
    MICRO,
    _cfg,
    _drive,
    _level,
    _new_leg,
    _now,
    _pair,
    _pin,
    _set,
    _set_position,
    _signal,
    _speed,
    _start,
    limit_pin,
    normally_closed,
)

HOME_MODES = ("dog_rear", "dog_front", "dog_rear_pg0", "dog_front_pg0", "data_set")


def _home_done(m: Machine, s, memo: dict, axis: int) -> None:
    """The zero point: the origin value (D9347:D9346) becomes the present position, CLR On
    for its width (>= 20 ms), M9344 and M9342 On."""
    _set_position(m, axis, _pair(m, axis, "origin"))
    memo["home_at"] = m.now_us
    pin = _pin(m, "clr", axis)
    if pin:
        m.bits[pin[0]][pin[1]] = 1
        memo["clr_until"] = m.now_us + _cfg(m).get("clr_ms", 20) * 1000
    _set(m, axis, _cfg(m)["home_done"], True)


def _zrn_begin(m: Machine, s, memo: dict, axis: int) -> bool:
    """The start (8-1-2): without a limit switch toward home the axis runs home-ward at S1
    (a DOG already On counts as its front edge, DECISION); with one, the search starts
    away from home when the DOG (case 2) or the limit switch (case 4) is On."""
    mode = _cfg(m).get("home_mode", "dog_rear")
    if mode not in HOME_MODES:
        raise SimFault(f"ZRN: home mode {mode!r} is not simulated ({', '.join(HOME_MODES)} are)")
    needs = () if mode == "data_set" else ("dog", "pg0") if mode.endswith("pg0") else ("dog",)
    for signal in needs:
        if _pin(m, signal, axis) is None:
            op_error(m, s, f"axis Y{axis}: no {signal.upper()} signal in the positioning parameters")
            return False
    home = _cfg(m).get("home_direction", -1)
    search = limit_pin(m, axis, home) is not None
    dog = _signal(m, "dog", axis) if mode != "data_set" else 0
    at_limit = search and _level(m, limit_pin(m, axis, home))
    away = search and (dog or at_limit)
    p = _start(m, s, memo, axis, -home if away else home)
    if p is None:
        return False
    _set(m, axis, _cfg(m)["home_done"], False)
    memo["mode"] = mode
    if mode == "data_set":  # no motion: the origin value becomes the position at once
        memo["prof"] = motion.halt(0.0, 0.0)
        memo["prof"].stop_at = 0.0  # reached: the move ends done
        _home_done(m, s, memo, axis)
        return True
    # speeds read once: nothing may change while ZRN runs (8-3 ZRN)
    memo["fast"] = _speed(m, axis, s.ops[0].get(m), p)
    memo["creep"] = _speed(m, axis, s.ops[1].get(m), p, top=min(p["max"], _cfg(m)["creep_max_hz"]))
    memo.update(dog=dog if search else 0, pg0_from=None, home=home, legs=True,
                own_limit=home if search else None,
                phase="leave_dog" if away else "approach", need_rise=bool(away and not dog))
    memo["prof"] = motion.run_on(0.0, 0.0, 0.0, memo["fast"], p["bias"], p["up"], p["down"])
    return True


def _zero_at(m: Machine, s, memo: dict, axis: int, t: float) -> None:
    x, _ = motion.at(memo["prof"], t)
    memo["prof"] = motion.halt(t, x)
    memo["prof"].stop_at = x  # reached: the move ends done
    memo["legs"] = False
    _home_done(m, s, memo, axis)


def _pg0_edges(m: Machine, axis: int, after: int, upto: int) -> list:
    """The zero signal's edges in (after, upto] of the pulse trains on PG0, as pulses.edges
    runs: the rising edges, or for an N/C contact (the form's polarity) the falling ones, half
    a period later (DECISION: a train cut off while On adds no edge at its end)."""
    kind, number = _pin(m, "pg0", axis)
    if not normally_closed(m, "pg0", axis):
        return pulses.edges(m, kind, number, after, upto)
    out = []
    for tr in m.pulse_trains.get((kind, number), ()):
        if tr.period_us is None:
            continue
        falling = pulses.Train(tr.start_us + tr.period_us / 2, tr.period_us, tr.end_us)
        first, last = falling.edges_upto(after), falling.edges_upto(upto)
        if last > first:
            out.append((falling, first, last - first))
    return out


def _pg0_edge_time(m: Machine, memo: dict, axis: int) -> float | None:
    """Counting PG0 after the DOG edge: the time (s from the start) of the zero-signal edge
    that makes the count (form `zero_count`), or None. A pulse train on PG0 (the stimulus's
    `X0 pulses ...`) is counted edge by edge in time; a plain input counts a rising edge of
    the signal (after the form's polarity) per scan that shows it."""
    kind, number = _pin(m, "pg0", axis)
    level = _signal(m, "pg0", axis)
    after, memo["pg0_last"] = memo["pg0_last"], m.now_us
    need = _cfg(m).get("zero_count", 1) - memo["pg0_seen"]
    if m.pulse_trains.get((kind, number)):
        for train, first, n in _pg0_edges(m, axis, after, m.now_us):
            if n >= need:
                return (float(train.edge_time(first + need - 1)) - memo["t0"]) / MICRO
            need -= n
            memo["pg0_seen"] += n
    elif level and not memo["pg0_level"]:
        memo["pg0_seen"] += 1
        if need <= 1:
            return _now(m, memo)
    memo["pg0_level"] = level
    return None


def _count_pg0(m: Machine, memo: dict, axis: int) -> None:
    memo.update(pg0_from=m.now_us, pg0_last=m.now_us, pg0_seen=0, pg0_level=_signal(m, "pg0", axis))


def _turn(m: Machine, s, memo: dict, t: float, speed: float, phase: str) -> None:
    """Turn back at t (the axis stands still there) and run at `speed` the other way."""
    p = memo["p"]
    _new_leg(m, s, memo, t, -memo["dir"])
    memo["prof"] = motion.run_on(0.0, 0.0, 0.0, speed, p["bias"], p["up"], p["down"])
    memo["phase"] = phase


def _search(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float,
            rise: bool, fall: bool) -> bool:
    """The search legs before the DOG's front edge (8-1-2 cases 2-4); True when the
    execution is dealt with. Case 3: the limit switch toward home ramps the axis down; it
    turns and runs away from home at S1 past the whole DOG (On, then Off), ramps down,
    turns again and approaches as in case 1. Case 2 starts with the DOG On (only its Off
    is awaited), case 4 on the limit switch."""
    p, phase = memo["p"], memo["phase"]
    if phase in ("limit_stop", "dog_stop"):  # a decelerating stop that ends in a turn
        if motion.ended(memo["prof"], t):
            _turn(m, s, memo, memo["prof"].end, memo["fast"],
                  "leave_dog" if phase == "limit_stop" else "approach")
        return True
    if phase == "leave_dog":
        memo["need_rise"] = memo["need_rise"] and not rise
        if fall and not memo["need_rise"]:
            memo["prof"], memo["phase"] = motion.stop(t, x, v, p["bias"], p["down"]), "dog_stop"
        return True
    if phase == "approach" and memo["own_limit"] is not None and not rise \
            and _level(m, limit_pin(m, axis, memo["home"])):
        memo["prof"], memo["phase"] = motion.stop(t, x, v, p["bias"], p["down"]), "limit_stop"
        memo["need_rise"] = True
        return True
    return False


def _zrn_replan(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    """Homing (8-1-2): the DOG's front edge ramps down to the creep speed S2; "dog_rear"
    stops at once at its rear edge; "dog_front" turns back at the creep speed once it is
    reached and stops at once where the DOG goes Off (DECISION: the chart's "the motor
    turns the other way" after the ramp down; the turn is from standstill); "dog_rear_pg0"
    / "dog_front_pg0" count the zero signal PG0 from the DOG's rear / front edge and stop at
    once at the `zero_count`-th. DECISION: DOG edges are seen by the execution whose scan
    first shows the new level; PG0 edges of a pulse train count from that scan's time."""
    dog = _signal(m, "dog", axis)
    p, mode = memo["p"], memo["mode"]
    rise, fall = dog and not memo["dog"], memo["dog"] and not dog
    memo["dog"] = dog
    if _search(m, s, memo, axis, t, x, v, rise, fall):
        return
    phase = memo["phase"]
    if phase == "approach":
        if rise:  # the front edge: down to the creep speed
            memo["prof"] = motion.run_on(t, x, v, memo["creep"], p["bias"], p["up"], p["down"])
            memo["phase"] = "creep"
            if mode == "dog_front_pg0":
                _count_pg0(m, memo, axis)
        if memo["phase"] == "approach" or mode != "dog_front":
            return
    if memo["own_limit"] is not None and _level(m, limit_pin(m, axis, memo["dir"])):
        # the limit switch past the DOG while creeping toward it: an abnormal stop
        memo["prof"] = motion.stop(t, x, v, p["bias"], p["down"])
        memo["stopping"], memo["abnormal"] = True, True
        return
    if phase == "leave_front":
        if fall:
            _zero_at(m, s, memo, axis, t)
        return
    if mode == "dog_rear" and fall:
        return _zero_at(m, s, memo, axis, t)
    if mode == "dog_front":
        reached = memo["prof"].segments[-1][0]  # the creep speed reached (run_on's last segment)
        if t >= reached - motion.EPS_T:
            _turn(m, s, memo, reached, memo["creep"], "leave_front")
        return
    if mode == "dog_rear_pg0" and fall and memo["pg0_from"] is None:
        _count_pg0(m, memo, axis)
        return
    if memo["pg0_from"] is not None:
        at = _pg0_edge_time(m, memo, axis)
        if at is not None:
            _zero_at(m, s, memo, axis, at)


def zrn(m: Machine, s) -> None:
    """ZRN S1 S2 D1 D2 (FNC 300): homing at S1 toward the home direction, S2 the creep
    speed (bias .. 30 kHz); done: M9344 and M9342 On, the position = the origin value."""
    _drive(m, s, _zrn_begin, _zrn_replan)


HOMING_ACTIONS = {"zrn": zrn}
