"""FBs positioning programs as plain data, and the dialect tables that describe them.

A program is what FUN140 HSPSO (or FUN147 MHSPO) runs from its SR table: numbered steps,
each a speed, a drive command, an optional transfer condition and a GOTO or MEND
(manual 001 ch. 11, "定位程式格式"). The dialect data live in
mlctool/targets/fbs/positioning.toml.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

TABLES = Path(__file__).resolve().parent / "positioning.toml"


@dataclass(frozen=True, slots=True)
class Val:
    """One operand: a constant (K), a register (R/D), a bit (X/Y/M/S), NEXT, or blank ("")."""

    kind: str
    n: int = 0

    @property
    def is_reg(self) -> bool:
        return self.kind in ("R", "D")

    def text(self) -> str:
        if self.kind == "K":
            return str(self.n)
        if self.kind in ("", "NEXT"):
            return " " if not self.kind else "NEXT"
        return f"{self.kind}{self.n}"


BLANK = Val("")
NEXT = Val("NEXT")


@dataclass(frozen=True, slots=True)
class Motion:
    op: str  # DRV DRVC DRVZ (FUN140) | LIN LINE (FUN147)
    coord: str = "ADR"  # ADR relative | ABS absolute
    sign: str = ""  # "" blank (sign of the value decides) | "+" | "-"
    travel: tuple[Val, ...] = ()  # one for DRV/DRVC, four (Ps0..Ps3) for LIN/LINE
    unit: str = "Ut"  # Ut (FUN141 unit) | Ps (one pulse)
    mode: int = 0  # DRVZ MD0..MD2

    def driven_axes(self) -> tuple[int, ...]:
        """The axes (Ps0-Ps3) a LIN/LINE outputs pulses to: not those with a blank travel, nor
        ADR 0 ("ADR with a travel of 0 or blank: that axis does not output"; ABS 0 moves to 0).
        Decision: a register travel counts as driving its axis, whatever it holds."""
        return tuple(i for i, v in enumerate(self.travel)
                     if v.kind and not (self.coord == "ADR" and v.kind == "K" and v.n == 0))


@dataclass(frozen=True, slots=True)
class Cond:
    """Transfer condition: WAIT TIME,t | WAIT bit | ACT TIME,t | EXT bit (t in 10 ms)."""

    op: str  # WAIT | ACT | EXT
    time: bool  # TIME form (value in 0.01 s) rather than a bit
    val: Val


@dataclass(frozen=True, slots=True)
class Step:
    speed: Val
    motion: Motion
    cond: Cond | None
    goto: Val | None  # NEXT, K step number, R/D register; None when the step ends with MEND
    mend: bool = False


@dataclass(frozen=True, slots=True)
class PosProgram:
    dialect: str  # "hspso" | "mhspo"
    steps: tuple[Step, ...]


# FUN147 MHSPO drives U/D and A/B axes only (11.6 FUN147: "務必設定 Pulse Output 之工作模式 ...
# 為 U/D 或 A/B 等二種模式之一，Pulse Output 才能正常輸出"); the FUN140 page allows all three.
MHSPO_FORBIDDEN_MODE = "PR"


def mhspo_mode_conflicts(program: PosProgram, pulse_modes) -> list[tuple[int, int]]:
    """(step index, axis) of every LIN/LINE that drives an axis whose pulse output mode
    (target spelling "UD"/"PR"/"AB") FUN147 does not allow."""
    return [(k, i) for k, step in enumerate(program.steps) for i in step.motion.driven_axes()
            if i < len(pulse_modes) and pulse_modes[i] == MHSPO_FORBIDDEN_MODE]


@dataclass(frozen=True, slots=True)
class Dialect:
    name: str
    instruction: str
    extension: str
    header: int
    step_words: int
    max_steps: int
    speed_max: int
    travel_max: int
    travel_digits: int
    motions: tuple[str, ...]
    conditions: tuple[str, ...]
    foreign: tuple[str, ...]
    foreign_code: str
    max_segments: int

    def table_words(self, n_steps: int) -> int:
        """N x 9 + 2 (FUN140) or N x 15 + 2 (FUN147): header, step count, steps."""
        return n_steps * self.step_words + 2


@dataclass(frozen=True, slots=True)
class Tables:
    dialects: dict[str, Dialect]
    registers: dict[str, tuple[int, int]]
    bits: dict[str, tuple[int, int]]

    def dialect_for(self, path: str) -> Dialect | None:
        low = path.lower()
        for d in self.dialects.values():
            if low.endswith(d.extension):
                return d
        return None

    def by_header(self, word: int) -> Dialect | None:
        return next((d for d in self.dialects.values() if d.header == word), None)


@cache
def tables() -> Tables:
    raw = tomllib.loads(TABLES.read_text("utf-8"))
    dialects = {
        name: Dialect(name=name, instruction=d["instruction"], extension=d["extension"],
                      header=d["header"], step_words=d["step_words"], max_steps=d["max_steps"],
                      speed_max=d["speed_max"], travel_max=d["travel_max"],
                      travel_digits=d["travel_digits"], motions=tuple(d["motions"]),
                      conditions=tuple(d["conditions"]), foreign=tuple(d["foreign"]),
                      foreign_code=d["foreign_code"], max_segments=d["max_segments"])
        for name, d in raw["dialect"].items()
    }
    return Tables(dialects, {k: tuple(v) for k, v in raw["registers"].items()},
                  {k: tuple(v) for k, v in raw["bits"].items()})


def is_positioning_source(path: str) -> bool:
    return tables().dialect_for(path) is not None
