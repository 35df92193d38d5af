"""PID control (manual 6-10 FNC 88 PID, 6-11 FNC 92 TPID) on virtual time.

PID S1 S2 S3 D follows the page's velocity-form formulas:

    PVnf = a PVnf-1 + (1 - a) PVn                      (input filter, a = S3+2 %)
    EVn  = PVnf - SV (forward, S3+1 b0 Off) | SV - PVnf (reverse, b0 On)
    Dn   = TD/(Ts + KD TD) (PVnf - 2 PVnf-1 + PVnf-2) + KD TD/(Ts + KD TD) Dn-1   (forward;
           the reverse form has the opposite sign of the PV term)
    dMV  = KP {(EVn - EVn-1) + Ts/TI EVn + Dn},   MVn = sum of dMV

with Ts = S3 ms, KP = S3+3 %, TI = S3+4 x 100 ms (0: no integral), KD = S3+5 %, TD = S3+6 x
10 ms (0: no derivative). Decisions (docs/vs.md "PID"):

- The first execution after the condition goes On samples at once with a history equal to
  the present (PVnf-1 = PVnf-2 = PVnf = PVn, EVn-1 = EVn, Dn-1 = 0) and MV starting from the
  value D holds (the output held while Off, 6-10: "D200 keeps its value"); later samples
  come every Ts of virtual time (remainders carried, no drift).
- MV is accumulated unrounded; D receives it rounded half away from zero. A value written to
  D by the program or the stimulus between samples becomes the MV (bumpless manual mode).
- The history lives in the simulator, not in the work area S3+7..S3+19 (not written).
- Errors (6-10 error table): 6730-6736 (parameters) stop the instruction; 6740 (Ts <= the
  scan time: sampled every scan with Ts = the scan time), 6742 dPV, 6743 dEV, 6744 integral,
  6745 proportional, 6746 derivative, 6747 result out of -32768..32767 continue with the
  value clamped. Codes go to D9067 with M9067 On (alarm OPERATION_ERROR).
- Auto-tuning (b4) is not simulated: a run-time fault naming it.
"""

from __future__ import annotations

import math

from mlctool.sim.operands import WordRef
from mlctool.sim.state import Machine, SimFault, s16
from mlctool.targets.vs.common import op_error, state

LIMIT = 32767


def _round(x: float) -> int:
    return int(math.floor(abs(x) + 0.5)) * (1 if x >= 0 else -1)


def _clamp(m: Machine, s, x: float, code: int, what: str) -> float:
    if -LIMIT - 1 <= x <= LIMIT:
        return x
    op_error(m, s, f"{what} {x:.0f} outside -32768..32767", code, goes_on=True)
    return max(-LIMIT - 1.0, min(float(LIMIT), x))


def _params(m: Machine, ref, count: int) -> tuple[list[int], int]:
    if not isinstance(ref, WordRef):
        raise SimFault(f"{ref.text}: the parameter block is a D or R register block")
    words = m.words[ref.kind]
    a = ref.addr(m)
    if a + count > len(words):
        raise SimFault(f"{ref.text}: the parameter block of {count} runs past {ref.kind}{len(words) - 1}")
    return words, a


_CHECKS = (  # (offset, test of a bad value, code, what the page says)
    (0, lambda v: v < 1, 6730, "sampling time Ts < 1"),
    (2, lambda v: v < 0 or v >= 100, 6732, "input filter a outside 0-99"),
    (3, lambda v: v < 1, 6733, "proportional gain KP < 1"),
    (4, lambda v: v < 0, 6734, "integral time TI < 0"),
    (5, lambda v: v < 0 or v > 100, 6735, "derivative gain KD outside 0-100"),
    (6, lambda v: v < 0, 6736, "derivative time TD < 0"),
)


def pid(m: Machine, s) -> None:
    """PID S1 S2 S3 D (FNC 88): one sample every Ts while the condition is On; Off holds D."""
    was_on = m.edge[s.index]
    m.edge[s.index] = m.acc
    if not m.acc:
        return
    sv_ref, pv_ref, par_ref, out_ref = s.ops
    words, a = _params(m, par_ref, 20)
    p = [s16(words[a + k]) for k in range(7)]
    for off, bad, code, what in _CHECKS:
        if bad(p[off]):
            op_error(m, s, f"S3+{off} = {p[off]}: {what}", code)
            return
    mode = words[a + 1]
    if mode & 0x10:
        raise SimFault(f"PID {s.ins.texts[2]}+1 b4: auto-tuning is not simulated")
    if mode & 0x04 and mode & 0x20:
        op_error(m, s, f"{s.ins.texts[2]}+1: b2 (output alarm) and b5 (output limits) both On")
        return
    if mode & 0x26:
        _params(m, par_ref, 25)
    hist = state(m, s, {})
    if not was_on or not hist:
        hist.clear()
        hist.update(t=m.now_us, due=0, mv=float(out_ref.get(m)), written=None)
    elapsed = m.now_us - hist["t"]
    hist["t"] = m.now_us
    ts_us = p[0] * 1000
    if elapsed >= ts_us:  # the sampling time is not longer than a scan (6740)
        op_error(m, s, f"sampling time {p[0]} ms <= the scan time {elapsed / 1000:g} ms", 6740,
                 goes_on=True)
        hist["due"] = 0
        _sample(m, s, hist, p, mode, elapsed / 1000)
        return
    hist["due"] -= elapsed
    if hist["due"] <= 0:
        hist["due"] += ts_us
        _sample(m, s, hist, p, mode, float(p[0]))


