"""Keypads, 7-segment displays and the printer output of the VS family (6-9 FNC 70 TKY,
71 HKY, 74 SEGL, 77 PR): like scan_io.py (MTR, DSW), the stimulus plays the keys (X levels)
and the Y lines are driven scan by scan; HKY, SEGL and PR count executions, as their pages
count scans (HKY 8 scans a key, SEGL 12 scans a cycle, PR "T = the scan time").

Keys (TKY, HKY), DECISION for "the first pressed has priority": a key enters when it is
pressed and no key of the pad was pressed at the previous reading; several keys rising at
once: the lowest number; a key held keeps the others out until every key is released.
"""

from __future__ import annotations

from mlctool.sim.state import Machine
from mlctool.targets.vs.common import op_error, read_block, relay, set_relay, state

TKY_KEYS = 10  # S..S+9: the decimal keys 0-9 (S occupies 10 points)
HKY_LINES = 4  # S..S+3 inputs x D1..D1+3 outputs: 16 keys


def _digits(width: int) -> int:
    return 8 if width == 32 else 4  # 16-bit 0-9,999, 32-bit 0-99,999,999; more digits overflow


def _enter(m: Machine, s, dst, digit: int, radix: int) -> None:
    """Shift a digit in at the right; the leftmost digit past the width is lost ("溢位")."""
    keep = radix ** _digits(s.width)
    dst.set(m, (dst.get(m) % keep * radix + digit) % keep)


def _first_new_key(memo: dict, pressed: list[int]) -> int | None:
    held_before = memo.get("held", False)
    memo["held"] = bool(pressed)
    return None if held_before or not pressed else min(pressed)


# ------------------------------------------------------------------ TKY (FNC 70)

def tky(m: Machine, s) -> None:
    """TKY S D1 D2: keys S..S+9 are the digits 0-9; a key entered shifts its digit into D1
    (BIN); D2+k On from key k's press until another key is pressed, D2+10 On while any key is
    held. Off: D1 keeps its value, D2..D2+10 Off (the page's time chart)."""
    src, dst, out = s.ops
    memo = state(m, s, {})
    if not m.acc:
        if memo:
            for k in range(TKY_KEYS + 1):
                out.setbit(m, False, k)
            memo.clear()
        return
    pressed = [k for k in range(TKY_KEYS) if src.bit(m, k)]
    key = _first_new_key(memo, pressed)
    if key is not None:
        _enter(m, s, dst, key, 10)
        for k in range(TKY_KEYS):
            out.setbit(m, k == key, k)
    out.setbit(m, bool(pressed), TKY_KEYS)
    memo["on"] = True


# ------------------------------------------------------------------ HKY (FNC 71)

def hky(m: Machine, s) -> None:
    """HKY S D1 D2 D3: a 4x4 matrix; output D1+r drives row r, inputs S..S+3 are its columns,
    key = 4r + c (DECISION: the figure's layout is lost; the FX one: row 0 = 0 1 2 3, row 1 =
    4 5 6 7, row 2 = 8 9 A B, row 3 = C D E F). Each row takes 2 executions (drive, then read
    at the next), so a cycle is the page's 8 scans; M9029 On one scan at each cycle's end.
    The keys are judged per cycle: digits 0-9 shift into D2 (BIN, 4/8 digits); A-F set
    D3..D3+5 (held until another function key); D3+6 On while a digit key is held, D3+7
    while a function key is. M9167 On: all 16 keys are hex digits (D3..D3+5 not used).
    Off: D2 keeps its value, D3..D3+7 and the row outputs Off, the next On starts at row 0."""
    src, lines, dst, out = s.ops
    memo = state(m, s, {})
    if memo.pop("done", False):
        set_relay(m, "done", False)
    if not m.acc:
        if memo:
            for k in range(8):
                out.setbit(m, False, k)
            for r in range(HKY_LINES):
                lines.setbit(m, False, r)
            memo.clear()
        return
    if "phase" not in memo:
        memo.update(phase=0, seen=[])
    else:
        memo["phase"] += 1
    row, reading = divmod(memo["phase"], 2)
    if reading:  # the row went out at the previous execution: its columns show now
        memo["seen"] += [4 * row + c for c in range(HKY_LINES) if src.bit(m, c)]
        if row == HKY_LINES - 1:
            _hky_cycle(m, s, memo, dst, out)
            memo.update(phase=-1, seen=[])
            row = HKY_LINES  # all rows Off until the next execution drives row 0
    for r in range(HKY_LINES):
        lines.setbit(m, r == row, r)


def _hky_cycle(m: Machine, s, memo: dict, dst, out) -> None:
    hex_mode = relay(m, "hky_hex")
    pressed = memo["seen"]
    key = _first_new_key(memo, pressed)
    if key is not None:
        if hex_mode or key < 10:
            _enter(m, s, dst, key, 16 if hex_mode else 10)
        else:
            for k in range(6):
                out.setbit(m, k == key - 10, k)
    out.setbit(m, any(k < 10 or hex_mode for k in pressed), 6)
    out.setbit(m, not hex_mode and any(k >= 10 for k in pressed), 7)
    set_relay(m, "done", True)
    memo["done"] = True


