"""Helpers of the FX-family routines (Vigor VS): flags, operation errors, blocks of words or
bits, strings in registers, counts read from operands, per-step memory.

Everything is read from target.toml ([flags], [special]); a target without those keys gets
no flags and no error registers, so NC5 is untouched.
"""

from __future__ import annotations

from mlctool.sim import semantics as base
from mlctool.sim.operands import BitRef, ConstRef, CounterRef, GroupRef, WordRef
from mlctool.sim.semantics import set_flags  # noqa: F401 - the FX routines' import of it
from mlctool.sim.state import Machine, SimFault, s16, s32

OPERATION_ERROR_CODE = 6706  # "operand or operand value out of range" (vs_reading.md 5.8)


def flag(m: Machine, name: str) -> int:
    n = m.target.settings.get("flags", {}).get(name)
    return m.bits["M"][n] if n is not None else 0


def special(m: Machine, name: str) -> int | None:
    """A special relay/register number of target.toml [special] (None: the target has none)."""
    return m.target.settings.get("special", {}).get(name)


def relay(m: Machine, name: str) -> int:
    n = special(m, name)
    return m.bits["M"][n] if n is not None else 0


def set_relay(m: Machine, name: str, on: bool) -> None:
    n = special(m, name)
    if n is not None:
        m.bits["M"][n] = 1 if on else 0


def scans_left(m: Machine, progress: list[int], m1: int) -> bool:
    """An instruction that takes m1 scans (SORT, SORT2: progress[0] scans done so far): False
    once it has finished, the scan after the last one clearing the done flag M9029 it set."""
    if progress[0] == m1:  # done: the flag was On for one scan
        set_relay(m, "done", False)
        progress[0] += 1
    return progress[0] < m1


def op_error(m: Machine, s, why: str, code: int | None = None, goes_on: bool = False) -> None:
    """"運算錯誤" (operation error): the instruction is not executed, the run goes on, the
    alarm is reported; semantics.alarm sets M9067/D9067 on targets that have them. `code`:
    the page's own error number for D9067 (PID 6730-6747) instead of the target's default;
    `goes_on`: the instruction still runs (PID 6740-6747: "continues")."""
    base.alarm(m, base.OPERATION_ALARM, f"{s.ins.mnemonic}: {why}"
               + ("; continues" if goes_on else "; not executed"))
    err = m.target.settings.get("operation_error")
    if err and code is not None:
        m.words["D"][err["register"]] = code


def state(m: Machine, s, default):
    """Memory of one step that outlives the scan (SORT progress, PID history ...); cleared by
    a power cycle."""
    return m.fx_state.setdefault(s.index, default)


# ------------------------------------------------------------------ counts

def count(m: Machine, ref) -> int:
    """n operands: a constant, or the 16-bit word of a register even in a 32-bit instruction
    (SER n, WSFR n1 ...)."""
    if isinstance(ref, WordRef) and ref.width == 32:
        return s16(m.words[ref.kind][ref.addr(m)])
    return ref.get(m)


def table_count(m: Machine, s, k: int) -> int | None:
    """Operand k's count (`count`) if it lies in the table's range for it, else None after an
    operation error (5-1: "運算元...超出範圍" is an operation error, the instruction is not
    executed): a register or an index-modified constant may hold anything."""
    return base.count_in(m, s, k, count(m, s.ops[k]))


# ------------------------------------------------------------------ blocks

def _size(ref, width: int) -> int:
    return 2 if width == 32 else 1


def _room(ref, a: int, extent: int, length: int) -> None:
    """A block that runs past the device's last number is a fault, never a traceback."""
    if a + extent > length:
        raise SimFault(f"{ref.text}: a block of {extent} from {ref.kind}{a} runs past "
                       f"{ref.kind}{length - 1}")


def read_block(m: Machine, ref, n: int, width: int) -> list[int]:
    """n consecutive values from ref on: words (pairs when 32-bit), Kn groups, bits, or a
    constant repeated (BK+ S2 = K100)."""
    if n <= 0:
        return []
    if isinstance(ref, ConstRef):
        return [ref.get(m)] * n
    if isinstance(ref, GroupRef):
        a = ref.addr(m, ref.n * n)
        bits = m.bits[ref.kind]
        _room(ref, a, ref.n * n, len(bits))
        out = []
        for k in range(n):
            v = sum(bits[a + k * ref.n + i] << i for i in range(ref.n))
            out.append(ref.wrap(v) if ref.n == width else v)
        return out
    if isinstance(ref, BitRef):
        a = ref.addr(m, n)
        _room(ref, a, n, len(m.bits[ref.kind]))
        return list(m.bits[ref.kind][a:a + n])
    if isinstance(ref, CounterRef):
        a = ref.addr(m)
        if m.is_c32(a):
            a = ref.addr(m, n)
            _room(ref, a, n, len(m.cval))
            return [s32(v) for v in m.cval[a:a + n]]
        words = m.cval
    elif isinstance(ref, WordRef):
        words = m.words[ref.kind]
    else:
        raise SimFault(f"{ref.text}: not a block operand")
    size = _size(ref, width)
    a = ref.addr(m, n * size)
    _room(ref, a, n * size, len(words))
    if size == 1:
        return [s16(v) for v in words[a:a + n]]
    return [s32(words[a + 2 * k] | (words[a + 2 * k + 1] << 16)) for k in range(n)]


