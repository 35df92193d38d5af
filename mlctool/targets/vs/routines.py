"""Vigor VS routines of the basic and chapter 4-5 instructions that the engine's generic
routines (sim/semantics.py) do not cover or cover differently: the step ladder (STL/RET),
master control (MC/MCR), result edges, ADD/SUB with the status flags, CMP/ZCP, XCH, BMOV,
FILL, SWAP, FLT/INT, SUM. Keyed by `op` like semantics.py; simulation.py merges them with the
chapter modules' tables into the target's Simulation.
"""

from __future__ import annotations

import math

from mlctool.sim import semantics as base
from mlctool.sim.decode import STL_JOINED
from mlctool.sim.operands import ConstRef, WordRef
from mlctool.sim.state import Machine, SimFault, bits_f32, f32_bits, put_words, s16, s32, to_f32
from mlctool.targets.vs.common import (  # set_flags: M9020 zero / M9021 borrow / M9022 carry
    count,
    op_error,
    read_block,
    relay,
    set_flags,
    write_block,
)

# ------------------------------------------------------------------ step ladder (4-6-1)

def stl(m: Machine, s):
    """STL Sn opens the step's bus: the rung result and every load inside are ANDed with Sn.

    An active step runs its block; in the scan after it went Off the block runs once more
    with the bus Off (its OUT coils and timers go Off); otherwise the block is not executed:
    the scan goes on at the next STL or RET (4-1-3, 4-6-1).

    STLs written one after the other are one block: the STL contacts of a parallel merge in
    series (4-3-3, 4-6-2: `STL S22 / STL S24 / LD X3 / SET S25`). Its bus is On only while
    every one of them is On, and a transfer from it resets all of them. decode.py marks an
    STL that the next one joins (target STL_JOINED); the block's last STL decides, for the
    whole merge, whether it runs."""
    n = s.ops[0].addr(m)
    if m.stl_joining:  # the STL before this one is joined by it: the same block goes on
        m.stl_steps = (*m.stl_steps, n)
        on = m.bus and bool(m.bits["S"][n])
    else:
        m.stl_steps = (n,)
        on = bool(m.bits["S"][n])
    m.bus = on
    m.acc = on
    m.blocks.clear()
    m.stack.clear()
    m.stl_joining = s.target == STL_JOINED
    if m.stl_joining:
        return None
    was_on = m.edge[s.index]
    m.edge[s.index] = on
    if not on and not was_on and s.target >= 0:
        return s.target
    return None


def ret(m: Machine, s) -> None:
    m.stl_steps = ()
    m.stl_joining = False
    m.bus = m.mc_stack[-1] if m.mc_stack else True
    m.acc = False


def _transfer(m: Machine, s) -> None:
    """SET/OUT Sx inside an active step: Sx On now, the source steps (every step of a merge,
    4-3-3) Off at the end of the scan (both are On for the rest of the transfer scan, 4-1-3);
    M9040 inhibits transfers."""
    relay = m.target.settings.get("stl_inhibit_relay")
    if relay is not None and m.bits["M"][relay]:
        return
    s.ops[0].setbit(m, 1)
    n = s.ops[0].addr(m)
    m.stl_leaving.update(k for k in m.stl_steps if k != n)


def step_set(m: Machine, s) -> None:
    if m.acc:
        if m.stl_steps:
            _transfer(m, s)
        else:
            s.ops[0].setbit(m, 1)


def step_out(m: Machine, s) -> None:
    if not m.stl_steps:
        s.ops[0].setbit(m, m.acc)  # an ordinary coil outside step ladder
    elif m.acc:
        _transfer(m, s)


# ------------------------------------------------------------------ master control (3-6)

def mc(m: Machine, s) -> None:
    """MC Nn moves the rail behind its condition: level n's rail is the outer rail AND the
    condition. m.mc_stack holds the rail inside each open level, innermost last (RET after a
    step ladder inside the block goes back to it)."""
    m.bus = m.bus and m.acc
    m.mc_stack.append(m.bus)


def mcr(m: Machine, s) -> None:
    """MCR Nn closes level n and every deeper one: the rail is level n-1's again (the
    left-hand rail after MCR N0)."""
    n = s.ins.operands[0].number
    if n < len(m.mc_stack):
        m.bus = m.mc_stack[n - 1] if n else True
        del m.mc_stack[n:]
    m.acc = False


