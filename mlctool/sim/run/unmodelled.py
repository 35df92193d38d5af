"""W608: the program writes a special device whose function the simulator does not model
(the target's unmodelled_specials.toml: VS M9039 constant scan, D9000 watchdog time ...).

On the PLC such a write changes what the PLC does; in the simulator it only stores the value,
so a run that passes may not pass on the PLC. `mlc sim` and `mlc test` say so once per device,
at the program's first write of it, before the run: the warning is a property of the program,
found from its text (OUT/SET/RST/PLS/PLF, ZRST's range, an application instruction's
destination with the words or Kn bits it covers). A write through an index register, or to a
block past its first device (FMOV, BMOV n), is not seen. Nothing here changes the run or its
exit code.
"""

from __future__ import annotations

from collections.abc import Iterator

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Image, Instr
from mlctool.targetapi.model import Target
from mlctool.targetapi.specials import unmodelled_specials

_WRITERS = ("out", "set", "rst", "pls", "plf", "alt")  # basic instructions writing their first operand


def unmodelled_writes(image: Image, target: Target) -> list[Diagnostic]:
    """W608 for each unmodelled special device the program writes, at its first write, in
    program order."""
    table = unmodelled_specials(target.name)
    if not table:
        return []
    found: dict[tuple[str, int], Diagnostic] = {}
    for ins in image.instrs:
        for kind, first, last in _written(ins, target):
            for row in table:
                if row.kind != kind or row.hi < first or row.lo > last:
                    continue
                for n in range(max(first, row.lo), min(last, row.hi) + 1):
                    if (kind, n) not in found:
                        name = target.device_name(kind, n)
                        found[(kind, n)] = diag(
                            ins.file, Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic)), "W608",
                            f"{name} ({row.function}; manual {row.section}) is written by "
                            f"{' '.join((ins.mnemonic, *ins.texts))}, and the simulator does not model "
                            "it: the run goes on as if the write only stored the value",
                            f"why: {row.why}")
    return list(found.values())


def _written(ins: Instr, target: Target) -> Iterator[tuple[str, int, int]]:
    """(device kind, first, last number) of each device span the instruction writes, where the
    text tells (no index register)."""
    spec = ins.spec
    if spec.op == "zrst" and len(ins.operands) > 1:
        a, b = ins.operands[0], ins.operands[1]
        if not a.index and not b.index and a.kind == b.kind:
            yield a.device, min(a.number, b.number), max(a.number, b.number)
        return
    for k, (o, s) in enumerate(zip(ins.operands, spec.operands, strict=False)):
        if o.is_const or o.index:
            continue
        if spec.api is None:
            if spec.op in _WRITERS and k == 0:
                yield o.device, o.number, o.number
            continue
        if not s.writes:
            continue
        if o.is_group:
            yield o.device, o.number, o.number + 4 * o.digits - 1
        elif o.is_bit_of_word:
            yield o.device, o.number, o.number
        elif o.kind not in target.devices:
            continue
        elif target.devices[o.kind].kind == "bit":
            yield o.kind, o.number, o.number + s.bits - 1
        else:
            yield o.kind, o.number, o.number + (s.words[1] if spec.width == 32 else s.words[0]) - 1
