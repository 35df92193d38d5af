"""`.table TABLE KIND FIELD ...`: one row of a communication table in IL source.

Some targets keep tables beside the program (Vigor VS: MBUS/LINK tables named Q0-Q31 or by
name, built in the vendor editor and stored with the project, manual 1-3 and 6-13). Their
row layout is data: target.toml `[tables.KIND]` lists the fields (name, operand kinds,
optional `range`/`values`, `by`+`ranges` for a range chosen by another field, `block` for a
device block as long as another field, `optional` for a trailing field, `repeat` for a last
field that takes one or more values, e.g. the words of a data table) and `forbid` (a
field value not allowed with some values of another). Nothing here names a table kind.

`parse_row` is shared by the checker (problems become diagnostics) and the simulator (which
reads the rows from the image's directives).
"""

from __future__ import annotations

from dataclasses import dataclass

from mlctool.syntax.operands import Operand, OperandSyntaxError, parse_operand
from mlctool.targetapi.model import Target


@dataclass(frozen=True)
class Row:
    kind: str  # "MBUS"
    table: int  # the Q number
    fields: dict[str, Operand]  # name -> operand (constants and devices as written)
    repeats: tuple[Operand, ...] = ()  # every value of a `repeat` last field, in order

    def value(self, name: str) -> int:
        return int(self.fields[name].value)


@dataclass(frozen=True)
class Problem:
    index: int  # operand position in the directive (0 = TABLE), -1 = the directive itself
    code: str
    message: str


def table_kinds(target: Target) -> dict:
    return target.settings.get("tables", {})


def parse_row(target: Target, texts: list[str], symbols: dict[str, str]) -> tuple[Row | None, list[Problem]]:
    """Operand texts after `.table` -> (row, problems); row is None when any problem."""
    kinds = table_kinds(target)
    usage = "usage: .table TABLE KIND FIELD ..., KIND one of " + (", ".join(kinds) or "(none on this target)")
    if len(texts) < 2:
        return None, [Problem(-1, "E105", f".table needs a table and a kind; {usage}")]
    kind = texts[1].upper()
    spec = kinds.get(kind)
    if spec is None:
        return None, [Problem(1, "E105", f"no table kind {texts[1]!r} on target {target.name}; {usage}")]
    fields = spec["fields"]
    required = [f for f in fields if not f.get("optional")]
    values = texts[2:]
    names = " ".join(f["name"] + ("?" if f.get("optional") else "..." if f.get("repeat") else "")
                     for f in fields)
    repeat = bool(fields) and fields[-1].get("repeat", False)
    if not len(required) <= len(values) <= (len(values) if repeat else len(fields)):
        return None, [Problem(-1, "E105", f".table {kind} takes {names} ({spec.get('section', '')}); "
                                        f"{len(values)} given")]
    problems: list[Problem] = []
    table = _pointer(target, spec, texts[0], symbols, problems)
    ops: dict[str, Operand] = {}
    specs = fields + [fields[-1]] * (len(values) - len(fields)) if repeat else fields
    repeats: list[Operand] = []
    for k, (f, text) in enumerate(zip(specs, values, strict=False)):
        op = _operand(target, f, text, symbols, k + 2, problems)
        if op is not None:
            ops.setdefault(f["name"], op)
            if f.get("repeat"):
                repeats.append(op)
                _limits(target, spec, f, {f["name"]: op}, k + 2, problems)
    if problems:
        return None, problems
    for k, f in enumerate(fields[:len(values)]):
        if not f.get("repeat"):
            _limits(target, spec, f, ops, k + 2, problems)
    if problems:
        return None, problems
    return Row(kind, table, ops, tuple(repeats)), []


def _pointer(target: Target, spec: dict, text: str, symbols: dict[str, str], problems: list) -> int:
    kind = spec["pointer"]
    op = _parse(target, symbols.get(text.upper(), text))
    dev = target.devices.get(kind)
    if op is None or op.kind != kind or op.index or dev is None or not dev.lo <= op.number <= dev.hi:
        where = f"{kind}{dev.lo}-{kind}{dev.hi}" if dev else kind
        problems.append(Problem(0, "E105", f"{text!r} is not a table: tables are {where} "
                                           f"or a name given one with .define NAME {kind}n"))
        return -1
    return op.number


def _parse(target: Target, text: str) -> Operand | None:
    try:
        return parse_operand(text, target.operand_syntax)
    except OperandSyntaxError:
        return None


def _operand(target: Target, f: dict, text: str, symbols: dict[str, str], idx: int,
             problems: list) -> Operand | None:
    op = _parse(target, symbols.get(text.upper(), text))
    allowed = f["kinds"].split()
    if op is None or op.kind not in allowed or op.index:
        problems.append(Problem(idx, "E204", f"{f['name']} {text!r}: takes {' '.join(allowed)} "
                                             "(no index)"))
        return None
    if not op.is_const:
        dev = target.devices.get(op.kind)
        if dev is None or not dev.lo <= op.number <= dev.hi:
            problems.append(Problem(idx, "E205" if dev else "E204", f"{f['name']} {text!r}: no such device"))
            return None
    return op


def _limits(target: Target, spec: dict, f: dict, ops: dict[str, Operand], idx: int, problems: list) -> None:
    name = f["name"]
    op = ops[name]
    if op.is_const:
        v = int(op.value)
        lo, hi = f.get("range", (None, None))
        if f.get("by"):
            lo, hi = f["ranges"].get(str(ops[f["by"]].value), (lo, hi))
        if "values" in f and v not in f["values"]:
            shown = ", ".join(f"H{x:02X}" for x in f["values"])
            problems.append(Problem(idx, "E206", f"{name} {v} (H{v:X}): one of {shown}"))
        elif lo is not None and not lo <= v <= hi:
            why = f" with {f['by']} H{int(ops[f['by']].value):02X}" if f.get("by") else ""
            problems.append(Problem(idx, "E206", f"{name} {v} outside {lo}..{hi}{why}"))
        for rule in spec.get("forbid", ()):
            if rule["field"] == name and v == rule["value"] and rule["when"] in ops \
                    and int(ops[rule["when"]].value) in rule["is"]:
                problems.append(Problem(idx, "E206", rule["message"]))
    elif f.get("block"):
        count = int(ops[f["block"]].value)
        dev = target.devices[op.kind]
        if op.number + count - 1 > dev.hi:
            problems.append(Problem(idx, "E206", f"{name}: {count} words from {op.kind}{op.number} "
                                                 f"pass {op.kind}{dev.hi}"))
