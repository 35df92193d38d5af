"""Bounds on numbers as written, shared by every reader of text (IL, stimulus files, options).

Python refuses to convert a decimal string of more than 4,300 digits to int (a guard against
quadratic conversion), so every number a user can write is bounded before conversion, with a
diagnostic that says so. DECISION: 20 digits, the length of the largest 64-bit value; no
device number, step, label, time or constant of any target comes near it.
"""

from __future__ import annotations

import re

MAX_DIGITS = 20
_LONG_RUN = re.compile(f"[0-9]{{{MAX_DIGITS + 1},}}")


def long_number(text: str) -> re.Match | None:
    """The first run of more than MAX_DIGITS digits in `text` (its span), or None."""
    return _LONG_RUN.search(text)


def too_long_message(what: str, digits: int) -> str:
    return f"{what} has a number of {digits} digits; numbers have at most {MAX_DIGITS}"


def clip(text: str, n: int = 40) -> str:
    """`text` for a message: at most n characters."""
    return text if len(text) <= n else text[:n - 1] + "…"


def is_decimal(text: str) -> bool:
    """ASCII digits only, at most MAX_DIGITS of them: what int(text) reads safely. (str.isdigit
    also takes "²" and other digits int() refuses.)"""
    return 0 < len(text) <= MAX_DIGITS and text.isascii() and text.isdigit()
