"""The operand rules an instruction page states beyond kinds and ranges (device numbers ending
in 0, Kn sizes, operands that must agree, per-model constant ranges, outputs, timers or
inputs only one instruction may use, blocks that may not overlap, instructions used in
pairs, relays the PLC clears itself): E230-E235, W230-W232, E206.

Generic: the rules are data, `operand_rules.toml` in the target's tables folder (the Vigor VS
pages, docs/vs-audit.md); a target without the file gets none of these diagnostics. Only
operands written as plain devices or constants are judged: an indexed operand's device is
known at run time only.
"""

from __future__ import annotations

import tomllib
from functools import cache
from pathlib import Path

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Instr, Module
from mlctool.syntax.operands import Operand
from mlctool.targetapi.model import Target
from mlctool.targetapi.registry import UnknownTarget, target_package


@cache
def _rules(target_name: str) -> dict[int, list[dict]]:
    """FNC number -> the rules of its page."""
    try:
        path = Path(target_package(target_name).tables) / "operand_rules.toml"
    except UnknownTarget:
        return {}
    if not path.is_file():
        return {}
    out: dict[int, list[dict]] = {}
    for rule in tomllib.loads(path.read_text("utf-8")).get("rule", []):
        out.setdefault(rule["fnc"], []).append(rule)
    return out


def _at(ins: Instr, code: str, msg: str, *notes: str) -> Diagnostic:
    return diag(ins.file, Span(ins.line, ins.col, ins.line, ins.col + len(ins.mnemonic)), code, msg, *notes)


def _operand(ins: Instr, role: str) -> tuple[Operand | None, str]:
    """The operand written for `role` and its text (None when absent or indexed)."""
    for k, o in enumerate(ins.spec.operands):
        if o.role == role and k < len(ins.operands):
            op = ins.operands[k]
            return (None if op.index else op), ins.texts[k] if k < len(ins.texts) else str(op)
    return None, ""


def _name(target: Target, op: Operand) -> str:
    """X20 for the ordinal 16 of octal X; K4M0 for a group."""
    dev = target.devices.get(op.device)
    name = dev.name_of(op.number) if dev else f"{op.device}{op.number}"
    return f"K{op.digits}{name}" if op.is_group else name


def check_operand_rules(module: Module, target: Target) -> list[Diagnostic]:
    rules = _rules(target.name)
    if not rules:
        return []
    out: list[Diagnostic] = []
    everything = [i for i in module.instrs if i.valid]
    instrs = [i for i in everything if i.spec.api is not None]
    for ins in instrs:
        for rule in rules.get(ins.spec.api, ()):
            check = _LINE_RULES.get(rule["kind"])
            if check is not None:
                out += check(ins, rule, target)
    for api, page in rules.items():
        for rule in page:
            check = _PROGRAM_RULES.get(rule["kind"])
            if check is not None:
                out += check([i for i in instrs if i.spec.api == api], everything, rule, target)
    return out


# ------------------------------------------------------------------ one instruction

def _ends_in_0(ins: Instr, rule: dict, target: Target) -> list[Diagnostic]:
    out = []
    for role in rule["operands"]:
        op, text = _operand(ins, role)
        if op is None or op.is_const:
            continue
        dev = target.devices.get(op.device)
        if dev is not None and op.number % dev.radix:
            out.append(_at(ins, "E230", f"{ins.mnemonic} operand {role} {text}: the device number must "
                           f"end in 0 ({rule['section']})"))
    return out


def _group(ins: Instr, rule: dict, target: Target) -> list[Diagnostic]:
    out = []
    digits = rule.get("digits32", rule["digits"]) if ins.spec.width == 32 else rule["digits"]
    step = rule.get("multiple_of", 1)
    for role in rule["operands"]:
        op, text = _operand(ins, role)
        if op is None or not op.is_group:
            continue
        if op.digits != digits or op.number % step:
            where = f" from a device number that is a multiple of {step}" if step > 1 else ""
            out.append(_at(ins, "E231", f"{ins.mnemonic} operand {role} {text}: a bit group here is "
                           f"K{digits}{op.device}{where} ({rule['section']})"))
    return out


def _pair(ins: Instr, rule: dict, target: Target) -> list[Diagnostic]:
    first, _ = _operand(ins, rule["if"])
    second, text = _operand(ins, rule["then"])
    if first is None or second is None or first.kind != rule["is"] or second.kind == rule["must"]:
        return []
    return [_at(ins, "E232", f"{ins.mnemonic}: {rule['if']} is a {rule['is']}, so {rule['then']} must be a "
                f"{rule['must']}, not {text} ({rule['section']})")]


