"""The checked program: instructions with resolved operands, step counts and addresses.

This is the data every later stage (assembler, linker, simulator) consumes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from mlctool.syntax.operands import Operand
from mlctool.targets.model import InstrSpec


@dataclass(slots=True)
class Instr:
    spec: InstrSpec
    operands: tuple[Operand, ...]
    texts: tuple[str, ...]  # operands as written (symbols kept), for listings and messages
    steps: int
    addr: int
    file: str
    line: int
    col: int = 1
    table: tuple[int, ...] = ()  # VRT's 64-entry table
    valid: bool = True  # False: operands had errors (kept so the rung checks see the line)

    @property
    def mnemonic(self) -> str:
        return self.spec.mnemonic

    @property
    def label(self) -> int | None:
        """The P number this instruction defines (P label) or None."""
        return self.operands[0].number if self.spec.cls == "label" else None


@dataclass(slots=True)
class Module:
    """One source file, checked: a main program or a subroutine library (`.library`)."""

    path: str  # as given (relative), never made absolute
    target: str
    instrs: list[Instr]
    exports: set[int] = field(default_factory=set)  # exported P numbers
    symbols: dict[str, str] = field(default_factory=dict)  # name -> operand text
    library: bool = False

    @property
    def total_steps(self) -> int:
        return sum(i.steps for i in self.instrs)

    def labels(self) -> dict[int, int]:
        """P number -> instruction index (first definition)."""
        out: dict[int, int] = {}
        for k, ins in enumerate(self.instrs):
            if ins.spec.cls == "label":
                out.setdefault(ins.operands[0].number, k)
        return out


@dataclass(slots=True)
class Image:
    """A linked program: the main module, FEND, library subroutines, END, at final addresses."""

    target: str
    instrs: list[Instr]
    modules: list[tuple[str, int, int]] = field(default_factory=list)  # (path, first addr, end addr)
    symbols: dict[str, str] = field(default_factory=dict)  # device symbols of all modules
    # directives of all modules as written, (module path, text): tables kept beside the code
    # (`.table` rows) reach the simulator this way
    directives: list[tuple[str, str]] = field(default_factory=list)

    @property
    def total_steps(self) -> int:
        return sum(i.steps for i in self.instrs)

    def labels(self) -> dict[int, int]:
        """P number -> instruction index."""
        return {ins.operands[0].number: k for k, ins in enumerate(self.instrs) if ins.spec.cls == "label"}
