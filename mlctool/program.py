"""The checked program: instructions with resolved operands, step counts and addresses.

This is the data every later stage (assembler, linker, simulator) consumes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from operator import attrgetter

from mlctool.syntax.operands import Operand
from mlctool.targetapi.model import InstrSpec


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
        return self.operands[0].number if self.spec.cls == "label" and self.operands else None


@dataclass(slots=True)
class Module:
    """One source file, checked: a main program or a subroutine library (`.library`)."""

    path: str  # as given (relative), never made absolute
    target: str
    instrs: list[Instr]
    exports: set[int] = field(default_factory=set)  # exported P numbers
    symbols: dict[str, str] = field(default_factory=dict)  # name -> operand text
    library: bool = False
    dialect: str = ""  # `.dialect fx`: the family the program was written for (check/specials.py)

    @property
    def total_steps(self) -> int:
        return sum(map(_steps_of, self.instrs))  # (no generator: a 64k-step program has 40k instructions)

    def labels(self) -> dict[int, int]:
        """P number -> instruction index (first definition). A label with operand errors
        (`P256` on NC5: E205, kept without operands to end its rung) defines nothing."""
        out: dict[int, int] = {}
        for k, ins in enumerate(self.instrs):
            if ins.spec.cls == "label" and ins.operands:
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
    # SHA-256 (hex) of the linked object file read (`mlc sim prog.mlx`), "" for a program
    # built from sources: with it the compiled engine's code is cached on disk (mlctool/cache.py)
    digest: str = ""

    @property
    def total_steps(self) -> int:
        return sum(map(_steps_of, self.instrs))  # (no generator: a 64k-step program has 40k instructions)

    def labels(self) -> dict[int, int]:
        """P number -> instruction index."""
        return {ins.operands[0].number: k for k, ins in enumerate(self.instrs)
                if ins.spec.cls == "label" and ins.operands}


class FormIndex:
    """Where each instruction form occurs in a list of instructions, from one pass over it.
    The rules that look for a few forms (labels, jumps, FOR/NEXT, MC, END ...) visit only
    their instructions instead of each walking the whole program (issue 19: the speed of
    checking)."""

    __slots__ = ("_groups", "_specs")

    def __init__(self, instrs: list[Instr]):
        groups: dict[int, list[int]] = {}
        specs: dict[int, InstrSpec] = {}
        for k, ins in enumerate(instrs):
            key = id(ins.spec)
            found = groups.get(key)
            if found is None:
                found = groups[key] = []
                specs[key] = ins.spec
            found.append(k)
        self._groups = groups
        self._specs = specs

    def where(self, ops: tuple[str, ...] = (), classes: tuple[str, ...] = ()) -> list[int]:
        """Positions, in order, of the instructions whose form has one of `ops` or `classes`."""
        return self.matching(lambda spec: spec.op in ops or spec.cls in classes)

    def matching(self, test) -> list[int]:
        """Positions, in order, of the instructions whose form passes `test(spec)`."""
        parts = [g for key, g in self._groups.items() if test(self._specs[key])]
        if len(parts) == 1:
            return list(parts[0])
        return sorted(k for part in parts for k in part)


_steps_of = attrgetter("steps")

# Instruction classes after which a load opens a new rung (2.2): the rung's result has been
# used by an output, or a row of its own (label, END/FEND/..., interrupt pointer, STL) stands
# between. The checker, the ladder builder and the simulator all take rung boundaries from
# rung_starts(), so the three never disagree on where a rung begins.
RUNG_END_CLASSES = frozenset({"output", "free", "label", "interrupt", "bus"})
_BLOCK_SCAN_STOP = frozenset({"free", "label", "interrupt", "bus", "mps", "mrd", "mpp"})


def _block_is_combined(instrs: list[Instr], k: int) -> bool:
    """Whether the block opened by the load at `k` is combined with the result before it
    (by ANB/ORB, or as a further input of a multi-input output) before the next output."""
    level = 0  # blocks opened from k on that are still waiting
    for ins in instrs[k:]:
        cls = ins.spec.cls
        if cls == "load":
            level += 1
        elif cls in ("anb", "orb"):
            level -= 1
            if level == 0:
                return True
        elif cls == "output":
            return len(ins.spec.inputs) - 1 >= level
        elif cls in _BLOCK_SCAN_STOP:
            return False
    return False


def rung_starts(instrs: list[Instr]) -> list[bool]:
    """For each instruction, whether it is a load that starts a new rung.

    A load starts a rung after an output or a row (RUNG_END_CLASSES); anywhere else it opens
    a block of the current rung. One exception, the form GX Works2 and WPLSoft emit for a
    block after a coil inside an MPS branch (`MPS / AND X1 / OUT Y0 / LD X2 / OR X3 / ANB /
    OUT Y1 / MPP ...`): a load right after an output while an MPS is open opens a block of
    the same rung, when that block is combined with ANB/ORB before the next output. Without
    the ANB/ORB the load starts a rung as usual (and the open MPS is the error: E308)."""
    out = [False] * len(instrs)
    prev = "free"
    mps = 0
    for k, ins in enumerate(instrs):
        cls = ins.spec.cls
        if cls == "nop":  # no step of a rung: a load after `OUT Y1 / NOP` still starts one
            continue
        if cls == "load" and prev in RUNG_END_CLASSES:
            if not (prev == "output" and mps and _block_is_combined(instrs, k)):
                out[k] = True
                mps = 0
        elif cls == "mps":
            mps += 1
        elif cls == "mpp":
            mps = max(mps - 1, 0)
        elif cls in RUNG_END_CLASSES and cls != "output":
            mps = 0
        prev = cls
    return out
