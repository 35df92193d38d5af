"""Generic mechanisms the FX-family dialects need (issue 8), independent of any target's tables:
octal device numbers, bit-of-word operands, H/E/string constants, pulse forms, variants,
per-model availability and the step convention."""

from __future__ import annotations

import pytest

from mlctool.syntax.operands import (
    DEFAULT_SYNTAX,
    OperandSyntax,
    OperandSyntaxError,
    format_operand,
    parse_operand,
)
from mlctool.targetapi.model import _instructions, choose_variant

FX = OperandSyntax(octal=frozenset("XY"), hex_constants=True, float_prefix="E", float_exponent=True,
                   strings=True, bit_of_word=frozenset("DR"))


@pytest.mark.parametrize("text, number", [("X0", 0), ("X7", 7), ("X10", 8), ("Y377", 255), ("K4X20", 16)])
def test_octal_numbers_are_ordinals(text, number):
    op = parse_operand(text, FX)
    assert op.number == number and op.radix == 8
    assert format_operand(op) == text


@pytest.mark.parametrize("text", ["X8", "Y19", "K2X18"])
def test_octal_digits_8_and_9_do_not_exist(text):
    with pytest.raises(OperandSyntaxError, match="octal"):
        parse_operand(text, FX)


def test_decimal_kinds_stay_decimal_under_an_octal_syntax():
    assert parse_operand("M18", FX).number == 18
    assert parse_operand("X18", DEFAULT_SYNTAX).number == 18  # NC5: X is decimal


def test_bit_of_word():
    op = parse_operand("D100.F", FX)
    assert (op.kind, op.device, op.number, op.bit, op.is_bit_of_word) == ("D.b", "D", 100, 15, True)
    assert format_operand(parse_operand("r5.a", FX)) == "R5.A"
    with pytest.raises(OperandSyntaxError):
        parse_operand("M0.1", FX)  # only word kinds the target names
    with pytest.raises(OperandSyntaxError):
        parse_operand("D0.5")  # not on targets without bit operands (NC5)


def test_hex_float_and_string_constants():
    assert parse_operand("H7FFF", FX).value == 0x7FFF
    assert parse_operand("H10Z0", FX).index == ("Z", 0)
    assert parse_operand("E1.0235+2", FX).value == pytest.approx(102.35)
    assert parse_operand("E-0.5", FX).value == -0.5
    assert parse_operand('"AB C"', FX).value == "AB C"
    for text in ("H1F", "E1.0235+2", "E-0.5", '"x"'):
        op = parse_operand(text, FX)
        assert parse_operand(format_operand(op), FX).value == op.value


def test_nc5_keeps_rejecting_h_with_its_hint():
    for text in ("H1F", "H10"):
        with pytest.raises(OperandSyntaxError, match="no hexadecimal H constants; write K"):
            parse_operand(text)
    with pytest.raises(OperandSyntaxError):
        parse_operand('"AB"')


ENTRIES = [
    {"names": ["OUT", ""], "steps": [1, 0], "class": "output", "op": "out", "section": "t",
     "operands": [{"role": "D", "kinds": "Y M"}]},
    {"names": ["OUT", ""], "steps": [3, 0], "class": "output", "op": "tmr", "section": "t",
     "operands": [{"role": "D", "kinds": "T"}, {"role": "K", "kinds": "K D"}]},
    {"names": ["MOV", "DMOV"], "class": "output", "op": "mov", "section": "t", "pulse": True,
     "models": ["B"], "operands": [{"role": "S", "kinds": "K D"}, {"role": "D", "kinds": "D"}]},
]


def test_pulse_forms_variants_and_step_convention():
    first, variants = _instructions(ENTRIES, {"base": 1, "operand16": 2, "operand32": 4})
    assert sorted(first) == ["DMOV", "DMOVP", "MOV", "MOVP", "OUT"]
    assert first["MOVP"].pulse and not first["MOV"].pulse
    assert (first["MOV"].steps, first["DMOVP"].steps) == (5, 9)  # 1 + 2 x 2, 1 + 4 x 2
    assert first["MOV"].models == frozenset({"B"})
    outs = variants["OUT"]
    assert choose_variant(outs, 2, parse_operand("T0")).op == "tmr"
    assert choose_variant(outs, 1, parse_operand("Y0")).op == "out"
    assert choose_variant(outs, 1, parse_operand("T0")).op == "tmr"  # wrong count: T's variant explains


def test_steps_required_without_a_convention():
    with pytest.raises(KeyError):
        _instructions([dict(ENTRIES[2])])
