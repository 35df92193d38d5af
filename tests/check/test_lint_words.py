"""W403 and W404 as issue 16 #5 asks: the registers a multi-word result occupies (the 32-bit
product of a 16-bit MUL, quotient and remainder of DIV) count as that instruction's, and an
unused label is named as written, not by the P number mlctool gave it."""

from __future__ import annotations

import pytest

from mlctool.check import check_texts
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target


def _warnings(text: str, target: str, code: str) -> list[tuple[int, str]]:
    r = check_texts([SourceText("t.il", text)], load_target(target))
    assert not r.errors, [(d.span.line, d.code, d.message) for d in r.diagnostics]
    return [(d.span.line, d.message) for d in r.diagnostics if d.code == code]


@pytest.mark.parametrize("target", ["nc5", "vs"])
@pytest.mark.parametrize("text,line,words", [
    ("LD X0\nMUL D0 K10 D10\nLD X1\nMOV D11 D20\nEND\n", 4, "(D11, D10)"),   # the product's high word
    ("LD X0\nMOV K1 D11\nLD X1\nMUL D0 K10 D10\nEND\n", 4, "(D11, D10)"),   # written before
    ("LD X0\nDIV D0 K3 D30\nLD X1\nMOV K1 D31\nEND\n", 4, "(D31, D30)"),    # DIV's remainder
    ("LD X0\nDMUL D0 D2 D10\nLD X1\nMOV K1 D13\nEND\n", 4, "D10-D13"),       # the 64-bit product
    ("LD X0\nMUL D0 K10 D10\nLD X1\nDMOV K1 D11\nEND\n", 4, "(D11, D10)"),  # two spans overlap
])
def test_w403_sees_every_register_of_a_result(target, text, line, words):
    got = _warnings(text, target, "W403")
    assert [ln for ln, _ in got] == [line] and words in got[0][1], got


@pytest.mark.parametrize("target", ["nc5", "vs"])
def test_w403_leaves_disjoint_uses_alone(target):
    text = "LD X0\nMUL D0 K10 D10\nLD X1\nMOV D10 D20\nMOV K1 D12\nEND\n"
    assert _warnings(text, target, "W403") == []


def test_w404_names_a_named_label_as_written():
    text = "LD X0\nOUT Y0\nFILL_DONE:\nLD X1\nOUT Y1\nEND\n"
    got = _warnings(text, "vs", "W404")
    assert got == [(3, "FILL_DONE is never the target of CJ or CALL")]
    assert "P10" not in got[0][1]


@pytest.mark.parametrize("target", ["nc5", "vs"])
def test_w404_names_a_p_label_as_written(target):
    assert _warnings("LD X0\nOUT Y0\nP7:\nEND\n", target, "W404") == [(3, "P7 is never the target of CJ or CALL")]
