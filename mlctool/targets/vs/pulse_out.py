"""Pulse outputs of the VS family on Y0-Y3 (6-7 FNC 57 PLSY, 58 PWM, 59 PLSR), on virtual
time and never pulse by pulse: each execution works out how many pulses the axis has put
out since it started (an exact integer for PLSY, the trapezoid's area for PLSR), writes the
axis registers and flags, and gives the Y pin its level at that instant (a level per scan:
the first half of each pulse period is On).

Axis k (Y0 ... Y3), target.toml `[pulse_outputs]` (6-7 PLSY table): relays busy M9340+20k,
outputting +1, done +2, abnormal end +3, decelerating stop +5, immediate stop +6; registers
speed D9351:D9350+20k, pulse count D9353:D9352+20k (cumulative from power-on, the page's
"累計值"). A target without the table has no axes: the routines do nothing but drive Y.
"""

from __future__ import annotations

import math

from mlctool.sim.state import Machine
from mlctool.targets.vs.common import op_error, state

MICRO = 1_000_000
BUSY, OUTPUT, DONE, ABNORMAL, DECEL_STOP, STOP = 0, 1, 2, 3, 5, 6  # relay offsets of an axis


def _table(m: Machine) -> dict:
    return m.target.settings.get("pulse_outputs", {})


def _relay_no(m: Machine, axis: int, offset: int) -> int | None:
    t = _table(m)
    return t["relays"] + t["step"] * axis + offset if t else None


def _relay(m: Machine, axis: int, offset: int) -> int:
    n = _relay_no(m, axis, offset)
    return m.bits["M"][n] if n is not None else 0


def _set(m: Machine, axis: int, offset: int, on: bool) -> None:
    n = _relay_no(m, axis, offset)
    if n is not None:
        m.bits["M"][n] = 1 if on else 0


def _set_pair(m: Machine, axis: int, offset: int, value: int) -> None:
    t = _table(m)
    if t:
        n = t["registers"] + t["step"] * axis + offset
        v = value & 0xFFFFFFFF
        m.words["D"][n], m.words["D"][n + 1] = v & 0xFFFF, v >> 16


def _get_pair(m: Machine, axis: int, offset: int) -> int:
    t = _table(m)
    if not t:
        return 0
    n = t["registers"] + t["step"] * axis + offset
    return m.words["D"][n] | (m.words["D"][n + 1] << 16)


def _max_hz(m: Machine) -> int:
    per_model = _table(m).get("max_hz", {})
    return int(per_model.get(m.target.model or "", per_model.get("default", 200_000)))


def _frequency(m: Machine, ref) -> int:
    """S1 below 1 is 1, above the model's maximum the maximum (6-7 PLSY/PLSR)."""
    return min(max(ref.get(m), 1), _max_hz(m))


def _owners(m: Machine) -> dict:
    """Axis -> step index of the instruction occupying it (M9340 "BUSY" until its condition
    goes Off); cleared by a power cycle with the rest of fx_state."""
    return m.fx_state.setdefault(-1_000_001, {})


def _acquire(m: Machine, s, axis: int) -> bool:
    owners = _owners(m)
    if owners.get(axis, s.index) != s.index:
        return False  # another instruction holds the axis: this one is not executed (M9340 On)
    owners[axis] = s.index
    _set(m, axis, BUSY, True)
    return True


def _release(m: Machine, s, axis: int, y) -> None:
    if _owners(m).get(axis) == s.index:
        del _owners(m)[axis]
        for offset in (BUSY, OUTPUT, DONE, ABNORMAL):
            _set(m, axis, offset, False)
        _set_pair(m, axis, 0, 0)
    y.setbit(m, 0)


def _show(m: Machine, memo: dict, axis: int, y, pulses: int, hz: int, phase_on: bool) -> None:
    _set_pair(m, axis, 2, memo["count0"] + pulses)
    _set_pair(m, axis, 0, hz)
    _set(m, axis, OUTPUT, hz > 0)
    y.setbit(m, 1 if hz > 0 and phase_on else 0)


# ------------------------------------------------------------------ PLSY (FNC 57)

def _plsy_count(m: Machine, memo: dict) -> None:
    """Pulses x 10^6 since the start, at the frequency the previous execution read."""
    memo["micro"] += (m.now_us - memo["last"]) * memo["hz"]
    memo["last"] = m.now_us


