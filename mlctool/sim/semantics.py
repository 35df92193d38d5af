"""One routine per `op` of instructions.toml (manual ch. 2 and ch. 4).

Contacts (`CONTACTS`) return the contact's state; the scan combines it with the rung
according to the instruction's class (load / and / or). Everything else (`ACTIONS`) reads
the rung result `m.acc`. Application instructions are continuous-execution (3.2.4): they run
on every scan whose condition is On and leave their destination alone otherwise (4.2 MOV).
There are no status flags (every page: 旗標信號：無). Program flow (CJ, CALL, FOR ...)
lives in scan.py.
"""

from __future__ import annotations

import math
import operator

from mlctool.sim.operands import BitRef, ConstRef, WordBitRef
from mlctool.sim.state import F32_QUIET_NAN, Machine, bits_f32, f32_bits, s32, to_f32

ARITH_ALARM = "MLC_ARITH_ERROR"  # named by 4.3 API-16 (DIV by 0)
OPERATION_ALARM = "OPERATION_ERROR"  # 4.8 API-61 "運算錯誤"; also our undefined-input cases


def alarm(m: Machine, name: str, message: str) -> None:
    """A fault the manual names or that leaves the instruction not executed: recorded, run goes on.

    Targets with error registers (target.toml `operation_error`, VS M9067/D9067) also get
    the relay On and the code in the register: the target's code for this alarm
    (`operation_error.codes`, VS CALL_NESTING 6702), else its default code."""
    m.alarms.append((m.now_us, m.pc, name, message))
    err = m.target.settings.get("operation_error")
    codes = err.get("codes", {}) if err else {}
    if err and (name in (ARITH_ALARM, OPERATION_ALARM) or name in codes):
        m.bits["M"][err["relay"]] = 1
        m.words["D"][err["register"]] = codes.get(name, err["code"])
        for n in err.get("also_relays", ()):
            m.bits["M"][n] = 1


def warn(m: Machine, code: str, message: str) -> None:
    """A run-time warning (a W code of codes.toml): the PLC goes on as the manual says, but
    what happened is likely not what the program meant (W330: a positioning instruction
    started on an empty table). Reported at the instruction, once per instruction and
    message in a run; it does not fail the run."""
    m.warnings.append((m.now_us, m.pc, code, message))


# the generic ops whose routines set the target's status flags (set_flags: here and in
# targets/vs/routines.py); on a target with flags the compiled engine keeps their routines
FLAG_OPS = frozenset({"add", "sub", "mul", "div", "fadd", "fsub", "fmul", "fdiv", "int", "sum"})


def set_flags(m: Machine, **values: bool) -> None:
    """M9020 zero / M9021 borrow / M9022 carry ... (target.toml [flags]); none on NC5."""
    flags = m.target.settings.get("flags", {})
    for name, on in values.items():
        if name in flags:
            m.bits["M"][flags[name]] = 1 if on else 0


def _mask(width: int) -> int:
    return 0xFFFFFFFF if width == 32 else 0xFFFF


# ------------------------------------------------------------------ contacts (2.2, 4.7)

def contact(m: Machine, s) -> bool:
    return bool(s.ops[0].bit(m))


def contact_not(m: Machine, s) -> bool:
    return not s.ops[0].bit(m)


def contact_rise(m: Machine, s) -> bool:
    """LDP/ANDP/ORP: On for the one execution that sees the device go Off->On.

    Each instruction keeps its own memory of the state it saw last time it executed.
    """
    cur = s.ops[0].bit(m)
    prev = m.edge[s.index]
    m.edge[s.index] = cur
    return bool(cur and not prev)


def contact_fall(m: Machine, s) -> bool:
    cur = s.ops[0].bit(m)
    prev = m.edge[s.index]
    m.edge[s.index] = cur
    return bool(prev and not cur)


def _compare(rel):
    def run(m: Machine, s) -> bool:
        return rel(s.ops[0].get(m), s.ops[1].get(m))
    return run


CONTACTS = {
    "contact": contact, "contact_not": contact_not,
    "contact_rise": contact_rise, "contact_fall": contact_fall,
    "cmp_eq": _compare(operator.eq), "cmp_ne": _compare(operator.ne),
    "cmp_gt": _compare(operator.gt), "cmp_lt": _compare(operator.lt),
    "cmp_ge": _compare(operator.ge), "cmp_le": _compare(operator.le),
}


# ------------------------------------------------------------------ block and stack operators

def anb(m: Machine, s) -> None:
    m.acc = m.blocks.pop() and m.acc if m.blocks else m.acc


