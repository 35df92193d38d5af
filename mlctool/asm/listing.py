"""Human and machine views of an object: listings, objdump text/JSON, and IL that rebuilds it.

`to_il` puts every instruction and directive back on its own line and column, so a source
saved under the unit's name rebuilds the same module: same code, same line table, same bytes.
"""

from __future__ import annotations

import json

from mlctool.asm.encode import unit_instrs
from mlctool.asm.objfile import ObjectFile
from mlctool.program import Instr
from mlctool.syntax.operands import format_operand
from mlctool.syntax.source import pad


def instr_text(ins: Instr) -> str:
    """An instruction as IL: mnemonic, operands as written (symbols kept), VRT table."""
    if ins.spec.cls in ("label", "interrupt"):
        return f"{ins.texts[0] if ins.texts else format_operand(ins.operands[0])}:"
    words = [ins.spec.mnemonic, *ins.texts]
    words += [f"K{v}" for v in ins.table]
    return " ".join(words)


def operand_strings(ins: Instr) -> list[str]:
    """Operands resolved (symbols replaced by their devices), then VRT table entries."""
    return [format_operand(o) for o in ins.operands] + [f"K{v}" for v in ins.table]


def _width(obj: ObjectFile) -> int:
    return max(5, len(str(obj.total_steps)))


def objdump_text(obj: ObjectFile) -> str:
    w = _width(obj)
    out = [f"; {obj.kind} for target {obj.target}, {obj.total_steps} steps, "
           f"{len(obj.instrs)} instructions"]
    for u in obj.units:
        kind = "library" if u.library else "main"
        exports = " ".join(f"P{p}" for p in u.exports)
        out.append(f"; unit {u.path} ({kind}) {u.first:0{w}d}-{u.end:0{w}d}"
                   + (f" exports {exports}" if exports else ""))
        for name, value in u.symbols.items():
            out.append(f";   {name} = {value}")
    out.append(f"{'addr':>{w}} steps  {'mnemonic':8} {'operands':28} source")
    for k, ins in enumerate(obj.instrs):
        ops = " ".join(_shown(ins))
        mark = " (inserted by the linker)" if k in obj.inserted else ""
        # by display width: a Chinese label name takes two columns a character
        out.append(f"{ins.addr:0{w}d} {ins.steps:5d}  {ins.spec.mnemonic:8} {pad(ops, 28)} {ins.file}:{ins.line}{mark}")
    return "\n".join(out) + "\n"


def _shown(ins: Instr) -> list[str]:
    """Operands as written, with the device a symbol stands for."""
    shown = []
    for text, op in zip(ins.texts, ins.operands, strict=False):
        canon = format_operand(op)
        shown.append(text if text.upper() == canon else f"{text}={canon}")
    if ins.table:
        shown.append(f"[{len(ins.table)} table entries]")
    return shown


def objdump_json(obj: ObjectFile) -> str:
    symbols = []
    for ins, u in zip(obj.instrs, obj.unit_of, strict=True):
        if ins.spec.cls == "label":
            p = ins.operands[0].number
            symbols.append({"kind": "label", "name": f"P{p}", "addr": ins.addr, "module": obj.units[u].path,
                            "exported": p in obj.units[u].exports})
    for u in obj.units:
        for name, value in u.symbols.items():
            symbols.append({"kind": "device", "name": name, "value": value, "module": u.path})
    doc = {
        "target": obj.target,
        "kind": obj.kind,
        "total_steps": obj.total_steps,
        "modules": [{"path": u.path, "library": u.library, "first": u.first, "end": u.end} for u in obj.units],
        "instructions": [
            {"addr": i.addr, "steps": i.steps, "mnemonic": i.spec.mnemonic, "operands": operand_strings(i),
             "texts": list(i.texts), "file": i.file, "line": i.line}
            for i in obj.instrs
        ],
        "symbols": symbols,
    }
    return json.dumps(doc, ensure_ascii=False) + "\n"


def unit_il(obj: ObjectFile, k: int) -> str:
    """One unit's source, each statement on its original line and column."""
    unit = obj.units[k]
    at: dict[int, str] = {}
    for d in unit.directives:
        at[d.line] = " " * (d.col - 1) + d.text
    for ins in unit_instrs(obj, k):
        at[ins.line] = " " * (ins.col - 1) + f"{instr_text(ins):24} ; {ins.addr:05d} ({ins.steps})"
    last = max(at, default=0)
    lines = [at.get(n, "") for n in range(1, last + 1)]
    lines.append(f"; {unit.path}: {'library ' if unit.library else ''}module for {obj.target}, "
                 f"written by mlc objdump --il")
    return "\n".join(line.rstrip() for line in lines) + "\n"


def listing(obj: ObjectFile, lines: dict[str, list[str]] | None = None) -> str:
    """Address, steps and source text of every instruction (the source line when known)."""
    lines = lines or {}
    w = _width(obj)
    out = [f"; listing: {obj.kind} for {obj.target}, {obj.total_steps} steps",
           f"{'addr':>{w}} steps  source"]
    for k, ins in enumerate(obj.instrs):
        src = lines.get(ins.file)
        text = src[ins.line - 1].strip() if src and 0 < ins.line <= len(src) else instr_text(ins)
        if k in obj.inserted:
            text = f"{instr_text(ins)}    ; inserted by the linker before the library code"
        out.append(f"{ins.addr:0{w}d} {ins.steps:5d}  {ins.file}:{ins.line}: {text}")
    return "\n".join(out) + "\n"
