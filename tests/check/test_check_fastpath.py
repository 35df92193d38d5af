"""The checker's fast yes for plain device operands (resolve.plainly_legal) never says yes
where the full operand check (check_operand) would report anything."""

from __future__ import annotations

import pytest

from mlctool.check.resolve import _Arg, _Resolver
from mlctool.syntax.operands import Operand
from mlctool.syntax.parser import ParsedFile
from mlctool.targetapi import load_target


def _numbers(dev) -> set[int]:
    """Every boundary of the device's range and areas, and its neighbours."""
    edges = {dev.lo, dev.hi} | {x for a in dev.areas for x in (a.lo, a.hi)}
    return {n + d for n in edges for d in (-2, -1, 0, 1, 2) if dev.lo <= n + d <= dev.hi}


@pytest.mark.parametrize("name", ["nc5", "vs", "fbs"])
def test_fast_yes_agrees_with_the_full_check(name):
    target = load_target(name)
    r = _Resolver(ParsedFile("t.il", [], [], []), target)
    compared = yes = 0
    for spec in sorted(set(target.instructions.values()), key=lambda s: s.mnemonic):
        for k, o in enumerate(spec.operands):
            if o.word_range_of:
                continue
            for kind in sorted(o.kinds):
                dev = target.devices.get(kind)
                if dev is None or dev.kind == "pointer":
                    continue
                for n in sorted(_numbers(dev)):
                    op = Operand(kind, number=n)
                    yes += _fast_yes_holds(r, spec, k, o, op, f"{kind}{n}", r.plainly_legal(spec, k, o, op))
                    compared += 1
    assert compared > 1000 and yes > 100  # the fast path is taken, and only where it may be


def _fast_yes_holds(r, spec, k, o, op, text: str, fast: bool) -> bool:
    """A fast path's yes for operand k is a yes of the full check_operand, with nothing reported."""
    r._problems = []
    full = r.check_operand(spec, o, op, _Arg(k, text), [op] * len(spec.operands))
    if fast:
        assert full and not r._problems, (spec.mnemonic, k, text, r._problems)
    return fast


@pytest.mark.parametrize("name", ["nc5", "vs", "fbs"])
def test_fast_yes_for_constants_agrees_with_the_full_check(name):
    """plain_line's yes for a K or H constant (legal_values) is never a constant that
    check_operand would report anything about."""
    target = load_target(name)
    r = _Resolver(ParsedFile("t.il", [], [], []), target)
    compared = yes = 0
    for spec in sorted(set(target.instructions.values()), key=lambda s: s.mnemonic):
        for k, o in enumerate(spec.operands):
            for kind in ("K", "H"):
                spans = r.plain_spans(spec, o, kind)
                edges = {v + d for lo, hi in spans for v in (lo, hi) for d in (-1, 0, 1)} | {0, 1, -1, 70000}
                for v in sorted(edges):
                    if kind == "H" and v < 0:
                        continue
                    op = Operand(kind, value=v)
                    yes += _fast_yes_holds(r, spec, k, o, op, f"{kind}{v}", any(lo <= v <= hi for lo, hi in spans))
                    compared += 1
    assert compared > 200 and yes > 30, (compared, yes)
