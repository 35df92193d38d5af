"""Positioning-program text (the manual's notation) -> PosProgram and diagnostics.

What the manual's own examples show is accepted (notes A4.3): `,` and full-width `，`,
the minus signs `-` `−` `－`, full-width blanks, blank fields, any indentation, labels
`001`.. starting a step with its SPD on the same line, and `;`/`；` comments. Keywords
are matched case-insensitively. Every violation gets the manual's error code as `Fnnn`
(FUN140/147 error register codes 30-60) with line and column; the choice of code for
each rule is documented in docs/fbs-positioning.md.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.limits import long_number, too_long_message
from mlctool.targets.fbs.model import (
    BLANK,
    MHSPO_FORBIDDEN_MODE,
    NEXT,
    Cond,
    Dialect,
    Motion,
    PosProgram,
    Step,
    Val,
    tables,
)

# characters NFKC leaves alone but the manual uses as minus signs
_MINUS = {"\u2212": "-", "\u2010": "-", "\u2011": "-", "\u2012": "-", "\u2013": "-", "\uFE63": "-"}
_LABEL = re.compile(r"\s*([0-9]+)")
_WORD = re.compile(r"\s*([A-Za-z]+)")
_INT = re.compile(r"[+-]?[0-9]+")
_REG = re.compile(r"([A-Za-z])([0-9]+)")


def normalize(line: str) -> str:
    """Full-width characters (a Chinese IME's ，－３００) and the manual's minus signs ->
    ASCII, one character for one (columns stay). DECISION (issue 30.16, one rule for numbers:
    mlctool/limits.py): only the full-width forms of ASCII (U+FF01-U+FF5E, the ideographic
    space), which are ASCII typed another way; other compatibility forms that NFKC would make
    digits ("²" -> "2", "①" -> "1") stay what they are, and are no number."""
    out = []
    for c in line:
        if c in _MINUS:
            out.append(_MINUS[c])
        elif "\uFF01" <= c <= "\uFF5E":
            out.append(chr(ord(c) - 0xFEE0))
        else:
            out.append(" " if c == "\u3000" else c)
    return "".join(out).replace("\t", " ")


@dataclass(slots=True)
class Field:
    text: str  # stripped
    col: int  # 1-based column of the text (of the field start if blank)

    @property
    def end(self) -> int:
        return self.col + max(len(self.text), 1)


def split_fields(text: str, col0: int) -> list[Field]:
    """Comma-separated fields of `text` (starting at column col0), blanks kept as ''."""
    fields, start = [], 0
    for part in text.split(","):
        lead = len(part) - len(part.lstrip())
        fields.append(Field(part.strip(), col0 + start + (lead if part.strip() else 0)))
        start += len(part) + 1
    return fields


@dataclass
class _StepBuilder:
    number: int
    line: int
    col: int
    speed: Val | None = None
    motion: Motion | None = None
    cond: Cond | None = None
    goto: Val | None = None
    mend: bool = False
    done: bool = False  # GOTO or MEND seen
    last_line: int = 0
    where: dict = field(default_factory=dict)  # part -> (line, col, end)


class _Parser:
    def __init__(self, path: str, text: str, dialect: Dialect, pulse_modes: tuple[str, ...] = ()):
        self.path = path
        self.pulse_modes = pulse_modes
        self.text = text
        self.d = dialect
        self.t = tables()
        self.diags: list[Diagnostic] = []
        self.steps: list[_StepBuilder] = []
        self.line = 0

    def err(self, code: str, msg: str, col: int = 1, end: int | None = None, line: int | None = None) -> None:
        line = line or self.line
        self.diags.append(diag(self.path, Span(line, col, line, end or col + 1), code, msg))

    def at(self, f: Field, code: str, msg: str) -> None:
        self.err(code, msg, f.col, f.end)

    # ---------------------------------------------------------------- lines
    def run(self) -> list[_StepBuilder]:
        for k, raw in enumerate(self.text.split("\n"), start=1):
            self.line = k
            line = normalize(raw)
            cut = line.find(";")
            if cut >= 0:
                line = line[:cut]
            if line.strip():
                self.parse_line(line)
        return self.steps

    def parse_line(self, line: str) -> None:
        long = long_number(line)
        if long:  # bounded before any int() (mlctool/limits.py)
            self.err("F034", too_long_message("the line", len(long[0])), long.start() + 1, long.end() + 1)
            return
        pos = 0
        m = _LABEL.match(line)
        if m:
            self.start_step(int(m[1]), m.start(1) + 1, m.end(1) + 1)
            pos = m.end()
            if not line[pos:].strip():
                return
        m = _WORD.match(line, pos)
        if not m:
            rest = len(line[pos:]) - len(line[pos:].lstrip()) + pos
            self.err("F034", f"expected a statement (SPD, DRV, WAIT, GOTO, MEND, ...), found {line[rest:].strip()!r}",
                     rest + 1, len(line.rstrip()) + 1)
            return
        kw = Field(m[1].upper(), m.start(1) + 1)
        ops_text = line[m.end():]
        if ops_text and not ops_text[0].isspace() and ops_text.strip():
            self.err("F034", f"expected a blank after {kw.text}", m.end() + 1)
            return
        fields = split_fields(ops_text, m.end() + 1) if ops_text.strip() else []
        self.statement(kw, fields)

    def start_step(self, number: int, col: int, end: int) -> None:
        expect = len(self.steps) + 1
        if number != expect:
            self.err("F035", f"step label {number:03d} out of sequence: expected {expect:03d}", col, end)
        if len(self.steps) == self.d.max_steps:
            self.err("F036", f"more than {self.d.max_steps} steps", col, end)
        self.steps.append(_StepBuilder(expect, self.line, col))

    # ---------------------------------------------------------------- statements
    def statement(self, kw: Field, fields: list[Field]) -> None:
        step = self.steps[-1] if self.steps else None
        if kw.text in self.d.foreign:
            self.at(kw, self.d.foreign_code, f"{kw.text} is not a statement of {self.d.instruction} programs")
            return
        known = ("SPD", "GOTO", "MEND", *self.d.motions, *self.d.conditions)
        if kw.text not in known:
            code = "F043" if kw.text.startswith(("DR", "LI")) else "F034"
            self.at(kw, code, f"unknown statement {kw.text!r}; {self.d.instruction} programs use "
                    + " ".join(known))
            return
        if step is None:
            self.at(kw, "F035", f"{kw.text} outside a step: a step starts with its number, e.g. '001 SPD 1000'")
            return
        if step.done:
            self.at(kw, "F035", f"{kw.text} after the GOTO/MEND that ends step {step.number:03d}")
            return
        step.last_line = self.line
        order = {"SPD": 0, **{m: 1 for m in self.d.motions}, **{c: 2 for c in self.d.conditions},
                 "GOTO": 3, "MEND": 3}
        have = (step.speed is not None, step.motion is not None, step.cond is not None)
        rank = order[kw.text]
        if rank < 3 and have[rank]:
            self.at(kw, "F035", f"step {step.number:03d} already has its "
                    + ("speed" if rank == 0 else "drive command" if rank == 1 else "transfer condition"))
            return
        if rank > 0 and not have[0]:
            self.at(kw, "F035", f"step {step.number:03d} must start with SPD, before {kw.text}")
        if rank > 1 and not have[1] and step.speed is not None:
            self.at(kw, "F043", f"step {step.number:03d} has no drive command before {kw.text}")
        step.where[kw.text if rank != 1 else "motion"] = (self.line, kw.col, kw.end)
        if kw.text == "GOTO" and fields:  # a bad target is reported at the operand
            step.where["GOTO"] = (self.line, fields[0].col, fields[0].end)
        if kw.text == "SPD":
            step.speed = self.speed(kw, fields) or Val("K", 1)
        elif rank == 1:
            step.motion = self.motion(kw, fields) or Motion(kw.text)
        elif rank == 2:
            step.cond = self.condition(kw, fields) or Cond(kw.text, True, Val("K", 0))
        elif kw.text == "GOTO":
            step.goto = self.goto(kw, fields) or NEXT
            step.done = True
        else:
            if fields:
                self.at(fields[0], "F034", "MEND takes no operand")
            step.mend = step.done = True

    def one(self, kw: Field, fields: list[Field], what: str) -> Field | None:
        if len(fields) != 1 or not fields[0].text:
            where = fields[1] if len(fields) > 1 else kw
            self.at(where, "F034", f"{kw.text} takes one operand: {what}")
            return None
        return fields[0]

    def register(self, f: Field, code: str, pair: bool) -> Val | None:
        """Rxxxx / Dxxxx: a register number inside the FBs register space (pairs: both words)."""
        m = _REG.fullmatch(f.text)
        kind = m[1].upper() if m else ""
        if kind not in self.t.registers:
            return None
        lo, hi = self.t.registers[kind]
        n = int(m[2])
        if not lo <= n <= hi - (1 if pair else 0):
            what = f"{kind}{n}:{kind}{n + 1} (a 32-bit pair)" if pair else f"{kind}{n}"
            self.at(f, code, f"{what} is outside {kind}{lo}-{kind}{hi}")
            return Val(kind, lo)
        return Val(kind, n)

    def speed(self, kw: Field, fields: list[Field]) -> Val | None:
        f = self.one(kw, fields, f"a frequency 1-{self.d.speed_max} or a register pair Rxxxx/Dxxxx")
        if f is None:
            return None
        if _INT.fullmatch(f.text):
            v = int(f.text)
            if v == 0 or v < 0:
                self.at(f, "F031", f"SPD {v}: the frequency must be 1-{self.d.speed_max}")
            elif v > self.d.speed_max:
                self.at(f, "F037", f"SPD {v} exceeds the maximum frequency {self.d.speed_max}")
            return Val("K", v) if 1 <= v <= self.d.speed_max else None
        reg = self.register(f, "F030", pair=True)
        if reg is None:
            code = "F030" if _REG.fullmatch(f.text) else "F031"
            self.at(f, code, f"SPD {f.text!r}: expected a number 1-{self.d.speed_max} or Rxxxx/Dxxxx")
        return reg

    def travel(self, f: Field, allow_signed: bool, allow_blank: bool) -> Val | None:
        if not f.text:
            if allow_blank:
                return BLANK
            self.at(f, "F033", "travel is blank")
            return None
        if _INT.fullmatch(f.text):
            digits = f.text.lstrip("+-")
            v = int(f.text)
            if f.text[0] in "+-" and not allow_signed:
                self.at(f, "F033", f"travel {f.text}: with a + or - direction the travel is unsigned")
                return None
            if len(digits.lstrip("0")) > self.d.travel_digits or abs(v) > self.d.travel_max:
                self.at(f, "F040", f"travel {f.text} outside -{self.d.travel_max}..{self.d.travel_max}")
                return None
            return Val("K", v)
        reg = self.register(f, "F032", pair=True)
        if reg is None:
            code = "F032" if _REG.fullmatch(f.text) else "F033"
            self.at(f, code, f"travel {f.text!r}: expected a number or Rxxxx/Dxxxx")
        return reg

    def coord_unit(self, kw: Field, first: Field, last: Field) -> tuple[str, str] | None:
        coord, unit = first.text.upper(), last.text
        if coord not in ("ADR", "ABS"):
            self.at(first, "F043", f"{kw.text}: first operand must be ADR or ABS, not {first.text!r}")
            return None
        if unit.upper() not in ("UT", "PS"):
            self.at(last, "F043", f"{kw.text}: last operand must be Ut or Ps, not {last.text!r}")
            return None
        return coord, "Ut" if unit.upper() == "UT" else "Ps"

    def motion(self, kw: Field, fields: list[Field]) -> Motion | None:
        if kw.text == "DRVZ":
            f = self.one(kw, fields, "MD0, MD1 or MD2")
            if f is None:
                return None
            m = re.fullmatch(r"MD([0-9]+)", f.text.upper())
            if not m or int(m[1]) > 2:
                self.at(f, "F050", f"DRVZ mode {f.text!r}: the modes are MD0, MD1, MD2")
                return None
            return Motion("DRVZ", mode=int(m[1]))
        if kw.text in ("LIN", "LINE"):
            return self.line_motion(kw, fields)
        if len(fields) != 4:
            self.at(fields[-1] if fields else kw, "F043",
                    f"{kw.text} takes 4 operands: ADR|ABS, +|-|blank, travel, Ut|Ps (got {len(fields)})")
            return None
        cu = self.coord_unit(kw, fields[0], fields[3])
        sign_f = fields[1]
        sign = sign_f.text
        if sign not in ("", "+", "-"):
            self.at(sign_f, "F043", f"{kw.text}: direction must be +, - or blank, not {sign!r}")
            return None
        if cu is None:
            return None
        coord, unit = cu
        if coord == "ABS" and sign and kw.text != "DRVC":
            # DRV's direction operand is "valid for relative coordinates" (11.6); the DRVC row
            # prints `ABS，−` as a form (docs/fbs-positioning.md)
            self.at(sign_f, "F043", f"{kw.text} ABS takes a blank direction (the target decides it)")
            return None
        if kw.text == "DRVC" and coord == "ADR" and not sign:
            self.at(sign_f, "F043", "DRVC ADR needs a + or - direction: the first segment's direction "
                    "governs the whole chain")
            return None
        travel = self.travel(fields[2], allow_signed=not sign or coord == "ABS", allow_blank=False)
        if travel is None:
            return None
        if kw.text == "DRVC" and travel.kind == "K" and travel.n == 0:
            self.at(fields[2], "F033", "DRVC travel 0: a segment of a DRVC chain needs a travel")
            return None
        return Motion(kw.text, coord, sign, (travel,), unit)

    def line_motion(self, kw: Field, fields: list[Field]) -> Motion | None:
        if len(fields) != 6:
            self.at(fields[-1] if fields else kw, "F060",
                    f"{kw.text} takes 6 operands: ADR|ABS, X, Y, Z, W, Ut|Ps (got {len(fields)})")
            return None
        cu = self.coord_unit(kw, fields[0], fields[5])
        travels = [self.travel(f, allow_signed=True, allow_blank=True) for f in fields[1:5]]
        if cu is None or any(t is None for t in travels):
            return None
        if all(t.kind == "" for t in travels):
            self.at(fields[1], "F033", f"{kw.text}: every axis travel is blank")
            return None
        motion = Motion(kw.text, cu[0], "", tuple(travels), cu[1])
        for i in motion.driven_axes():
            if i < len(self.pulse_modes) and self.pulse_modes[i] == MHSPO_FORBIDDEN_MODE:
                self.at(fields[1 + i], "E236", f"{kw.text} drives Ps{i}, whose pulse output mode is P/R "
                        "(mlc.toml pulse_modes): FUN147 takes U/D or A/B only (11.6)")
        return motion

    def bit(self, f: Field) -> Val | None:
        m = _REG.fullmatch(f.text)
        kind = m[1].upper() if m else ""
        if kind not in self.t.bits:
            return None
        lo, hi = self.t.bits[kind]
        if not lo <= int(m[2]) <= hi:
            self.at(f, "F034", f"{f.text}: {kind} contacts here are {kind}{lo}-{kind}{hi}")
            return Val(kind, lo)
        return Val(kind, int(m[2]))

    def condition(self, kw: Field, fields: list[Field]) -> Cond | None:
        if fields and fields[0].text.upper() == "TIME":
            if len(fields) != 2 or not fields[1].text:
                self.at(fields[-1], "F034", f"{kw.text} TIME takes one value: TIME,t (t in 0.01 s)")
                return None
            f = fields[1]
            if re.fullmatch(r"[0-9]+", f.text):
                if len(f.text.lstrip("0")) > 5:
                    self.at(f, "F034", f"{kw.text} TIME,{f.text}: at most 5 digits (99999 x 0.01 s)")
                    return None
                return Cond(kw.text, True, Val("K", int(f.text)))
            reg = self.register(f, "F034", pair=False)
            if reg is None:
                self.at(f, "F034", f"{kw.text} TIME,{f.text!r}: expected 0-99999 or Rxxxx/Dxxxx")
            return Cond(kw.text, True, reg) if reg else None
        if kw.text == "ACT":
            self.at(fields[0] if fields else kw, "F034", "ACT takes TIME,t (t in 0.01 s)")
            return None
        f = self.one(kw, fields, "TIME,t or a contact X0-X255, Y0-Y255, M0-M1911, S0-S999")
        if f is None:
            return None
        b = self.bit(f)
        if b is None:
            self.at(f, "F034", f"{kw.text} {f.text!r}: expected a contact X0-X255, Y0-Y255, M0-M1911, S0-S999"
                    + (" or TIME,t" if kw.text == "WAIT" else ""))
        return Cond(kw.text, False, b) if b else None

    def goto(self, kw: Field, fields: list[Field]) -> Val | None:
        f = self.one(kw, fields, "NEXT, a step number or Rxxxx/Dxxxx")
        if f is None:
            return None
        if f.text.upper() == "NEXT":
            return NEXT
        if re.fullmatch(r"[0-9]+", f.text):
            n = int(f.text)
            if not 1 <= n <= self.d.max_steps:
                self.at(f, "F034", f"GOTO {f.text}: steps are 1-{self.d.max_steps}")
                return None
            return Val("K", n)
        reg = self.register(f, "F034", pair=False)
        if reg is None:
            self.at(f, "F034", f"GOTO {f.text!r}: expected NEXT, a step number or Rxxxx/Dxxxx")
        return reg


def _finish_steps(p: _Parser) -> list[Step]:
    """Complete-step checks, then the builders as Steps (defaults where parts are missing)."""
    out = []
    for s in p.steps:
        end_line = s.last_line or s.line
        if s.speed is None and "SPD" not in s.where:
            p.err("F035", f"step {s.number:03d} has no SPD", s.col, s.col + 3, line=s.line)
        if s.motion is None and "motion" not in s.where:
            p.err("F043", f"step {s.number:03d} has no drive command ({'/'.join(p.d.motions)})",
                  s.col, s.col + 3, line=s.line)
        if not s.done:
            p.err("F035", f"step {s.number:03d} does not end with GOTO or MEND", 1, 2, line=end_line)
        out.append(Step(s.speed or Val("K", 1), s.motion or Motion(p.d.motions[0], travel=(Val("K", 0),) *
                        (4 if p.d.name == "mhspo" else 1)),
                        s.cond, None if s.mend else (s.goto or NEXT), s.mend))
    return out


def _check_program(p: _Parser, steps: list[Step]) -> None:
    n = len(steps)
    if n == 0:
        p.err("F034", f"no steps: a {p.d.instruction} program has 1-{p.d.max_steps} steps", line=1)
        return
    for k, (s, b) in enumerate(zip(steps, p.steps, strict=True), start=1):
        line, col, end = b.where.get("GOTO", (b.last_line or b.line, 1, 2))
        if s.goto is not None and s.goto.kind == "K" and s.goto.n > n:
            p.err("F034", f"GOTO {s.goto.n}: the program has {n} step{'s' if n != 1 else ''}", col, end, line=line)
        if s.motion.op != "DRVC":
            continue
        # DRVC chains (DRVC row): only bare GOTO to the next segment, which is DRV or DRVC,
        # never DRVZ; at most max_segments segments; ABS only in the first segment.
        mline, mcol, mend = b.where.get("motion", (b.line, 1, 2))
        if s.cond is not None or s.mend or s.goto is None or s.goto.is_reg:
            p.err("F043", "a DRVC step continues into the next segment: it ends with GOTO NEXT or GOTO n "
                  "and has no WAIT/ACT/EXT or MEND", mcol, mend, line=mline)
            continue
        nxt = k + 1 if s.goto.kind == "NEXT" else s.goto.n
        if nxt > n:
            p.err("F043", "DRVC in the last step: the chain must end with a DRV step", mcol, mend, line=mline)
            continue
        follow = steps[nxt - 1].motion
        fb = p.steps[nxt - 1]
        fline, fcol, fend = fb.where.get("motion", (fb.line, 1, 2))
        if follow.op == "DRVZ":
            p.err("F042", f"DRVC (step {k:03d}) cannot be followed by DRVZ", fcol, fend, line=fline)
        elif follow.coord == "ABS":
            p.err("F041", f"ABS inside a DRVC chain: only its first segment (step {k:03d} chains here) may be ABS",
                  fcol, fend, line=fline)
    _check_chain_lengths(p, steps)


def _check_chain_lengths(p: _Parser, steps: list[Step]) -> None:
    """Follow each chain from a DRVC that no DRVC continues into; count its segments."""
    n = len(steps)

    def nxt(k: int) -> int | None:
        s = steps[k - 1]
        if s.motion.op != "DRVC" or s.goto is None or s.goto.is_reg or s.cond or s.mend:
            return None
        j = k + 1 if s.goto.kind == "NEXT" else s.goto.n
        return j if j <= n else None

    entered = {j for k in range(1, n + 1) if (j := nxt(k)) is not None}
    for k in range(1, n + 1):
        if steps[k - 1].motion.op != "DRVC" or k in entered:
            continue
        seen, j, segs = set(), k, 1
        while (j2 := nxt(j)) is not None and j2 not in seen:
            seen.add(j)
            j, segs = j2, segs + 1
        if segs > p.d.max_segments:
            b = p.steps[k - 1]
            line, col, end = b.where.get("motion", (b.line, 1, 2))
            p.err("F043", f"DRVC chain from step {k:03d} has {segs} segments; at most {p.d.max_segments}",
                  col, end, line=line)


def parse_program(path: str, text: str, dialect: Dialect,
                  pulse_modes: tuple[str, ...] = ()) -> tuple[PosProgram, list[Diagnostic]]:
    """The program and its diagnostics; `pulse_modes` (Ps0-Ps3, "UD"/"PR"/"AB", from mlc.toml)
    lets a FUN147 program be checked against the modes of the axes it drives (E236)."""
    p = _Parser(path, text, dialect, pulse_modes)
    p.run()
    steps = _finish_steps(p)
    _check_program(p, steps)
    diags = sorted(set(p.diags), key=Diagnostic.sort_key)
    return PosProgram(dialect.name, tuple(steps)), diags