def _sample(m: Machine, s, hist: dict, p: list[int], mode: int, ts: float) -> None:
    sv_ref, pv_ref, par_ref, out_ref = s.ops
    words, a = _params(m, par_ref, 20)
    sv, pv = sv_ref.get(m), pv_ref.get(m)
    alpha, kp, ti, kd, td = p[2] / 100, p[3] / 100, p[4] * 100, p[5] / 100, p[6] * 10
    reverse = bool(mode & 0x01)
    if "pvf" not in hist:  # first sample: the history is the present
        hist.update(pv=pv, pvf=float(pv), pvf2=float(pv), ev=(sv - pv) if reverse else (pv - sv),
                    d=0.0)
    if hist["written"] is not None and out_ref.get(m) != hist["written"]:
        hist["mv"] = float(out_ref.get(m))  # D written from outside: it is the MV now
    dpv = pv - hist["pv"]
    _clamp(m, s, dpv, 6742, "measured value change")
    pvf = alpha * hist["pvf"] + (1 - alpha) * pv
    ev = sv - pvf if reverse else pvf - sv
    _clamp(m, s, ev - hist["ev"], 6743, "deviation change")
    curve = pvf - 2 * hist["pvf"] + hist["pvf2"]
    if td:
        k = td / (ts + kd * td)
        d = k * (-curve if reverse else curve) + kd * k * hist["d"]
        d = _clamp(m, s, d, 6746, "derivative term")
    else:
        d = 0.0
    integral = _clamp(m, s, ts / ti * ev, 6744, "integral term") if ti else 0.0
    prop = _clamp(m, s, kp * (ev - hist["ev"]), 6745, "proportional term")
    dmv = prop + kp * (integral + d)
    mv_before = hist["mv"]
    mv = _clamp(m, s, mv_before + dmv, 6747, "PID result")
    if mode & 0x20:  # output limits S3+22 (upper), S3+23 (lower)
        mv = max(float(s16(words[a + 23])), min(float(s16(words[a + 22])), mv))
    alarms = words[a + 24] if mode & 0x06 else 0
    if mode & 0x02:  # input change alarm: S3+20 increase, S3+21 decrease (as a negative)
        alarms = _alarm_bits(alarms, 0, dpv, s16(words[a + 20]), s16(words[a + 21]))
    out = _round(mv)
    if mode & 0x04:  # output change alarm: S3+22 increase, S3+23 decrease (as a negative)
        alarms = _alarm_bits(alarms, 2, out - _round(mv_before), s16(words[a + 22]),
                             s16(words[a + 23]))
    if mode & 0x06:
        words[a + 24] = alarms
        m.writer[(par_ref.kind, a + 24)] = m.pc
    out_ref.set(m, out)
    hist.update(pv=pv, pvf2=hist["pvf"], pvf=pvf, ev=ev, d=d, mv=mv, written=out)


def _alarm_bits(flags: int, bit: int, change: float, up: int, down: int) -> int:
    """Bits `bit` (increase over `up`) and `bit`+1 (decrease below -`down`) of S3+24."""
    flags &= ~(3 << bit)
    if change > up:
        flags |= 1 << bit
    if change < -down:
        flags |= 2 << bit
    return flags


# ------------------------------------------------------------------ TPID (6-11 FNC 92)

TPID_OUTPUT_FULL = 1000  # output amount 0-1000 in 0.1 % (S3+10m)


