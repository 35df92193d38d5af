"""Steps of a written instruction (target.toml [[step_rules]] and the "1~2" short rule):
Target.step_spans, which the checker keeps per form and kind, gives what the rules say."""

from __future__ import annotations

import pytest

from mlctool.syntax.operands import Operand
from mlctool.targetapi import load_target


def _steps_by_the_rules(t, spec, op) -> int:
    """instr_steps as target.toml states it, rule by rule (the reference for step_spans)."""
    for rule in t.settings.get("step_rules", ()):
        if spec.op in rule["ops"] and op.kind in rule["kinds"] and rule.get("lo", 0) <= op.number <= rule.get("hi", 1 << 31):
            return rule["steps"]
    if spec.short_steps:
        short = t.settings.get("short_operand", {}).get(op.kind)
        return 1 if short is not None and short[0] <= op.number <= short[1] else 2
    return spec.steps


@pytest.mark.parametrize("name", ["nc5", "vs", "fbs"])
def test_step_spans_give_the_rules_steps(name):
    """Target.step_spans (kept per form and kind by the checker) and instr_steps give the
    steps of the [[step_rules]] and the short rule for every form, kind and boundary number."""
    target = load_target(name)
    edges = {0, 1, 1 << 31}
    for rng in target.settings.get("short_operand", {}).values():
        edges |= {rng[0] - 1, rng[0], rng[1], rng[1] + 1}
    for rule in target.settings.get("step_rules", ()):
        edges |= {rule.get("lo", 0) - 1, rule.get("lo", 0), rule.get("hi", 0), rule.get("hi", 0) + 1}
    compared = 0
    for spec in set(target.instructions.values()):
        kinds = {k for o in spec.operands[:1] for k in o.kinds} | {"D.b", "K"}
        for kind in sorted(kinds):
            for n in sorted(e for e in edges if e >= 0):
                op = Operand(kind, number=n)
                assert target.instr_steps(spec, (op,)) == _steps_by_the_rules(target, spec, op), (spec.mnemonic, kind, n)
                compared += 1
        assert target.instr_steps(spec, ()) == spec.steps
    assert compared > 300


def test_load_target_gives_one_target_however_the_call_spells_it():
    """load_target's cache: the default model spelled three ways, and a model in either case,
    give the same Target object (a second copy would be parsed again and compared unequal
    by identity in the caches keyed on it)."""
    assert load_target("vs") is load_target("vs", None) is load_target("vs", model=None)
    assert load_target("vs", "vs1") is load_target("vs", "VS1")
    assert load_target("vs", "VS1") is not load_target("vs")
