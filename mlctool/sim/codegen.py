"""What the compiled engine's code generators share: the instruction classes and operand
kinds they inline, the expression helpers, and `Unsupported` (the program goes to the
reference interpreter)."""

from __future__ import annotations

import re
import sys

from mlctool.sim.operands import BitRef, WordRef

RUNG_CLASSES = frozenset({"load", "and", "or", "anb", "orb", "mps", "mrd", "mpp", "inv"})
BIT_KINDS = ("X", "Y", "M", "A", "T", "C")
WORD_KINDS = ("D", "V", "Z", "T")
_CMP = {"cmp_eq": "==", "cmp_ne": "!=", "cmp_gt": ">", "cmp_lt": "<", "cmp_ge": ">=", "cmp_le": "<="}
_FLOAT = {"fadd": "+", "fsub": "-", "fmul": "*"}
_ARITH = {"add": "+", "sub": "-", "wand": "&", "wor": "|", "wxor": "^"}
_GATHER = 0x0102040810204080  # (x * _GATHER) >> 56: the low bits of x's 8 bytes, byte k at bit k
_LITTLE = sys.byteorder == "little"  # the 'Q' views of the bit stores read bytes little-endian first
# The float buffer's 16-bit halves (engine.py FH) holding the low and high word of a D pair
_FL, _FHI = (0, 1) if _LITTLE else (1, 0)


class Unsupported(Exception):
    """The program needs the reference interpreter."""


def _bit_simple(ref) -> bool:
    return type(ref) is BitRef and ref.ix is None and ref.kind in BIT_KINDS


def _s16(expr: str) -> str:
    return f"(({expr} ^ 32768) - 32768)"


def _s32(expr: str) -> str:
    return f"(({expr} ^ 2147483648) - 2147483648)"


def _word(ref) -> bool:
    """A D/T/V/Z word operand (plain or index-modified) the generator reads and writes inline."""
    return type(ref) is WordRef and ref.kind in WORD_KINDS


_CONST_EXPR = re.compile(r"[0-9()+\-*&|^~<> ]+")


def _fold(expr: str) -> int | None:
    """The value of an expression of integer literals (known words folded in), or None."""
    return eval(expr, {"__builtins__": {}}) if _CONST_EXPR.fullmatch(expr) else None  # noqa: S307
