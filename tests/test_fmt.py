"""`mlc fmt`: canonical layout, idempotent, code unchanged."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mlctool.check.resolve import resolve
from mlctool.syntax.layout import FormatOptions, format_source
from mlctool.syntax.parser import parse
from mlctool.syntax.source import decode
from mlctool.targets import load_target
from tests.conftest import SAMPLES

NC5 = load_target("nc5")


def _fmt(text: str, steps: str = "drop") -> str:
    out, diags = format_source(decode("f.il", text.encode())[0], NC5, FormatOptions(steps))
    assert not diags
    return out


def _code(text: str):
    """What the assembler sees: instructions with operands, steps and addresses."""
    module, _ = resolve(parse(decode("f.il", text.encode())[0]), NC5)
    return [(i.mnemonic, i.operands, i.steps, i.addr, i.table) for i in module.instrs]


MESSY = """; conveyor
.define START X0
0000 ld start   ; start button
ani m1
out y0
// second rung
ld x1
tmr t0,k50
P10:
ld t0
out y1 // motor


mov k10 d0
END
"""


def test_canonical_layout():
    assert _fmt(MESSY) == """; conveyor
.define START X0
LD      start                           ; start button
ANI     M1
OUT     Y0

// second rung
LD      X1
TMR     T0 K50

P10:
LD      T0
OUT     Y1                              // motor

MOV     K10 D0
END
"""


def test_steps_renumbered_and_kept():
    out = _fmt(MESSY, "renumber")
    assert "00000 LD      start" in out and "00008 LD      T0" in out and "00014 END" in out
    assert _fmt(out, "keep") == out
    assert "0000 LD" not in _fmt("0000 ld x0\nout y0\nend\n")


def _samples():
    return sorted(p for p in SAMPLES.rglob("*.il"))


@pytest.mark.parametrize("path", _samples(), ids=lambda p: str(p.relative_to(SAMPLES)))
def test_samples_idempotent_and_code_unchanged(path: Path):
    text = path.read_text("utf-8")
    once = _fmt(text)
    assert _fmt(once) == once
    assert _code(once) == _code(text)


RUNG_LINES = st.sampled_from(["ld x0", "LDI M1 ; c", "and x2", "or m3", "ANB", "ORB", "mps", "mrd", "mpp",
                              "out y0", "SET M5 // s", "mov k1,d0", "dmov k70000 d2", "P3", "P4:",
                              "; comment", "", "   ", "cj p3", "fend", "ld= d0 k5", "0007 inc d1"])


@settings(max_examples=200, deadline=None)
@given(st.lists(RUNG_LINES, max_size=30))
def test_generated_idempotent_and_code_unchanged(lines):
    text = "\n".join(lines) + "\nEND\n"
    once = _fmt(text)
    assert _fmt(once) == once
    assert _code(once) == _code(text)


def test_cli_check_and_syntax_errors(mlc, tmp_path):
    p = tmp_path / "a.il"
    p.write_text(MESSY)
    r = mlc("fmt", "--check", str(p))
    assert r.code == 1 and "+LD      start" in r.out and p.read_text() == MESSY
    assert mlc("fmt", str(p)).code == 0
    assert mlc("fmt", "--check", str(p)).code == 0
    bad = tmp_path / "bad.il"
    bad.write_text("LD X0 @\nEND\n")
    r = mlc("fmt", str(bad))
    assert r.code == 1 and "E103" in r.err and bad.read_text() == "LD X0 @\nEND\n"