def write_block(m: Machine, ref, values: list[int], width: int) -> None:
    n = len(values)
    if n == 0:
        return
    if isinstance(ref, GroupRef):
        a = ref.addr(m, ref.n * n)
        bits = m.bits[ref.kind]
        _room(ref, a, ref.n * n, len(bits))
        for k, v in enumerate(values):
            for i in range(ref.n):
                bits[a + k * ref.n + i] = (v >> i) & 1
                m.writer[(ref.kind, a + k * ref.n + i)] = m.pc
        return
    if isinstance(ref, BitRef):
        a = ref.addr(m, n)
        _room(ref, a, n, len(m.bits[ref.kind]))
        for k, v in enumerate(values):
            m.bits[ref.kind][a + k] = 1 if v else 0
            m.writer[(ref.kind, a + k)] = m.pc
        return
    if isinstance(ref, CounterRef):
        a = ref.addr(m)
        if m.is_c32(a):
            a = ref.addr(m, n)
            _room(ref, a, n, len(m.cval))
            for k, v in enumerate(values):
                m.cval[a + k] = s32(v)
                m.writer[("C", a + k)] = m.pc
            return
        words, kind = m.cval, "C"
    elif isinstance(ref, WordRef):
        words, kind = m.words[ref.kind], ref.kind
    else:
        raise SimFault(f"{ref.text} cannot be written")
    size = _size(ref, width)
    a = ref.addr(m, n * size)
    _room(ref, a, n * size, len(words))
    for k, v in enumerate(values):
        for h in range(size):
            words[a + k * size + h] = (v >> (16 * h)) & 0xFFFF
            m.writer[(kind, a + k * size + h)] = m.pc


def span(m: Machine, ref, n: int, width: int) -> tuple[str, int, int] | None:
    """(device kind, first, last) of a block, for the overlap rules (BK+, $+); None: constant."""
    if isinstance(ref, ConstRef):
        return None
    if isinstance(ref, GroupRef):
        a = ref.addr(m, ref.n * n)
        return ref.kind, a, a + ref.n * n - 1
    size = 1 if isinstance(ref, BitRef) else _size(ref, width)
    a = ref.addr(m)
    return ref.kind, a, a + n * size - 1


def overlap(a, b) -> bool:
    return a is not None and b is not None and a[0] == b[0] and a[1] <= b[2] and b[1] <= a[2]


# ------------------------------------------------------------------ strings (6-18, 2-13)

class NoTerminator(Exception):
    """A string in registers with no 00H before the end of the device range."""


def read_string(m: Machine, ref) -> bytes:
    """Characters of a string operand: a "..." constant, or registers holding two characters a
    word (low byte first) up to the terminator 00H (6-18 $+ figure)."""
    if isinstance(ref, ConstRef):
        if isinstance(ref.value, str):
            return ref.value.encode("ascii", "replace")
        raise SimFault(f"{ref.text}: a string operand takes registers or \"...\"")
    if not isinstance(ref, WordRef):
        raise SimFault(f"{ref.text}: strings are held in word registers")
    words = m.words[ref.kind]
    out = bytearray()
    for a in range(ref.addr(m), len(words)):
        for byte in (words[a] & 0xFF, words[a] >> 8):
            if byte == 0:
                return bytes(out)
            out.append(byte)
    raise NoTerminator(ref.text)


def write_string(m: Machine, ref, text: bytes) -> None:
    """Two characters a word, then the terminator: 00H after an odd count, a 0000H word after
    an even one (6-18 $+)."""
    data = bytes(text) + b"\0" + (b"\0" if len(text) % 2 == 0 else b"")
    words = [data[k] | (data[k + 1] << 8) for k in range(0, len(data), 2)]
    if not isinstance(ref, WordRef):
        raise SimFault(f"{ref.text}: strings are written to word registers")
    a = ref.addr(m, len(words))
    _room(ref, a, len(words), len(m.words[ref.kind]))
    for k, w in enumerate(words):
        m.words[ref.kind][a + k] = w
        m.writer[(ref.kind, a + k)] = m.pc
