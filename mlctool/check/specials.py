"""W217: another family's special device read as if it were special (targets/<name>/specials.toml).

An FX program's `LD M8000` (RUN on) or a Delta DVP program's `LD M1002` (initial pulse) checks
clean on the VS, where those are ordinary relays nothing drives, and does nothing. Heuristic:
a device read (a contact, or a source operand) and never written anywhere in the program
(OUT/SET/RST/PLS/PLF, ZRST, a destination of an application instruction, or through a Kn
group) that is in FX's special ranges (M8000-M8511, D8000-D8511), or that Delta DVP numbers as
a special with a VS counterpart (M1000, M1002, M1013, D1010 ...). A program that writes the
device uses it as an ordinary one, and says nothing here. A module with `.dialect fx` (or `dvp`; `mlc import`
writes it) is judged by that family alone: an FX program's M1000 is an ordinary relay, not
Delta's RUN monitor.

The other way round: a device of those ranges written and never read is a setting for the
CPU (the FX set-up `LD M8002 / MOV H0C87 D8120` of public Modbus-slave listings: D8120 the
port's format, D8121 the station), which on the VS is an ordinary register nobody reads.
"""

from __future__ import annotations

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Instr, Module
from mlctool.targetapi.model import Target
from mlctool.targetapi.specials import families

_CONTACTS = ("contact", "contact_not", "contact_rise", "contact_fall")
_WRITERS = ("out", "set", "rst", "pls", "plf", "alt")


def foreign_specials(modules: list[Module], target: Target) -> list[Diagnostic]:
    fams = families(target.name)
    if not fams:
        return []
    instrs = [ins for m in modules for ins in m.instrs]
    dialects = {m.path: m.dialect for m in modules}
    written: set[tuple[str, int]] = set()
    spans: list[tuple[str, int, int]] = []
    reads: list[tuple[Instr, str, int]] = []
    writes: list[tuple[Instr, str, int]] = []
    for ins in instrs:
        spec = ins.spec
        for k, (o, s) in enumerate(zip(ins.operands, spec.operands, strict=False)):
            if o.is_const or o.index:
                continue
            if o.is_group:
                if s.writes or spec.api is None:
                    spans.append((o.device, o.number, o.number + 4 * o.digits - 1))
                continue
            if spec.op == "zrst" and k == 0 and len(ins.operands) > 1:
                spans.append((o.kind, min(o.number, ins.operands[1].number), max(o.number, ins.operands[1].number)))
            elif (spec.op in _WRITERS and k == 0) or (spec.api is not None and s.writes):
                written.add((o.kind, o.number))
                writes.append((ins, o.kind, o.number))
            elif spec.op in _CONTACTS or (spec.api is not None and not s.writes):
                reads.append((ins, o.kind, o.number))
    read = {(kind, number) for _, kind, number in reads}
    read_spans = [(o.device, o.number, o.number + 4 * o.digits - 1) for ins in instrs
                  for o, s in zip(ins.operands, ins.spec.operands, strict=False)
                  if o.is_group and not s.writes and ins.spec.api is not None]
    out, seen = [], set()
    # (places, devices that make a place ordinary use, the ranges that do too, what it says)
    for places, ordinary, ranges, how in ((writes, read, read_spans, "written but never read"),
                                          (reads, written, spans, "read but never written")):
        for ins, kind, number in places:
            key = (kind, number)
            if key in seen or key in ordinary or any(k == kind and lo <= number <= hi for k, lo, hi in ranges):
                continue
            dialect = dialects.get(ins.file)
            found = _foreign({dialect: fams[dialect]} if dialect in fams else fams, ins, kind, number, target, how)
            if found is not None:
                seen.add(key)
                out.append(found)
    return out


def _foreign(fams, ins: Instr, kind: str, number: int, target: Target, how: str) -> Diagnostic | None:
    """W217 for kind/number if a family numbers it as a special, else None."""
    for fam in fams.values():
        if not fam.is_special(kind, number):
            continue
        special = fam.mapping.get((kind, number))
        if special is None and fam.name != "fx":
            continue  # DVP's M1000-M1999 are common ordinary relays: only its known specials
        name = f"{kind}{number}"
        there = (f"its {fam.title} function ({special.function}) is {special.device} on target {target.name} "
                 f"(manual {special.section})" if special else
                 f"the {fam.title} special {name} has no known counterpart on target {target.name}")
        return diag(ins.file, Span(ins.line, ins.col, ins.line, ins.col + len(ins.spec.mnemonic)), "W217",
                    f"{name} is {how}: an ordinary device on target {target.name}, "
                    f"not the {fam.title} special; {there}",
                    "`mlc import` maps them when it reads the export (docs/vs.md, Special devices)")
    return None
