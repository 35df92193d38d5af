"""FBs positioning language (manual 001 ch. 11): every statement form, every static error
code with line/column, the register-table layout and round trips text <-> table."""

from __future__ import annotations

from pathlib import Path

import pytest

from mlctool.codes import CODES
from mlctool.targets.fbs.image import ImageError, parse_sr, read_image, to_csv, to_json
from mlctool.targets.fbs.lang import normalize, parse_program
from mlctool.targets.fbs.model import BLANK, NEXT, Cond, Motion, Val, tables
from mlctool.targets.fbs.table import TableError, decode, encode, program_text

ROOT = Path(__file__).resolve().parents[3]
SAMPLES = ROOT / "samples" / "fbs"
HSPSO = tables().dialects["hspso"]
MHSPO = tables().dialects["mhspo"]


def parse(text: str, dialect=HSPSO):
    return parse_program("t.pos", text, dialect)


def codes(text: str, dialect=HSPSO):
    return [(d.code, d.span.line, d.span.col) for d in parse(text, dialect)[1]]


def one_step(motion: str, cond: str = "", end: str = "MEND", spd: str = "1000") -> str:
    return f"001 SPD {spd}\n {motion}\n" + (f" {cond}\n" if cond else "") + f" {end}\n"


# ---------------------------------------------------------------- statement forms

FORMS = [
    ("DRV ADR,+,10000,Ut", Motion("DRV", "ADR", "+", (Val("K", 10000),), "Ut")),
    ("DRV ADR,-,10000,Ps", Motion("DRV", "ADR", "-", (Val("K", 10000),), "Ps")),
    ("DRV ADR,  ,  10000,Ut", Motion("DRV", "ADR", "", (Val("K", 10000),), "Ut")),
    ("DRV ADR,  ,-10000,Ut", Motion("DRV", "ADR", "", (Val("K", -10000),), "Ut")),
    ("DRV ADR,+,R20,Ut", Motion("DRV", "ADR", "+", (Val("R", 20),), "Ut")),
    ("DRV ADR,-,D20,Ps", Motion("DRV", "ADR", "-", (Val("D", 20),), "Ps")),
    ("DRV ADR, ,R20,Ut", Motion("DRV", "ADR", "", (Val("R", 20),), "Ut")),
    ("DRV ABS,  ,   0 ,Ut", Motion("DRV", "ABS", "", (Val("K", 0),), "Ut")),
    ("DRV ABS, ,−10000,Ut", Motion("DRV", "ABS", "", (Val("K", -10000),), "Ut")),
    ("DRV ABS, ,D7,Ps", Motion("DRV", "ABS", "", (Val("D", 7),), "Ps")),
    ("DRV  ADR,－ ,300,Ut", Motion("DRV", "ADR", "-", (Val("K", 300),), "Ut")),
    ("DRV ADR,− ,300,Ut", Motion("DRV", "ADR", "-", (Val("K", 300),), "Ut")),
    ("DRV ADR，−，999999， Ut", Motion("DRV", "ADR", "-", (Val("K", 999999),), "Ut")),
    ("DRV ADR,+,99999999,Ut", Motion("DRV", "ADR", "+", (Val("K", 99999999),), "Ut")),
    ("DRV ADR,+,0,Ut", Motion("DRV", "ADR", "+", (Val("K", 0),), "Ut")),
    ("drv adr,+,5,ut", Motion("DRV", "ADR", "+", (Val("K", 5),), "Ut")),
    ("DRVZ MD0", Motion("DRVZ", mode=0)),
    ("DRVZ MD1", Motion("DRVZ", mode=1)),
    ("DRVZ MD2", Motion("DRVZ", mode=2)),
]


@pytest.mark.parametrize("text,motion", FORMS, ids=[f[0] for f in FORMS])
def test_drive_forms(text, motion):
    prog, diags = parse(one_step(text))
    assert not diags, diags
    assert prog.steps[0].motion == motion


CONDS = [
    ("WAIT TIME,100", Cond("WAIT", True, Val("K", 100))),
    ("WAIT TIME，R500", Cond("WAIT", True, Val("R", 500))),
    ("WAIT TIME,D9", Cond("WAIT", True, Val("D", 9))),
    ("WAIT X255", Cond("WAIT", False, Val("X", 255))),
    ("WAIT Y0", Cond("WAIT", False, Val("Y", 0))),
    ("WAIT M1911", Cond("WAIT", False, Val("M", 1911))),
    ("WAIT S999", Cond("WAIT", False, Val("S", 999))),
    ("ACT TIME,50", Cond("ACT", True, Val("K", 50))),
    ("ACT TIME,R7", Cond("ACT", True, Val("R", 7))),
    ("EXT X3", Cond("EXT", False, Val("X", 3))),
    ("EXT M5", Cond("EXT", False, Val("M", 5))),
]