def orb(m: Machine, s) -> None:
    m.acc = (m.blocks.pop() or m.acc) if m.blocks else m.acc


def mps(m: Machine, s) -> None:
    m.stack.append(m.acc)


def mrd(m: Machine, s) -> None:
    if m.stack:
        m.acc = m.stack[-1]


def mpp(m: Machine, s) -> None:
    if m.stack:
        m.acc = m.stack.pop()


def inv(m: Machine, s) -> None:
    m.acc = not m.acc


def nop(m: Machine, s) -> None:
    """NOP and P labels keep the current result (2.2 NOP)."""


# ------------------------------------------------------------------ coils (2.2)

def out(m: Machine, s) -> None:
    s.ops[0].setbit(m, m.acc)


def set_(m: Machine, s) -> None:
    if m.acc:
        s.ops[0].setbit(m, 1)


def rst(m: Machine, s) -> None:
    """2.2 RST: Y/M/A Off; T/C value 0 and contact Off; D/V/Z 0; a word's bit (D0.5) Off."""
    if m.acc:
        if isinstance(s.ops[0], WordBitRef):  # only that bit, never the whole word
            s.ops[0].setbit(m, 0)
            return
        clear(m, s.ops[0], s.ops[0].addr(m))


def reset_device(m: Machine, kind: str, a: int) -> None:
    """Device `kind` number `a` to Off/0 (a timer or counter: value, contact and state)."""
    if kind == "T":
        m.reset_timer(a)
    elif kind == "C":
        m.reset_counter(a)
    elif kind in m.bits:
        m.bits[kind][a] = 0
    else:
        m.words[kind][a] = 0


def clear(m: Machine, ref, a: int) -> None:
    reset_device(m, ref.kind, a)
    m.writer[(ref.kind, a)] = m.pc


def pls(m: Machine, s) -> None:
    """PLS: D On for one scan after the condition goes Off->On (2.2 PLS)."""
    prev = m.edge[s.index]
    m.edge[s.index] = m.acc
    s.ops[0].setbit(m, m.acc and not prev)


def plf(m: Machine, s) -> None:
    prev = m.edge[s.index]
    m.edge[s.index] = m.acc
    s.ops[0].setbit(m, prev and not m.acc)


# ------------------------------------------------------------------ timers and counters (1.6, 1.7)

def tmr(m: Machine, s) -> None:
    """TMR: counts base ticks of virtual time while its rung is On; Off clears it (2.2 TMR).

    The value advances by the whole ticks elapsed since the timer's last update and stops at
    the preset; the contact is On while value >= preset (1.6.1).
    """
    n = s.ops[0].addr(m)
    m.t_seen[n] = 1
    base = m.target.timer_base(n)
    if not m.acc:
        if base.get("retentive"):  # retentive timers hold their value; only RST clears them
            m.t_running[n] = 0
        else:
            m.reset_timer(n)
        return
    m.writer[("T", n)] = m.pc
    preset = s.ops[1].get(m)
    rng = m.target.settings.get("timer_preset_range")
    if rng is not None and not rng[0] <= preset <= rng[1]:
        preset = 0  # VS 3-9: a preset outside 0-32767 is taken as 0
    advance_timer(m, n, preset & 0xFFFF)


def advance_timer(m: Machine, n: int, preset: int) -> None:
    m.t_preset[n] = preset
    if not m.t_running[n]:
        m.t_running[n] = 1
        m.t_last[n] = m.now_us
        m.t_frac[n] = 0
    else:
        ticks, m.t_frac[n] = divmod(m.now_us - m.t_last[n] + m.t_frac[n], m.timer_base_us(n))
        m.t_last[n] = m.now_us
        v = m.words["T"][n]
        if v < preset:
            m.words["T"][n] = min(v + ticks, preset)
    m.bits["T"][n] = 1 if m.words["T"][n] >= preset else 0