def result_rise(m: Machine, s) -> None:
    """MEP: the result so far, On only in the scan it goes Off->On (3-3)."""
    prev = m.edge[s.index]
    m.edge[s.index] = m.acc
    m.acc = bool(m.acc and not prev)


def result_fall(m: Machine, s) -> None:
    prev = m.edge[s.index]
    m.edge[s.index] = m.acc
    m.acc = bool(prev and not m.acc)


# ------------------------------------------------------------------ arithmetic with flags (5-3)


def _add_sub(sign: int):
    @base._on
    def run(m: Machine, s) -> None:
        r = s.ops[0].get(m) + sign * s.ops[1].get(m)
        w = s.width
        lo, hi = -(1 << (w - 1)), (1 << (w - 1)) - 1
        wrapped = s32(r) if w == 32 else s16(r)
        s.ops[2].set(m, wrapped)
        set_flags(m, zero=wrapped == 0, carry=r > hi, borrow=r < lo)
    return run


# ------------------------------------------------------------------ data (ch. 6)

def _words(m: Machine, ref, count: int) -> tuple[list, int]:
    if not isinstance(ref, WordRef):
        raise SimFault(f"{ref.text}: block operands of word devices only are simulated")
    return m.words[ref.kind], ref.addr(m, count)


@base._on
def cmp3(m: Machine, s) -> None:
    """CMP S1 S2 D: D = S1 > S2, D+1 = S1 = S2, D+2 = S1 < S2 (FNC 10)."""
    a, b = s.ops[0].get(m), s.ops[1].get(m)
    for k, on in enumerate((a > b, a == b, a < b)):
        s.ops[2].setbit(m, on, k)


@base._on
def zcp(m: Machine, s) -> None:
    """ZCP S1 S2 S D: D = S < S1, D+1 = S1 <= S <= S2, D+2 = S > S2; S1 > S2 uses S1 as both (FNC 11)."""
    lo, hi, v = s.ops[0].get(m), s.ops[1].get(m), s.ops[2].get(m)
    hi = max(lo, hi) if lo <= hi else lo
    for k, on in enumerate((v < lo, lo <= v <= hi, v > hi)):
        s.ops[3].setbit(m, on, k)


@base._on
def xch(m: Machine, s) -> None:
    """XCH D1 D2 exchanges the two (FNC 17); M9160 On makes it SWAP (2-14-1 "指定XCH指令執行
    SWAP功能"). DECISION: as FX's M8160, the bytes of each word of D1 are exchanged when D1
    and D2 are one device; two different devices are an operation error (6705)."""
    d1, d2 = s.ops
    if relay(m, "xch_swap"):
        if d1.text != d2.text:
            op_error(m, s, f"M9160 On (SWAP) needs D1 = D2, not {d1.text} and {d2.text}", code=6705)
            return
        _swap(m, s)
        return
    a, b = d1.get(m), d2.get(m)
    d1.set(m, b)
    d2.set(m, a)


@base._on
def bmov(m: Machine, s) -> None:
    """BMOV S D n: n words or Kn groups; overlapping blocks copied in the order that keeps
    S (the whole block is read before it is written); M9024 On turns the direction round,
    D -> S (FNC 15, 2-14-1)."""
    src, dst = s.ops[0], s.ops[1]
    n = count(m, s.ops[2])
    if not 1 <= n <= 512:
        op_error(m, s, f"n = {n} is outside 1-512")
        return
    if relay(m, "bmov_reverse"):
        src, dst = dst, src
    if isinstance(src, WordRef) and isinstance(dst, WordRef) and src.kind != "C" and dst.kind != "C":
        words_s, a = _words(m, src, n)
        words_d, b = _words(m, dst, n)
        # DECISION (as FMOV and MEAN, 6-3/6-6 "只有有效範圍會被傳送"): a block running past the
        # device's end moves only the part inside both ranges
        n = max(0, min(n, len(words_s) - a, len(words_d) - b))
        put_words(words_d, b, words_s[a:a + n])
        for k in range(n):
            m.writer[(dst.kind, b + k)] = m.pc
        return
    write_block(m, dst, read_block(m, src, n, 16), 16)


