"""MPG (8-3 FNC 314): handwheel following, on the axis moves of targets/vs/positioning/moves.py."""

from __future__ import annotations

from fractions import Fraction

from mlctool.sim.hardware import motion, pulses
from mlctool.sim.state import Machine, s16
from mlctool.targets.vs.common import op_error, state
from mlctool.targets.vs.positioning.moves import (
    MICRO,
    _cfg,
    _claim,
    _level,
    _pair,
    _params,
    _pin,
    _set_position,
)
from mlctool.targets.vs.pulse_out import (
    ABNORMAL,
    DECEL_STOP,
    OUTPUT,
    STOP,
    _relay,
    _release,
    _set,
    _set_pair,
)

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
    if not _claim(m, s, axis):
        return False
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
        started: dict = {}  # kept only once the output has started (as moves._drive)
        if not _mpg_begin(m, s, started, y.addr(m)):
            memo.update(started)
            memo["refused"] = True
            return
        memo.update(started)
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


POS_MPG_ACTIONS = {"mpg": mpg}
