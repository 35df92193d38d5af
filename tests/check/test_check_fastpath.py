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
                    fast = r.plainly_legal(spec, k, o, op)
                    r._problems = []
                    full = r.check_operand(spec, o, op, _Arg(k, f"{kind}{n}"), [op] * len(spec.operands))
                    yes += fast
                    if fast:
                        assert full and not r._problems, (spec.mnemonic, k, kind, n, r._problems)
                    compared += 1
    assert compared > 1000 and yes > 100  # the fast path is taken, and only where it may be
