"""PosProgram <-> SR register table (16-bit words), and PosProgram -> program text.

The manual fixes only SR+0 (A55AH / A55CH), SR+1 (step count) and the step size (9 / 15
registers); the word layout inside a step is ours, documented in docs/fbs-positioning.md.
32-bit fields are low word first, as every FBs register pair (manual: "D10（Low Word）與
D11（High Word）").
"""

from __future__ import annotations

from mlctool.targets.fbs.model import (
    BLANK,
    NEXT,
    Cond,
    Dialect,
    Motion,
    PosProgram,
    Step,
    Val,
    tables,
)

OPERAND = {"K": 0, "R": 1, "D": 2, "": 3}  # 2-bit operand kind
OPERAND_OF = {v: k for k, v in OPERAND.items()}
DRIVE = {"hspso": ("DRV", "DRVC", "DRVZ"), "mhspo": ("LIN", "LINE")}
SIGN = {"": 0, "+": 1, "-": 2}
SIGN_OF = {v: k for k, v in SIGN.items()}
COND = {None: 0, ("WAIT", True): 1, ("WAIT", False): 2, ("ACT", True): 3, ("EXT", False): 4}
COND_OF = {v: k for k, v in COND.items()}
BIT = {"X": 0, "Y": 1, "M": 2, "S": 3}
BIT_OF = {v: k for k, v in BIT.items()}
GOTO = {"NEXT": 0, "K": 1, "R": 2, "D": 3}
GOTO_OF = {v: k for k, v in GOTO.items()}
MEND_WORD = 0xFFFF


class TableError(ValueError):
    """A table that is not a program: `code` is the manual's error code (F034-F036)."""

    def __init__(self, code: str, message: str, offset: int = 0):
        super().__init__(message)
        self.code = code
        self.message = message
        self.offset = offset


def _pair(v: int) -> list[int]:
    v &= 0xFFFFFFFF
    return [v & 0xFFFF, v >> 16]


def _val_words(v: Val) -> list[int]:
    """Two words: a constant (32-bit, two's complement) or a register number and 0."""
    return _pair(v.n) if v.kind == "K" else [v.n & 0xFFFF, 0]


def _cond_words(c: Cond | None) -> list[int]:
    if c is None:
        return [0, 0, 0]
    head = COND[(c.op, c.time)]
    if c.time:
        head |= OPERAND[c.val.kind] << 4
        return [head, *_val_words(c.val)]
    return [head | BIT[c.val.kind] << 8, c.val.n, 0]


def _end_word(s: Step) -> int:
    if s.mend:
        return MEND_WORD
    return GOTO[s.goto.kind] << 14 | (s.goto.n & 0x3FFF)


def encode_step(s: Step, dialect: str) -> list[int]:
    m = s.motion
    flags = OPERAND[s.speed.kind] | DRIVE[dialect].index(m.op) << 2 | (m.coord == "ABS") << 4 \
        | SIGN[m.sign] << 5 | (m.unit == "Ps") << 7
    if dialect == "hspso":
        travel = m.travel[0] if m.travel else Val("K", 0)
        flags |= OPERAND[travel.kind] << 8 | m.mode << 10
        words = [flags, *_val_words(s.speed), *_val_words(travel)]
    else:
        for i, t in enumerate(m.travel):
            flags |= OPERAND[t.kind] << (8 + 2 * i)
        words = [flags, *_val_words(s.speed)]
        for t in m.travel:
            words += _val_words(t) if t.kind else [0, 0]
    return words + _cond_words(s.cond) + [_end_word(s)]


def encode(program: PosProgram) -> list[int]:
    d = tables().dialects[program.dialect]
    words = [d.header, len(program.steps)]
    for s in program.steps:
        words += encode_step(s, program.dialect)
    assert len(words) == d.table_words(len(program.steps))
    return words


# ---------------------------------------------------------------- decoding


def _s32(lo: int, hi: int) -> int:
    v = lo | hi << 16
    return v - (1 << 32) if v & 0x80000000 else v