# ------------------------------------------------------------------ SEGL (FNC 74)

def _polarity(n: int) -> tuple[int, int]:
    """n 0-3 (one set) / 4-7 (two sets): (data inverted, strobe inverted). DECISION: the
    page's table is flattened; FX order: n%4 = 0 same/same, 1 same data/inverted strobe,
    2 inverted data/same strobe, 3 both inverted ("different" = the opposite level)."""
    return (n % 4) // 2, n % 2


def segl(m: Machine, s) -> None:
    """SEGL S D n: D..D+3 the BCD data lines of set 1 (D+10..D+13 octal-next, i.e. the 9th-12th
    outputs, set 2 when n = 4-7), D+4..D+7 the latch strobes of 10^0 .. 10^3 (DECISION: the
    FX order, like DSW's lines). A cycle is the page's 12 executions, 3 per digit: data out
    with the strobe Off, then the strobe On for two executions (the display latches); M9029
    On one scan after each cycle. S above 9,999 (S+1 for set 2): operation error, no output.
    Off: every line Off (at the data/strobe polarity's Off level)."""
    src, dst, n_ref = s.ops
    n = n_ref.get(m)
    sets = 2 if n >= 4 else 1
    inv_data, inv_strobe = _polarity(n)
    memo = state(m, s, {})
    if memo.pop("done", False):
        set_relay(m, "done", False)
    outputs = 12 if sets == 2 else 8
    if not m.acc:
        if memo:
            for k in range(outputs):
                dst.setbit(m, bool(inv_strobe if 4 <= k < 8 else inv_data), k)
            memo.clear()
        return
    values = read_block(m, src, sets, 16)
    bad = [v for v in values if not 0 <= v <= 9999]
    if bad:
        op_error(m, s, f"{bad[0]} is outside 0-9,999")
        return
    memo["step"] = memo.get("step", -1) + 1
    if memo["step"] == 12:
        memo["step"] = 0
    digit, phase = divmod(memo["step"], 3)
    for k, value in enumerate(values):
        d = value // 10 ** digit % 10
        for b in range(4):
            dst.setbit(m, bool((d >> b) & 1) != bool(inv_data), 8 * k + b)
    for k in range(4):
        dst.setbit(m, (k == digit and phase > 0) != bool(inv_strobe), 4 + k)
    if memo["step"] == 11:
        set_relay(m, "done", True)
        memo["done"] = True


# ------------------------------------------------------------------ PR (FNC 77)

def pr(m: Machine, s) -> None:
    """PR S D: ASCII characters from S (low byte first) out on D..D+7 (D+7 the highest bit),
    strobe D+8, busy D+9. M9027 Off: 8 characters (S..S+3); On: 16 (S..S+7), a 00H ends the
    text. Each character takes 3 executions ("T T T"): data out, strobe On, strobe Off; busy
    On from the first execution to the last character's third. Condition Off in mid-output:
    stop, the lines Off, the next On sends from the first character again. Once sent, PR
    rests while the condition stays On (the page: "stops by itself"). DECISION, reading the
    page literally: in the 16-character mode M9029 turns On (one scan) at the first
    execution with the condition Off after a complete output; the 8-character chart shows
    no M9029, so that mode leaves it."""
    src, dst = s.ops
    memo = state(m, s, {})
    if memo.pop("done", False):
        set_relay(m, "done", False)
    if not m.acc:
        if memo.get("sent") and memo.get("long"):
            set_relay(m, "done", True)
            memo.clear()
            memo["done"] = True
            return
        if memo.get("step") is not None:
            _pr_lines(m, dst, 0, False, False)
        memo.pop("step", None)
        memo.pop("sent", None)
        return
    if memo.get("sent"):
        return
    if memo.get("step") is None:
        long = bool(relay(m, "pr_sixteen"))
        memo.update(step=0, long=long, text=_pr_text(m, src, long))
    else:
        memo["step"] += 1
    text = memo["text"]
    c, phase = divmod(memo["step"], 3)
    if c >= len(text):
        _pr_lines(m, dst, 0, False, False)
        memo.update(sent=True, step=None)
        return
    _pr_lines(m, dst, text[c], phase == 1, True)


def _pr_text(m: Machine, src, long: bool) -> list[int]:
    words = m.cval if src.kind == "C" else m.words[src.kind]  # (counters' values live in cval)
    a = src.addr(m)
    chars = []
    for k in range(8 if long else 4):
        w = words[a + k] & 0xFFFF if a + k < len(words) else 0
        chars += [w & 0xFF, w >> 8]
    if long and 0 in chars:
        chars = chars[:chars.index(0)]
    return chars


def _pr_lines(m: Machine, dst, char: int, strobe: bool, busy: bool) -> None:
    for b in range(8):
        dst.setbit(m, bool((char >> b) & 1), b)
    dst.setbit(m, strobe, 8)
    dst.setbit(m, busy, 9)


KEYPAD_DISPLAY_ACTIONS = {"tky": tky, "hky": hky, "segl": segl, "pr": pr}
