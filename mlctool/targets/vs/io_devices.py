"""I/O conversions of the VS family that need no peripheral: PRUN (6-10 FNC 81, octal copy)
and SEGD (6-9 FNC 73, 7-segment decode). MTR/DSW: scan_io.py; TKY, HKY, SEGL, PR:
keypad_display.py; communication (RS, LINK, CPUL, DBRD, DBWR, DTRD) is not simulated yet:
E905 (docs/vs.md "Not yet")."""

from __future__ import annotations

from mlctool.sim import semantics as base
from mlctool.sim.operands import GroupRef
from mlctool.sim.state import Machine
from mlctool.targets.vs.common import op_error

# 7-segment codes of 0-F, bit 0 = segment a ... bit 6 = g (6-9 SEGD table; the rows the
# extraction kept (g, f) match the FX table, incl. 7 = 27H with segment f)
SEVEN_SEGMENT = (0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x27,
                 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79, 0x71)


@base._on
def segd(m: Machine, s) -> None:
    """SEGD S D: the low 4 bits of S as a 7-segment code in the low 8 bits of D (K2Y20:
    Y20-Y27). DECISION: a word destination keeps its high 8 bits (the FX rule; the page
    shows only K2Y)."""
    code = SEVEN_SEGMENT[s.ops[0].get(m) & 0xF]
    dst = s.ops[1]
    if isinstance(dst, GroupRef):
        dst.set(m, code)
    else:
        dst.set(m, (dst.get(m) & ~0xFF) | code)


@base._on
def prun(m: Machine, s) -> None:
    """PRUN S D: octal copy between KnX and KnM (either way: KnX -> KnM, KnM -> KnY). Bit i of
    the octal group (X20 + i written in octal) pairs with M number base + the octal digits
    of i read as decimal: K4X20 -> M0-M7, M10-M17 (M8, M9 unchanged), and back."""
    src, dst = s.ops
    n = src.n if isinstance(src, GroupRef) else 16
    n = min(n, dst.n if isinstance(dst, GroupRef) else n)
    octal_src = m.target.devices[src.kind].radix == 8
    spread = int(format(n - 1, "o")) + 1  # decimal devices the octal group pairs with
    a = src.addr(m, n if octal_src else spread)
    b = dst.addr(m, spread if octal_src else n)
    if a + (n if octal_src else spread) - 1 > src.hi or b + (spread if octal_src else n) - 1 > dst.hi:
        op_error(m, s, f"{src.text} -> {dst.text}: the octal copy runs past the device range")
        return
    sbits, dbits = m.bits[src.kind], m.bits[dst.kind]
    for i in range(n):
        decimal = int(format(i, "o"))  # 8 -> 10: the decimal device that pairs with octal bit i
        if octal_src:
            dbits[b + decimal] = sbits[a + i]
            m.writer[(dst.kind, b + decimal)] = m.pc
        else:
            dbits[b + i] = sbits[a + decimal]
            m.writer[(dst.kind, b + i)] = m.pc


IO_DEVICE_ACTIONS = {"segd": segd, "prun": prun}
