"""Memory card data bank (VS 6-11 FNC 90 DBRD, 91 DBWR; 2-8).

The VS-MC / VS-MCR card adds 655,360 words of flash memory that keeps its data without power
(2-8 "具停電保持特性"); DBRD reads n words from bank address S into D on, DBWR writes n
words from S on to bank address D. The bank is simulated as `Machine.databank` (address ->
raw 16-bit word, 0 until written), which the stimulus presets and checks (`DB#100=5`,
`expect DB#100:d=70000`; docs/stimulus.md) and a power cycle keeps. DECISIONS (docs/vs.md):
the card is always installed (target.toml `[data_bank]`); the write time the page gives
(about 15 ms per 128 words, the scan waits) does not lengthen the simulated scan.
"""

from __future__ import annotations

from mlctool.sim import semantics as base
from mlctool.sim.operands import ConstRef, WordRef
from mlctool.sim.state import Machine, s16, s32
from mlctool.targets.vs.common import count, op_error, read_block, write_block

MAX_N = 32767  # n = 1-32,767 (both pages)


def size(target) -> int:
    """Words of the data bank on the target (0: none)."""
    return int((target.settings.get("data_bank") or {}).get("words", 0))


def _address(m: Machine, ref) -> int:
    """The 32-bit bank address operand of a 16-bit instruction (the pages: "S/D is 32-bit
    data"; a D or R takes two registers, the high word in the second). DECISION: other kinds
    (KnX ... T, C, V, Z) give their 16-bit value, unsigned."""
    if isinstance(ref, ConstRef):
        return int(ref.value) + _index32(m, ref)
    if isinstance(ref, WordRef) and ref.kind in ("D", "R"):
        a = ref.addr(m, 2)
        words = m.words[ref.kind]
        return s32(words[a] | (words[a + 1] << 16))
    return ref.get(m) & 0xFFFF


def _index32(m: Machine, ref) -> int:
    """A K/H address's index: the pages say it takes both V and Z, i.e. the 32-bit index of
    2-9 (target.toml `index32`: written Zn, the pair Vn high, Zn low)."""
    pair = m.target.settings.get("index32")
    if ref.ix is None or not pair or ref.ix not in (pair["low"], pair["high"]):
        return ref.index_value(m)
    n = ref.ixn
    return s32(m.words[pair["low"]][n] | (m.words[pair["high"]][n] << 16))


def _span(m: Machine, s, address_ref, block_ref) -> tuple[int, int] | None:
    """(bank address, n), or None after an operation error: n outside 1-32767, addresses
    outside 0-655359 (the block's last one too), or a register block past the device range."""
    n = count(m, s.ops[2])
    if not 1 <= n <= MAX_N:
        op_error(m, s, f"n = {n} is outside 1-{MAX_N}")
        return None
    top = size(m.target) - 1
    first = _address(m, address_ref)
    if not 0 <= first or first + n - 1 > top:
        op_error(m, s, f"data bank addresses {first} .. {first + n - 1} are outside 0-{top}")
        return None
    if isinstance(block_ref, WordRef):
        a, hi = block_ref.addr(m), len(m.words[block_ref.kind]) - 1
        if a + n - 1 > hi:
            op_error(m, s, f"{n} words from {block_ref.kind}{a} pass {block_ref.kind}{hi}")
            return None
    return first, n


@base._on
def dbrd(m: Machine, s) -> None:
    """DBRD S D n (6-11 FNC 90): n words from data bank address S (32-bit) into D on; with
    the condition Off nothing is read and D keeps what it holds (the page)."""
    span = _span(m, s, s.ops[0], s.ops[1])
    if span:
        first, n = span
        write_block(m, s.ops[1], [s16(m.databank.get(first + k, 0)) for k in range(n)], 16)


@base._on
def dbwr(m: Machine, s) -> None:
    """DBWR S D n (6-11 FNC 91): n words from S on to data bank address D (32-bit)."""
    span = _span(m, s, s.ops[1], s.ops[0])
    if span:
        first, n = span
        for k, v in enumerate(read_block(m, s.ops[0], n, 16)):
            m.databank[first + k] = v & 0xFFFF


DATABANK_ACTIONS = {"dbrd": dbrd, "dbwr": dbwr}
