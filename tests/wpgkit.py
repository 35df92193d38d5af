"""Test fixtures: GX Developer program bodies (.wpg) written by the project's own code, in the
layout mlctool/wpg.py reads (docs/formats.md): the signature, the CPU type at 0x26, 04 00 FF FF
at 0x40, the program's tokens (tests/gxwkit.py: mlctool/gxw_tokens.toml read backwards; a NOP
is the empty frame 02 02, a comment line a text record), then one 02 02 per unused step of the program memory. The header's
bytes the reader does not read (the title, the bytes not identified) are seeded random, so a
test shows they are not read. Not an exporter: GX Developer opens a project, not a body alone.
"""

from __future__ import annotations

import random
import struct

import gxwkit

from mlctool.gxdeveloper import CPU_AT as CPU_FIELD
from mlctool.gxdeveloper import HEADER, SIGNATURE
from mlctool.wpg import BODY_MARK

FX3U, FX2N, FX1N = 0x0208, 0x0205, 0x0207
NOP = b"\x02\x02"


def header(cpu: int = FX3U, seed: int = 0) -> bytes:
    rng = random.Random(seed)
    out = bytearray(rng.randbytes(HEADER))
    out[:len(SIGNATURE)] = SIGNATURE
    struct.pack_into("<H", out, CPU_FIELD, cpu)
    return bytes(out) + BODY_MARK


def tokens(lines: list[tuple[str, list[str]]]) -> bytes:
    """Instructions (mnemonic, operands) -> tokens (tests/gxwkit.py's), NOP the empty frame."""
    return b"".join(NOP if m == "NOP" else gxwkit.tokens([(m, ops)]) for m, ops in lines)


def body(lines: list[tuple[str, list[str]]], fill: int, cpu: int = FX3U, seed: int = 0) -> bytes:
    """A .wpg: the header, the program's tokens (END last), `fill` NOP frames after END."""
    return header(cpu, seed) + tokens(lines) + NOP * fill


def steps(text: str, target) -> int:
    """The target's step count of an IL program (its instructions' steps, END included)."""
    from mlctool.check import check_texts
    from mlctool.syntax.source import SourceText

    result = check_texts([SourceText("p.il", text)], target)
    errors = [d.message for d in result.diagnostics if d.severity == "error"]
    if errors:
        raise ValueError(errors)
    return sum(ins.steps for ins in result.modules[0].instrs)


def il_lines(text: str, target) -> list[tuple[str, list[str]]]:
    """IL of the target (`.dialect fx`) -> FX instructions (mnemonic, operands), as GX writes
    them (M9000 -> M8000): tests/gxwkit.py's, with NOP lines kept."""
    return gxwkit.il_lines(text, target, nop=True)


def il_body(text: str, target, memory: int = 8000, **kw) -> bytes:
    """IL of the target (`.dialect fx`) -> a .wpg filling a program memory of `memory` steps."""
    return body(il_lines(text, target), memory - steps(text, target), **kw)
