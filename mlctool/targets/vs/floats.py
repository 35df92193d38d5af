"""The D-float family (manual 6-12, FNC 111-135): zone compare, decimal floats, exp/log,
square root, negation, trigonometry. Operands are binary floats in register pairs; K/H
constants are converted to float first ("來源運算元指定常數K或H時 ... 先變換為2進制浮點數")."""

from __future__ import annotations

import math
from decimal import ROUND_HALF_UP, Decimal

from mlctool.sim import semantics as base
from mlctool.sim.state import Machine, f32_bits, s16, to_f32
from mlctool.targets.vs.common import op_error, set_flags

F32_MAX = float.fromhex("0x1.fffffep127")
F32_MIN_NORMAL = 2.0 ** -126  # DEXP: results below are an operation error


def _in(m: Machine, ref) -> float:
    return to_f32(ref.getf(m))


@base._on
def ezcp(m: Machine, s) -> None:
    """DEZCP S1 S2 S D: D = S < S1, D+1 = S1 <= S <= S2, D+2 = S > S2; S1 > S2 uses S1 as both
    limits (FNC 111)."""
    lo, hi, v = (_in(m, r) for r in s.ops[:3])
    if lo > hi:
        hi = lo
    for k, on in enumerate((v < lo, lo <= v <= hi, v > hi)):
        s.ops[3].setbit(m, on, k)


@base._on
def ebcd(m: Machine, s) -> None:
    """DEBCD S D: binary float -> decimal float, D = mantissa (1000-9999 or 0, sign kept),
    D+1 = exponent: value = D x 10^(D+1) (FNC 118: 1.234 x 10^2 -> D10 = 1234, D11 = -1).
    DECISION: the mantissa is rounded half-up to 4 significant digits."""
    x = _in(m, s.ops[0])
    if not math.isfinite(x):
        op_error(m, s, f"{x} has no decimal form")
        return
    if x == 0:
        mant, exp = 0, 0
    else:
        d = Decimal(x)
        exp = d.copy_abs().adjusted() - 3
        mant = int((d.scaleb(-exp)).quantize(Decimal(1), rounding=ROUND_HALF_UP))
        if abs(mant) == 10000:
            mant, exp = mant // 10, exp + 1
    s.ops[1].set_words(m, [mant & 0xFFFF, exp & 0xFFFF])


@base._on
def ebin(m: Machine, s) -> None:
    """DEBIN S D: decimal float (S mantissa, S+1 exponent) -> binary float (FNC 119:
    D2 = 2345, D3 = 5 -> 2.345 x 10^8)."""
    src = s.ops[0]
    raw = src.get(m)  # the pair as one 32-bit value: low word mantissa, high word exponent
    mant, exp = s16(raw), s16(raw >> 16)
    x = float(Decimal(mant).scaleb(exp))  # (10.0 ** 32767 overflows; this is inf, then the error)
    if abs(x) > F32_MAX:
        op_error(m, s, f"{mant} x 10^{exp} is beyond the float range")
        return
    _out(m, s, x)


def _out(m: Machine, s, x: float, zero_flag: bool = False) -> None:
    """Store a float result in the last operand; only the pages that name a flag set it
    (DESQR: zero M9020); the others touch none (flags change only where the manual says)."""
    r = to_f32(x) if abs(x) <= F32_MAX else math.copysign(F32_MAX, x)
    s.ops[-1].set(m, f32_bits(r))
    if zero_flag:
        set_flags(m, zero=r == 0)


def _unary(fn, domain=None, why="", zero_flag=False):
    """S D: D = fn(S); outside `domain` the instruction is an operation error."""
    @base._on
    def run(m: Machine, s) -> None:
        x = _in(m, s.ops[0])
        if domain is not None and not domain(x):
            op_error(m, s, f"{x} {why}")
            return
        try:
            r = fn(x)
        except (OverflowError, ValueError):
            op_error(m, s, f"{x}: result out of range")
            return
        _out(m, s, r, zero_flag)
    return run


@base._on
def eexp(m: Machine, s) -> None:
    """DEXP S D: e^S; a result outside 2^-126 .. 2^128 is an operation error (FNC 124)."""
    x = _in(m, s.ops[0])
    try:
        r = math.exp(x)
    except OverflowError:
        r = math.inf
    if not F32_MIN_NORMAL <= r < 2.0 ** 128:
        op_error(m, s, f"e^{x} is outside 2^-126 .. 2^128")
        return
    _out(m, s, r)


@base._on
def eneg(m: Machine, s) -> None:
    """DENEG D: the float's sign changes (FNC 128)."""
    d = s.ops[0]
    d.set(m, f32_bits(-_in(m, d)))


FLOAT_ACTIONS = {
    "dezcp": ezcp, "debcd": ebcd, "debin": ebin, "dexp": eexp, "deneg": eneg,
    "dloge": _unary(math.log, lambda x: x > 0, "is not > 0"),
    "dlog10": _unary(math.log10, lambda x: x > 0, "is not > 0"),
    "desqr": _unary(math.sqrt, lambda x: x >= 0, "is negative", zero_flag=True),
    "dsin": _unary(math.sin), "dcos": _unary(math.cos), "dtan": _unary(math.tan),
    "dasin": _unary(math.asin, lambda x: -1 <= x <= 1, "is outside -1.0 .. 1.0"),
    "dacos": _unary(math.acos, lambda x: -1 <= x <= 1, "is outside -1.0 .. 1.0"),
    "datan": _unary(math.atan),
}
