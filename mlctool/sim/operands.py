"""Operands decoded once per image into small accessor objects (no parsing per scan).

Every accessor knows the instruction's width: `get` returns a signed 16- or 32-bit integer,
`set` wraps to the width. 32-bit values live in pairs (n+1 high, n low) for D, T and the
16-bit counters (3.2.5 item 4); C64-C79 hold 32 bits themselves; 32-bit V is (Z n, V n).
Index modification (1.8.2, 3.4) adds the signed index register at run time; an address
outside the device range is a fatal fault (the manual leaves it undefined).
"""

from __future__ import annotations

from mlctool.sim.state import Machine, SimFault, bits_f32, f32_bits, s16, s32
from mlctool.syntax.operands import Operand
from mlctool.targetapi.model import Target


class Ref:
    __slots__ = ("kind", "num", "width", "ix", "ixn", "hi", "text", "allowed")

    def __init__(self, op: Operand, width: int, hi: int, text: str):
        self.kind = op.device if not op.is_const else op.kind
        self.num = op.number
        self.width = width
        self.ix, self.ixn = op.index if op.index else (None, 0)
        self.hi = hi  # highest valid device number
        self.text = text
        # the numbers the instruction's table allows this operand (JOGF D1: Y0-Y3), where
        # narrower than the device: an index-modified operand is held to them at run time
        self.allowed: tuple[tuple[int, int], ...] = ()

    def index_value(self, m: Machine) -> int:
        if self.ix is None:
            return 0
        if self.width == 32 and self.ix == "V":
            return s32(m.words["V"][self.ixn] | (m.words["Z"][self.ixn] << 16))
        return s16(m.words[self.ix][self.ixn])

    def addr(self, m: Machine, extent: int = 1) -> int:
        """The device number the operand addresses; an index-modified one must lie, with the
        `extent` devices from it, inside the device (the checker saw only its base)."""
        a = self.num
        if self.ix is not None:
            a += self.index_value(m)
            if a < 0 or a + extent - 1 > self.hi:
                raise SimFault(f"{self.text} with {self.ix}{self.ixn}={self.index_value(m)} addresses "
                               f"{self.kind}{a}" + (f"-{self.kind}{a + extent - 1}" if extent > 1 else "")
                               + f", outside {self.kind}0-{self.kind}{self.hi}")
            if self.allowed and not any(lo <= a <= hi for lo, hi in self.allowed):
                spans = ", ".join(f"{self.kind}{lo}-{self.kind}{hi}" for lo, hi in self.allowed)
                raise SimFault(f"{self.text} with {self.ix}{self.ixn}={self.index_value(m)} addresses "
                               f"{self.kind}{a}; the instruction takes {spans} here")
        return a

    def block(self, m: Machine, extent: int) -> int:
        """addr of a block whose length the instruction fixes (MUL D's words, DECO D's 2^n
        bits, FCMP's three bits): all of it must exist, indexed or not, since its length may
        come from a register (n = D1) the checker cannot read. (Instructions whose page says
        a block past the end moves only its valid part, FMOV/BMOV, cut it themselves.)"""
        a = self.addr(m, extent)
        if a + extent - 1 > self.hi:
            raise SimFault(f"{self.text}: {extent} devices from {self.kind}{a} run past {self.kind}{self.hi}")
        return a

    def wrap(self, v: int) -> int:
        return s32(v) if self.width == 32 else s16(v)

    # float view of a 32-bit operand
    def getf(self, m: Machine) -> float:
        return bits_f32(self.get(m))

    def setf(self, m: Machine, x: float) -> None:
        self.set(m, f32_bits(x))

    def get(self, m: Machine) -> int:  # pragma: no cover - overridden
        raise NotImplementedError

    def set(self, m: Machine, v: int) -> None:
        raise SimFault(f"{self.text} cannot be written")


