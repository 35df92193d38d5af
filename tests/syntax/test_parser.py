"""The IL grammar: statements, spans, error columns; the regex fast path equals lark."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from mlctool.syntax.operands import (
    DEFAULT_SYNTAX,
    Operand,
    OperandSyntaxError,
    format_operand,
    parse_operand,
)
from mlctool.syntax.parser import parse
from mlctool.syntax.source import decode


def _parse(text: str, fast: bool = True):
    src, diags = decode("t.il", text.encode())
    assert not diags
    return parse(src, fast=fast)


def _shape(pf):
    return [(s.line, s.kind, s.name.text, s.name.col, [(w.text, w.col) for w in s.operands],
             (s.step.text, s.step.col) if s.step else None) for s in pf.statements]


def test_forms_from_the_issue():
    pf = _parse("0000 LD X0\n000013,LD,X0\nP10\nP11:\n  mov  K10,D0  ; comment\nDLD= D0 K5 // c\n"
                ".define START X0\n\n; only a comment\nDAND<> D0 K1\n")
    assert _shape(pf) == [
        (1, "instr", "LD", 6, [("X0", 9)], ("0000", 1)),
        (2, "instr", "LD", 8, [("X0", 11)], ("000013", 1)),
        (3, "instr", "P10", 1, [], None),
        (4, "label", "P11", 1, [], None),
        (5, "instr", "mov", 3, [("K10", 8), ("D0", 12)], None),
        (6, "instr", "DLD=", 1, [("D0", 6), ("K5", 9)], None),
        (7, "directive", ".define", 1, [("START", 9), ("X0", 15)], None),
        (10, "instr", "DAND<>", 1, [("D0", 8), ("K1", 11)], None),
    ]
    assert pf.diagnostics == []


def test_full_width_separators_and_tabs():
    pf = _parse("LD\tX0\nMOV\u3000K1\uff0cD0\n")
    assert [[w.text for w in s.operands] for s in pf.statements] == [["X0"], ["K1", "D0"]]


def test_syntax_error_column_and_recovery():
    pf = _parse("LD X0\nOUT Y0 @\nLD X1\nP1: X\n:\nOUT Y1\n")
    got = [(d.code, d.span.line, d.span.col) for d in pf.diagnostics]
    assert got == [("E103", 2, 8), ("E103", 4, 5), ("E103", 5, 1)]
    assert "expected" in pf.diagnostics[0].message
    assert [s.line for s in pf.statements] == [1, 3, 6]


def test_noqa_comments():
    pf = _parse("OUT Y0 ; mlc: noqa W401, W402\nOUT Y0 // mlc: noqa\nOUT Y0 ; noqa\n")
    assert pf.noqa == {1: frozenset({"W401", "W402"}), 2: None}


# -- fast path == lark on arbitrary lines ------------------------------------------------
PIECES = ["LD", "ld", "DLD=", "AND<>", "OR>=", "X0", "K-5", "F1.5", "D5V0", "P10", ":", ",", " ",
          "\t", ";c", "//c", "0000", "12", ".define", "@", "=", "<", "\u3000", "K2M0Z1", "A_B"]


@settings(max_examples=400, deadline=None)
@given(st.lists(st.lists(st.sampled_from(PIECES), max_size=8).map("".join), max_size=12))
def test_fast_path_matches_lark(lines):
    text = "\n".join(lines) + "\n"
    fast, slow = _parse(text, True), _parse(text, False)
    assert _shape(fast) == _shape(slow)
    assert [(d.code, d.span) for d in fast.diagnostics] == [(d.code, d.span) for d in slow.diagnostics]


# lines shaped like statements (the fast path's labels and directives included), with the
# pieces that could make the regexes and lark's lexer part ways
SEPS = st.sampled_from(["", " ", "\t", ",", " , ", "\u3000", "\uff0c"])
NAMES = st.sampled_from(["LD", "P10", "DLD<>", "AB-", "AB-1", "$MOV", "\u7dca\u6025", ".define", ".export",
                         ".library", ".d_1", ".", "..x", "x.", "12"])
WORDS = st.sampled_from(["X0", "START", "P1", ".x", "K-5", '"a b"', '"', "1", ":", "@", "=", "\u7dca"])


@st.composite
def statement_lines(draw):
    step = draw(st.sampled_from(["", "0000", "12"]))
    line = draw(SEPS) + (step + draw(SEPS) if step else "") + draw(NAMES)
    for _ in range(draw(st.integers(0, 3))):
        line += draw(SEPS) + draw(WORDS)
    line += draw(st.sampled_from(["", ":", " :", ": ", ":X"])) + draw(SEPS)
    return line + draw(st.sampled_from(["", ";c", "// c", ";:"]))


@settings(max_examples=400, deadline=None)
@given(st.lists(statement_lines(), max_size=10))
def test_fast_path_matches_lark_on_statement_shapes(lines):
    text = "\n".join(lines) + "\n"
    fast, slow = _parse(text, True), _parse(text, False)
    assert _shape(fast) == _shape(slow)
    assert [(d.code, d.span) for d in fast.diagnostics] == [(d.code, d.span) for d in slow.diagnostics]


def test_usual_files_need_no_lark():
    import subprocess
    import sys

    code = ("import sys\nfrom mlctool.syntax.parser import parse\nfrom mlctool.syntax.source import decode\n"
            "src, _ = decode('t.il', b'.define A X0\\n0000 P10:\\nP11 :  ; c\\nLD A\\n.export P10\\nEND\\n')\n"
            "pf = parse(src)\nassert [s.kind for s in pf.statements] == "
            "['directive', 'label', 'label', 'instr', 'directive', 'instr'], pf.statements\n"
            "assert 'lark' not in sys.modules\n")
    subprocess.run([sys.executable, "-c", code], check=True)


# -- operands ----------------------------------------------------------------------------
def test_operand_forms():
    assert parse_operand("d5v0") == Operand("D", number=5, index=("V", 0))
    assert parse_operand("K20V0") == Operand("K", value=20, index=("V", 0))
    assert parse_operand("K2M0Z1") == Operand("KnM", number=0, digits=2, index=("Z", 1))
    assert parse_operand("F12.3") == Operand("F", value=12.3, decimals=1)
    assert parse_operand("K-32768").value == -32768
    assert parse_operand("P255") == Operand("P", number=255)


def test_operand_errors_are_helpful():
    for text, needle in [("10", "K prefix"), ("H1F", "no hexadecimal"), ("X", "not a device"), ("K1.5", "not a device")]:
        try:
            parse_operand(text)
        except OperandSyntaxError as e:
            assert needle in str(e), (text, str(e))
        else:
            raise AssertionError(text)


def test_indexed_bit_of_word_is_named_as_such():
    """VS 5-1: D.b and R.b may not be index-modified; D0.1Z0 and D0Z0.1 say so (they were
    'undefined symbol'), on a target with bit operands only."""
    from mlctool.targetapi import load_target

    vs = load_target("vs").operand_syntax
    for text in ("D0.1Z0", "d0z0.1", "R5.FV1"):
        try:
            parse_operand(text, vs)
        except OperandSyntaxError as e:
            assert "bit of a word (D.b/R.b) cannot be index-modified" in str(e), (text, str(e))
        else:
            raise AssertionError(text)
    assert parse_operand("D0.1", vs).bit == 1
    nc5 = load_target("nc5").operand_syntax  # no bit operands: not this message
    try:
        parse_operand("D0.1Z0", nc5)
    except OperandSyntaxError as e:
        assert "index-modified" not in str(e)


@given(st.sampled_from(["X0", "Y17", "M65535", "D5V0", "K-7", "K20Z3", "K4Y0", "K8M100V2", "F1.250", "F-3", "P7", "T255"]))
def test_format_round_trip(text):
    op = parse_operand(text)
    assert parse_operand(format_operand(op)) == op


# -- the operand shortcut == every form in order -----------------------------------------
OPERAND_PIECES = st.sampled_from(list("KHFEUGDMXYTCVZSPRNIW0123456789.+-\"") + ["EC1D", "U1", "K4", "D0", "10"])


@settings(max_examples=600, deadline=None)
@given(st.lists(OPERAND_PIECES, min_size=1, max_size=6).map("".join), st.booleans())
def test_operand_shortcut_matches_the_full_parse(text, lower):
    from mlctool.syntax.operands import full_parse_operand
    from mlctool.targetapi import available_targets, load_target

    text = text.lower() if lower else text
    for name in available_targets():
        syntax = load_target(name).operand_syntax
        try:
            want = full_parse_operand(text, syntax)
        except OperandSyntaxError as e:
            want = str(e)
        try:
            got = parse_operand.__wrapped__(text, syntax)
        except OperandSyntaxError as e:
            got = str(e)
        assert got == want, (name, text)


def test_plain_devices_are_whole_operands():
    """parse_operand builds plain devices and K constants without Operand's __init__
    (operands._device, _k_constant): every field is set, and the object is the one __init__
    builds (equal, same hash, same repr)."""
    import dataclasses

    from mlctool.targetapi import load_target

    vs = load_target("vs").operand_syntax  # octal X/Y
    for text, syntax, want in [("M1005", DEFAULT_SYNTAX, Operand("M", number=1005)),
                               ("d5v1", DEFAULT_SYNTAX, Operand("D", number=5, index=("V", 1))),
                               ("X17", vs, Operand("X", number=15, radix=8)),
                               ("K105", DEFAULT_SYNTAX, Operand("K", value=105)),
                               ("k007", vs, Operand("K", value=7))]:
        got = parse_operand.__wrapped__(text, syntax)
        assert type(got) is Operand
        assert [getattr(got, f.name) for f in dataclasses.fields(Operand)] == \
            [getattr(want, f.name) for f in dataclasses.fields(Operand)]
        assert got == want and hash(got) == hash(want) and repr(got) == repr(want)


def test_plain_lines_read_as_the_regexes_read_them(monkeypatch):
    """The plainest lines (`MOV K10 D0`: one space between words) are split at their spaces
    (parser._plain_line); the statements are those of the instruction regex's reading."""
    import random

    from progen import random_program

    from mlctool.syntax import parser
    from mlctool.syntax.source import SourceText
    from mlctool.targetapi import load_target

    lines = ["LD X0", "MOV K10 D0", "LD= D0 K-5", "$MOV \"a b\" D0", "OUT  Y0", "ld x0 ; c", "AND<> D0 D1",
             "DMOV K70000 D0", "OUT Y0 ", " OUT Y0", "LD X0,X1", "MOVP F1.5 D0", "LD\tX0"]
    for name in ("nc5", "vs"):
        lines += random_program(random.Random(name), load_target(name), 300)
    src = SourceText("t.il", "\n".join(lines) + "\n")
    taken = []
    real = parser._plain_line()
    monkeypatch.setattr(parser, "_plain_line", lambda: lambda text: taken.append(text) or real(text))
    split = parse(src)
    monkeypatch.setattr(parser, "_plain_line", lambda: lambda text: None)
    assert split.statements == parse(src).statements
    assert sum(real(t) is not None for t in taken) > 200  # the split is taken
