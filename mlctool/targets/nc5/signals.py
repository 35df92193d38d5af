"""The NC5's special M/D by name: the rows of signals.tsv (manual 5.2.1, 5.2.2, 5.3.16-5.3.20)
for code of this target (tests/targets/nc5/test_nc5_addresses.py holds the virtual NC's
addresses, nc/addresses.py, to these rows).

Generic code does not import this: it reaches the same table through
mlctool/targetapi/signals.py (`signals_of`, `describe_device`).

    rows()                      every row, in the manual's order
    lookup("M31064")            SignalAt: the row, the channel (1), the device number
    row("M3x064")               the row of a pattern as the manual prints it
    device("M3x064", 2)         "M32064": the pattern on a channel
"""

from __future__ import annotations

from mlctool.syntax.operands import OperandSyntaxError, parse_operand
from mlctool.targetapi import load_target
from mlctool.targetapi.signals import Signal, SignalAt, SignalTable, signals_of


def table() -> SignalTable:
    found = signals_of(load_target("nc5"))
    assert found is not None, "target.toml [signals] of nc5"
    return found


def rows() -> tuple[Signal, ...]:
    return table().signals


def row(pattern: str) -> Signal:
    """The row of a pattern as the manual prints it (M2x000, M30000); KeyError if none."""
    for s in rows():
        if s.device == pattern.replace("X", "x"):
            return s
    raise KeyError(pattern)


def lookup(device: str) -> SignalAt | None:
    """The signal a device (M21000, d31024) is, with its channel; None if it is none."""
    try:
        op = parse_operand(device.strip())
    except OperandSyntaxError:
        return None
    if op.is_const or op.index or op.is_group:
        return None
    return table().at(op.kind, op.number)


def device(pattern: str, channel: int) -> str:
    """The device of a pattern on a channel: ("M2x000", 1) -> "M21000"."""
    s = row(pattern)
    lo, hi = table().channels
    if "x" in s.device and not lo <= channel <= hi:
        raise ValueError(f"{pattern}: channel {channel} outside {lo}-{hi}")
    return f"{s.kind}{s.number(channel)}"
