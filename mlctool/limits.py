"""Numbers as written, shared by every reader of text (IL, stimulus files, device models,
imports, options): one rule for what a number is, and bounds on its size.

DECISION (issue 30.8, 30.16): a number is written in ASCII digits, and nothing else counts.
Python's own readers are wider: int() and float() take any Unicode decimal digit ("٣" is 3,
"３" is 3), blanks around and underscores inside ("1_000"); str.isdigit() also takes "²" and
"¹⁰", which int() then refuses (a crash where the check passed). Every number of every input
is read by `integer` or `real` below (or by a regex of [0-9], which is ASCII), so "٣" is an
error with its place like any other word that is no number.

Python refuses to convert a decimal string of more than 4,300 digits to int (a guard against
quadratic conversion), so every number a user can write is bounded before conversion, with a
diagnostic that says so. DECISION: 20 digits, the length of the largest 64-bit value; no
device number, step, label, time or constant of any target comes near it.
"""

from __future__ import annotations

import math
import re

MAX_DIGITS = 20
_LONG_RUN = re.compile(f"[0-9]{{{MAX_DIGITS + 1},}}")
_INTEGER = {10: re.compile(r"[+-]?([0-9]+)"), 16: re.compile(r"[+-]?([0-9A-Fa-f]+)"),
            # base 0: Python's prefixes, as int(text, 0) reads them (0x1F, 0o17, 0b101, 31)
            0: re.compile(r"[+-]?(?:0[xX]([0-9A-Fa-f]+)|0[oO]([0-7]+)|0[bB]([01]+)|(0+|[1-9][0-9]*))")}
_REAL = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]{1,4})?")
_NOT_FINITE = {"inf", "+inf", "-inf", "nan", "+nan", "-nan"}


def integer(text: str, base: int = 10) -> int:
    """The integer `text` writes: an optional sign and ASCII digits of `base` (10, 16, or 0 for
    Python's 0x/0o/0b prefixes), at most MAX_DIGITS of them; no blanks, no underscores.
    ValueError with a message otherwise."""
    m = _INTEGER[base].fullmatch(text)
    if m is None:
        raise ValueError(f"{clip(text)!r} is not {'a hexadecimal' if base == 16 else 'an'} integer "
                         "(ASCII digits)")
    digits = next(g for g in m.groups() if g is not None) if base == 0 else m[1]
    if len(digits) > MAX_DIGITS:
        raise ValueError(too_long_message(f"{clip(text)!r}", len(digits)))
    return int(text, base)


def real(text: str, finite: bool = True) -> float:
    """The number `text` writes: an optional sign, ASCII digits with a decimal point and an
    exponent (1.5, -.25, 2e3); `inf` and `nan` too unless `finite`. ValueError otherwise."""
    if _REAL.fullmatch(text) is None and (finite or text.lower() not in _NOT_FINITE):
        raise ValueError(f"{clip(text)!r} is not a number (ASCII digits, e.g. 1.5)")
    value = float(text)
    if finite and not math.isfinite(value):
        raise ValueError(f"{clip(text)!r} is too large")
    return value


def long_number(text: str) -> re.Match | None:
    """The first run of more than MAX_DIGITS digits in `text` (its span), or None."""
    return _LONG_RUN.search(text)


def too_long_message(what: str, digits: int) -> str:
    return f"{what} has a number of {digits} digits; numbers have at most {MAX_DIGITS}"


def clip(text: str, n: int = 40) -> str:
    """`text` for a message: at most n characters."""
    return text if len(text) <= n else text[:n - 1] + "…"


def is_decimal(text: str) -> bool:
    """ASCII digits only (no sign), at most MAX_DIGITS of them: a number `integer` reads."""
    return 0 < len(text) <= MAX_DIGITS and text.isascii() and text.isdigit()
