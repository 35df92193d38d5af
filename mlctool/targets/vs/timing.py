"""Timers and sequences in registers, on virtual time or scans (manual 6-2 FNC 7 WDT; 6-8
FNC 62 ABSD, 63 INCD, 64 TTMR, 65 STMR, 67 RAMP; 6-15 FNC 169 HOUR, 176 TFT, 177 TFH,
178 TFK; 6-16 FNC 184 RND, 186 DUTY).

Each routine keeps its own memory per step (common.state): the virtual time of its last
execution and the remainder below its unit, so a long scan adds several units at once and
nothing is lost between scans (as the T timers do, 2-5-3).
"""

from __future__ import annotations

from mlctool.sim.state import Machine, s16, s32
from mlctool.targets.vs.common import (
    count,
    op_error,
    read_block,
    relay,
    set_relay,
    special,
    state,
    write_block,
)

US_PER_S = 1_000_000


def _elapsed(m: Machine, memo: dict, unit_us: int) -> int:
    """Whole units since the previous execution of this step, the remainder carried."""
    total = m.now_us - memo.get("last", m.now_us) + memo.get("rest", 0)
    memo["last"] = m.now_us
    units, memo["rest"] = divmod(total, unit_us)
    return units


def _restart(memo: dict, m: Machine) -> None:
    memo["last"] = m.now_us
    memo["rest"] = 0


# ------------------------------------------------------------------ WDT (6-2)

def wdt(m: Machine, s) -> None:
    """WDT: refreshes the watchdog timer (D9000). DECISION: the simulator has no watchdog
    (virtual scans never overrun it), so WDT changes no device; it is accepted, not refused."""


# ------------------------------------------------------------------ HOUR, TFT, TFH, TFK (6-15)

def hour(m: Machine, s) -> None:
    """HOUR S D1 D2 (FNC 169): while the condition is On, D1 counts hours (16-bit: D1, 32-bit:
    the pair D1) and the next register the seconds below the hour; Off holds them (use a
    latched D1 to keep them over power). D2 is On whenever D1 >= S, condition On or Off;
    counting stops at the largest value of the width."""
    src, d1, d2 = s.ops
    memo = state(m, s, {})
    hours_words = 2 if s.width == 32 else 1
    words = read_block(m, d1, hours_words + 1, 16)
    hours = s32((words[0] & 0xFFFF) | (words[1] << 16)) if s.width == 32 else s16(words[0])
    seconds = words[-1] & 0xFFFF
    top = (1 << 31) - 1 if s.width == 32 else 32767
    if m.acc:
        if not memo.get("on"):
            _restart(memo, m)
        total = hours * 3600 + seconds + _elapsed(m, memo, US_PER_S)
        hours, seconds = divmod(total, 3600)
        if hours >= top:
            hours, seconds = top, 0
        values = ([hours & 0xFFFF, (hours >> 16) & 0xFFFF] if s.width == 32 else [hours & 0xFFFF])
        write_block(m, d1, values + [seconds], 16)
    memo["on"] = bool(m.acc)
    d2.setbit(m, hours >= src.get(m))


def _register_timer(unit_ms: int):
    """TFT/TFH/TFK D1 S D2 (FNC 176-178): a timer in register D1 counting units of 10 ms /
    100 ms / 1 s while the condition is On; D2 On when D1 reaches S (S outside 0-32767 is 0);
    Off: D1 = 0, D2 Off. DECISION: D1 stops at S (as the T timers' present value)."""
    def run(m: Machine, s) -> None:
        d1, src, d2 = s.ops
        memo = state(m, s, {})
        if not m.acc:
            memo["on"] = False
            d1.set(m, 0)
            d2.setbit(m, 0)
            return
        preset = src.get(m)
        if not 0 <= preset <= 32767:
            preset = 0
        if not memo.get("on"):
            _restart(memo, m)
            memo["on"] = True
            d1.set(m, 0)
        v = d1.get(m) & 0xFFFF
        if v < preset:
            v = min(preset, v + _elapsed(m, memo, unit_ms * 1000))
            d1.set(m, s16(v))
        else:
            _restart(memo, m)
        d2.setbit(m, v >= preset)
    return run


# ------------------------------------------------------------------ TTMR, STMR (6-8)