@pytest.mark.parametrize("text,cond", CONDS, ids=[c[0] for c in CONDS])
def test_condition_forms(text, cond):
    prog, diags = parse(one_step("DRV ADR,+,10,Ut", text, "GOTO NEXT"))
    assert not diags, diags
    assert prog.steps[0].cond == cond


@pytest.mark.parametrize("text,goto", [("GOTO NEXT", NEXT), ("GOTO 1", Val("K", 1)),
                                       ("GOTO R10", Val("R", 10)), ("GOTO D3", Val("D", 3))])
def test_goto_forms(text, goto):
    prog, diags = parse(one_step("DRV ADR,+,10,Ut", "", text))
    assert not diags and prog.steps[0].goto == goto and not prog.steps[0].mend


def test_speed_forms_and_mend():
    prog, diags = parse("001 SPD 921600\n DRV ADR,+,1,Ps\n GOTO NEXT\n002 SPD D100\n DRVZ MD0\n MEND\n"
                        "003 SPD R8070\n DRV ADR,+,1,Ps\n WAIT X0\n MEND\n")
    assert not diags
    assert [s.speed for s in prog.steps] == [Val("K", 921600), Val("D", 100), Val("R", 8070)]
    assert [s.mend for s in prog.steps] == [False, True, True]
    assert prog.steps[2].cond == Cond("WAIT", False, Val("X", 0)) and prog.steps[2].goto is None


def test_lin_line_forms():
    prog, diags = parse("001 SPD 1840000\n LIN ADR,500,-400,R300,D2,Ut\n GOTO NEXT\n"
                        "002 SPD 5000\n LINE ABS, ,0, , ,Ps\n EXT X1\n GOTO 1\n", MHSPO)
    assert not diags, diags
    a, b = prog.steps
    assert a.motion == Motion("LIN", "ADR", "", (Val("K", 500), Val("K", -400), Val("R", 300), Val("D", 2)), "Ut")
    assert b.motion == Motion("LINE", "ABS", "", (BLANK, Val("K", 0), BLANK, BLANK), "Ps")


def test_normalize_keeps_columns():
    s = "DRV ADR，－，３００， Ut；注釋"
    n = normalize(s)
    assert len(n) == len(s) and n.startswith("DRV ADR,-,300, Ut;")


def test_comments_and_blank_lines():
    prog, diags = parse("; head\n\n001 SPD 10 ; c\n\n  DRV ADR,+,1,Ps ；注\n  MEND ;\n")
    assert not diags and len(prog.steps) == 1


# ---------------------------------------------------------------- error codes

