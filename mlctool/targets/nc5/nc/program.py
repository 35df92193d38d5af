"""The part programs the virtual NC runs: a small G-code subset, read before the run.

    O1000                     (a program number line: ignored)
    N10 G90 G00 X10. Y-5      ; comments: (...) and ; to the end of the line
    /G01 Z-1.5 F300 M08       ; '/' first: skipped while block skip (M2x010) is On
    G04 P500                  ; dwell 500 ms (G04 X0.5: 0.5 s)
    S1200 M03 T5
    M30

Words: G (00 01 04 17 21 54-59 90 91 94), M, S, T, F, P (with G04), N, and the channel's
axis letters. A number is in mm whether or not it has a decimal point (DECISION: the model
reads `X10` as 10 mm, calculator style); at most 3 decimals (0.001 mm, N1.001).
Anything else is a diagnostic before the run (E260-E265, docs/nc5.md "Part programs").
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from decimal import Decimal

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.targets.nc5.nc.addresses import AXIS_ORDER

MAX_BYTES = 1 << 20  # a part program of the model is small; 1 MiB is a wrong file
MAX_MM = Decimal("99999.999")
MAX_S = 2147483647  # D2x024's range (6.10); S shares it
MAX_CODE = 9999  # M and T numbers (4 digits, the registers' decimal display)
SUPPORTED_G = {0, 1, 4, 17, 21, 54, 55, 56, 57, 58, 59, 90, 91, 94}
NOT_HANDSHAKEN_M = {0, 1, 2, 30, 98, 99}  # 5.2.1 D3x048: M00 M01 M02 M30 M98 M99 raise no M flag
SUBPROGRAM_M = {96, 97, 98, 99}
_WORD = re.compile(r"([A-Za-z])([+-]?(?:\d+\.?\d*|\.\d+))?")


@dataclass
class Block:
    line: int
    skippable: bool = False  # '/' first: skipped while M2x010 is On
    motion: int | None = None  # 0 G00, 1 G01 (modal)
    absolute: bool | None = None  # G90 True, G91 False (modal)
    dwell_us: int | None = None
    axes: dict[str, int] = field(default_factory=dict)  # letter -> 0.001 mm
    feed: int | None = None  # F, 0.001 mm/min
    s: int | None = None
    t: int | None = None
    m: int | None = None


@dataclass
class PartProgram:
    path: str
    blocks: list[Block]


class _Bad(Exception):
    def __init__(self, col: int, width: int, code: str, message: str):
        self.col, self.width, self.code, self.message = col, width, code, message


def parse(path: str, text: str, axes: str, macro: bool = False) -> tuple[PartProgram, list[Diagnostic]]:
    """The blocks of `text`, or the diagnostics of every wrong line (file, line, column). A
    macro (5.3.8) may end with M99 (its return)."""
    blocks, diags = [], []
    feed_given = False
    motion = 0  # G00 at the start (DECISION: the model starts in G00)
    for no, raw in enumerate(text.splitlines(), 1):
        try:
            block = _block(no, raw, axes, macro)
        except _Bad as e:
            diags.append(diag(path, Span.at(no, e.col, e.width), e.code, e.message))
            continue
        if block is None:
            continue
        motion = block.motion if block.motion is not None else motion
        if block.feed is not None and not block.skippable:
            feed_given = True
        if motion == 1 and block.axes and not feed_given and block.feed is None:
            diags.append(diag(path, Span.at(no, 1, len(raw.rstrip())), "E265",
                              "G01 with no F before it: the feed would be 0 (give F in this block "
                              "or an earlier one that block skip cannot skip)"))
        blocks.append(block)
    return PartProgram(path, blocks), diags


def _block(no: int, raw: str, axes: str, macro: bool = False) -> Block | None:
    code = _strip_comments(raw)
    stripped = code.strip()
    if not stripped or stripped == "%":
        return None
    block = Block(no)
    pos = len(code) - len(code.lstrip())
    if code[pos] == "/":
        block.skippable = True
        pos += 1
    seen: dict[str, int] = {}
    gs: list[tuple[int, int]] = []
    dwell_ms: int | None = None
    while pos < len(code):
        ch = code[pos]
        if ch in " \t":
            pos += 1
            continue
        start, col = pos, pos + 1
        m = _WORD.match(code, pos)
        if m is None:
            raise _Bad(col, 1, "E260", f"{ch!r} is not a word (a letter and a number: X10.5, G01)")
        letter, number = m[1].upper(), m[2]
        width = m.end() - pos
        pos = m.end()
        if letter == "O" and not seen and not gs:
            return None  # the program number line (O1000)
        if number is None:
            raise _Bad(col, 1, "E260", f"{letter} needs a number (e.g. {letter}10)")
        if pos < len(code) and code[pos] == ".":
            raise _Bad(col, pos - start + 1, "E260", f"{code[start:pos + 1]!r}: a number has one decimal point")
        if letter == "G":
            g = _integer(number, col, width, "G")
            if g not in SUPPORTED_G:
                raise _Bad(col, width, "E261", f"G{g:02d} is not in the model's subset (G00 G01 G04 G17 G21 "
                                               "G54-G59 G90 G91 G94; docs/nc5.md)")
            gs.append((g, col))
            continue
        if letter in seen and letter != "T":
            raise _Bad(col, width, "E263", f"two {letter} words in one block (the model takes one; "
                                           f"the first is at column {seen[letter]})")
        seen[letter] = col
        if letter == "P":
            dwell_ms = _bounded(number, col, width, "P", 10**6)  # ms
        else:
            _word(block, letter, number, col, width, axes, macro)
    _g_codes(block, gs)
    if block.dwell_us is not None:  # G04: P in ms, else X in s (X read as mm: 0.001 units)
        x = block.axes.pop("X", None)
        block.dwell_us = dwell_ms * 1000 if dwell_ms is not None else x * 1000 if x is not None else None
        if block.dwell_us is None:
            raise _Bad(gs[0][1], 1, "E263", "G04 needs its time: P (ms) or X (s)")
    if block.dwell_us is None and "P" in seen:
        raise _Bad(seen["P"], 1, "E263", "P without G04 (the model uses P only as G04's dwell)")
    if block.dwell_us is not None and block.axes:
        raise _Bad(seen[next(iter(block.axes))], 1, "E263", "G04 takes no axis move in its block")
    return block


def _strip_comments(raw: str) -> str:
    """The line without (...) and ; comments, blanks kept so columns stay the file's."""
    out = []
    depth_col = 0
    in_paren = False
    for i, ch in enumerate(raw):
        if in_paren:
            out.append(" ")
            if ch == ")":
                in_paren = False
            continue
        if ch == "(":
            in_paren, depth_col = True, i + 1
            out.append(" ")
        elif ch == ";":
            break
        else:
            out.append(ch)
    if in_paren:
        raise _Bad(depth_col, 1, "E260", "comment '(' without its ')'")
    return "".join(out)


