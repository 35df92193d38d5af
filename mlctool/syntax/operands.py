"""Operand text -> Operand: devices, bit groups, constants, pointers, index suffixes.

Purely syntactic: whether a device kind or number is legal is the checker's business
(mlctool/check/operands.py), which asks the target.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from functools import lru_cache


@dataclass(frozen=True, slots=True)
class Operand:
    kind: str  # a device letter (X Y M A T C D V Z P ...), "K", "F", or "KnX"/"KnY"/...
    number: int = 0  # device number; for Kn groups the first bit device's number
    value: int | float = 0  # K/F constants
    digits: int = 0  # n of a Kn group
    index: tuple[str, int] | None = None  # ("V", 0) for a D5V0 style suffix
    decimals: int = 0  # digits after the point of an F constant as written

    @property
    def is_const(self) -> bool:
        return self.kind in ("K", "F")

    @property
    def is_group(self) -> bool:
        return self.kind.startswith("Kn")

    @property
    def device(self) -> str:
        """The device kind a group or device lives in (X for K2X0)."""
        return self.kind[2:] if self.is_group else self.kind

    def __str__(self) -> str:
        return format_operand(self)


class OperandSyntaxError(ValueError):
    pass


_INDEX_REGS = "VZ"  # index registers: never the device of a Kn bit group
_INDEX = r"(?:(?P<ix>[VZ])(?P<ixn>[0-9]+))?"
_GROUP = re.compile(r"K(?P<n>[0-9]+)(?P<dev>[A-Z])(?P<num>[0-9]+)" + _INDEX)
_K = re.compile(r"K(?P<val>[+-]?[0-9]+)" + _INDEX)
_F = re.compile(r"F(?P<val>[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))")
_DEV = re.compile(r"(?P<dev>[A-Z])(?P<num>[0-9]+)" + _INDEX)


def _index(m) -> tuple[str, int] | None:
    return (m["ix"], int(m["ixn"])) if m["ix"] else None


@lru_cache(maxsize=65536)
def parse_operand(text: str) -> Operand:
    """Parse one operand as written (case-insensitive). Raises OperandSyntaxError."""
    t = text.upper()
    if len(t) > 40:
        raise OperandSyntaxError("operand is too long")
    # K20V0 is the constant K20 modified by V0 (3.4's example), not a bit group of "V"
    if (m := _GROUP.fullmatch(t)) and m["dev"] not in _INDEX_REGS:
        return Operand("Kn" + m["dev"], number=int(m["num"]), digits=int(m["n"]), index=_index(m))
    if m := _K.fullmatch(t):
        return Operand("K", value=int(m["val"]), index=_index(m))
    if m := _F.fullmatch(t):
        try:
            d = Decimal(m["val"])
        except InvalidOperation as e:  # pragma: no cover - the regex admits only decimals
            raise OperandSyntaxError(f"bad float constant {text!r}") from e
        decimals = max(0, -d.as_tuple().exponent) if "." in m["val"] else 0
        return Operand("F", value=float(d), decimals=decimals)
    if m := _DEV.fullmatch(t):
        return Operand(m["dev"], number=int(m["num"]), index=_index(m))
    if re.fullmatch(r"H[0-9A-F]+", t):
        raise OperandSyntaxError(f"{text!r}: this target has no hexadecimal H constants; write K{int(t[1:], 16)}")
    if re.fullmatch(r"[+-]?[0-9]+", t):
        raise OperandSyntaxError(f"{text!r}: a constant needs the K prefix (K{t})")
    raise OperandSyntaxError(f"{text!r} is not a device, constant or pointer")


def format_operand(op: Operand) -> str:
    ix = f"{op.index[0]}{op.index[1]}" if op.index else ""
    if op.kind == "K":
        return f"K{op.value}{ix}"
    if op.kind == "F":
        return "F" + (f"{op.value:.{op.decimals}f}" if op.decimals else f"{op.value:.0f}")
    if op.is_group:
        return f"K{op.digits}{op.device}{op.number}{ix}"
    return f"{op.kind}{op.number}{ix}"


SYMBOL = re.compile(r"[A-Za-z_][A-Za-z0-9_.]*")
