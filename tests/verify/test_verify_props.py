"""The property language of `mlc verify` (docs/verify.md): statements, expressions,
assumptions, and every kind of bad input as a diagnostic at its line and column."""

from __future__ import annotations

import pytest

from mlctool.targetapi import load_target
from mlctool.verify.props import And, Atom, Not, Or, evaluate, parse_props_text
from mlctool.verify.space import SpaceError, input_space

NC5 = load_target("nc5")
SYMBOLS = {"MOTOR": "Y0", "BUSY": "M1", "START": "X0"}


def parse(text: str):
    return parse_props_text("p.props", text, NC5, SYMBOLS)


def test_statements_and_expressions():
    p, diags = parse("scan 20ms\nilk: never MOTOR and BUSY\nalways not (Y0 and Y1) or D0 >= 5\n"
                     "response X5 -> not Y0 within 2 scans\nresponse X5 -> Y0=0 within 100ms\n"
                     "reachable D0=1..3\nstable Y0 for 3 scans   # no chattering\n")
    assert diags == []
    assert p.scan_us == 20_000
    kinds = [(q.kind, q.name, q.line) for q in p.properties]
    assert kinds == [("never", "ilk", 2), ("always", "line 3", 3), ("response", "line 4", 4),
                     ("response", "line 5", 5), ("reachable", "line 6", 6), ("stable", "line 7", 7)]
    ilk = p.properties[0].expr
    assert isinstance(ilk, And) and [a.view.name for a in ilk.args] == ["Y0", "M1"]
    assert isinstance(p.properties[1].expr, Or) and isinstance(p.properties[1].expr.args[0], Not)
    assert p.properties[2].scans == 2 and p.properties[3].time_us == 100_000
    rng = p.properties[4].expr
    assert isinstance(rng, Atom) and rng.op == "range" and rng.value == (1, 3)
    values = {"Y0": 1, "Y1": 0, "D0": 2}
    assert evaluate(p.properties[1].expr, lambda v: values[v.name])
    assert evaluate(rng, lambda v: values[v.name])


def test_assumptions():
    p, diags = parse("assume free X0 X1 X2\nassume constant X3\nassume X2=0\nassume onehot X0 X1\n"
                     "assume D100 in 0..3\nassume D101 in {1, 5}\nassume hold X0 for 3 scans\n"
                     "assume initial M0=1 D5=7\nassume not (X0 and X3)\n")
    assert diags == []
    space = input_space(p, [])
    names = [i.view.name for i in space.inputs]
    assert names == ["X0", "X1", "X2", "X3", "D100", "D101"]
    k = {n: j for j, n in enumerate(names)}
    assert {v[k["X2"]] for v in space.vectors} == {0}
    assert all(v[k["X0"]] + v[k["X1"]] == 1 for v in space.vectors)
    assert not any(v[k["X0"]] and v[k["X3"]] for v in space.vectors)
    assert {v[k["D101"]] for v in space.vectors} == {1, 5}
    assert len(space.vectors) == 2 * 2 * 4 * 2 - 4 * 2  # onehot: 2 of X0/X1; X3 excluded with X0
    assert space.constant == (k["X3"],) and space.holds == ((k["X0"], 3),)
    assert [(v.name, x) for v, x in space.initial] == [("M0", 1), ("D5", 7)]


@pytest.mark.parametrize("text,code,line,col", [
    ("never MOTR and BUSY\n", "E701", 1, 7),             # did you mean MOTOR
    ("always Y0 and\n", "E700", 1, 14),                   # ends too soon
    ("always (Y0 or Y1\n", "E700", 1, 17),
    ("nevr Y0\n", "E700", 1, 1),                          # did you mean never
    ("response X0 -> Y0\n", "E700", 1, 1),                 # no `within`
    ("stable Y0 for 0 scans\n", "E700", 1, 15),
    ("always D0 < 70000\n", "E700", 1, 13),               # outside the device's range
    ("assume X0=0\nassume X0=1\n", "E702", 2, 8),          # contradicts line 1
    ("assume D0 in 5..1\n", "E702", 1, 14),                # empty range
    ("assume initial M0=1 M0=0\n", "E702", 1, 21),
    ("assume free Y0\n", "E700", 1, 13),                   # not an input
    ("assume D0 > 3\n", "E700", 1, 8),                     # a word input needs a range or set
    ("scan 0ms\n", "E700", 1, 6),
    ("always X0 ==\n", "E700", 1, 12),
])
def test_bad_input_is_a_diagnostic(text, code, line, col):
    _, diags = parse(text)
    assert diags, text
    d = diags[0]
    assert (d.code, d.span.line, d.span.col) == (code, line, col), d


def test_unknown_device_suggests_a_symbol():
    _, diags = parse("never MOTR and BUSY\n")
    assert "did you mean 'MOTOR'" in diags[0].message


def test_contradictory_constraints_name_the_line():
    p, diags = parse("assume onehot X0 X1\nassume not X0\nassume not X1\n")
    assert diags == []
    with pytest.raises(SpaceError) as e:
        input_space(p, [])
    d = e.value.diagnostic
    assert (d.code, d.span.line) == ("E702", 3)
