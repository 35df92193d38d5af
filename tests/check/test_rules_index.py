"""The rules that visit only the instructions of the forms they look for (program.FormIndex)
find what a walk over every instruction finds: the walks of the former code are kept here
as references and compared on generated programs (issue 19 §2: the speed of checking)."""

from __future__ import annotations

import random

import pytest
from progen import random_program

from mlctool.check import check_texts
from mlctool.check.lint import (
    _at,
    _dead_code,
    double_coils,
    exclusive_regions,
    referenced_labels,
    set_without_reset,
)
from mlctool.program import FormIndex
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target


def _walked_dead_code(instrs):
    out, dead = [], False
    for ins in instrs:
        if ins.spec.cls in ("label", "interrupt"):
            dead = False
        elif dead and ins.spec.op not in ("end", "fend", "nop"):
            out.append(_at(ins, None, "W406", f"{ins.mnemonic} is never executed: it follows FEND/SRET/IRET "
                           "and no label"))
            dead = False
        if ins.spec.op in ("fend", "sret", "iret"):
            dead = True
    return out


def _walked_double_coils(instrs):
    seen, out = {}, []
    for ins, region in zip(instrs, exclusive_regions(instrs), strict=True):
        o = ins.operands
        if ins.spec.op != "out" or o[0].index:
            continue
        by_region = seen.setdefault((o[0].kind, o[0].number), {})
        f = by_region.get(region) or (None if region else next(iter(by_region.values()), None)) \
            or by_region.get(0)
        if f is not None:
            out.append(_at(ins, None, "W401", f"{ins.texts[0]} is also driven at {f.file}:{f.line}; "
                           "the last OUT in the scan wins (1.3.2)"))
        by_region.setdefault(region, ins)
    return out


def _walked_set_without_reset(instrs):
    reset, ranges = set(), []
    for ins in instrs:
        if ins.spec.op in ("rst", "out", "alt", "pls", "plf") and not ins.operands[0].index:
            reset.add((ins.operands[0].kind, ins.operands[0].number))
        elif ins.spec.op == "zrst":
            a, b = ins.operands
            ranges.append((a.kind, min(a.number, b.number), max(a.number, b.number)))
        elif ins.spec.api is not None:
            for o, s in zip(ins.operands, ins.spec.operands, strict=False):
                if s.writes:
                    reset.add((o.kind, o.number))
                    if o.is_group:
                        ranges.append((o.device, o.number, o.number + 4 * o.digits - 1))
    out, seen = [], set()
    for ins in instrs:
        if ins.spec.op == "set" and not ins.operands[0].index:
            key = (ins.operands[0].kind, ins.operands[0].number)
            if key in reset or key in seen or any(k == key[0] and lo <= key[1] <= hi for k, lo, hi in ranges):
                continue
            seen.add(key)
            out.append(_at(ins, None, "W405", f"{ins.texts[0]} is SET but never reset"))
    return out


# STL/RET, SET/RST, FEND/SRET/NOP lines often, so each rule has something to find
EXTRA = ["STL S20", "STL S21", "RET", "SET Y0", "SET M5", "RST M5", "ZRST M0 M9", "FEND", "SRET", "NOP",
         "IRET", "END", "OUT Y0", "OUT Y1", "P5:"]


@pytest.mark.parametrize("name", ["nc5", "vs", "fbs"])
def test_indexed_rules_find_what_a_walk_finds(name):
    target = load_target(name)
    rnd = random.Random(name)
    found = 0
    for _ in range(15):
        lines = [rnd.choice(EXTRA) if rnd.random() < 0.3 else line
                 for line in random_program(rnd, target, rnd.randint(50, 300))]
        module = check_texts([SourceText("gen.il", "\n".join(lines) + "\n")], target).modules[0]
        instrs = [i for i in module.instrs if i.valid]
        forms = FormIndex(instrs)
        assert _dead_code(instrs, forms) == _walked_dead_code(instrs)
        assert double_coils(instrs, forms=forms) == _walked_double_coils(instrs)
        module.instrs = instrs
        assert set_without_reset([module]) == _walked_set_without_reset(instrs)
        assert set_without_reset([module], [forms]) == _walked_set_without_reset(instrs)
        assert referenced_labels([module], [forms]) == referenced_labels([module])
        for ops in [("out",), ("fend", "sret", "iret"), ("nothing",)]:
            assert forms.where(ops=ops) == [k for k, i in enumerate(instrs) if i.spec.op in ops]
        assert forms.where(classes=("label",)) == [k for k, i in enumerate(instrs) if i.spec.cls == "label"]
        found += len(_walked_dead_code(instrs)) + len(_walked_double_coils(instrs)) \
            + len(_walked_set_without_reset(instrs))
    assert found > 20  # the comparisons compare findings, not empty lists