def _val(kind_code: int, lo: int, hi: int, where: int, signed: bool = True) -> Val:
    kind = OPERAND_OF[kind_code]
    if kind == "":
        return BLANK
    if kind == "K":
        return Val("K", _s32(lo, hi) if signed else lo | hi << 16)
    if hi:
        raise TableError("F034", f"register operand with a non-zero high word {hi:04X}H", where + 1)
    return Val(kind, lo)


def decode_step(w: list[int], dialect: Dialect, base: int) -> Step:
    flags = w[0]
    drives = DRIVE[dialect.name]
    drive = flags >> 2 & 3
    if drive >= len(drives) or flags >> 5 & 3 == 3 or OPERAND_OF[flags & 3] == "":
        raise TableError("F043", f"step flags {flags:04X}H: no such drive command", base)
    speed = _val(flags & 3, w[1], w[2], base + 1, signed=False)
    coord = "ABS" if flags & 0x10 else "ADR"
    sign = SIGN_OF[flags >> 5 & 3]
    unit = "Ps" if flags & 0x80 else "Ut"
    if dialect.name == "hspso":
        if flags & 0xF000 or flags >> 8 & 3 == 3 or flags >> 10 & 3 == 3:
            raise TableError("F043", f"step flags {flags:04X}H: undefined bits or codes", base)
        op = drives[drive]
        if op == "DRVZ":
            motion = Motion("DRVZ", mode=flags >> 10 & 3)
        else:
            motion = Motion(op, coord, sign, (_val(flags >> 8 & 3, w[3], w[4], base + 3),), unit)
        rest = w[5:]
        at = base + 5
    else:
        travels = tuple(_val(flags >> (8 + 2 * i) & 3, w[3 + 2 * i], w[4 + 2 * i], base + 3 + 2 * i)
                        for i in range(4))
        motion = Motion(drives[drive], coord, sign, travels, unit)
        rest = w[11:]
        at = base + 11
    cond = _decode_cond(rest[0], rest[1], rest[2], at)
    end = rest[3]
    if end == MEND_WORD:
        return Step(speed, motion, cond, None, True)
    kind = GOTO_OF[end >> 14]
    goto = NEXT if kind == "NEXT" else Val(kind, end & 0x3FFF)
    if kind == "NEXT" and end & 0x3FFF:
        raise TableError("F034", f"GOTO word {end:04X}H: NEXT with a number", at + 3)
    return Step(speed, motion, cond, goto, False)


def _decode_cond(head: int, lo: int, hi: int, at: int) -> Cond | None:
    kind = head & 0xF
    if kind not in COND_OF or head & 0xF0C0:
        raise TableError("F034", f"transfer condition word {head:04X}H is not defined", at)
    spec = COND_OF[kind]
    if spec is None:
        if head or lo or hi:
            raise TableError("F034", "no transfer condition but its operand words are not 0", at)
        return None
    op, is_time = spec
    if is_time:
        if head >> 8:
            raise TableError("F034", f"transfer condition word {head:04X}H is not defined", at)
        return Cond(op, True, _val(head >> 4 & 3, lo, hi, at + 1, signed=False))
    if head >> 4 & 3 or hi or head >> 8 > 3:
        raise TableError("F034", f"transfer condition word {head:04X}H is not defined", at)
    return Cond(op, False, Val(BIT_OF[head >> 8], lo))


def decode(words: list[int]) -> PosProgram:
    """A register table (SR+0 onward) -> PosProgram. Raises TableError."""
    if len(words) < 2:
        raise TableError("F035", f"a table has at least 2 registers, got {len(words)}")
    d = tables().by_header(words[0])
    if d is None:
        raise TableError("F034", f"SR+0 = {words[0]:04X}H: a valid program starts with "
                         + " or ".join(f"{x.header:04X}H" for x in tables().dialects.values()))
    n = words[1]
    if n > d.max_steps:
        raise TableError("F036", f"SR+1 = {n} steps; at most {d.max_steps}", 1)
    if n == 0:
        raise TableError("F034", "SR+1 = 0: no steps", 1)
    if len(words) != d.table_words(n):
        raise TableError("F035", f"{n} steps take {d.table_words(n)} registers ({n} x {d.step_words} + 2); "
                         f"the table has {len(words)}")
    steps = []
    for k in range(n):
        base = 2 + k * d.step_words
        steps.append(decode_step(words[base:base + d.step_words], d, base))
    return PosProgram(d.name, tuple(steps))


