"""ASCII codes and check codes (manual 6-9 FNC 76 ASC; 6-10 FNC 82 ASCI, 83 HEX, 84 CCD;
6-12 FNC 116 DESTR, 117 DEVAL; 6-16 FNC 188 CRC; 6-21 FNC 260 DABIN, 261 BINDA).

M9161 (target.toml [special] `eight_bit`) selects the 8-bit mode of ASC/ASCI/HEX/CCD/CRC:
one byte a word (the low byte; the high byte 0 or ignored) instead of two (low byte first).
"""

from __future__ import annotations

import math
from decimal import ROUND_DOWN, ROUND_HALF_UP, Decimal

from mlctool.sim import semantics as base
from mlctool.sim.state import Machine, f32_bits, to_f32
from mlctool.targets.vs.common import (
    NoTerminator,
    count,
    op_error,
    read_block,
    read_string,
    relay,
    set_flags,
    write_block,
    write_string,
)

HEX_DIGITS = "0123456789ABCDEF"
F32_MAX = float.fromhex("0x1.fffffep127")


def _eight_bit(m: Machine) -> bool:
    return bool(relay(m, "eight_bit"))


def _read_bytes(m: Machine, ref, n: int) -> list[int]:
    """n bytes from ref on: low then high byte of each word, or low bytes only (M9161 On)."""
    if _eight_bit(m):
        return [v & 0xFF for v in read_block(m, ref, n, 16)]
    words = read_block(m, ref, (n + 1) // 2, 16)
    return [(words[k // 2] >> (8 * (k % 2))) & 0xFF for k in range(n)]


def _write_bytes(m: Machine, ref, data: list[int]) -> None:
    """Bytes into words: one a word (M9161 On, high byte 0) or two a word, low byte first
    (an odd count keeps the last word's high byte)."""
    if _eight_bit(m):
        write_block(m, ref, list(data), 16)
        return
    words = []
    for k in range(0, len(data), 2):
        if k + 1 < len(data):
            words.append(data[k] | (data[k + 1] << 8))
        else:  # the high byte of the last word stays as it was
            old = read_block(m, ref, k // 2 + 1, 16)[-1] & 0xFF00
            words.append(data[k] | old)
    write_block(m, ref, words, 16)


# ------------------------------------------------------------------ ASC, ASCI, HEX, CCD, CRC

def asc(m: Machine, s) -> None:
    """ASC S D: the letters typed in the instruction (up to 8) as ASCII into D: two a word
    (4 words) or one a word (M9161 On, 8 words). Fewer than 8 letters are filled up with
    spaces, 20H (6-9 FNC 76: "不足8個時，則會以空白鍵補滿8個字母")."""
    if not m.acc:
        return
    text = s.ops[0].value if isinstance(getattr(s.ops[0], "value", None), str) else s.ops[0].text
    data = list(text.strip('"').encode("ascii", "replace")[:8])
    data += [0x20] * (8 - len(data))
    if _eight_bit(m):
        write_block(m, s.ops[1], data, 16)
    else:
        write_block(m, s.ops[1], [data[k] | (data[k + 1] << 8) for k in range(0, 8, 2)], 16)


@base._on
def asci(m: Machine, s) -> None:
    """ASCI S D n: the n lowest hex digits of S, S+1 ... (S the lowest word) as ASCII codes,
    the most significant first (FNC 82; D0 = 4567H, D1 = 89ABH, n = 8 -> "89AB4567").
    DECISION: the digit order is the FX one; the page's figure is lost."""
    src, dst, nr = s.ops
    n = count(m, nr)
    if not 1 <= n <= 256:
        op_error(m, s, f"n = {n} is outside 1-256")
        return
    words = read_block(m, src, (n + 3) // 4, 16)
    value = sum((w & 0xFFFF) << (16 * k) for k, w in enumerate(words))
    digits = [(value >> (4 * k)) & 0xF for k in reversed(range(n))]
    _write_bytes(m, dst, [ord(HEX_DIGITS[d]) for d in digits])


@base._on
def hex_(m: Machine, s) -> None:
    """HEX S D n: n ASCII codes (hex digits, the first the most significant) as a number into
    D, D+1 ... (D the lowest word); a code that is no hex digit: operation error (FNC 83)."""
    src, dst, nr = s.ops
    n = count(m, nr)
    if not 1 <= n <= 256:
        op_error(m, s, f"n = {n} is outside 1-256")
        return
    text = bytes(_read_bytes(m, src, n)).decode("latin-1")
    if any(c not in HEX_DIGITS for c in text):
        op_error(m, s, f"{text!r} holds a character that is no hex digit 0-9, A-F")
        return
    value = int(text, 16)
    words = (n + 3) // 4
    write_block(m, dst, [(value >> (16 * k)) & 0xFFFF for k in range(words)], 16)


@base._on
def ccd(m: Machine, s) -> None:
    """CCD S D n: D = the sum of n bytes, D+1 = their horizontal parity (XOR) (FNC 84)."""
    src, dst, nr = s.ops
    n = count(m, nr)
    if not 1 <= n <= 256:
        op_error(m, s, f"n = {n} is outside 1-256")
        return
    data = _read_bytes(m, src, n)
    parity = 0
    for b in data:
        parity ^= b
    write_block(m, dst, [sum(data) & 0xFFFF, parity], 16)


def crc16(data: list[int]) -> int:
    """CRC-16 of X16 + X15 + X2 + 1, the Modbus form (reflected, start FFFFH): the page's
    01H 03H 04H EDH 85H A3H 28H gives 58A6H."""
    crc = 0xFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


@base._on
def crc(m: Machine, s) -> None:
    """CRC S D n: the CRC-16 of n bytes into D (16-bit mode), or its low/high byte into D and
    D+1 (M9161 On) (FNC 188)."""
    src, dst, nr = s.ops
    n = count(m, nr)
    if not 1 <= n <= 256:
        op_error(m, s, f"n = {n} is outside 1-256")
        return
    c = crc16(_read_bytes(m, src, n))
    write_block(m, dst, [c & 0xFF, c >> 8] if _eight_bit(m) else [c], 16)


# ------------------------------------------------------------------ DABIN, BINDA (6-21)

def _places(s) -> int:
    return 10 if s.width == 32 else 5  # digits after the sign: 11 / 6 characters


@base._on
def dabin(m: Machine, s) -> None:
    """DABIN S D: sign (20H +, 2DH -) and 5 (10) decimal digits, two characters a word from
    the low byte of S, into the number D; 20H, 00H and 30H in the digits are 0; another
    character or a value past the width: operation error (FNC 260)."""
    places = _places(s)
    words = read_block(m, s.ops[0], (places + 2) // 2, 16)
    chars = [(words[k // 2] >> (8 * (k % 2))) & 0xFF for k in range(places + 1)]
    sign, digits = chars[0], chars[1:]
    if sign not in (0x20, 0x2D) or any(c not in (0x20, 0x00) and not 0x30 <= c <= 0x39 for c in digits):
        op_error(m, s, "S holds a character that is no sign (20H/2DH) or digit")
        return
    value = int("".join(chr(c) if 0x30 <= c <= 0x39 else "0" for c in digits))
    value = -value if sign == 0x2D else value
    lo, hi = (-(1 << 31), (1 << 31) - 1) if s.width == 32 else (-32768, 32767)
    if not lo <= value <= hi:
        op_error(m, s, f"{value} is outside {lo}..{hi}")
        return
    s.ops[1].set(m, value)


@base._on
def binda(m: Machine, s) -> None:
    """BINDA S D: S as sign (20H/2DH) and 5 (10) digits, leading zeros as 20H, two characters
    a word into D from the low byte (FNC 261). 16-bit: M9091 Off adds a 0000H word, On adds
    nothing; 32-bit: the last word's high byte is 00H (M9091 Off) or 20H (On)."""
    places = _places(s)
    v = s.ops[0].get(m)
    text = str(abs(v)).rjust(places)
    chars = [0x2D if v < 0 else 0x20] + [ord(c) for c in text]
    keep = bool(relay(m, "binda_mode"))
    if s.width == 32:
        chars.append(0x20 if keep else 0x00)
    words = [chars[k] | (chars[k + 1] << 8) for k in range(0, len(chars), 2)]
    if s.width == 16 and not keep:
        words.append(0)
    write_block(m, s.ops[1], words, 16)


# ------------------------------------------------------------------ DESTR, DEVAL (6-12)

def _float_in(m: Machine, ref) -> float:
    return to_f32(ref.getf(m))


def _set_float(m: Machine, ref, x: float) -> None:
    raw = f32_bits(x)
    write_block(m, ref, [raw & 0xFFFF, raw >> 16], 16)


@base._on
def destr(m: Machine, s) -> None:
    """DESTR S1 S2 D: the float S1 as an ASCII string in D (FNC 116). S2 = 0 decimal / 1
    exponent form, S2+1 the total characters (2-24; exponent form at least S2+2 + 6), S2+2
    the decimals (0-7); sign 20H/2DH, then 20H up to the number, rounded half-up; exponent
    form: one integer digit, E, sign 2BH/2DH, two digits; terminator 00H / 0000H.
    DECISION: a number that does not fit the total is an operation error."""
    x = _float_in(m, s.ops[0])
    form, total, decimals = read_block(m, s.ops[1], 3, 16)
    if form not in (0, 1) or not 0 <= decimals <= 7 or not 2 <= total <= 24:
        op_error(m, s, f"format {form}, {total} characters, {decimals} decimals: "
                       "0/1, 2-24, 0-7")
        return
    if not math.isfinite(x):
        op_error(m, s, "the value is not a finite float")
        return
    q = Decimal(1).scaleb(-decimals)
    if form == 0:
        body = str(Decimal(abs(x)).quantize(q, rounding=ROUND_HALF_UP))
    else:
        mant, exp = Decimal(abs(x)), 0
        if mant:
            exp = mant.adjusted()
            mant = mant.scaleb(-exp).quantize(q, rounding=ROUND_HALF_UP)
            if mant >= 10:  # 9.9996 -> 10.000: one more in the exponent
                exp += 1
                mant = (mant / 10).quantize(q, rounding=ROUND_HALF_UP)
        else:
            mant = mant.quantize(q)
        if abs(exp) > 99:
            op_error(m, s, f"the exponent {exp} has more than 2 digits")
            return
        body = f"{mant}E{'-' if exp < 0 else '+'}{abs(exp):02d}"
    if len(body) + 1 > total:
        op_error(m, s, f"{body} does not fit {total} characters")
        return
    text = ("-" if x < 0 else " ") + body.rjust(total - 1)
    write_string(m, s.ops[2], text.encode("ascii"))


@base._on
def deval(m: Machine, s) -> None:
    """DEVAL S D: a decimal or exponent-form string into the float D (FNC 117): sign 2BH/20H
    (+) or 2DH (-), spaces and zeros before the first significant digit ignored, 6
    significant digits kept, the rest dropped; at most 24 characters. Result 0: M9020;
    below 2^-126: D = 2^-126, M9021; 2^128 and over: D = the largest float, M9022."""
    try:
        raw = read_string(m, s.ops[0])
    except NoTerminator:
        op_error(m, s, f"{s.ops[0].text}: no 00H terminator before the end of the device")
        return
    text = raw.decode("latin-1")
    if len(text) > 24:
        op_error(m, s, f"the string has {len(text)} characters, more than 24")
        return
    body = text.strip(" ")
    negative = body[:1] == "-"
    if body[:1] in "+-" and body:
        body = body[1:].lstrip(" ")
    mant, _, exp = body.partition("E")
    try:
        if not mant or not all(c.isdigit() or c == "." for c in mant) or mant.count(".") > 1:
            raise ValueError
        value = Decimal(mant)
        if exp:
            value = value.scaleb(int(exp))
    except (ValueError, ArithmeticError):
        op_error(m, s, f"{text!r} is not a number in decimal or exponent form")
        return
    if value:
        q = Decimal(1).scaleb(value.adjusted() - 5)  # 6 significant digits, the rest dropped
        value = value.quantize(q, rounding=ROUND_DOWN)
    x = float(-value if negative else value)
    if x == 0:
        _set_float(m, s.ops[1], 0.0)
        set_flags(m, zero=True, borrow=False, carry=False)
    elif abs(x) < 2.0 ** -126:
        _set_float(m, s.ops[1], math.copysign(2.0 ** -126, x))
        set_flags(m, zero=False, borrow=True, carry=False)
    elif abs(x) >= 2.0 ** 128:
        _set_float(m, s.ops[1], math.copysign(F32_MAX, x))
        set_flags(m, zero=False, borrow=False, carry=True)
    else:
        _set_float(m, s.ops[1], to_f32(x))
        set_flags(m, zero=False, borrow=False, carry=False)


ASCII_ACTIONS = {
    "asc": asc, "asci": asci, "hex": hex_, "ccd": ccd, "crc": crc, "dabin": dabin,
    "binda": binda, "destr": destr, "deval": deval,
}
