"""String instructions (manual 6-18, FNC 200-209). A string lives in registers, two ASCII
characters a word (low byte first), ended by 00H (odd length) or a 0000H word (even); "..."
constants are strings too. A string without its terminator is an operation error."""

from __future__ import annotations

from mlctool.limits import is_decimal
from mlctool.sim import semantics as base
from mlctool.sim.state import Machine
from mlctool.targets.vs.common import (
    NoTerminator,
    count,
    op_error,
    read_block,
    read_string,
    span,
    write_block,
    write_string,
)


def _strings(fn):
    """Run fn; a source without a terminator becomes the page's operation error."""
    @base._on
    def run(m: Machine, s) -> None:
        try:
            fn(m, s)
        except NoTerminator as e:
            op_error(m, s, f"the string at {e} has no 00H terminator")
    run.__name__ = fn.__name__
    return run


def _limits(s) -> tuple[int, int]:
    """STR/VAL: total characters 2-8 and decimals 0-5 (16-bit), 2-13 and 0-10 (32-bit)."""
    return (13, 10) if s.width == 32 else (8, 5)


def _str(m: Machine, s) -> None:
    """STR S1 S2 D: S2 as text of S1 characters with S1+1 decimals: sign (20H or 2DH),
    spaces, digits with the point (0 added before it: -0.00123450), terminator (FNC 200)."""
    fmt, src, dst = s.ops
    total, decimals = read_block(m, fmt, 2, 16)
    top, top_dec = _limits(s)
    if not (2 <= total <= top and 0 <= decimals <= top_dec):
        op_error(m, s, f"format {total} characters / {decimals} decimals is out of range")
        return
    v = src.get(m)
    digits = str(abs(v)).rjust(decimals + 1, "0")
    body = digits if decimals == 0 else f"{digits[:-decimals]}.{digits[-decimals:]}"
    if len(body) + 1 > total:
        op_error(m, s, f"{v} does not fit {total} characters")
        return
    sign = "-" if v < 0 else " "
    write_string(m, dst, (sign + body.rjust(total - 1)).encode("ascii"))


def _val(m: Machine, s) -> None:
    """VAL S D1 D2: text -> D1 = characters, D1+1 = decimals, D2 = the digits as one integer
    (-123.45 -> -12345); spaces after the sign are skipped (FNC 201)."""
    src, fmt, dst = s.ops
    text = read_string(m, src).decode("ascii", "replace")
    top, top_dec = _limits(s)
    if not 2 <= len(text) <= top:
        op_error(m, s, f"{len(text)} characters is outside 2-{top}")
        return
    if text[0] not in " -":
        op_error(m, s, "the first character is not a space or '-'")
        return
    body = text[1:].lstrip(" ")
    whole, _, frac = body.partition(".")
    if not is_decimal(whole + frac) or not is_decimal(whole) or len(frac) > top_dec:
        op_error(m, s, f"{text!r} is not a number of this format")
        return
    v = int(whole + frac) * (-1 if text[0] == "-" else 1)
    lo, hi = (-(1 << 31), (1 << 31) - 1) if s.width == 32 else (-32768, 32767)
    if not lo <= v <= hi:
        op_error(m, s, f"{v} does not fit {s.width} bits")
        return
    write_block(m, fmt, [len(text), len(frac)], 16)
    dst.set(m, v)


def _concat(m: Machine, s) -> None:
    """$+ S1 S2 D: S1 then S2 into D; the same device twice is an operation error (FNC 202)."""
    a, b, dst = s.ops
    where = [span(m, r, 1, 16) for r in s.ops]
    if any(w is not None and where.count(w) > 1 for w in where):
        op_error(m, s, "S1, S2 and D name the same device")
        return
    write_string(m, dst, read_string(m, a) + read_string(m, b))


def _len(m: Machine, s) -> None:
    """LEN S D: the characters before the 00H terminator (FNC 203); more than 32767 (an R
    string can hold 48000) is the page's operation error, D unchanged."""
    n = len(read_string(m, s.ops[0]))
    if n > 32767:
        op_error(m, s, f"the string has {n} characters, more than 32767")
        return
    s.ops[1].set(m, n)


def _side(right: bool):
    """RIGHT/LEFT S D n: n characters from the right/left end; n = 0 writes the empty string;
    n < 0 or longer than S is an operation error (FNC 204/205)."""
    def run(m: Machine, s) -> None:
        text = read_string(m, s.ops[0])
        n = count(m, s.ops[2])
        if not 0 <= n <= len(text):
            op_error(m, s, f"n = {n} is outside 0-{len(text)}")
            return
        write_string(m, s.ops[1], (text[len(text) - n:] if right else text[:n]))
    return run


def _midr(m: Machine, s) -> None:
    """MIDR S1 D S2: S2+1 characters from character S2 (1 = first); S2+1 = 0: not executed,
    -1: to the end (FNC 206)."""
    text = read_string(m, s.ops[0])
    start, n = read_block(m, s.ops[2], 2, 16)
    if n == 0:
        return
    if n == -1:
        n = len(text) - start + 1
    if start < 1 or n < 0 or start + n - 1 > len(text):
        op_error(m, s, f"characters {start}..{start + n - 1} are outside 1-{len(text)}")
        return
    write_string(m, s.ops[1], text[start - 1:start - 1 + n])


def _midw(m: Machine, s) -> None:
    """MIDW S1 D S2: the first S2+1 characters of S1 (-1: all of it) overwrite D's string from
    character S2; what would run past D's end is dropped; 0: not executed (FNC 207)."""
    text = read_string(m, s.ops[0])
    into = bytearray(read_string(m, s.ops[1]))
    start, n = read_block(m, s.ops[2], 2, 16)
    if n == 0:
        return
    if n == -1:
        n = len(text)
    if not 1 <= start <= len(into) or not 0 <= n <= len(text):
        op_error(m, s, f"position {start} / {n} characters out of range")
        return
    piece = text[:n][:len(into) - start + 1]
    into[start - 1:start - 1 + len(piece)] = piece
    write_string(m, s.ops[1], bytes(into))


def _instr(m: Machine, s) -> None:
    """INSTR S1 S2 D n: position (1 = first) of S1 in S2 searching from character n, 0 when
    absent; n <= 0: not executed; n past S2's end: operation error (FNC 208)."""
    needle, hay = read_string(m, s.ops[0]), read_string(m, s.ops[1])
    n = count(m, s.ops[3])
    if n <= 0:
        return
    if n > len(hay):
        op_error(m, s, f"n = {n} is past the {len(hay)} characters of S2")
        return
    s.ops[2].set(m, hay.find(needle, n - 1) + 1)


def _mov(m: Machine, s) -> None:
    write_string(m, s.ops[1], read_string(m, s.ops[0]))


STRING_ACTIONS = {
    "str": _strings(_str), "val": _strings(_val), "str_concat": _strings(_concat),
    "len": _strings(_len), "right": _strings(_side(True)), "left": _strings(_side(False)),
    "midr": _strings(_midr), "midw": _strings(_midw), "instr": _strings(_instr),
    "str_mov": _strings(_mov),
}