def execution_error(program: PosProgram) -> int:
    """The error code FUN140 (or FUN147) raises when it executes a table that breaks the rules the
    build checks (a table the PLC program wrote at run time): the "執行 FUN140 與 執行 FUN147 時
    可能之錯誤碼" list of 11.6, with the build's codes (F034 -> 34, F041 -> 41, F042 -> 42,
    F043 -> 43). 0 when the table is runnable. Decisions in docs/fbs.md."""
    d = tables().dialects[program.dialect]
    steps, n = program.steps, len(program.steps)
    if program.dialect == "mhspo":
        return _mhspo_execution_error(program, d)

    def nxt(k: int) -> int | None:
        s = steps[k - 1]
        if s.motion.op != "DRVC" or s.goto is None or s.goto.is_reg or s.cond or s.mend:
            return None
        j = k + 1 if s.goto.kind == "NEXT" else s.goto.n
        return j if j <= n else None

    for k, s in enumerate(steps, start=1):
        if s.goto is not None and s.goto.kind == "K" and not 1 <= s.goto.n <= n:
            return 34
        if s.motion.op != "DRVC":
            continue
        j = nxt(k)
        if j is None:
            return 43  # a DRVC step must continue into a next segment
        follow = steps[j - 1].motion
        if follow.op == "DRVZ":
            return 42
        if follow.coord == "ABS":
            return 41
    entered = {j for k in range(1, n + 1) if (j := nxt(k)) is not None}
    for k in range(1, n + 1):
        if steps[k - 1].motion.op != "DRVC" or k in entered:
            continue
        seen, j, segs = set(), k, 1
        while (j2 := nxt(j)) is not None and j2 not in seen:
            seen.add(j)
            j, segs = j2, segs + 1
        if segs > d.max_segments:
            return 43
    return 0


def _mhspo_execution_error(program: PosProgram, d) -> int:
    """FUN147's share of the same 11.6 list: the build's checks of a FUN147 program with
    constant operands (register operands are checked by the interpolation when it reads
    them): 34 a constant GOTO beyond the last step (F034), 33 every axis travel blank
    (F033), 31/37 a constant SPD of 0 / over the maximum (F031/F037), 40 a constant travel
    outside +-travel_max (F040). 0 when the table is runnable."""
    n = len(program.steps)
    for s in program.steps:
        if s.goto is not None and s.goto.kind == "K" and not 1 <= s.goto.n <= n:
            return 34
        if s.speed.kind == "K" and s.speed.n == 0:
            return 31
        if s.speed.kind == "K" and s.speed.n > d.speed_max:
            return 37
        if all(v.kind == "" for v in s.motion.travel):
            return 33
        if any(v.kind == "K" and abs(v.n) > d.travel_max for v in s.motion.travel):
            return 40
    return 0


# ---------------------------------------------------------------- text


def _travel_text(v: Val) -> str:
    return " " if v.kind == "" else v.text()


def step_lines(k: int, s: Step) -> list[str]:
    m = s.motion
    lines = [f"{k:03d} SPD {s.speed.text()}"]
    if m.op == "DRVZ":
        lines.append(f"    DRVZ MD{m.mode}")
    elif m.op in ("LIN", "LINE"):
        lines.append(f"    {m.op} {m.coord}," + ",".join(_travel_text(t) for t in m.travel) + f",{m.unit}")
    else:
        lines.append(f"    {m.op} {m.coord},{m.sign or ' '},{m.travel[0].text()},{m.unit}")
    if s.cond is not None:
        arg = f"TIME,{s.cond.val.text()}" if s.cond.time else s.cond.val.text()
        lines.append(f"    {s.cond.op} {arg}")
    lines.append("    MEND" if s.mend else f"    GOTO {s.goto.text()}")
    return lines


def program_text(program: PosProgram) -> str:
    """Canonical program text: parses back to the same program."""
    out = []
    for k, s in enumerate(program.steps, start=1):
        out += step_lines(k, s)
    return "\n".join(out) + "\n"