def _same(ins: Instr, rule: dict, target: Target) -> list[Diagnostic]:
    op, text = _operand(ins, rule["then"])
    other, other_text = _operand(ins, rule["as"])
    if op is None or other is None or op.kind != rule["device"] or (op.kind, op.number) == (other.kind, other.number):
        return []
    return [_at(ins, "E232", f"{ins.mnemonic}: {rule['then']} {text} must be {rule['as']} {other_text} itself "
                f"({rule['section']})")]


def _n_by_device(ins: Instr, rule: dict, target: Target) -> list[Diagnostic]:
    dev, _ = _operand(ins, rule["device"])
    n, text = _operand(ins, rule["n"])
    if dev is None or n is None or not n.is_const or dev.is_const:
        return []
    allowed = rule["allowed"].get(_name(target, dev))
    if allowed is None or n.value in allowed:
        return []
    values = " or ".join(f"K{v}" for v in allowed)
    return [_at(ins, "E232", f"{ins.mnemonic} {_name(target, dev)} takes {rule['n']} = {values}, not {text} "
                f"({rule['section']})")]


def _not_above(ins: Instr, rule: dict, target: Target) -> list[Diagnostic]:
    low, low_text = _operand(ins, rule["low"])
    high, high_text = _operand(ins, rule["high"])
    if low is None or high is None or not (low.is_const and high.is_const) or low.is_float or high.is_float:
        return []
    if isinstance(low.value, str) or isinstance(high.value, str) or low.value <= high.value:
        return []
    return [_at(ins, "E232", f"{ins.mnemonic}: {rule['low']} {low_text} is above {rule['high']} {high_text} "
                f"({rule['section']})")]


def _model_range(ins: Instr, rule: dict, target: Target) -> list[Diagnostic]:
    op, text = _operand(ins, rule["operand"])
    span = rule["ranges"].get(target.model or "")
    if op is None or not op.is_const or span is None or isinstance(op.value, str):
        return []
    lo, hi = span
    if lo <= op.value <= hi:
        return []
    return [_at(ins, "E206", f"{ins.mnemonic} operand {rule['operand']}: {text} outside K{lo}..K{hi} on model "
                f"{target.model} ({rule['section']})")]


def _max_length(ins: Instr, rule: dict, target: Target) -> list[Diagnostic]:
    op, text = _operand(ins, rule["operand"])
    if op is None or op.kind != "$" or not isinstance(op.value, str) or len(op.value) <= rule["max"]:
        return []
    return [_at(ins, "E206", f"{ins.mnemonic} operand {rule['operand']}: {text} has {len(op.value)} "
                f"characters, more than {rule['max']} ({rule['section']})")]


_LINE_RULES = {"ends_in_0": _ends_in_0, "group": _group, "pair": _pair, "same": _same,
               "n_by_device": _n_by_device, "not_above": _not_above, "model_range": _model_range,
               "max_length": _max_length}


# ------------------------------------------------------------------ the whole program

def _one_user(users: list[Instr], instrs: list[Instr], rule: dict, target: Target) -> list[Diagnostic]:
    out = []
    first: dict[tuple[str, int], Instr] = {}
    for ins in users:
        for role in rule["operands"]:
            op, text = _operand(ins, role)
            if op is None or op.is_const:
                continue
            key = (op.kind, op.number)
            if key in first:
                f = first[key]
                out.append(_at(ins, "E233", f"{ins.mnemonic} {text}: already the output of {f.mnemonic} at "
                               f"line {f.line} ({rule['section']})"))
            else:
                first[key] = ins
    for other in rule.get("not_with", ()):
        for ins in instrs:
            if ins.spec.api not in other["fnc"]:
                continue
            op, text = _operand(ins, other["operand"])
            if op is not None and not op.is_const and (op.kind, op.number) in first:
                f = first[(op.kind, op.number)]
                out.append(_at(ins, "E233", f"{ins.mnemonic} {text}: already the output of {f.mnemonic} at "
                               f"line {f.line} ({rule['section']})"))
    return out


def _own_timer(users: list[Instr], instrs: list[Instr], rule: dict, target: Target) -> list[Diagnostic]:
    out = []
    for ins in users:
        timer, text = _operand(ins, rule["operand"])
        if timer is None or timer.is_const:
            continue
        for other in instrs:
            if other is ins:
                continue
            if any(op.kind == timer.kind and op.number == timer.number and not op.index for op in other.operands):
                out.append(_at(other, "W230", f"{other.mnemonic} uses {text}, the timer of {ins.mnemonic} at "
                               f"line {ins.line} ({rule['section']})"))
    return out


