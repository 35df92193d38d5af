"""The link map: module address ranges, label addresses, device cross-reference.

The cross-reference expands what an operand occupies (a K4Y0 group is Y0-Y15, a 32-bit D0 is
D0 and D1, an FCMP destination three bits) from the operand tables, so "who writes D1" finds
a DMOV to D0. Index-modified operands are listed as written (their device is known only at
run time) and count as reads of the index register.
"""

from __future__ import annotations

from collections import defaultdict

from mlctool.asm.objfile import ObjectFile
from mlctool.program import Instr
from mlctool.syntax.operands import Operand, format_operand
from mlctool.targetapi.model import OperandSpec, Target


def _cells(ins: Instr, o: OperandSpec, op: Operand, target: Target) -> list[str]:
    if op.is_const or op.kind == "P":
        return []
    if op.index:
        return [format_operand(op)]
    if op.is_group:
        return [f"{op.device}{n}" for n in range(op.number, op.number + 4 * op.digits)]
    dev = target.devices.get(op.kind)
    if dev is not None and dev.kind == "bit":
        count = o.bits
    elif dev is not None and dev.kind in ("timer", "counter"):
        count = 1  # one timer/counter, 16- or 32-bit alike
    else:
        count = o.words[1 if ins.spec.width == 32 else 0]
    return [f"{op.kind}{n}" for n in range(op.number, op.number + count)]


def _range_cells(ins: Instr) -> list[str]:
    """Operands 1 and 2 of a range instruction (the table's `same-kind` rule, ZRST) name
    every device between them."""
    if "same-kind" not in ins.spec.constraints or any(o.index for o in ins.operands[:2]):
        return []
    a, b = ins.operands[:2]
    lo, hi = sorted((a.number, b.number))
    return [f"{a.kind}{n}" for n in range(lo, hi + 1)]


def xref(obj: ObjectFile, target: Target) -> dict[str, tuple[list[int], list[int]]]:
    """device -> (addresses reading it, addresses writing it)."""
    reads: dict[str, list[int]] = defaultdict(list)
    writes: dict[str, list[int]] = defaultdict(list)
    for ins in obj.instrs:
        ranged = _range_cells(ins)
        for k, (o, op) in enumerate(zip(ins.spec.operands, ins.operands, strict=False)):
            cells = ranged if ranged and k < 2 else _cells(ins, o, op, target)
            if "r" in o.access:
                for c in cells:
                    reads[c].append(ins.addr)
            if "w" in o.access:
                for c in cells:
                    writes[c].append(ins.addr)
            if op.index:
                reads[f"{op.index[0]}{op.index[1]}"].append(ins.addr)
    keys = sorted(set(reads) | set(writes), key=_device_order)
    return {k: (sorted(set(reads.get(k, []))), sorted(set(writes.get(k, [])))) for k in keys}


def _device_order(name: str):
    head = name.rstrip("0123456789VZ")
    digits = name[len(head):]
    num = "".join(c for c in digits if c.isdigit())
    return (head, int(num) if num.isdigit() and digits.isdigit() else -1, name)


def link_map(obj: ObjectFile, target: Target, output: str = "") -> str:
    w = max(5, len(str(obj.total_steps)))
    out = [f"; link map{' of ' + output if output else ''}: target {obj.target}, "
           f"{obj.total_steps} of {target.capacity} steps", "", "[modules]"]
    for u in obj.units:
        out.append(f"{u.first:0{w}d}-{max(u.end - 1, u.first):0{w}d}  {u.end - u.first:6d} steps  "
                   f"{u.path}{' (library)' if u.library else ' (main)'}")
    for k in sorted(obj.inserted):
        ins = obj.instrs[k]
        out.append(f"{ins.addr:0{w}d}  {ins.spec.mnemonic} inserted by the linker before the library code")
    end = obj.instrs[-1] if obj.instrs else None
    if end is not None and obj.kind == "program":
        out.append(f"{end.addr:0{w}d}  {end.spec.mnemonic} from {end.file}:{end.line}")
    out += ["", "[labels]"]
    refs: dict[int, list[int]] = defaultdict(list)
    for ins in obj.instrs:
        if ins.spec.op in ("cj", "call") and not ins.operands[0].index:
            refs[ins.operands[0].number].append(ins.addr)
    labels = [(ins.operands[0].number, ins, u) for ins, u in zip(obj.instrs, obj.unit_of, strict=True)
              if ins.spec.cls == "label"]
    for p, ins, u in sorted(labels, key=lambda t: t[0]):
        unit = obj.units[u]
        scope = "exported" if p in unit.exports else "local"
        used = " ".join(f"{a:0{w}d}" for a in refs.get(p, []))
        out.append(f"P{p:<4d} {ins.addr:0{w}d}  {scope:8} {unit.path}:{ins.line}"
                   + (f"  used at {used}" if used else ""))
    out += ["", "[symbols]"]
    for u in obj.units:
        for name, value in u.symbols.items():
            out.append(f"{name:16} {value:10} {u.path}")
    out += ["", "[xref]  device: read at ... | written at ..."]
    for dev, (r, wr) in xref(obj, target).items():
        rs = " ".join(f"{a:0{w}d}" for a in r) or "-"
        ws = " ".join(f"{a:0{w}d}" for a in wr) or "-"
        out.append(f"{dev:8} r: {rs} | w: {ws}")
    return "\n".join(out) + "\n"