def cnt(m: Machine, s) -> None:
    """CNT/DCNT: +1 on each Off->On of the rung (2.2 CNT); stops at the preset (1.7).

    16-bit: preset K0 acts as K1. 32-bit: wraps at 2^31-1; counts down while its direction
    relay (target.toml counter_direction_base) is On. The contact is set at the end of the
    scan (1.7 table: "在掃描結束時，統一執行所規劃的接點動作").
    """
    prev = m.edge[s.index]
    m.edge[s.index] = m.acc
    n = s.ops[0].addr(m)
    if m.is_c32(n) and m.target.settings.get("counter32_mode") == "fx":
        # VS 2-6-2: counts past the preset both ways; contact On at value >= preset
        if m.acc and not prev:
            down = m.bits["M"][m.target.settings["counter_direction_base"] + n - m.c32_lo]
            m.cval[n] = s32(m.cval[n] + (-1 if down else 1))
            m.writer[("C", n)] = m.pc
            m.bits["C"][n] = 1 if m.cval[n] >= s.ops[1].get(m) else 0
        return
    if m.is_c32(n):
        preset = s.ops[1].get(m)
        reached = m.bits["C"][n] or n in m.c_pending
        if m.acc and not prev and not reached:
            base = m.target.settings.get("counter_direction_base")
            k = n - m.c32_lo
            down = base is not None and k < m.target.settings.get("counter_direction_count", 0) \
                and m.bits["M"][base + k]
            m.cval[n] = s32(m.cval[n] + (-1 if down else 1))
            m.writer[("C", n)] = m.pc
        if m.cval[n] == preset and not m.bits["C"][n]:
            m.c_pending[n] = 1
        return
    preset = max(s.ops[1].get(m) & 0xFFFF, 1)
    rng = m.target.settings.get("counter16_preset_range")
    if rng is not None and not rng[0] <= s.ops[1].get(m) <= rng[1]:
        preset = 1  # VS 3-9: a preset outside 1-32767 is taken as 1
    v = m.cval[n]
    if m.acc and not prev and v < preset:
        v += 1
        m.cval[n] = v
        m.writer[("C", n)] = m.pc
    if v >= preset and not m.bits["C"][n]:
        m.c_pending[n] = 1


# ------------------------------------------------------------------ application instructions

def _on(fn):
    """Application instruction: executed only while the rung is On."""
    def run(m: Machine, s) -> None:
        if m.acc:
            fn(m, s)
    run.__name__ = fn.__name__
    return run


@_on
def mov(m: Machine, s) -> None:
    s.ops[1].set(m, s.ops[0].get(m))


@_on
def fmov(m: Machine, s) -> None:
    """FMOV (API-67): a float move. Constants become floats; registers are copied as they are."""
    src, dst = s.ops
    if isinstance(src, ConstRef):
        dst.set(m, f32_bits(to_f32(src.getf(m))))
    else:
        dst.set(m, src.get(m))


@_on
def cml(m: Machine, s) -> None:
    s.ops[1].set(m, ~s.ops[0].get(m))


@_on
def bcd(m: Machine, s) -> None:
    v = s.ops[0].get(m)
    limit = 99_999_999 if s.width == 32 else 9_999
    if not 0 <= v <= limit:
        alarm(m, OPERATION_ALARM, f"{s.ins.mnemonic}: {v} is outside 0-{limit}; not executed")
        return
    out_v = 0
    for k, digit in enumerate(reversed(str(v))):
        out_v |= int(digit) << (4 * k)
    s.ops[1].set(m, out_v)