class ConstRef(Ref):
    __slots__ = ("value", "is_f")

    def __init__(self, op: Operand, width: int, text: str):
        super().__init__(op, width, 0, text)
        self.value = op.value
        self.is_f = op.kind == "F"

    def get(self, m: Machine) -> int:
        if self.is_f:  # an F constant in an integer view: its IEEE-754 pattern (DMOV F1.5 D0)
            return s32(f32_bits(self.value))
        return self.wrap(int(self.value) + self.index_value(m))

    def getf(self, m: Machine) -> float:
        # K and F constants are converted to float (4.8: "變換成二進浮點數值")
        return float(self.value) + self.index_value(m) if not self.is_f else float(self.value)


class WordRef(Ref):
    """D, T (present value), V, Z."""

    __slots__ = ()

    def _pair(self, m: Machine, a: int) -> tuple[list[int], int, list[int], int]:
        if self.kind == "V":
            return m.words["V"], a, m.words["Z"], a
        w = m.words[self.kind]
        return w, a, w, a + 1

    def get(self, m: Machine) -> int:
        if self.width == 16 or self.kind == "Z":
            return s16(m.words[self.kind][self.addr(m)])
        lo, la, hi, ha = self._pair(m, self.addr(m, 2 if self.kind != "V" else 1))
        return s32(lo[la] | (hi[ha] << 16))

    def set(self, m: Machine, v: int) -> None:
        if self.width == 16 or self.kind == "Z":
            a = self.addr(m)
            m.words[self.kind][a] = v & 0xFFFF
            m.writer[(self.kind, a)] = m.pc
            return
        lo, la, hi, ha = self._pair(m, self.addr(m, 2 if self.kind != "V" else 1))
        lo[la] = v & 0xFFFF
        hi[ha] = (v >> 16) & 0xFFFF
        m.writer[(self.kind, la)] = m.pc
        m.writer[("Z" if self.kind == "V" else self.kind, ha)] = m.pc

    def set_words(self, m: Machine, words: list[int]) -> None:
        """Consecutive 16-bit words from the operand on (MUL/DIV destinations)."""
        a = self.block(m, len(words))
        w = m.words[self.kind]
        for k, x in enumerate(words):
            w[a + k] = x & 0xFFFF
            m.writer[(self.kind, a + k)] = m.pc


