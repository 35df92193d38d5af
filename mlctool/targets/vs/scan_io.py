"""Scanning input instructions of the VS family (6-7 FNC 52 MTR, 6-9 FNC 72 DSW): they drive
a Y scanning sequence scan by scan and read the X inputs the stimulus gives while a line is
driven, as the pages' wiring figures show. The stimulus plays the switches: it sets the X
levels the scan that reads a line should see.

Steps last at least a time slice of virtual time (MTR 10 ms a half-row, DSW 100 ms a digit)
and at least one execution; a step moves on at the first execution that finds its slice
over, so a 10 ms scan gives MTR's "2 scans a row" and a 1 ms scan its 20 ms.
"""

from __future__ import annotations

from mlctool.sim.state import Machine
from mlctool.targets.vs.common import op_error, read_block, set_relay, state, write_block

MTR_HALF_ROW_US = 10_000  # a row: drive it, then read it (2 scans, 20 ms below 10 ms scans)
DSW_DIGIT_US = 100_000  # each scan output On 0.1 s (6-9 DSW time chart)


def _advance(m: Machine, memo: dict, slice_us: int) -> bool:
    """True when the present step's slice is over (the step moves on at this execution)."""
    if m.now_us - memo["since"] >= slice_us:
        memo["since"] = m.now_us
        return True
    return False


def _done_on(m: Machine, memo: dict) -> None:
    set_relay(m, "done", True)  # M9029 for one scan: the next execution turns it Off
    memo["done"] = True


def _done_off(m: Machine, memo: dict) -> None:
    if memo.pop("done", False):
        set_relay(m, "done", False)


def _drive(m: Machine, d1, lines: int, on_line: int | None) -> None:
    for k in range(lines):
        d1.setbit(m, k == on_line, k)


# ------------------------------------------------------------------ MTR (6-7 FNC 52)

def _matrix_offset(m: Machine, d2, row: int, i: int) -> int:
    """Row r, input i -> D2 + r*10 + i for decimal devices (M0-M7, M10-M17 in the page's
    figure), D2 + r*8 + i (the next octal numbers) for Y."""
    return row * (8 if m.target.devices[d2.kind].radix == 8 else 10) + i


def mtr(m: Machine, s) -> None:
    """MTR S D1 D2 n: n rows of 8 switches. Row r: D1+r On for one half-row, then the 8
    inputs S..S+7 are read into row r of D2 (the scan after D1+r went out sees them) while
    D1+r stays On for the second half; then the next row. M9029 On for the scan that
    completes the last row. Off: the scan outputs go Off, D2 keeps its states; the next On
    starts again from row 0."""
    src, d1, d2, n_ref = s.ops
    rows = n_ref.get(m)
    memo = state(m, s, {})
    _done_off(m, memo)
    if not m.acc:
        if memo:
            _drive(m, d1, rows, None)
            memo.clear()
        return
    if not memo:
        memo.update(row=0, half=0, since=m.now_us)
    elif _advance(m, memo, MTR_HALF_ROW_US):
        if memo["half"] == 0:
            memo["half"] = 1
            for i in range(8):
                d2.setbit(m, src.bit(m, i), _matrix_offset(m, d2, memo["row"], i))
            if memo["row"] == rows - 1:
                _done_on(m, memo)
        else:
            memo.update(row=(memo["row"] + 1) % rows, half=0)
    _drive(m, d1, rows, memo["row"])


# ------------------------------------------------------------------ DSW (6-9 FNC 72)

def dsw(m: Machine, s) -> None:
    """DSW S D1 D2 n: n sets (1-2) of 4-digit BCD switches on S..S+3 (and S+4..S+7), read by
    D1..D1+3 in turn, each On 0.1 s (D1 the 10^0 digit ... D1+3 the 10^3, the page's wiring
    figure); each digit is what the inputs show at the last execution inside its 0.1 s (not
the slice's first: the line is output at its end). After
    the fourth digit D2 (and D2+1) get the BIN values and M9029 is On for one scan; the cycle
    repeats while the condition is On. Off: the outputs go Off, D2 keeps its value, the next
    On starts at the 10^0 digit. DECISION: a switch digit above 9 (not BCD) is an operation
    error; that set's D2 is not written for the cycle."""
    src, d1, d2, n_ref = s.ops
    sets = n_ref.get(m)
    memo = state(m, s, {})
    _done_off(m, memo)
    if not m.acc:
        if memo:
            _drive(m, d1, 4, None)
            memo.clear()
        return
    if not memo:
        memo.update(digit=0, since=m.now_us, digits=[[0] * 4 for _ in range(sets)])
    elif _advance(m, memo, DSW_DIGIT_US):
        memo["digit"] = (memo["digit"] + 1) % 4
        if memo["digit"] == 0:
            values = read_block(m, d2, sets, 16)
            for k, digits in enumerate(memo["digits"]):
                if max(digits) > 9:
                    op_error(m, s, f"switch set {k + 1} reads {digits} (10^0 first): not BCD")
                    continue
                values[k] = sum(d * 10 ** i for i, d in enumerate(digits))
            write_block(m, d2, values, 16)
            _done_on(m, memo)
    elif m.now_us > memo["since"]:  # the line went out at the slice's first scan: read
        for k in range(sets):
            memo["digits"][k][memo["digit"]] = sum(src.bit(m, 4 * k + b) << b for b in range(4))
    _drive(m, d1, 4, memo["digit"])


SCAN_IO_ACTIONS = {"mtr": mtr, "dsw": dsw}