def tpid(m: Machine, s) -> None:
    """TPID S1 S2 S3 S4 n (FNC 92): n temperature loops. S1/S2: n set values / measured values;
    S3: control cycle (x 10 ms), S3+1 response speed, +2 direction bits (0 reverse = heating,
    1 forward), +3 manual bits, +4 AT bits, +5 output bits, +6 absolute alarm bits, +7
    deviation alarm bits, S3+10m output amount of loop m (0-1000 = 0-100.0 %); S4+6(m-1):
    KP (x 0.01), TI (x 100 ms), TD (x 10 ms), overshoot deviation, absolute alarm, deviation
    alarm. Off: the output bits Off and the amounts 0 (6-11).

    DECISIONS (the page prints no formula): each loop runs the FNC 88 velocity form once per
    control cycle (Ts = the cycle, no input filter, KD = 0), output clamped 0-1000; the
    response speed S3+1 and the overshoot deviation are accepted and have no effect; the
    output bit is On for the first amount/1000 of each cycle (time-proportional), judged at
    each execution; alarms every execution: absolute (heating: PV > setting, cooling: PV <
    setting), deviation (PV > SV + setting or PV < SV - setting)."""
    sv_ref, pv_ref, par_ref, pid_ref, n_ref = s.ops
    n = n_ref.get(m)
    if not 1 <= n <= 16:
        op_error(m, s, f"n = {n} is outside 1-16")
        return
    words, a = _params(m, par_ref, 10 + 10 * n)
    gains, g = _params(m, pid_ref, 6 * n)
    was_on = m.edge[s.index]
    m.edge[s.index] = m.acc
    hist = state(m, s, {})
    if not m.acc:
        if was_on:
            words[a + 5] = 0
            for k in range(1, n + 1):
                words[a + 10 * k] = 0
            hist.clear()
        return
    cycle = s16(words[a])
    if not 10 <= cycle <= LIMIT:
        op_error(m, s, f"control cycle S3 = {cycle} outside 10-32767 (x 10 ms)")
        return
    if words[a + 4] & ((1 << n) - 1):
        raise SimFault(f"TPID {s.ins.texts[2]}+4: auto-tuning is not simulated")
    cycle_us = cycle * 10_000
    sample = not hist or m.now_us - hist["start"] >= cycle_us
    if sample:
        start = m.now_us if not hist else hist["start"] + cycle_us
        hist.setdefault("loops", {})
        hist["start"] = start
    svs = [sv_ref.get(m)] if n == 1 else _block(m, sv_ref, n)
    pvs = [pv_ref.get(m)] if n == 1 else _block(m, pv_ref, n)
    outputs, absolute, deviation = 0, 0, 0
    for k in range(n):
        sv, pv = svs[k], pvs[k]
        forward = words[a + 2] >> k & 1
        kp, ti, td, _, abs_set, dev_set = (s16(gains[g + 6 * k + j]) for j in range(6))
        amount_at = a + 10 * (k + 1)
        if sample and not words[a + 3] >> k & 1:
            words[amount_at] = _tpid_loop(hist["loops"], k, sv, pv, forward, kp, ti, td,
                                          cycle * 10.0, s16(words[amount_at]))
            m.writer[(par_ref.kind, amount_at)] = m.pc
        amount = max(0, min(TPID_OUTPUT_FULL, s16(words[amount_at])))
        if m.now_us - hist["start"] < cycle_us * amount // TPID_OUTPUT_FULL:
            outputs |= 1 << k
        if (pv < abs_set) if forward else (pv > abs_set):
            absolute |= 1 << k
        if pv > sv + dev_set or pv < sv - dev_set:
            deviation |= 1 << k
    keep = ~((1 << n) - 1) & 0xFFFF
    for off, bits in ((5, outputs), (6, absolute), (7, deviation)):
        words[a + off] = (words[a + off] & keep) | bits
        m.writer[(par_ref.kind, a + off)] = m.pc


def _block(m: Machine, ref, n: int) -> list[int]:
    words, a = _params(m, ref, n)
    return [s16(w) for w in words[a:a + n]]


def _tpid_loop(loops: dict, k: int, sv: int, pv: int, forward: int, kp: int, ti: int, td: int,
               ts: float, amount: int) -> int:
    """One control cycle of loop k: the velocity form of FNC 88 (KP x 0.01, TI x 100 ms, TD x
    10 ms), the amount kept unrounded between cycles and clamped to 0-1000."""
    ev = pv - sv if forward else sv - pv
    h = loops.get(k)
    if h is None:
        h = loops[k] = {"ev": ev, "pv": float(pv), "pv2": float(pv), "mv": float(amount)}
    curve = pv - 2 * h["pv"] + h["pv2"]
    d = (td * 10 / ts) * (curve if forward else -curve) if td else 0.0
    integral = ts / (ti * 100) * ev if ti else 0.0
    mv = h["mv"] + kp / 100 * ((ev - h["ev"]) + integral + d)
    mv = max(0.0, min(float(TPID_OUTPUT_FULL), mv))
    h.update(ev=ev, pv2=h["pv"], pv=float(pv), mv=mv)
    return _round(mv)


PID_ACTIONS = {"pid": pid, "tpid": tpid}