def _word(block: Block, letter: str, number: str, col: int, width: int, axes: str, macro: bool = False) -> None:
    if letter == "N":
        _integer(number, col, width, "N")
    elif letter == "F":
        f = _millimetres(number, col, width)
        if f <= 0:
            raise _Bad(col, width, "E264", f"F{number}: a feed is more than 0 mm/min")
        block.feed = f
    elif letter == "S":
        block.s = _bounded(number, col, width, "S", MAX_S)
    elif letter == "T":
        block.t = _bounded(number, col, width, "T", MAX_CODE)  # DECISION (notes #18): the last T counts
    elif letter == "M":
        m = _bounded(number, col, width, "M", MAX_CODE)
        if m in SUBPROGRAM_M and not (macro and m == 99):
            raise _Bad(col, width, "E262", f"M{m}: subprograms and interrupts (M96-M99) are not in "
                                           "the model's subset (a macro may end with M99)")
        block.m = m
    elif letter in AXIS_ORDER:
        if letter not in axes:
            raise _Bad(col, 1, "E262", f"axis {letter} is not one of this channel's axes "
                                       f"({','.join(axes)}: the model line's axes=)")
        block.axes[letter] = _millimetres(number, col, width)
    else:
        raise _Bad(col, 1, "E262", f"address {letter} is not in the model's subset (G M S T F P N "
                                   f"and the axes {','.join(axes)}; docs/nc5.md)")


def _g_codes(block: Block, gs: list[tuple[int, int]]) -> None:
    groups: dict[str, int] = {}
    for g, col in gs:
        group = "motion" if g in (0, 1, 4) else "distance" if g in (90, 91) else f"G{g}"
        if group in groups:
            raise _Bad(col, 1, "E263", f"G{g:02d} and another G code of its group in one block "
                                       f"(column {groups[group]})")
        groups[group] = col
        if g in (0, 1):
            block.motion = g
        elif g in (90, 91):
            block.absolute = g == 90
        elif g == 4:
            block.dwell_us = 0  # P or X gives the time (_block)


def _integer(number: str, col: int, width: int, letter: str) -> int:
    if not re.fullmatch(r"[+-]?\d+", number):
        raise _Bad(col, width, "E260", f"{letter}{number}: {letter} takes a whole number")
    if len(number) > 10:
        raise _Bad(col, width, "E264", f"{letter}{number}: out of range")
    return int(number)


def _bounded(number: str, col: int, width: int, letter: str, hi: int) -> int:
    v = _integer(number, col, width, letter)
    if not 0 <= v <= hi:
        raise _Bad(col, width, "E264", f"{letter}{number}: {letter} takes 0-{hi}")
    return v


def _millimetres(number: str, col: int, width: int) -> int:
    """`-12.5` -> -12500 (0.001 mm)."""
    d = Decimal(number)
    if d.as_tuple().exponent < -3:
        raise _Bad(col, width, "E264", f"{number}: at most 3 decimals (0.001 mm, N1.001)")
    if abs(d) > MAX_MM:
        raise _Bad(col, width, "E264", f"{number}: the model takes -{MAX_MM} to {MAX_MM}")
    return int(d * 1000)