def _blocks_apart(users: list[Instr], instrs: list[Instr], rule: dict, target: Target) -> list[Diagnostic]:
    out = []
    for ins in users:
        first, first_text = _operand(ins, rule["first"])
        second, second_text = _operand(ins, rule["second"])
        m1, _ = _operand(ins, rule["m1"])
        m2, _ = _operand(ins, rule["m2"])
        if None in (first, second, m1, m2) or not (m1.is_const and m2.is_const):
            continue
        if first.is_const or second.is_const or first.is_group or second.is_group or first.kind != second.kind:
            continue
        size = m1.value * m2.value * (2 if ins.spec.width == 32 else 1)
        a, b = first.number, second.number
        if a != b and a < b + size and b < a + size:
            out.append(_at(ins, "E234", f"{ins.mnemonic}: the blocks of {first_text} and {second_text} "
                           f"({size} words each) overlap ({rule['section']})"))
    return out


def _counter_inputs(target: Target, number: int) -> list[int]:
    """The X ordinals a software high-speed counter counts from (target.toml
    [high_speed_counters]: its 1-phase, 2-phase or A/B pins, its reset and start inputs)."""
    table = target.settings.get("high_speed_counters", {})
    lo, hi = table.get("counters", (1, 0))
    if not lo <= number <= hi:
        return []
    pins: list[str] = []
    for key in ("inputs", "two_phase", "ab_phase", "reset", "start"):
        found = table.get(key, {}).get(str(number))
        pins += [found] if isinstance(found, str) else list(found or ())
    return [int(p[1:], 8) for p in pins if p.startswith("X")]


def _input_claims(ins: Instr, target: Target) -> list[tuple[int, str]]:
    """(X ordinal, what uses it) of the high-speed input functions an instruction uses: a
    high-speed counter it drives or compares, an external interrupt pointer IXnP/IXnF
    (numbered n x 100 + 1/0, target.toml [interrupts])."""
    out = []
    if ins.spec.op == "interrupt" and ins.operands:
        n = ins.operands[0].number
        if n % 100 in (0, 1) and n // 100 <= 7:
            out.append((n // 100, f"interrupt pointer IX{n // 100}{'P' if n % 100 else 'F'}"))
    for op in ins.operands:
        if op.kind == "C" and not op.index:
            out += [(x, f"high-speed counter C{op.number}") for x in _counter_inputs(target, op.number)]
    return out


def _own_input(users: list[Instr], instrs: list[Instr], rule: dict, target: Target) -> list[Diagnostic]:
    claims: dict[int, tuple[Instr, str]] = {}
    for ins in instrs:
        if ins.spec.api != rule["fnc"]:
            for x, what in _input_claims(ins, target):
                claims.setdefault(x, (ins, what))
    out = []
    for ins in users:
        op, text = _operand(ins, rule["operand"])
        if op is None or op.kind != "X":
            continue
        if op.number in claims:
            other, what = claims[op.number]
            out.append(_at(ins, "E235", f"{ins.mnemonic} {text}: the input is already used by {what} "
                           f"({other.mnemonic} at line {other.line}; {rule['section']})"))
        else:
            claims[op.number] = (ins, f"{ins.mnemonic}")
    return out


def _paired(users: list[Instr], instrs: list[Instr], rule: dict, target: Target) -> list[Diagnostic]:
    if not users or any(i.spec.api == rule["with"] for i in instrs):
        return []
    partner = rule["partner"]
    return [_at(ins, "W231", f"{ins.mnemonic} without a {partner} in the program ({rule['section']})")
            for ins in users]


def _no_reset(users: list[Instr], instrs: list[Instr], rule: dict, target: Target) -> list[Diagnostic]:
    if not users:
        return []
    relays = set(rule["relays"])
    return [_at(ins, "W232", f"RST M{ins.operands[0].number}: the PLC clears it itself when the send is "
                f"done ({rule['section']})")
            for ins in instrs if ins.mnemonic == "RST" and ins.operands and ins.operands[0].kind == "M"
            and ins.operands[0].number in relays and not ins.operands[0].index]


_PROGRAM_RULES = {"one_user": _one_user, "own_timer": _own_timer, "blocks_apart": _blocks_apart,
                  "own_input": _own_input, "paired": _paired, "no_reset": _no_reset}