@base._on
def fill(m: Machine, s) -> None:
    """FMOV S D n: S into n destinations (32-bit: n pairs) (FNC 16)."""
    n = s.ops[2].get(m)
    size = 2 if s.width == 32 else 1
    dst, b = _words(m, s.ops[1], n * size)
    n = max(0, min(n, (len(dst) - b) // size))  # "只有有效範圍會被傳送" (6-3 FMOV)
    v = s.ops[0].get(m)
    for k in range(n):
        dst[b + k * size] = v & 0xFFFF
        if size == 2:
            dst[b + k * size + 1] = (v >> 16) & 0xFFFF
    for k in range(n * size):
        m.writer[(s.ops[1].kind, b + k)] = m.pc


def _swap(m: Machine, s) -> None:
    v = s.ops[0].get(m) & (0xFFFFFFFF if s.width == 32 else 0xFFFF)
    words = [(v >> (16 * k)) & 0xFFFF for k in range(s.width // 16)]
    r = sum((((w & 0xFF) << 8) | (w >> 8)) << (16 * k) for k, w in enumerate(words))
    s.ops[0].set(m, r)


swap = base._on(_swap)
swap.__doc__ = "SWAP S: the bytes of each word exchanged (FNC 147)."


def _pair(m: Machine, ref) -> tuple[list, int]:
    """The two words of a float operand, whatever the instruction's width (FLT D, INT S)."""
    if not isinstance(ref, WordRef):
        raise SimFault(f"{ref.text}: a float is a pair of word registers")
    return m.words[ref.kind], ref.block(m, 2)


@base._on
def flt(m: Machine, s) -> None:
    """FLT S D: integer -> binary float; D is always a pair (FNC 49)."""
    words, a = _pair(m, s.ops[1])
    raw = f32_bits(float(s.ops[0].get(m)))
    words[a], words[a + 1] = raw & 0xFFFF, raw >> 16
    m.writer[(s.ops[1].kind, a)] = m.writer[(s.ops[1].kind, a + 1)] = m.pc


@base._on
def int_(m: Machine, s) -> None:
    """INT S D: binary float (a pair) -> integer, fraction dropped (FNC 129)."""
    src = s.ops[0]
    if isinstance(src, ConstRef):  # K/H/E converted to a float (5-1)
        x = to_f32(src.getf(m))
    else:
        words, a = _pair(m, src)
        x = to_f32(bits_f32(words[a] | (words[a + 1] << 16)))
    lo, hi = (-(1 << 31), (1 << 31) - 1) if s.width == 32 else (-32768, 32767)
    if not math.isfinite(x) or not lo <= math.trunc(x) <= hi:
        set_flags(m, carry=True)
        return
    r = math.trunc(x)
    s.ops[1].set(m, r)
    set_flags(m, zero=r == 0, borrow=r != x)


@base._on
def sum_bits(m: Machine, s) -> None:
    """SUM S D: number of 1 bits of S (FNC 43)."""
    v = s.ops[0].get(m) & (0xFFFFFFFF if s.width == 32 else 0xFFFF)
    r = bin(v).count("1")
    s.ops[1].set(m, r)
    set_flags(m, zero=r == 0)


# ------------------------------------------------------------------ counters (2-6, 3-9)

def counter(m: Machine, s) -> None:
    """OUT C: counts the Off->On edges of its rung (2-6).

    16-bit C0-C199: up to the preset (outside 1-32767 taken as 1, 3-9), then the value and
    the contact hold. A value at or above the preset that did not come from counting (a MOV
    into the counter, a preset lowered below it) changes nothing until the next count input,
    which turns the contact On and makes the value the preset (2-6-1 "在下次計數輸入信號ON時，
    則接點立即變成ON，同時現在值內容變成與設定值相同"). DECISION: the contact changes when OUT C
    executes ("立即", as the 32-bit counters' and FX's), so a contact after the coil sees it in
    the same scan (NC5's counters set theirs at the end of the scan).

    32-bit C200-C234: up, or down while M9200+n is On; the value goes on past the preset and
    wraps at +-2^31. The contact turns On when a count up reaches the preset (preset-1 ->
    preset) and Off when a count down leaves it (preset -> preset-1), the page's -6 -> -5 /
    -5 -> -6 (2-6-2); any other count leaves it alone, so a value DMOVed past the preset
    counts "but the contact does not change" (2-6-2). DECISION: the contact follows those two
    transitions only (the table's 上數到達設定值時ON, 下數到達設定值時OFF)."""
    prev = m.edge[s.index]
    m.edge[s.index] = m.acc
    rise = m.acc and not prev
    n = s.ops[0].addr(m)
    settings = m.target.settings
    if m.is_c32(n):
        if not rise:
            return
        down = m.bits["M"][settings["counter_direction_base"] + n - m.c32_lo]
        old = s32(m.cval[n])
        new = s32(old + (-1 if down else 1))
        m.cval[n] = new
        m.writer[("C", n)] = m.pc
        preset = s.ops[1].get(m)
        if not down and new == preset:
            m.bits["C"][n] = 1
        elif down and old == preset:
            m.bits["C"][n] = 0
        return
    raw = s.ops[1].get(m)
    lo, hi = settings["counter16_preset_range"]
    preset = raw if lo <= raw <= hi else 1
    if not rise:
        return
    v = m.cval[n]
    m.cval[n] = v + 1 if v < preset else preset
    m.writer[("C", n)] = m.pc
    if m.cval[n] >= preset:
        m.bits["C"][n] = 1


# ------------------------------------------------------------------ rotation (6-5)

def _rotate(left: bool):
    """ROR/ROL D n: D turns n bits (0-16, 32-bit 0-32); the last bit out goes to the carry
    M9022 (FNC 30/31 "並將被旋出的資料傳送到進制標誌位M9022中"). n = 0 moves nothing and
    leaves M9022 alone; n outside the range (a register) is an operation error."""
    @base._on
    def run(m: Machine, s) -> None:
        w = s.width
        mask = (1 << w) - 1
        n = count(m, s.ops[1])
        if not 0 <= n <= w:
            op_error(m, s, f"n = {n} is outside 0-{w}")
            return
        if n == 0:
            return
        v = s.ops[0].get(m) & mask
        k = n % w
        r = (((v << k) | (v >> (w - k))) if left else ((v >> k) | (v << (w - k)))) & mask
        s.ops[0].set(m, r)
        set_flags(m, carry=bool(r & 1) if left else bool(r >> (w - 1)))
    return run


@base._on
def zrst(m: Machine, s) -> None:
    """ZRST D1 D2: D1..D2 reset; D1 > D2 resets only D1 (6-6 "當D1 > D2的號碼時，只有D1所指定
    的元件被復歸"), not D2 as on NC5."""
    d1, d2 = s.ops
    a, b = d1.addr(m), d2.addr(m)
    for k in range(a, max(a, b) + 1):
        base.clear(m, d1, k)


# ------------------------------------------------------------------ step monitor (4-5)

def step_monitor(m: Machine) -> None:
    """M9047 On: D9040-D9047 hold the numbers of the On step relays, lowest first (0 past the
    last), M9046 is On when some step is (4-5). DECISION: refreshed before every scan (the
    END of the previous one), so the program reads the steps as the last scan left them;
    with M9047 Off they are left as they are."""
    mon = m.target.settings["step_monitor"]
    if not m.bits["M"][mon["enable"]]:
        return
    first, last = mon["registers"]
    on = [n for n, b in enumerate(m.bits["S"]) if b][:last - first + 1]
    for k in range(last - first + 1):
        m.words["D"][first + k] = on[k] if k < len(on) else 0
    m.bits["M"][mon["any"]] = 1 if on else 0


# ------------------------------------------------------------------ device clear (2-14-1)

def device_clear(m: Machine) -> None:
    """M9031 On: every non-latched Y, M, S, T, C, D, R is cleared, the special relays and
    registers excepted; M9032 On: every latched one (2-14-1). DECISION: done before each scan
    the relay is On (the END of the scan that turned it On), as FX M8031/M8032 do at END."""
    cfg = m.target.settings["device_clear"]
    which = {latched for relay, latched in ((cfg["non_latched"], False), (cfg["latched"], True))
             if m.bits["M"][relay]}
    if not which:
        return
    for kind in cfg["kinds"]:
        for a in m.target.devices[kind].areas:
            if a.latched not in which or "special" in a.name or a.write == "absent":
                continue
            for n in range(a.lo, a.hi + 1):
                base.reset_device(m, kind, n)


BASIC_ACTIONS = {
    "stl": stl, "ret": ret, "step_set": step_set, "step_out": step_out, "mc": mc, "mcr": mcr,
    "result_rise": result_rise, "result_fall": result_fall,
    "add": _add_sub(1), "sub": _add_sub(-1),
    "cmp": cmp3, "zcp": zcp, "xch": xch, "bmov": bmov, "fill": fill, "swap": swap,
    "flt": flt, "int": int_, "sum": sum_bits, "fcmp3": base.fcmp,
    "ror": _rotate(False), "rol": _rotate(True), "zrst": zrst,  # OUT C: hsc.counter_coil
}
