"""Rotation through the carry and shift registers (manual 6-5, FNC 32-39)."""

from __future__ import annotations

from mlctool.sim import semantics as base
from mlctool.sim.state import Machine
from mlctool.targets.vs.common import (
    count,
    flag,
    op_error,
    read_block,
    set_flags,
    table_count,
    write_block,
)


def _rotate_carry(left: bool):
    """RCR/RCL D n: D and the carry M9022 rotate together as one (w+1)-bit ring, n = 0-16
    (0-32) bits a time (FNC 32/33: "連同進制標誌位M9022，一次向右旋轉n個位元")."""
    @base._on
    def run(m: Machine, s) -> None:
        w = s.width
        ring = w + 1
        v = (s.ops[0].get(m) & ((1 << w) - 1)) | (flag(m, "carry") << w)
        n = count(m, s.ops[1]) % ring
        r = ((v << n) | (v >> (ring - n))) if left else ((v >> n) | (v << (ring - n)))
        r &= (1 << ring) - 1
        s.ops[0].set(m, r & ((1 << w) - 1))
        set_flags(m, carry=bool(r >> w))
    return run


def _shift(values: list[int], fill: list[int], right: bool) -> list[int]:
    """The block moved by len(fill) places; the fill enters at the far end (right shift: the
    top, FNC 34 "X0-X3被移入M12-M15") or at the start (left shift: M0-M3)."""
    k = len(fill)
    return values[k:] + fill if right else fill + values[:len(values) - k]


def _block_shift(right: bool, width: int):
    """SFTR/SFTL S D n1 n2 (width 1): the n1 bits from D move n2 places and the n2 bits from S
    fill in; WSFR/WSFL (width 16): the same on n1 words or Kn groups (FNC 34-37)."""
    @base._on
    def run(m: Machine, s) -> None:
        src, dst, n1r, n2r = s.ops
        n1, n2 = count(m, n1r), count(m, n2r)
        if not 1 <= n2 <= n1:
            op_error(m, s, f"n2 = {n2} is outside 1-n1 ({n1})")
            return
        fill = read_block(m, src, n2, width)
        write_block(m, dst, _shift(read_block(m, dst, n1, width), fill, right), width)
    return run


@base._on
def sfwr(m: Machine, s) -> None:
    """SFWR S D n: pointer D + 1, then S into D[pointer]. A full file (pointer >= n-1) takes
    nothing and turns the carry M9022 On (FNC 38). DECISION: a write that fits turns it Off."""
    src, dst, _ = s.ops
    n = table_count(m, s, 2)
    if n is None:
        return
    ptr = read_block(m, dst, 1, 16)[0]
    if ptr >= n - 1:
        set_flags(m, carry=True)
        return
    ptr = max(ptr, 0) + 1
    value = src.get(m)
    write_block(m, dst, [ptr], 16)
    block = read_block(m, dst, n, 16)
    block[ptr] = value
    write_block(m, dst, block, 16)
    set_flags(m, carry=False)


@base._on
def sfrd(m: Machine, s) -> None:
    """SFRD S D n: D = S[1]; S[2..n-1] move down one; pointer S - 1 (FIFO, FNC 39). An empty
    file (pointer 0) reads nothing and turns the zero flag M9020 On. DECISION: a read turns
    it On when it empties the file, Off otherwise; S[n-1] keeps its value."""
    src, dst, _ = s.ops
    n = table_count(m, s, 2)
    if n is None:
        return
    block = read_block(m, src, n, 16)
    ptr = block[0]
    if ptr <= 0:
        set_flags(m, zero=True)
        return
    dst.set(m, block[1])
    block[1:n - 1] = block[2:n]
    block[0] = ptr - 1
    write_block(m, src, block, 16)
    set_flags(m, zero=ptr - 1 == 0)


SHIFT_ACTIONS = {
    "rcr": _rotate_carry(False), "rcl": _rotate_carry(True),
    "sftr": _block_shift(True, 1), "sftl": _block_shift(False, 1),
    "wsfr": _block_shift(True, 16), "wsfl": _block_shift(False, 16),
    "sfwr": sfwr, "sfrd": sfrd,
}