@_on
def bin_(m: Machine, s) -> None:
    raw = s.ops[0].get(m) & _mask(s.width)
    v = 0
    for k in reversed(range(s.width // 4)):
        digit = (raw >> (4 * k)) & 0xF
        if digit > 9:
            alarm(m, OPERATION_ALARM, f"{s.ins.mnemonic}: {raw:#x} is not BCD; not executed")
            return
        v = v * 10 + digit
    s.ops[1].set(m, v)


def _arith(fn):
    @_on
    def run(m: Machine, s) -> None:
        s.ops[2].set(m, fn(s.ops[0].get(m), s.ops[1].get(m)))
    return run


@_on
def mul(m: Machine, s) -> None:
    """16-bit: 32-bit product in (D+1, D); 32-bit: 64-bit product in D..D+3 (4.3 API-15)."""
    p = s.ops[0].get(m) * s.ops[1].get(m)
    n = 2 if s.width == 16 else 4
    s.ops[2].set_words(m, [(p >> (16 * k)) & 0xFFFF for k in range(n)])
    set_flags(m, mul_div_zero=p == 0)  # VS 6-4 MUL: M9023 when the product is 0


@_on
def div(m: Machine, s) -> None:
    """Quotient in D, remainder after it (4.3 API-16); truncates toward zero. /0: alarm."""
    a, b = s.ops[0].get(m), s.ops[1].get(m)
    if b == 0:
        alarm(m, ARITH_ALARM, f"{s.ins.mnemonic}: divisor is 0; not executed")
        return
    q = abs(a) // abs(b) * (1 if (a < 0) == (b < 0) else -1)
    r = a - q * b
    if s.width == 16:
        words = [q & 0xFFFF, r & 0xFFFF]
    else:
        words = [q & 0xFFFF, (q >> 16) & 0xFFFF, r & 0xFFFF, (r >> 16) & 0xFFFF]
    s.ops[2].set_words(m, words)
    # VS 6-4 DIV: M9023 when the quotient is 0, M9025 when it passes 32,767 / 2,147,483,647
    set_flags(m, mul_div_zero=q == 0, div_overflow=q > _mask(s.width) >> 1)


def _unary(fn):
    @_on
    def run(m: Machine, s) -> None:
        s.ops[0].set(m, fn(s.ops[0].get(m)))
    return run


def _rotate(left: bool):
    @_on
    def run(m: Machine, s) -> None:
        w = s.width
        v = s.ops[0].get(m) & _mask(w)
        n = s.ops[1].get(m) % w
        r = ((v << n) | (v >> (w - n))) if left else ((v >> n) | (v << (w - n)))
        s.ops[0].set(m, r & _mask(w))
    return run


@_on
def zrst(m: Machine, s) -> None:
    """ZRST D1 D2 (4.5 API-25): clears D1..D2; if D1 > D2 only D2 is cleared."""
    d1, d2 = s.ops
    b = d2.addr(m)
    a = d1.addr(m)
    if a > b:
        a = b
    for k in range(a, b + 1):
        clear(m, d2, k)


def _source_bits(m: Machine, ref, count: int) -> int:
    """`count` bits from a bit-device start, or the low bits of a word/constant."""
    if isinstance(ref, BitRef):
        a = ref.block(m, count)
        bits = m.bits[ref.kind]
        return sum(bits[a + i] << i for i in range(count))
    return ref.get(m) & ((1 << count) - 1)


def count_in(m: Machine, s, k: int, value: int | None = None, limit: tuple[int, int] | None = None) -> int | None:
    """Operand k's value (a count: n of DECO, BON, SFRD ...; `value` when the routine reads
    it its own way) if it lies in the range the table gives the operand for this form
    (`limit` where the page narrows it), else None: an operation error, the instruction not
    executed. The checker holds a constant to the range (E206); a count in a register or an
    index-modified constant is known at run time only."""
    n = s.ops[k].get(m) if value is None else value
    o = s.ins.spec.operands[k]
    rng = limit or (o.range32 if s.width == 32 else o.range16)
    if rng is None or rng[0] <= n <= rng[1]:
        return n
    alarm(m, OPERATION_ALARM, f"{s.ins.mnemonic}: {o.role} = {n} is outside {rng[0]}-{rng[1]}; not executed")
    return None


@_on
def deco(m: Machine, s) -> None:
    """DECO S D n: bit (value of S's low n bits) of D's 2^n bits On, the others Off (API-26)."""
    src, dst, _ = s.ops
    bits = isinstance(dst, BitRef)
    n = count_in(m, s, 2, limit=None if bits else (1, 4))
    if n is None:
        return
    v = _source_bits(m, src, n)
    if bits:
        dst.block(m, 1 << n)  # the whole block exists before any bit of it is written
        for i in range(1 << n):
            dst.setbit(m, i == v, i)
    else:
        dst.set(m, 1 << v)  # bits above 2^n become 0 (example 2)


@_on
def enco(m: Machine, s) -> None:
    """ENCO S D n: number of the highest On bit among S's low 2^n bits (API-27)."""
    src, dst, _ = s.ops
    n = count_in(m, s, 2, limit=None if isinstance(src, BitRef) else (1, 4))
    if n is None:
        return
    v = _source_bits(m, src, 1 << n)
    if v == 0:
        alarm(m, OPERATION_ALARM, "ENCO: no source bit is On; not executed")
        return
    dst.set(m, v.bit_length() - 1)


@_on
def bon(m: Machine, s) -> None:
    src, dst, _ = s.ops
    n = count_in(m, s, 2)
    if n is not None:
        dst.setbit(m, (src.get(m) >> n) & 1)


@_on
def alt(m: Machine, s) -> None:
    """ALT toggles D on every scan its condition is On (continuous execution, 3.2.4)."""
    s.ops[0].setbit(m, not s.ops[0].bit(m))


@_on
def vrt(m: Machine, s) -> None:
    """VRT S n D: the n bits from S (S = bit 0) index the 64-entry table (API-57)."""
    src, _, dst = s.ops
    n = count_in(m, s, 1)
    if n is not None:
        dst.set(m, s.table[_source_bits(m, src, n)])


_F32_MIN = 2.0 ** -126  # the smallest normal single-precision magnitude (VS 2-13)
_QUIET_NAN = bits_f32(F32_QUIET_NAN)  # every NaN result (state.F32_QUIET_NAN)


def _float(fn):
    @_on
    def run(m: Machine, s) -> None:
        a, b = to_f32(s.ops[0].getf(m)), to_f32(s.ops[1].getf(m))
        r = fn(m, s, a, b)
        if r is not None:
            s.ops[2].setf(m, r if r == r else _QUIET_NAN)
            # targets with flags (VS 6-12 EADD-EDIV): zero; carry past the largest magnitude
            # (D holds the infinity); borrow below the smallest (D holds what single precision
            # keeps: a subnormal or 0). DECISION: judged on the exact result, before rounding
            if m.target.settings.get("flags"):
                set_flags(m, zero=r == 0, carry=math.isinf(to_f32(r)), borrow=0 < abs(r) < _F32_MIN)
    return run


def _fdiv(m: Machine, s, a: float, b: float) -> float | None:
    if b == 0:
        alarm(m, OPERATION_ALARM, "FDIV: divisor is 0 (運算錯誤); not executed")
        return None
    return a / b


@_on
def fcmp(m: Machine, s) -> None:
    """FCMP: D = S1 > S2, D+1 = S1 = S2, D+2 = S1 < S2 (order of '(>、=、<)')."""
    a, b = to_f32(s.ops[0].getf(m)), to_f32(s.ops[1].getf(m))
    for k, on in enumerate((a > b, a == b, a < b)):
        s.ops[2].setbit(m, on, k)


@_on
def fint(m: Machine, s) -> None:
    x = to_f32(s.ops[0].getf(m))
    if not math.isfinite(x) or not -2**31 <= math.trunc(x) < 2**31:
        alarm(m, OPERATION_ALARM, f"FINT: {x} does not fit 32 bits; not executed")
        return
    s.ops[1].set(m, math.trunc(x))


@_on
def fdot(m: Machine, s) -> None:
    src = s.ops[0]
    v = math.trunc(src.value) if isinstance(src, ConstRef) else src.get(m)
    s.ops[1].setf(m, float(v))


def _fconv(factor: float):
    @_on
    def run(m: Machine, s) -> None:
        s.ops[1].setf(m, to_f32(s.ops[0].getf(m)) * factor)
    return run


@_on
def wrtl(m: Machine, s) -> None:
    """WRTL S D: torque limit D for servo station S (4.9 API-68), kept in the servo table."""
    m.servo_limit[s.ops[0].get(m)] = s.ops[1].get(m)


@_on
def rdtl(m: Machine, s) -> None:
    """RDTL S D: D = station S's torque-limit-reached flag (4.9 API-69), from the servo table."""
    flag = 1 if m.servo_at_limit.get(s.ops[0].get(m)) else 0
    dst = s.ops[1]
    if isinstance(dst, BitRef):
        dst.setbit(m, flag)
    else:
        dst.set(m, flag)


ACTIONS = {
    "anb": anb, "orb": orb, "mps": mps, "mrd": mrd, "mpp": mpp, "inv": inv, "nop": nop,
    "label": nop,
    "out": out, "set": set_, "rst": rst, "pls": pls, "plf": plf, "tmr": tmr, "cnt": cnt,
    "mov": mov, "fmov": fmov, "cml": cml, "bcd": bcd, "bin": bin_,
    "add": _arith(operator.add), "sub": _arith(operator.sub), "mul": mul, "div": div,
    "wand": _arith(operator.and_), "wor": _arith(operator.or_), "wxor": _arith(operator.xor),
    "inc": _unary(lambda v: v + 1), "dec": _unary(lambda v: v - 1), "neg": _unary(operator.neg),
    "ror": _rotate(False), "rol": _rotate(True),
    "zrst": zrst, "deco": deco, "enco": enco, "bon": bon, "alt": alt, "vrt": vrt,
    "fadd": _float(lambda m, s, a, b: a + b), "fsub": _float(lambda m, s, a, b: a - b),
    "fmul": _float(lambda m, s, a, b: a * b), "fdiv": _float(_fdiv),
    "fcmp": fcmp, "fint": fint, "fdot": fdot,
    "frad": _fconv(math.pi / 180), "fdeg": _fconv(180 / math.pi),
    "wrtl": wrtl, "rdtl": rdtl,
}
