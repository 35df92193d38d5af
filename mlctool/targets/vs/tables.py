"""Data tables and word packing (manual 6-13 FNC 140 WSUM, 141 WTOB, 142 BTOW, 143 UNI,
144 DIS, 148 SORT2; 6-19 FNC 210 FDEL, 211 FINS, 212 POP, 213 SFR, 214 SFL; 6-11 FNC 102
ZPUSH, 103 ZPOP)."""

from __future__ import annotations

from mlctool.sim import semantics as base
from mlctool.sim.state import Machine, s16
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
    state,
    write_block,
)

MAX_SORT2_RUNNING = 2  # "僅允許兩個指令同時執行" (FNC 148 note 2)


@base._on
def wsum(m: Machine, s) -> None:
    """WSUM S D n: the sum of n values from S into a double-width D (16-bit -> a pair,
    32-bit -> 4 words, FNC 140); n <= 0: not executed."""
    src, dst, nr = s.ops
    n = count(m, nr)
    if n <= 0:
        op_error(m, s, f"n = {n}: n must be above 0")
        return
    total = sum(read_block(m, src, n, s.width))
    words = 2 if s.width == 16 else 4
    write_block(m, dst, [(total >> (16 * k)) & 0xFFFF for k in range(words)], 16)


@base._on
def wtob(m: Machine, s) -> None:
    """WTOB S D n: n bytes of S (low byte first) into the low bytes of D..D+n-1, high bytes
    0 (FNC 141); n = 0: not executed."""
    src, dst, nr = s.ops
    n = count(m, nr)
    if n <= 0:
        return
    words = [v & 0xFFFF for v in read_block(m, src, (n + 1) // 2, 16)]
    write_block(m, dst, [(words[k // 2] >> (8 * (k % 2))) & 0xFF for k in range(n)], 16)


@base._on
def btow(m: Machine, s) -> None:
    """BTOW S D n: the low bytes of n words of S packed two a word into D (low byte first);
    an odd count leaves the last high byte 0; high bytes of S are ignored (FNC 142)."""
    src, dst, nr = s.ops
    n = count(m, nr)
    if n <= 0:
        return
    b = [v & 0xFF for v in read_block(m, src, n, 16)] + [0]
    write_block(m, dst, [b[k] | (b[k + 1] << 8) for k in range(0, n, 2)], 16)


def _digits(m: Machine, s, nr) -> int:
    """UNI/DIS n: 1-4 digits; 0 is not executed, anything else an operation error (0 too)."""
    n = count(m, nr)
    if n and not 1 <= n <= 4:
        op_error(m, s, f"n = {n} is outside 0-4")
        return 0
    return n


@base._on
def uni(m: Machine, s) -> None:
    """UNI S D n: the low 4 bits of n words of S as the digits of D (S first = lowest), the
    missing digits 0 (FNC 143); n = 1-4, n = 0: not executed."""
    src, dst, nr = s.ops
    n = _digits(m, s, nr)
    if not n:
        return
    digits = read_block(m, src, n, 16)
    dst.set(m, s16(sum((d & 0xF) << (4 * k) for k, d in enumerate(digits))))


@base._on
def dis(m: Machine, s) -> None:
    """DIS S D n: the n lowest digits of S into D..D+n-1 (b4-b15 0) (FNC 144)."""
    src, dst, nr = s.ops
    n = _digits(m, s, nr)
    if not n:
        return
    v = src.get(m) & 0xFFFF
    write_block(m, dst, [(v >> (4 * k)) & 0xF for k in range(n)], 16)


def sort2(m: Machine, s) -> None:
    """SORT2 S m1 m2 D n: m1 rows of m2 fields, row after row (field j of row i at
    S + i*m2 + j), sorted on field n (1-m2) into D, ascending (M9165 Off) or descending (On)
    (FNC 148). As SORT: the page says it takes m1 scans, then M9029 is On for one scan and it
    stops until the condition goes Off and On again. DECISION: the sort is done at the m1-th
    consecutive scan with the condition On (stable: equal keys keep their order); at most two
    SORT2 run at once, a third waits (not started) until one finishes."""
    src, m1r, m2r, dst, nr = s.ops
    progress = state(m, s, [0])
    running = m.fx_state.setdefault("sort2_running", set())
    if not m.acc:
        progress[0] = 0
        running.discard(s.index)
        return
    m1, m2, n = count(m, m1r), count(m, m2r), count(m, nr)
    if not scans_left(m, progress, m1):
        return
    if not (1 <= m1 <= 32 and 1 <= m2 <= 6 and 1 <= n <= m2):
        op_error(m, s, f"m1={m1} m2={m2} n={n}: m1 = 1-32, m2 = 1-6, n = 1-m2")
        return
    # "S和D指定的範圍不可相互交錯重疊，但是，S=D則可允許" (FNC 148 note 4). DECISION: blocks
    # that overlap without being the same are an operation error (the page names no effect)
    blocks = span(m, src, m1 * m2, s.width), span(m, dst, m1 * m2, s.width)
    if blocks[0] != blocks[1] and overlap(*blocks):
        op_error(m, s, "the S and D blocks overlap")
        return
    if s.index not in running:
        if len(running) >= MAX_SORT2_RUNNING:
            return
        running.add(s.index)
    progress[0] += 1
    if progress[0] < m1:
        return
    table = read_block(m, src, m1 * m2, s.width)
    rows = [table[i * m2:(i + 1) * m2] for i in range(m1)]
    rows.sort(key=lambda r: r[n - 1], reverse=bool(relay(m, "sort2_descending")))
    write_block(m, dst, [v for r in rows for v in r], s.width)
    running.discard(s.index)
    set_relay(m, "done", True)


# ------------------------------------------------------------------ tables (6-19)

def _table(m: Machine, s, ref, extra: int) -> tuple[list[int], int] | None:
    """A table whose first word holds its count; the count's values after it."""
    size = s16(read_block(m, ref, 1, 16)[0])
    if size < 0:
        op_error(m, s, f"the table's count {size} is negative")
        return None
    return read_block(m, ref, size + 1 + extra, 16)[1:size + 1], size


@base._on
def fdel(m: Machine, s) -> None:
    """FDEL S D n: entry n (1 = the first) of table D moves to S, the later ones move up and
    the count drops by one (FNC 210); n must be 1..count. DECISION: the table is the second
    operand and the deleted entry goes to the first, as in FINS: the page's blanks are lost
    but its example FDELP D0 D2 D1 (n in D1) only fits a table at D2."""
    dst, tab, nr = s.ops
    got = _table(m, s, tab, 0)
    if got is None:
        return
    values, size = got
    n = count(m, nr)
    if not 1 <= n <= size:
        op_error(m, s, f"n = {n} is outside 1-{size} (the table's count)")
        return
    dst.set(m, values.pop(n - 1))
    # the vacated last place keeps its old value (the page shows only the moved entries)
    write_block(m, tab, [size - 1] + values, 16)


@base._on
def fins(m: Machine, s) -> None:
    """FINS S D n: S enters table D as entry n, the later ones move down and the count grows
    by one (FNC 211); n must be 1..count+1."""
    src, tab, nr = s.ops
    got = _table(m, s, tab, 0)
    if got is None:
        return
    values, size = got
    n = count(m, nr)
    if not 1 <= n <= size + 1:
        op_error(m, s, f"n = {n} is outside 1-{size + 1} (the table's count + 1)")
        return
    values.insert(n - 1, src.get(m))
    write_block(m, tab, [size + 1] + values, 16)


@base._on
def pop(m: Machine, s) -> None:
    """POP S D n: last in, first out over the SFWR file S..S+n-1 (S the pointer): D = S[S],
    then the pointer drops by one; pointer 0: nothing read, M9020 On; reading the last entry
    turns M9020 On (FNC 212)."""
    src, dst, nr = s.ops
    n = count(m, nr)
    if not 2 <= n <= 512:
        op_error(m, s, f"n = {n} is outside 2-512")
        return
    file = read_block(m, src, n, 16)
    p = file[0]
    if p <= 0:
        set_flags(m, zero=True)
        return
    if p > n - 1:
        op_error(m, s, f"the pointer {p} is past the file's {n - 1} entries")
        return
    dst.set(m, file[p])
    write_block(m, src, [p - 1], 16)
    set_flags(m, zero=p - 1 == 0)


def _bit_shift(left: bool):
    """SFR/SFL D n: the 16 bits of D shifted n places right/left, 0 entering; the last bit
    out goes to the carry M9022 (FNC 213/214); n = 0: nothing moves, the carry stays."""
    @base._on
    def run(m: Machine, s) -> None:
        dst, nr = s.ops
        n = count(m, nr)
        if not 0 <= n <= 15:
            op_error(m, s, f"n = {n} is outside 0-15")
            return
        if n == 0:
            return
        v = dst.get(m) & 0xFFFF
        if left:
            out, r = (v >> (16 - n)) & 1, (v << n) & 0xFFFF
        else:
            out, r = (v >> (n - 1)) & 1, v >> n
        dst.set(m, s16(r))
        set_flags(m, carry=bool(out))
    return run


# ------------------------------------------------------------------ index registers (6-11)

INDEX_ORDER = [(kind, k) for k in range(8) for kind in ("Z", "V")]  # Z0, V0, Z1 ... V7


@base._on
def zpush(m: Machine, s) -> None:
    """ZPUSH D: Z0, V0 ... Z7, V7 (16 words, the order of their mirror D9180-D9195) saved at
    D+1+16c, then the count D = c + 1 (FNC 102)."""
    ref = s.ops[0]
    c = s16(read_block(m, ref, 1, 16)[0])
    if c < 0:
        op_error(m, s, f"the count {c} is negative")
        return
    saved = [m.words[kind][k] for kind, k in INDEX_ORDER]
    earlier = read_block(m, ref, 1 + 16 * c, 16)[1:]  # the groups saved before stay
    write_block(m, ref, [c + 1] + earlier + saved, 16)


@base._on
def zpop(m: Machine, s) -> None:
    """ZPOP D: the last saved group back into Z0-V7, the count drops by one (FNC 103); a
    count of 0: nothing to restore, an operation error."""
    ref = s.ops[0]
    c = s16(read_block(m, ref, 1, 16)[0])
    if c <= 0:
        op_error(m, s, f"the count {c}: nothing saved")
        return
    block = read_block(m, ref, 1 + 16 * c, 16)
    for (kind, k), v in zip(INDEX_ORDER, block[1 + 16 * (c - 1):]):
        m.words[kind][k] = v & 0xFFFF
    write_block(m, ref, [c - 1], 16)


TABLE_ACTIONS = {
    "wsum": wsum, "wtob": wtob, "btow": btow, "uni": uni, "dis": dis, "sort2": sort2,
    "fdel": fdel, "fins": fins, "pop": pop, "sfr": _bit_shift(False), "sfl": _bit_shift(True),
    "zpush": zpush, "zpop": zpop,
}
