"""Special-module buffer memory (VS 6-9 FNC 78 FROM / 79 TO, 10-x module pages).

No module hardware is simulated: each slot (K1-K8 on VS2/VSM, K1-K16 on VS3; target.toml
`[buffer_memory]`) has a buffer memory of 16-bit registers BFM#0-#32767 that FROM reads, TO
writes and the stimulus drives and checks (`BFM1#5=123`, `expect BFM2#0=201`; docs/stimulus.md).
Registers hold 0 until written. 32-bit forms move pairs (BFM#m2 low, #m2+1 high), n pairs.
"""

from __future__ import annotations

from mlctool.sim import semantics as base
from mlctool.sim.state import Machine
from mlctool.targets.vs.common import op_error, read_block, write_block


def slots(target) -> int:
    """Number of module slots of the target's model (0: no buffer memory)."""
    table = target.settings.get("buffer_memory") or {}
    per_model = table.get("slots", {})
    return int(per_model.get(target.model or "", per_model.get("default", 0)))


def last_register(target) -> int:
    return int((target.settings.get("buffer_memory") or {}).get("last", 32767))


def _where(m: Machine, s, n_words: int) -> tuple[int, int] | None:
    """(slot, first register) of a FROM/TO, or None after an operation error."""
    slot, first = s.ops[0].get(m), s.ops[1].get(m)
    top = slots(m.target)
    if not 1 <= slot <= top:
        op_error(m, s, f"module K{slot} is outside K1-K{top}")
        return None
    if first < 0 or first + n_words - 1 > last_register(m.target):
        op_error(m, s, f"BFM#{first} .. #{first + n_words - 1} is outside #0-#{last_register(m.target)}")
        return None
    return slot, first


def _count(m: Machine, s) -> int | None:
    n = s.ops[3].get(m)
    if not 1 <= n <= 32767:
        op_error(m, s, f"n = {n} is outside 1-32767")
        return None
    return n


def _block(m: Machine, s) -> tuple[int, int, int, int] | None:
    """(slot, first register, n, words per register) of a FROM/TO, or None after an
    operation error."""
    n = _count(m, s)
    size = 2 if s.width == 32 else 1
    where = n and _where(m, s, n * size)
    return (*where, n, size) if where else None


@base._on
def from_(m: Machine, s) -> None:
    """FROM m1 m2 D n: n registers (pairs) from BFM#m2 of module m1 into D on (6-9 FNC 78)."""
    block = _block(m, s)
    if not block:
        return
    slot, first, n, size = block
    words = [m.bfm.get((slot, first + k), 0) for k in range(n * size)]
    values = [words[k] | (words[k + 1] << 16) for k in range(0, len(words), 2)] if size == 2 else words
    write_block(m, s.ops[2], values, s.width)


@base._on
def to(m: Machine, s) -> None:
    """TO m1 m2 S n: n registers (pairs) from S on into BFM#m2 of module m1 (6-9 FNC 79)."""
    block = _block(m, s)
    if not block:
        return
    slot, first, n, size = block
    for k, v in enumerate(read_block(m, s.ops[2], n, s.width)):
        for h in range(size):
            m.bfm[(slot, first + k * size + h)] = (v >> (16 * h)) & 0xFFFF


BFM_ACTIONS = {"from": from_, "to": to}
