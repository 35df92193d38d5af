"""Data instructions (manual 6-3 SMOV, 6-6 MEAN/ANS/ANR/SQR, 6-8 SER/SORT, 6-17 BK+/BK-/
BKCMP)."""

from __future__ import annotations

import math
import operator

from mlctool.sim import semantics as base
from mlctool.sim.state import Machine
from mlctool.targets.vs.common import (
    count,
    op_error,
    overlap,
    read_block,
    relay,
    scans_left,
    set_flags,
    set_relay,
    span,
    special,
    state,
    write_block,
)


def _digits(v: int, hexmode: bool) -> list[int] | None:
    """Four digits of v, lowest first: BCD of 0-9999, or the hex nibbles (M9168 On)."""
    if hexmode:
        return [(v >> (4 * k)) & 0xF for k in range(4)]
    if not 0 <= v <= 9999:
        return None
    return [(v // 10 ** k) % 10 for k in range(4)]


@base._on
def smov(m: Machine, s) -> None:
    """SMOV S m1 m2 D n: m2 digits of S from digit m1 down go to D from digit n down; the
    other digits of D stay (FNC 13). M9168 Off: S and D are BIN, taken as 4 BCD digits (a
    value outside 0-9999 is an operation error) and D is converted back; On: hex digits."""
    src, m1r, m2r, dst, nr = s.ops
    m1, m2, n = m1r.get(m), m2r.get(m), nr.get(m)
    if not (1 <= m1 <= 4 and 1 <= m2 <= m1 and m2 <= n <= 4):
        op_error(m, s, f"m1={m1} m2={m2} n={n} outside m1=1-4, m2=1-m1, n=m2-4")
        return
    hexmode = bool(relay(m, "smov_hex"))
    a, b = _digits(src.get(m), hexmode), _digits(dst.get(m), hexmode)
    if a is None or b is None:
        op_error(m, s, "a value outside 0-9999 has no 4-digit BCD form")
        return
    for k in range(m2):
        b[n - 1 - k] = a[m1 - 1 - k]
    base_ = 16 if hexmode else 10
    dst.set(m, sum(d * base_ ** k for k, d in enumerate(b)))


@base._on
def mean(m: Machine, s) -> None:
    """MEAN S D n: the sum of n values over n, remainder dropped (FNC 45); only the part of
    the block inside the device range is used (then divided by that count)."""
    src, dst, nr = s.ops
    n = count(m, nr)
    if not 1 <= n <= 64:
        op_error(m, s, f"n = {n} is outside 1-64")
        return
    size = 2 if s.width == 32 else 1
    length = len(m.words[src.kind]) if src.kind in m.words else None
    if length is not None and not src.ix:
        n = max(1, min(n, (length - src.addr(m)) // size))
    values = read_block(m, src, n, s.width)
    total = sum(values)
    q = abs(total) // n * (1 if total >= 0 else -1)  # remainder dropped (toward zero)
    dst.set(m, q)


@base._on
def sqr(m: Machine, s) -> None:
    """SQR S D: integer square root; M9021 when a fraction was dropped, M9020 when 0; a
    negative S is an operation error (FNC 48)."""
    v = s.ops[0].get(m)
    if v < 0:
        op_error(m, s, f"square root of {v}")
        return
    r = math.isqrt(v)
    s.ops[1].set(m, r)
    set_flags(m, zero=r == 0, borrow=r * r != v)


def ans(m: Machine, s) -> None:
    """ANS S m D: while the condition is On the 100 ms timer S times; at m x 100 ms the alarm
    step D is SET and stays On; Off resets the timer (FNC 46)."""
    t, preset, dst = s.ops
    n = t.addr(m)
    m.t_seen[n] = 1
    if not m.acc:
        m.reset_timer(n)
        return
    base.advance_timer(m, n, preset.get(m) & 0xFFFF)
    if m.bits["T"][n]:
        dst.setbit(m, 1)
    _alarm_monitor(m)


def _alarm_range(m: Machine) -> tuple[int, int]:
    lo, hi = m.target.settings.get("special", {}).get("alarm_steps", (900, 999))
    return lo, hi


@base._on
def anr(m: Machine, s) -> None:
    """ANR: the lowest active alarm step S900-S999 goes Off, one per execution (FNC 47)."""
    lo, hi = _alarm_range(m)
    bits = m.bits["S"]
    for n in range(lo, hi + 1):
        if bits[n]:
            bits[n] = 0
            m.writer[("S", n)] = m.pc
            break
    _alarm_monitor(m)


def _alarm_monitor(m: Machine) -> None:
    """M9049 On: M9048 = some alarm step is On, D9049 = the lowest one (6-6 ANS example).
    DECISION: updated when ANS/ANR execute."""
    if not relay(m, "alarm_monitor"):
        return
    lo, hi = _alarm_range(m)
    on = [n for n in range(lo, hi + 1) if m.bits["S"][n]]
    set_relay(m, "alarm_any", bool(on))
    reg = special(m, "alarm_lowest")
    if reg is not None and on:
        m.words["D"][reg] = on[0]


@base._on
def ser(m: Machine, s) -> None:
    """SER S1 S2 D n: D = number of values equal to S2, D+1 first and D+2 last equal index,
    D+3 index of the minimum, D+4 of the maximum; ties take the larger index (FNC 61).
    32-bit: S1, S2 and D are 32-bit, n a 16-bit count (D occupies 10 points)."""
    s1, s2, dst, nr = s.ops
    n = count(m, nr)
    limit = 128 if s.width == 32 else 256
    if not 1 <= n <= limit:
        op_error(m, s, f"n = {n} is outside 1-{limit}")
        return
    values = read_block(m, s1, n, s.width)
    key = s2.get(m)
    equal = [k for k, v in enumerate(values) if v == key]
    lo, hi = min(values), max(values)
    low = max(k for k, v in enumerate(values) if v == lo)
    high = max(k for k, v in enumerate(values) if v == hi)
    result = [len(equal), equal[0] if equal else 0, equal[-1] if equal else 0, low, high]
    write_block(m, dst, result, s.width)


def sort(m: Machine, s) -> None:
    """SORT S m1 m2 D n: m1 records of m2 fields (field j of record i at S + j*m1 + i) sorted
    ascending on field n into D (stable). The manual: it takes m1 scans, then M9029 is On for
    one scan and sorting stops (FNC 69). We sort at the m1-th consecutive scan the condition
    is On; Off restarts it."""
    src, m1r, m2r, dst, nr = s.ops
    progress = state(m, s, [0])
    if not m.acc:
        progress[0] = 0
        return
    m1, m2, n = m1r.get(m), m2r.get(m), nr.get(m)
    if not scans_left(m, progress, m1):
        return
    if not (1 <= m2 <= 6 and 1 <= n <= m2 and m1 >= 1):
        op_error(m, s, f"m1={m1} m2={m2} n={n}: m2 = 1-6 and n = 1-m2")
        return
    progress[0] += 1
    if progress[0] < m1:
        return
    table = read_block(m, src, m1 * m2, 16)
    rows = sorted(range(m1), key=lambda i: table[(n - 1) * m1 + i])
    write_block(m, dst, [table[j * m1 + i] for j in range(m2) for i in rows], 16)
    set_relay(m, "done", True)


def _block_arith(fn):
    """BK+/BK- S1 S2 D n: D[i] = S1[i] op S2[i] (S2 may be a constant), wrapping, no flags;
    overlapping blocks are an operation error (FNC 192/193)."""
    @base._on
    def run(m: Machine, s) -> None:
        s1, s2, dst, nr = s.ops
        n = nr.get(m)
        if not 1 <= n <= (256 if s.width == 32 else 512):
            op_error(m, s, f"n = {n} is out of range")
            return
        d = span(m, dst, n, s.width)
        if overlap(d, span(m, s1, n, s.width)) or overlap(d, span(m, s2, n, s.width)) \
                or overlap(span(m, s1, n, s.width), span(m, s2, n, s.width)):
            op_error(m, s, "the blocks overlap")
            return
        a, b = read_block(m, s1, n, s.width), read_block(m, s2, n, s.width)
        write_block(m, dst, [fn(x, y) for x, y in zip(a, b, strict=True)], s.width)
    return run


def _block_compare(rel):
    """BKCMP= ... S1 S2 D n: bit D[i] = S1[i] rel S2[i] (S1 may be a constant); M9090 On when
    every result is On (FNC 194-199)."""
    @base._on
    def run(m: Machine, s) -> None:
        s1, s2, dst, nr = s.ops
        n = nr.get(m)
        if n < 1:
            op_error(m, s, f"n = {n} is out of range")
            return
        dst.block(m, n)  # the n result bits exist (else a fault) before the blocks are read
        a, b = read_block(m, s1, n, s.width), read_block(m, s2, n, s.width)
        results = [1 if rel(x, y) else 0 for x, y in zip(a, b, strict=True)]
        write_block(m, dst, results, 1)
        set_relay(m, "bkcmp_all", all(results))
    return run


DATA_ACTIONS = {
    "smov": smov, "mean": mean, "sqr": sqr, "ans": ans, "anr": anr, "ser": ser, "sort": sort,
    "bk_add": _block_arith(operator.add), "bk_sub": _block_arith(operator.sub),
    "bkcmp_eq": _block_compare(operator.eq), "bkcmp_gt": _block_compare(operator.gt),
    "bkcmp_lt": _block_compare(operator.lt), "bkcmp_ne": _block_compare(operator.ne),
    "bkcmp_le": _block_compare(operator.le), "bkcmp_ge": _block_compare(operator.ge),
}
