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
_LITTLE = sys.byteorder == "little"  # the 'Q' views of the bit stores read bytes little-endian first
# Kn groups read 8 aligned device bytes as one 64-bit word q; q % K8_MOD is different for each
# of the 256 patterns of 0/1 bytes (engine._KN: lists indexed by it)
K8_MOD = 258
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


_FLOAT_EXPR = re.compile(r"[0-9.e+\-* ]+")


def _fold_float(expr: str) -> float | None:
    """The value of an expression of float literals (finite constants folded in), or None;
    Python evaluates it in double precision, as the generated code would."""
    return eval(expr, {"__builtins__": {}}) if _FLOAT_EXPR.fullmatch(expr) else None  # noqa: S307


# ---------------------------------------------------------------------------- rung results
# A rung result under construction is a tree of pure expressions: a leaf is the text of an
# expression without side effects (a device read, a compare, a local), a node is
# ("not", x), ("and", (x, ...)) or ("or", (x, ...)). It is rendered as one short-circuit
# Python boolean expression, the cheaper operands of each AND/OR first: reordering and
# skipping pure reads changes no state, and every consumer of a rung result (bit stores,
# `if a:`, m.acc, the edge memories) uses its truth value only (0/1/False/True alike).

_IDENT = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")
_SUBSCRIPT = re.compile(r"[A-Za-z_][A-Za-z_0-9]*\[[0-9]+\]")


def r_not(x):
    return x[1] if type(x) is tuple and x[0] == "not" else ("not", x)


def r_join(op: str, x, y):
    """x AND y / x OR y, flattened into one n-ary node."""
    parts = []
    for z in (x, y):
        if type(z) is tuple and z[0] == op:
            parts.extend(z[1])
        else:
            parts.append(z)
    return (op, tuple(parts))


def r_cost(x) -> int:
    """Rough evaluation cost: locals 1, constant subscripts 2, anything else 4."""
    if type(x) is str:
        return 1 if _IDENT.fullmatch(x) else 2 if _SUBSCRIPT.fullmatch(x) else 4
    if x[0] == "not":
        return r_cost(x[1])
    return sum(r_cost(c) for c in x[1])


def r_size(x) -> int:
    """Leaves and nesting of a tree (the generator settles large ones into `a`)."""
    if type(x) is str:
        return 1
    if x[0] == "not":
        return 1 + r_size(x[1])
    return 1 + sum(r_size(c) for c in x[1])


def r_text(x, inside: str = "") -> str:
    """The Python text of a tree; `inside`: the operator of the enclosing node (parentheses
    where Python's precedence, not > and > or, would regroup)."""
    if type(x) is str:
        return x
    op = x[0]
    if op == "not":
        return f"not {r_text(x[1], 'not')}"
    parts = sorted(x[1], key=r_cost)  # stable: equal costs keep the program's order
    text = f" {op} ".join(r_text(c, op) for c in parts)
    if inside == "not" or inside == "and" and op == "or":
        return f"({text})"
    return text