def plsy(m: Machine, s) -> None:
    """PLSY S1 S2 D: S2 pulses at S1 Hz on D (0: endless). Off: stops at once, Y Off, and the
    next On starts again from the first pulse. S1 may change while running (it applies from
    the execution that reads it); S2 is read at the start only. M9345/M9346 stop at once
    (PLSY has no ramp), M9343 On if pulses were still due; restart by turning the condition
    Off and On. DECISION: S2 < 0 is an operation error once per On (not executed until Off)."""
    f_ref, n_ref, y = s.ops
    axis = y.addr(m)
    memo = state(m, s, {})
    if not m.acc:
        if memo and not memo.get("refused") and not memo["ended"]:
            _plsy_count(m, memo)  # the output ran until the scan that finds the condition Off
            _set_pair(m, axis, 2, memo["count0"] + min(memo["micro"] // MICRO, memo["total"] or 1 << 62))
        if memo:
            _release(m, s, axis, y)
            memo.clear()
        return
    if not memo:
        total = n_ref.get(m)
        if total < 0:
            memo["refused"] = True
            op_error(m, s, f"pulse count {total} < 0")
            return
        if not _acquire(m, s, axis):
            return
        memo.update(total=total, micro=0, last=m.now_us, hz=_frequency(m, f_ref),
                    count0=_get_pair(m, axis, 2), ended=False)
    if memo.get("refused") or memo["ended"]:
        return
    _plsy_count(m, memo)
    pulses, phase = divmod(memo["micro"], MICRO)
    total = memo["total"]
    if total and pulses >= total:
        memo["ended"] = True
        _show(m, memo, axis, y, total, 0, False)
        _set(m, axis, DONE, True)
        return
    if _relay(m, axis, STOP) or _relay(m, axis, DECEL_STOP):
        memo["ended"] = True
        _show(m, memo, axis, y, pulses, 0, False)
        _set(m, axis, ABNORMAL, True)
        return
    memo["hz"] = _frequency(m, f_ref)
    _show(m, memo, axis, y, pulses, memo["hz"], phase < MICRO // 2)


# ------------------------------------------------------------------ PWM (FNC 58)

def pwm(m: Machine, s) -> None:
    """PWM S1 S2 D: D On for t = S1 of every period T = S2 time-base units (M9035 Off 1 ms,
    On 0.1 ms), measured from the execution that found the condition On; Off: D Off. t > T,
    t < 0 or T < 1: operation error (D Off). S1/S2 are read at each execution (the period
    counts on from the start)."""
    t_ref, period_ref, y = s.ops
    memo = state(m, s, {})
    if not m.acc:
        memo.clear()
        y.setbit(m, 0)
        return
    t, period = t_ref.get(m), period_ref.get(m)
    if not (0 <= t <= period and period >= 1):
        y.setbit(m, 0)
        op_error(m, s, f"t = {t}, T = {period}: needs 0 <= t <= T, T >= 1")
        return
    base = _table(m).get("pwm_base_relay")
    unit_tenths_ms = 1 if base is not None and m.bits["M"][base] else 10  # in 0.1 ms
    start = memo.setdefault("start", m.now_us)
    phase = ((m.now_us - start) // 100) % (period * unit_tenths_ms)
    y.setbit(m, 1 if phase < t * unit_tenths_ms else 0)


# ------------------------------------------------------------------ PLSR (FNC 59)

def _plan(t0: float, x0: float, v0: float, total: int, target: float,
          a: float) -> list[tuple[float, float, float, float]]:
    """Motion segments (start s, position, speed, acceleration) from (t0, x0, v0) to `total`
    pulses at speed 0: a linear ramp at rate a toward target, cruise, the ramp down at the
    same rate. A move too short to reach target peaks lower (triangle); a = 0 (S3 = 0)
    jumps to target at once. DECISION: when even a ramp straight down at rate a would pass
    `total` (a lowered S1 lowered the rate), the speed falls to 0 at the rate v0^2 / 2 rest
    that ends exactly at `total` (the count stays exact)."""
    rest = total - x0
    if a <= 0:
        return [(t0, x0, float(target), 0.0)]
    if v0 * v0 / (2 * a) > rest:
        return [(t0, x0, v0, -v0 * v0 / (2 * rest))]
    if v0 <= target:  # up toward target; a short move peaks where up and down meet
        peak = float(target)
        if (2 * peak * peak - v0 * v0) / (2 * a) > rest:
            peak = math.sqrt((2 * a * rest + v0 * v0) / 2)
    else:  # down to target first
        peak = float(target)
    ramp = (peak - v0) / a if peak >= v0 else (v0 - peak) / a
    x_ramp = abs(peak * peak - v0 * v0) / (2 * a)
    cruise = (rest - x_ramp - peak * peak / (2 * a)) / peak if peak > 0 else 0.0
    cruise = max(cruise, 0.0)
    t1, x1 = t0 + ramp, x0 + x_ramp
    return [(t0, x0, v0, a if peak >= v0 else -a), (t1, x1, peak, 0.0),
            (t1 + cruise, x1 + peak * cruise, peak, -a)]


def _at(segments, t: float) -> tuple[float, float]:
    """Position and speed at t s (a decelerating segment stops at speed 0)."""
    t0, x0, v0, a = next(seg for seg in reversed(segments) if seg[0] <= t)
    dt = t - t0
    if a < 0:
        dt = min(dt, v0 / -a)
    return x0 + v0 * dt + a * dt * dt / 2, v0 + a * dt


def _rate(hz: int, ramp_ms: int) -> float:
    """Hz per second of a ramp that takes S3 ms between 0 and S1 Hz (0: no ramp)."""
    return hz * 1000 / ramp_ms if ramp_ms else 0.0


def plsr(m: Machine, s) -> None:
    """PLSR S1 S2 S3 D: S2 pulses with a ramp of S3 ms from 0 to S1 Hz and back (6-7 chart).
    S2 <= 0: operation error; S3 < 0 is 0, > 32000 is 32000. Condition Off or M9345 while
    running: decelerating stop at the ramp's rate from the present speed (M9340/M9341 stay
    On until it stops); M9346: stop at once. M9343 when stopped by a stop relay before S2.
    S1 may change while running (6-7: "本指令執行當中，可以透過程序改變S1的內容值，其他參數
    改變均視為無效"); S2 and S3 are read at the start only. DECISIONS (the page says no more):
    a new S1 applies from the execution that reads it; the ramp rate is S1/S3 of the S1 in
    force (S3 stays the time between 0 and the target), so the speed moves from the present
    one to the new S1 at that rate, cruises, and the final deceleration at that rate is
    planned to end exactly at S2; a change read once the final deceleration (or a
    decelerating stop) has begun is ignored; the ramp starts at 0 Hz (no bias speed);
    count = whole pulses of the area under the speed curve."""
    f_ref, n_ref, ramp_ref, y = s.ops
    axis = y.addr(m)
    memo = state(m, s, {})
    if not memo and not m.acc:
        return
    if not memo:
        total = n_ref.get(m)
        if total <= 0:
            op_error(m, s, f"pulse count {total} <= 0")
            memo["refused"] = True
            return
        if not _acquire(m, s, axis):
            return
        hz = _frequency(m, f_ref)
        ramp_ms = min(max(ramp_ref.get(m), 0), 32000)
        a = _rate(hz, ramp_ms)
        memo.update(total=total, hz=hz, ramp_ms=ramp_ms, a=a, start=m.now_us,
                    segments=_plan(0.0, 0.0, 0.0, total, hz, a), count0=_get_pair(m, axis, 2),
                    ended=False, stopping=False)
    if memo.get("refused"):
        if not m.acc:
            memo.clear()
        return
    t = (m.now_us - memo["start"]) / MICRO
    x, v = _at(memo["segments"], t)
    x = min(x, memo["total"])
    stop_now = _relay(m, axis, STOP)
    slow_down = not m.acc or _relay(m, axis, DECEL_STOP)
    if not memo["ended"] and not stop_now and not slow_down and not memo["stopping"]:
        hz = _frequency(m, f_ref)
        last = memo["segments"][-1]
        final = last[3] < 0 and t >= last[0]
        if hz != memo["hz"] and not final and x < memo["total"]:
            memo["hz"], memo["a"] = hz, _rate(hz, memo["ramp_ms"])
            memo["segments"] = [seg for seg in memo["segments"] if seg[0] < t]
            memo["segments"] += _plan(t, x, v, memo["total"], hz, memo["a"])
            x, v = _at(memo["segments"], t)
    if not memo["ended"] and (stop_now or (slow_down and not memo["stopping"])):
        memo["abnormal"] = m.acc  # a stop relay, not the condition, ended it early
        if stop_now or memo["a"] == 0:
            memo["segments"].append((t, x, 0.0, 0.0))
        elif v > 0:
            memo["segments"].append((t, x, v, -memo["a"]))
        memo["stopping"] = True
        x, v = _at(memo["segments"], t)
    pulses = int(x + 1e-9)
    if not memo["ended"] and (pulses >= memo["total"] or v <= 0 and t > 0 or stop_now):
        memo["ended"] = True
        _show(m, memo, axis, y, pulses, 0, False)
        _set(m, axis, DONE if pulses >= memo["total"] else ABNORMAL,
             pulses >= memo["total"] or memo.get("abnormal", False))
    elif not memo["ended"]:
        _show(m, memo, axis, y, pulses, int(v + 1e-9), (x - pulses) < 0.5)
    if not m.acc and memo["ended"]:
        _release(m, s, axis, y)
        memo.clear()


PULSE_OUTPUT_ACTIONS = {"plsy": plsy, "pwm": pwm, "plsr": plsr}