ERRORS = [
    # (code, line, col, text)
    ("F030", 1, 9, "001 SPD R8071\n DRV ADR,+,1,Ps\n MEND\n"),
    ("F030", 1, 9, "001 SPD D4000\n DRV ADR,+,1,Ps\n MEND\n"),
    ("F031", 1, 9, "001 SPD 0\n DRV ADR,+,1,Ps\n MEND\n"),
    ("F031", 1, 9, "001 SPD fast\n DRV ADR,+,1,Ps\n MEND\n"),
    ("F032", 2, 12, "001 SPD 1\n DRV ADR,+,R9000,Ps\n MEND\n"),
    ("F033", 2, 12, "001 SPD 1\n DRV ADR,+,-100,Ut\n MEND\n"),
    ("F033", 2, 12, "001 SPD 1\n DRV ADR,+,ten,Ut\n MEND\n"),
    ("F034", 2, 2, "001 SPD 1\n JUMP 3\n"),
    ("F034", 3, 7, "001 SPD 1\n DRV ADR,+,1,Ps\n WAIT X256\n GOTO 1\n"),
    ("F034", 3, 7, "001 SPD 1\n DRV ADR,+,1,Ps\n GOTO 2\n"),
    ("F034", 3, 12, "001 SPD 1\n DRV ADR,+,1,Ps\n WAIT TIME,100000\n MEND\n"),
    ("F035", 4, 1, "001 SPD 1\n DRV ADR,+,1,Ps\n MEND\n003 SPD 1\n DRV ADR,+,1,Ps\n MEND\n"),
    ("F035", 2, 1, "001 SPD 1\n DRV ADR,+,1,Ps\n"),
    ("F035", 1, 1, "DRV ADR,+,1,Ps\n"),
    ("F035", 4, 2, "001 SPD 1\n DRV ADR,+,1,Ps\n MEND\n GOTO 1\n"),
    ("F036", 251, 1, "".join(f"{k:03d} SPD 1\n" for k in range(1, 252)).replace("\n", " ; \n")),
    ("F037", 1, 9, "001 SPD 921601\n DRV ADR,+,1,Ps\n MEND\n"),
    ("F040", 2, 12, "001 SPD 1\n DRV ADR,+,100000000,Ut\n MEND\n"),
    ("F040", 2, 12, "001 SPD 1\n DRV ABS, ,-100000000,Ut\n MEND\n"),
    ("F041", 5, 2, "001 SPD 1\n DRVC ADR,+,1,Ut\n GOTO NEXT\n002 SPD 2\n DRV ABS, ,5,Ut\n MEND\n"),
    ("F042", 5, 2, "001 SPD 1\n DRVC ABS, ,1,Ut\n GOTO NEXT\n002 SPD 2\n DRVZ MD0\n MEND\n"),
    ("F043", 2, 6, "001 SPD 1\n DRV XYZ,+,1,Ps\n MEND\n"),
    ("F043", 2, 10, "001 SPD 1\n DRV ABS,+,1,Ps\n MEND\n"),
    ("F043", 2, 14, "001 SPD 1\n DRV ADR,+,1,Pulse\n MEND\n"),
    ("F043", 2, 11, "001 SPD 1\n DRVC ADR, ,1,Ps\n GOTO NEXT\n002 SPD 1\n DRV ADR,+,1,Ps\n MEND\n"),
    ("F043", 2, 2, "001 SPD 1\n DRVC ADR,+,1,Ps\n GOTO NEXT\n"),
    ("F043", 2, 2, "001 SPD 1\n DRVC ADR,+,1,Ps\n WAIT X0\n GOTO NEXT\n002 SPD 1\n DRV ADR,+,1,Ps\n MEND\n"),
    ("F043", 2, 2, "001 SPD 1\n LIN ADR,1,2,3,4,Ut\n MEND\n"),
    ("F043", 1, 1, "001 SPD 1\n MEND\n"),
    ("F043", 2, 2, "".join(f"{k:03d} SPD 1\n DRVC ADR,+,1,Ps\n GOTO NEXT\n" for k in range(1, 9))
     + "009 SPD 1\n DRV ADR,+,1,Ps\n MEND\n"),
    ("F050", 2, 7, "001 SPD 1\n DRVZ MD3\n MEND\n"),
]


@pytest.mark.parametrize("code,line,col,text", ERRORS, ids=[f"{e[0]}-{k}" for k, e in enumerate(ERRORS)])
def test_error_codes(code, line, col, text):
    found = codes(text)
    assert (code, line, col) in found, found


def test_eight_drvc_segments_are_fine():
    text = "".join(f"{k:03d} SPD 1\n DRVC ADR,+,1,Ps\n GOTO NEXT\n" for k in range(1, 8)) \
        + "008 SPD 1\n DRV ADR,+,1,Ps\n MEND\n"
    assert codes(text) == []


@pytest.mark.parametrize("code,line,col,text", [
    ("F060", 2, 2, "001 SPD 1\n DRV ADR,+,1,Ps\n MEND\n"),
    ("F060", 3, 2, "001 SPD 1\n LIN ADR,1,2,3,4,Ut\n ACT TIME,5\n GOTO 1\n"),
    ("F060", 2, 16, "001 SPD 1\n LIN ADR,1,2,3,Ut\n MEND\n"),
    ("F040", 2, 10, "001 SPD 1\n LIN ADR,2000000,0,0,0,Ps\n MEND\n"),
    ("F033", 2, 10, "001 SPD 1\n LIN ADR, , , , ,Ps\n MEND\n"),
    ("F037", 1, 9, "001 SPD 1840001\n LIN ADR,1,0,0,0,Ps\n MEND\n"),
])
def test_interpolation_error_codes(code, line, col, text):
    assert (code, line, col) in codes(text, MHSPO)


def test_static_codes_cover_the_manual_list():
    """Every manual code 30-60 is a documented F code; the static ones are tested above,
    the run-time ones (38, 39, 51-53) in test_fbs_axis.py."""
    manual = [30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43, 50, 51, 52, 53, 60]
    assert all(f"F{n:03d}" in CODES for n in manual)
    static = {e[0] for e in ERRORS} | {"F060"}
    assert static == {f"F{n:03d}" for n in manual} - {"F038", "F039", "F051", "F052", "F053"}
    docs = (ROOT / "docs" / "check.md").read_text("utf-8")
    assert all(f"`F{n:03d}`" in docs for n in manual)