class CounterRef(Ref):
    """C as data: C0-C63 16-bit words (pairs in 32-bit instructions), C64-C79 32-bit each."""

    __slots__ = ()

    def get(self, m: Machine) -> int:
        if self.width == 16:
            return s16(m.cval[self.addr(m)])
        a = self.addr(m)
        if m.is_c32(a):
            return s32(m.cval[a])
        a = self.addr(m, 2)
        return s32(m.cval[a] | (m.cval[a + 1] << 16))

    def set(self, m: Machine, v: int) -> None:
        a = self.addr(m)
        m.writer[("C", a)] = m.pc
        if self.width == 16:
            m.cval[a] = v & 0xFFFF
        elif m.is_c32(a):
            m.cval[a] = s32(v)
        else:
            a = self.addr(m, 2)
            m.cval[a] = v & 0xFFFF
            m.cval[a + 1] = (v >> 16) & 0xFFFF
            m.writer[("C", a + 1)] = m.pc

    def set_words(self, m: Machine, words: list[int]) -> None:
        a = self.addr(m)
        if m.is_c32(a):  # C64-C79 hold 32 bits each: pair the words up
            a = self.block(m, len(words) // 2)
            for k in range(0, len(words), 2):
                m.cval[a + k // 2] = s32(words[k] | (words[k + 1] << 16))
                m.writer[("C", a + k // 2)] = m.pc
            return
        a = self.block(m, len(words))
        for k, x in enumerate(words):
            m.cval[a + k] = x & 0xFFFF
            m.writer[("C", a + k)] = m.pc


class GroupRef(Ref):
    """KnX/KnY/KnM/KnA: 4n consecutive bits, unused high bits zero-filled (3.3)."""

    __slots__ = ("n",)

    def __init__(self, op: Operand, width: int, hi: int, text: str):
        super().__init__(op, width, hi, text)
        self.n = 4 * op.digits

    def get(self, m: Machine) -> int:
        a = self.addr(m, self.n)
        bits = m.bits[self.kind]
        v = 0
        for i in range(self.n):
            if bits[a + i]:
                v |= 1 << i
        # K4 in 16-bit and K8 in 32-bit are signed; smaller groups are zero-filled (3.2.7)
        return self.wrap(v) if self.n == self.width else v

    def set(self, m: Machine, v: int) -> None:
        a = self.addr(m, self.n)
        bits = m.bits[self.kind]
        for i in range(self.n):
            bits[a + i] = (v >> i) & 1
            m.writer[(self.kind, a + i)] = m.pc

    def set_words(self, m: Machine, words: list[int]) -> None:
        """A result of several registers (MUL/DIV D) into groups one after another, each
        taking one register's value (a pair's in a 32-bit instruction), its low 4n bits:
        K4M0 as MUL's D is M0-M15 (the product's low word) and M16-M31 (its high word), as
        D would be D and D+1 (DECISION: the VS operand matrices are lost; a group stands for
        a register, so several registers are several groups, as in the block instructions)."""
        per = 2 if self.width == 32 else 1
        values = [sum((words[k + h] & 0xFFFF) << (16 * h) for h in range(per)) for k in range(0, len(words), per)]
        a = self.block(m, self.n * len(values))
        bits = m.bits[self.kind]
        for j, v in enumerate(values):
            for i in range(self.n):
                bits[a + j * self.n + i] = (v >> i) & 1
                m.writer[(self.kind, a + j * self.n + i)] = m.pc


class BitRef(Ref):
    """X Y M A, and T/C contacts; `k` selects a following bit (FCMP D, D+1, D+2)."""

    __slots__ = ()

    def bit(self, m: Machine, k: int = 0) -> int:
        return m.bits[self.kind][(self.block(m, k + 1) if k else self.addr(m)) + k]

    def setbit(self, m: Machine, v: int, k: int = 0) -> None:
        a = (self.block(m, k + 1) if k else self.addr(m)) + k
        m.bits[self.kind][a] = 1 if v else 0
        m.writer[(self.kind, a)] = m.pc

    def get(self, m: Machine) -> int:  # a bit read as a word (DECO/ENCO/VRT use bits directly)
        return self.bit(m)


class WordBitRef(Ref):
    """D0.5 / R5.3: one bit of a 16-bit word (VS 3-1, 5-1) as a contact, coil, SET or RST
    operand. Writing it changes only that bit; the writer record is the word's. Index
    modification addresses the word (DECISION: D0Z0.5 is not in the IL grammar, so only an
    unindexed word reaches here; addr still range-checks like any word)."""

    __slots__ = ("bitno",)

    def __init__(self, op: Operand, width: int, hi: int, text: str):
        super().__init__(op, width, hi, text)
        self.kind = op.device  # the word's device: D for D0.5
        self.bitno = op.bit

    def bit(self, m: Machine, k: int = 0) -> int:
        return (m.words[self.kind][self.addr(m)] >> (self.bitno + k)) & 1

    def setbit(self, m: Machine, v: int, k: int = 0) -> None:
        a = self.addr(m)
        mask = 1 << (self.bitno + k)
        w = m.words[self.kind]
        w[a] = (w[a] | mask) if v else (w[a] & ~mask & 0xFFFF)
        m.writer[(self.kind, a)] = m.pc

    def get(self, m: Machine) -> int:
        return self.bit(m)


def decode_operand(op: Operand, width: int, target: Target, text: str, as_bits: bool) -> Ref:
    """`as_bits`: the instruction uses a T/C operand as its contact (LD T0) rather than data."""
    if op.is_const:
        return ConstRef(op, width, text)
    dev = target.devices[op.device]
    if op.unit:  # U1G3: register 3 of m.words["U1G"], the unit's buffer memory (sim/unit_words.py)
        ref = WordRef(op, width, dev.hi, text)
        ref.kind = f"{op.unit}{op.kind}"
        return ref
    if op.is_group:
        return GroupRef(op, width, dev.hi, text)
    if op.is_bit_of_word:
        return WordBitRef(op, width, dev.hi, text)
    if dev.kind == "bit" or as_bits:
        return BitRef(op, width, dev.hi, text)
    if dev.kind == "counter":
        return CounterRef(op, width, dev.hi, text)
    return WordRef(op, width, dev.hi, text)