def ttmr(m: Machine, s) -> None:
    """TTMR D n (FNC 64, teaching timer): while the condition is On, D+1 = the seconds it has
    been On and D = D+1 x 10^n (n = 0-2); Off: D+1 = 0, D kept. DECISION: D follows D+1 at
    every execution while On."""
    dst, nr = s.ops
    memo = state(m, s, {})
    n = count(m, nr)
    if not m.acc:
        if memo.get("on"):
            write_block(m, dst, [read_block(m, dst, 1, 16)[0], 0], 16)
        memo["on"] = False
        return
    if not 0 <= n <= 2:
        op_error(m, s, f"n = {n} is outside 0-2")
        return
    if not memo.get("on"):
        memo.update(on=True, start=m.now_us)
    secs = min(32767, (m.now_us - memo["start"]) // US_PER_S)
    write_block(m, dst, [s16(min(32767, secs * 10 ** n)), secs], 16)


def stmr(m: Machine, s) -> None:
    """STMR S m D (FNC 65): timer S (100 ms) with setting m drives four outputs:
    D off-delay (On with the input, Off m after it goes Off), D+1 one shot after the input
    goes Off (On for m), D+2 one shot when it goes On (On for m, Off with the input), D+3
    On m after the input goes On, Off m after it goes Off (the page's flashing circuit: input
    = X20 AND NOT D+3 makes D+1 and D+2 alternate). S holds the 100 ms since the last edge
    (up to m); DECISION: the page's timing chart is lost, this is the FX behaviour it cites
    (Y20 off-delay, Y21 one shot at On->Off, Y22/Y23 the flashing pair)."""
    timer, mr, dst = s.ops
    memo = state(m, s, {"on": False, "since": None, "late": False})
    setting = mr.get(m)
    if not 1 <= setting <= 32767:
        op_error(m, s, f"m = {setting} is outside 1-32767")
        return
    on = bool(m.acc)
    if on != memo["on"]:  # an edge: "late" keeps whether D+3 was On when the input fell
        memo.update(on=on, since=m.now_us)
    if memo["since"] is None:  # never On yet: everything Off
        for k in range(4):
            dst.setbit(m, 0, k)
        return
    ticks = min(setting, (m.now_us - memo["since"]) // 100_000)
    done = ticks >= setting
    m.words["T"][timer.addr(m)] = ticks
    if on:
        outs = (1, 0, not done, done)
        memo["late"] = done
    else:
        outs = (not done, not done, 0, memo["late"] and not done)
    for k, v in enumerate(outs):
        dst.setbit(m, v, k)


# ------------------------------------------------------------------ ABSD, INCD (6-8)

def _counter_value(m: Machine, ref) -> int:
    return read_block(m, ref, 1, 32 if m.is_c32(ref.addr(m)) else 16)[0]


def absd(m: Machine, s) -> None:
    """ABSD S1 S2 D n (FNC 62, absolute cam): D+i On while S1[2i] <= counter S2 <= S1[2i+1]
    (pairs of 16-bit words; 32-bit: pairs of pairs); Off: the outputs keep their state.
    DECISION: a pair with lower > upper is On outside (upper, lower), the wrap of a cam."""
    if not m.acc:
        return
    table, ctr, dst, nr = s.ops
    n = count(m, nr)
    if not 1 <= n <= 64:
        op_error(m, s, f"n = {n} is outside 1-64")
        return
    limits = read_block(m, table, 2 * n, s.width)
    v = _counter_value(m, ctr)
    for i in range(n):
        lo, hi = limits[2 * i], limits[2 * i + 1]
        dst.setbit(m, lo <= v <= hi if lo <= hi else (v >= lo or v <= hi), i)


def incd(m: Machine, s) -> None:
    """INCD S1 S2 D n (FNC 63, relative cam): counter S2 is the program's (it counts what the
    program drives), S2+1 the step number: D+step is On; when S2 reaches S1[step], S2 is
    cleared and the next step begins; after the n-th, M9029 is On for one scan and step 0
    comes again. Off: S2 and S2+1 cleared, D..D+n-1 Off."""
    table, ctr, dst, nr = s.ops
    n = count(m, nr)
    c = ctr.addr(m)
    memo = state(m, s, {"flagged": False})
    if memo["flagged"]:
        set_relay(m, "done", False)
        memo["flagged"] = False
    if not m.acc:
        for k in (c, c + 1):
            m.reset_counter(k)
        for i in range(max(0, min(n, 64))):
            dst.setbit(m, 0, i)
        return
    if not 1 <= n <= 64:
        op_error(m, s, f"n = {n} is outside 1-64")
        return
    points = read_block(m, table, n, 16)
    step = m.cval[c + 1] % n
    if m.cval[c] >= points[step]:
        m.cval[c] = 0
        m.bits["C"][c] = 0
        step += 1
        if step == n:
            step = 0
            set_relay(m, "done", True)
            memo["flagged"] = True
        m.cval[c + 1] = step
    for i in range(n):
        dst.setbit(m, i == step, i)


# ------------------------------------------------------------------ RAMP (6-8)

def ramp(m: Machine, s) -> None:
    """RAMP S1 S2 D n (FNC 67): D goes from S1 to S2 in n executions (scans), D+1 counting
    them; D = S1 + (S2 - S1) x D+1 / n (dropped toward zero). At the n-th: M9029 On for one
    scan; M9026 Off: D back to S1, D+1 = 0, again; M9026 On: D stays at S2 (once). Off:
    D+1 = 0. DECISION: the completing scan already shows D = S1 in the repeating mode (the
    page: "執行完畢時M9029=ON，而D2的內容值被復歸成D0的設定值")."""
    s1, s2, dst, nr = s.ops
    memo = state(m, s, {"flagged": False})
    if memo["flagged"]:
        set_relay(m, "done", False)
        memo["flagged"] = False
    d = dst.block(m, 2)  # D and the count D+1 (also while Off)
    words = m.words[dst.kind]
    if not m.acc:
        words[d + 1] = 0
        return
    n = count(m, nr)
    if not 1 <= n <= 32767:
        op_error(m, s, f"n = {n} is outside 1-32767")
        return
    start, end = s1.get(m), s2.get(m)
    k = s16(words[d + 1])
    if k >= n:  # the single ramp is over (M9026 On)
        return
    k += 1
    if k >= n:
        set_relay(m, "done", True)
        memo["flagged"] = True
        if relay(m, "ramp_once"):
            value = end
        else:
            value, k = start, 0
    else:
        value = start + int((end - start) * k / n)
    write_block(m, dst, [value, k], 16)


# ------------------------------------------------------------------ RND, DUTY (6-16)

def rnd(m: Machine, s) -> None:
    """RND D (FNC 184): (D9161, D9160) = (D9161, D9160) x 1103515245 + 12345 (32 bits);
    D = bits 16-30 of it (0-32767). The pair is K1 at power-on (target.toml
    `[power_on]`), so a run is reproducible; a negative pair: operation error."""
    if not m.acc:
        return
    reg = special(m, "rnd_seed")
    words = m.words["D"]
    x = words[reg] | (words[reg + 1] << 16)
    if x & 0x80000000:
        op_error(m, s, f"(D{reg + 1}, D{reg}) = {s32(x)} is negative")
        return
    x = (x * 1103515245 + 12345) & 0xFFFFFFFF
    words[reg], words[reg + 1] = x & 0xFFFF, x >> 16
    m.writer[("D", reg)] = m.writer[("D", reg + 1)] = m.pc
    s.ops[0].set(m, (x >> 16) & 0x7FFF)


def duty(m: Machine, s) -> None:
    """DUTY n1 n2 D (FNC 186): D (M9330-M9334) On for n1 scans, Off for n2, counted in
    D9330-D9334 (cleared at n1 + n2 and at each Off->On of the condition). It starts at the
    condition's Off->On and does not stop when the condition goes Off (only a power cycle
    stops it). n1 = 0: D stays Off; n2 = 0 (n1 > 0): D stays On; n < 0 or D outside
    M9330-M9334: operation error."""
    n1r, n2r, dst = s.ops
    memo = state(m, s, {"was": False, "running": False})
    rising = m.acc and not memo["was"]
    memo["was"] = bool(m.acc)
    lo, hi = special(m, "duty_outputs")
    out = dst.addr(m)
    n1, n2 = n1r.get(m), n2r.get(m)
    if rising:
        if n1 < 0 or n2 < 0 or not lo <= out <= hi:
            op_error(m, s, f"n1 = {n1}, n2 = {n2}, {dst.text}: n >= 0, D = M{lo}-M{hi}")
            return
        memo["running"] = True
        m.words["D"][out] = 0
    elif not memo["running"]:
        return
    else:
        m.words["D"][out] = (m.words["D"][out] + 1) % max(1, n1 + n2)
    k = m.words["D"][out]
    dst.setbit(m, n1 > 0 and (n2 == 0 or k < n1))


TIMING_ACTIONS = {
    "wdt": wdt, "hour": hour, "tft": _register_timer(10), "tfh": _register_timer(100),
    "tfk": _register_timer(1000), "ttmr": ttmr, "stmr": stmr, "absd": absd, "incd": incd,
    "ramp": ramp, "rnd": rnd, "duty": duty,
}