# ---------------------------------------------------------------- tables


def test_table_layout_of_the_format_example():
    prog, _ = parse((SAMPLES / "man_program_format.pos").read_text("utf-8"))
    w = encode(prog)
    assert len(w) == 4 * 9 + 2 and w[:2] == [0xA55A, 4]
    # step 1: SPD 5000, DRV ADR,+,10000,Ut, WAIT TIME,100, GOTO NEXT
    assert w[2:11] == [0x0020, 5000, 0, 10000, 0, 1, 100, 0, 0x0000]
    # step 2: SPD R1000 (kind 1), travel D100 (kind 2 at b8), WAIT TIME,R500, GOTO NEXT
    assert w[11:20] == [0x0221, 1000, 0, 100, 0, 0x0011, 500, 0, 0]
    # step 4: SPD 2000, DRV ADR,-,R4072,Ps (b7 Ps, b8 R, b5-6 = 2), WAIT X1, GOTO 1
    assert w[29:38] == [0x01C0, 2000, 0, 4072, 0, 0x0002, 1, 0, 0x4001]


def test_negative_travel_and_mend_words():
    prog, _ = parse("001 SPD 70000\n DRV ABS, ,-10000,Ut\n MEND\n")
    w = encode(prog)
    assert w[2:] == [0x0010, 70000 & 0xFFFF, 1, (-10000) & 0xFFFF, 0xFFFF, 0, 0, 0, 0xFFFF]
    assert decode(w) == prog


ALL = sorted(SAMPLES.glob("*.pos")) + sorted(SAMPLES.glob("*.mpos"))


@pytest.mark.parametrize("path", ALL, ids=lambda p: p.name)
def test_samples_round_trip(path):
    d = tables().dialect_for(path.name)
    prog, diags = parse_program(path.name, path.read_text("utf-8"), d)
    assert not diags
    words = encode(prog)
    assert len(words) == d.table_words(len(prog.steps))
    assert decode(words) == prog
    again, diags = parse_program("x", program_text(prog), d)
    assert again == prog and not diags
    sr = parse_sr("R5000", len(words))
    assert read_image(to_csv(words, sr)) == (words, "R5000")
    assert read_image(to_json(words, sr, d.instruction)) == (words, "R5000")


def test_interpolation_table_size():
    prog, _ = parse((SAMPLES / "man_interpolation.mpos").read_text("utf-8"), MHSPO)
    w = encode(prog)
    assert w[:2] == [0xA55C, 3] and len(w) == 3 * 15 + 2


@pytest.mark.parametrize("words,code", [
    ([0x1234, 1] + [0] * 9, "F034"),
    ([0xA55A, 251], "F036"),
    ([0xA55A, 0], "F034"),
    ([0xA55A, 1] + [0] * 8, "F035"),
    ([0xA55A, 1, 0x000C, 1, 0, 1, 0, 0, 0, 0, 0], "F043"),
    ([0xA55A, 1, 0x0000, 1, 0, 1, 0, 9, 0, 0, 0], "F034"),
])
def test_bad_tables(words, code):
    with pytest.raises(TableError) as e:
        decode(words)
    assert e.value.code == code


def test_sr_must_fit_its_area():
    assert parse_sr("D3962", 38).name() == "D3962"
    for bad in ("D3963", "R3830", "R4000", "X0", "R8050"):
        with pytest.raises(ImageError):
            parse_sr(bad, 38)


def test_drvc_abs_takes_the_sign_the_row_prints():
    """11.6 DRVC row: `DRVC ADR，+，XXXXXXXX，Ut 或 ABS，−，Rxxxx，Ps`, and "DRVC 之運轉方向決定祇能由
    '+' 或 '−' 決定"; DRV's direction operand stays "相對值座標有效" (relative coordinates only)."""
    chain = "001 SPD 1000\n DRVC ABS,{sign},{travel},Ut\n GOTO NEXT\n002 SPD 500\n DRV ADR,-,5,Ut\n MEND\n"
    for sign, travel, value in (("-", "R10", Val("R", 10)), ("+", "-300", Val("K", -300)), ("", "300", Val("K", 300))):
        prog, diags = parse(chain.format(sign=sign, travel=travel))
        assert not diags, diags
        assert prog.steps[0].motion == Motion("DRVC", "ABS", sign, (value,), "Ut")
        assert decode(encode(prog)).steps[0].motion == prog.steps[0].motion  # the sign round-trips
    assert codes("001 SPD 1\n DRV ABS,-,1,Ps\n MEND\n") == [("F043", 2, 10)]
