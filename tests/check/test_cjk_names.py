"""Named labels with Chinese characters (VS 2-10 "程序指標以8個中文字或16個英文數字所組成",
the manual's `CALL 緊急停止`; issue 8): grammar, check, columns, objects, sim, fmt, imports,
JSON/SARIF. Only a target whose target.toml `named_labels` has `cjk_width` takes them."""

from __future__ import annotations

import dataclasses
import json
import re

from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import run_mlc
from mlctool.check import check_texts
from mlctool.fmt import format_source
from mlctool.imports import import_text
from mlctool.sim.run.run import Simulation, plan_scans
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.syntax.operands import CJK_RANGES, name_width
from mlctool.syntax.parser import grammar_text, parse
from mlctool.syntax.source import decode, display_width
from mlctool.targetapi import load_target

VS = load_target("vs")
NC5 = load_target("nc5")

PROGRAM = """LD X0
CALL 緊急停止
LD X1
CJ 跳過
LD X2
OUT Y0
跳過:
LD X3
OUT Y2
FEND
緊急停止:
LD X4
OUT Y1
SRET
END
"""


def _check(il: str, target=VS):
    src, diags = decode("t.il", il.encode("utf-8"))
    assert not diags
    return check_texts([src], target)


def codes(il: str, target=VS, severity: str | None = "error") -> list[str]:
    return [d.code for d in _check(il, target).diagnostics if severity is None or d.severity == severity]


# ------------------------------------------------------------------ grammar

def test_the_grammar_and_the_operand_module_name_the_same_characters():
    g = grammar_text()
    for terminal in ("MNEMONIC", "OPERAND"):
        line = next(x for x in g.splitlines() if x.startswith(terminal + ":"))
        assert CJK_RANGES in line, terminal


PIECES = ["LD", "CJ", "X0", "緊急", "停止", "A", "1", "_", ":", " ", "\u3000", ",", ";註解", "P1",
          "變頻器", "\uff1a", "Ｘ", "é", "0000", '"中"', "<>"]


@settings(max_examples=300, deadline=None)
@given(st.lists(st.lists(st.sampled_from(PIECES), max_size=7).map("".join), max_size=10))
def test_fast_path_matches_lark_on_chinese_names(lines):
    text = "\n".join(lines) + "\n"
    src, _ = decode("t.il", text.encode("utf-8"))
    fast, slow = parse(src, True), parse(src, False)

    def shape(pf):
        return [(s.line, s.kind, s.name.text, s.name.col, [(w.text, w.col) for w in s.operands]) for s in pf.statements]
    assert shape(fast) == shape(slow)
    assert [(d.code, d.span) for d in fast.diagnostics] == [(d.code, d.span) for d in slow.diagnostics]


# ------------------------------------------------------------------ check

def test_the_manual_example_checks():
    assert codes(PROGRAM, severity=None) == []
    m = _check(PROGRAM).modules[0]
    # names take free P numbers from P1023 down in order of definition (docs/vs.md)
    assert [(i.spec.op, i.operands[0].number) for i in m.instrs if i.spec.op in ("cj", "call")] == \
        [("call", 1022), ("cj", 1023)]


def test_length_counts_a_chinese_character_as_two():
    def label(name):
        return f"LD X0\nCJ {name}\nLD X1\nOUT Y0\n{name}:\nEND\n"
    assert codes(label("一二三四五六七八")) == []             # 8 characters (2-10)
    assert sorted(codes(label("一二三四五六七八九"))) == ["E203", "E304"]  # 9: too long, so no label
    assert codes(label("變頻器1通訊")) == []                  # the manual's mixed name: 11
    assert codes(label("ABCDEF緊急停止12")) == []             # 6 + 8 + 2 = 16
    assert sorted(codes(label("ABCDEF緊急停止123"))) == ["E203", "E304"]  # 17
    d = next(d for d in _check(label("一二三四五六七八九")).diagnostics if d.code == "E203")
    assert "18" in d.message and "counts 2" in d.message
    assert name_width("A緊", 2) == 3


def test_names_stay_apart_from_devices_instructions_and_symbols():
    assert "E103" in codes("LD X0\nCJ P1\nX1:\nP1:\nEND\n")       # still a device
    assert "E103" in codes("LD X0\nＸ１:\nEND\n")                  # fullwidth letters: no name
    assert codes("LD X0\nCJ 緊急\nLD X1\nOUT Y0\n緊急:\n緊急:\nEND\n") == ["E303"]  # twice
    assert codes("LD X0\nCJ 無此\nEND\n") == ["E304"]
    assert codes("LD 未定\nOUT Y0\nEND\n") == ["E215"]              # not a pointer position
    assert codes("緊急 X0\nEND\n") == ["E201"]                     # no instruction


def test_chinese_symbol_and_table_names():
    # 2-11: a table name of up to 8 Chinese characters, given one by .define (docs/vs.md)
    il = ".define 變頻器1通訊 Q0\n.define 啟動 X0\nLD 啟動\nOUT Y0\nEND\n"
    assert codes(il, severity=None) == []
    assert codes(".define 一二三四五六七八九 X0\nEND\n") == ["E106"]


def test_a_target_without_named_labels_reports_the_character_as_before():
    found = [(d.code, d.span.line, d.span.col) for d in _check(PROGRAM, NC5).diagnostics if d.code == "E103"]
    assert found == [("E103", 2, 6), ("E103", 4, 4), ("E103", 7, 1), ("E103", 11, 1)]
    # a string constant may hold anything, and a comment too
    assert codes('LD X0\n$MOV "中文" D0 ; 註解\nEND\n') == []


def test_columns_count_characters_in_json_and_sarif(tmp_path):
    (tmp_path / "t.il").write_text("LD X0\nCJ 無此標籤\nEND\n", "utf-8")
    r = run_mlc("check", "--target", "vs", "--format", "json", "t.il", cwd=tmp_path)
    d = json.loads(r.out)["diagnostics"][0]
    assert (d["code"], d["column"], d["end_column"]) == ("E304", 4, 8) and "無此標籤" in d["message"]
    r = run_mlc("check", "--target", "vs", "--format", "sarif", "t.il", cwd=tmp_path)
    run = json.loads(r.out)["runs"][0]
    assert run["columnKind"] == "unicodeCodePoints"
    assert run["results"][0]["locations"][0]["physicalLocation"]["region"]["startColumn"] == 4
    # the carets of the text report go by display width: two a character
    r = run_mlc("check", "--target", "vs", "t.il", cwd=tmp_path)
    assert "|    ^^^^^^^^\n" in r.err


# ------------------------------------------------------------------ objects, listings

def test_build_objdump_il_round_trip_is_byte_identical(tmp_path):
    (tmp_path / "t.il").write_text(PROGRAM, "utf-8")
    assert run_mlc("build", "--target", "vs", "t.il", "-o", "a.mlo", "--listing", "a.lst", cwd=tmp_path).code == 0
    il = run_mlc("objdump", "--il", "a.mlo", cwd=tmp_path)
    assert il.code == 0 and "CALL 緊急停止" in il.out and re.search(r"^跳過:", il.out, re.M)
    assert "緊急停止:" in (tmp_path / "a.lst").read_text("utf-8")
    again = tmp_path / "again"
    again.mkdir()
    (again / "t.il").write_text(il.out, "utf-8")
    assert run_mlc("build", "--target", "vs", "t.il", "-o", "a.mlo", cwd=again).code == 0
    assert (again / "a.mlo").read_bytes() == (tmp_path / "a.mlo").read_bytes()
    # the names as written, in UTF-8, are what the object keeps
    assert "緊急停止".encode() in (tmp_path / "a.mlo").read_bytes()
    # objdump's columns line up by display width
    text = run_mlc("objdump", "a.mlo", cwd=tmp_path).out.splitlines()
    rows = [x for x in text if "t.il:" in x]
    assert any("緊急停止" in x for x in rows)
    assert len({display_width(x[:x.index("t.il:")]) for x in rows}) == 1
    # and so does the terminal ladder: each wide character takes two cells
    lad = run_mlc("ladder", "--target", "vs", "t.il", cwd=tmp_path)
    assert lad.code == 0 and "緊急停止" in lad.out


# ------------------------------------------------------------------ simulation, both engines

STIM = """
0ms X0=1
0ms X1=1
0ms X2=1
0ms X4=1
30ms expect Y1=1 Y0=0
40ms X1=0
70ms expect Y0=1
80ms X4=0
110ms expect Y1=0
"""


def test_cj_and_call_to_chinese_labels_on_both_engines():
    src, _ = decode("t.il", PROGRAM.encode("utf-8"))
    from mlctool.asm.encode import image_from_object, object_from_module

    res = check_texts([src], VS)
    assert res.errors == 0
    image = image_from_object(object_from_module(res.modules[0]))
    unpinned = dataclasses.replace(VS, settings={k: v for k, v in VS.settings.items() if k != "engine"})
    for engine in ("interp", "compiled"):
        stim, sd = parse_stimulus_text("t.stim", STIM, VS)
        assert not sd
        r = Simulation(image, unpinned, stim, [], 10_000, [], False, engine=engine).run(plan_scans(stim, 10_000, None, None))
        assert r.fault is None and not r.failed, (engine, [(f.line, f.device, f.expected, f.actual) for f in r.failed])


# ------------------------------------------------------------------ fmt

def test_fmt_aligns_by_display_width_and_is_idempotent():
    text = "LD X0 ; 開始\nCALL 緊急停止 ; 呼叫\n緊急停止:  ; 標籤\nSRET\nEND\n"
    src, _ = decode("t.il", text.encode("utf-8"))
    once, d = format_source(src, VS)
    assert d == [] and once is not None
    lines = [x for x in once.splitlines() if ";" in x]
    assert {display_width(x[:x.index(";")]) for x in lines} == {40}  # comments line up on screen
    src2, _ = decode("t.il", once.encode("utf-8"))
    assert format_source(src2, VS)[0] == once
    # NC5: not formatted, the characters are syntax errors there
    assert format_source(src, NC5)[0] is None


NAME_CHARS = st.sampled_from(list("緊急停止跳過變頻器通訊ABCZ_019"))


@settings(max_examples=60, deadline=None)
@given(st.text(NAME_CHARS, min_size=1, max_size=12).filter(lambda s: not s[0].isdigit() and s[0] != "_"))
def test_any_name_within_16_checks_formats_and_round_trips(name):
    il = f"LD X0\nCJ {name}\nLD X1\nOUT Y0\n{name}:\nEND\n"
    got = codes(il)
    if re.fullmatch(r"[A-Z0-9_]+", name) and got:  # an ASCII name may read as a device or mnemonic
        return
    assert sorted(got) == ([] if name_width(name, 2) <= 16 else ["E203", "E304"])
    src, _ = decode("t.il", il.encode("utf-8"))
    once = format_source(src, VS)[0]
    assert format_source(decode("t.il", once.encode("utf-8"))[0], VS)[0] == once


# ------------------------------------------------------------------ imports

def test_imports_keep_chinese_labels():
    gx = ('"MAIN"\n"PLC Information:"\t"VS3"\n'
          '"Step Number"\t"Line Statement"\t"Instruction"\t"I/O(Device)"\t"Blank"\t"PI Statement"\t"Note"\n'
          '"0"\t""\t"LD"\t"X000"\t""\t""\t""\n"1"\t""\t"CJ"\t"跳過"\t""\t""\t"跳到標籤"\n'
          '"4"\t""\t"OUT"\t"Y000"\t""\t""\t""\n"5"\t""\t"跳過"\t""\t""\t""\t""\n"6"\t""\t"END"\t""\t""\t""\t""\n')
    data = "\ufeff".encode("utf-16-le") + gx.encode("utf-16-le")  # as GX Works2 writes: UTF-16 with BOM
    from mlctool.imports import decode_export

    text, _ = decode_export("g.csv", data)
    il, fmt, diags = import_text("g.csv", text, VS)
    assert (fmt, diags) == ("gxworks2", [])
    assert il == ".dialect fx\nLD X0\nCJ 跳過 ; 跳到標籤\nOUT Y0\n跳過:\nEND\n"
    wpl, fmt, diags = import_text("w.csv", "000000,LD,X0\n000001,CJ,緊急\n000004,OUT,Y0\n000005,緊急:\n000006,END\n", VS)
    assert (fmt, diags) == ("wplsoft", []) and wpl == ".dialect dvp\nLD X0\nCJ 緊急\nOUT Y0\n緊急:\nEND\n"
    assert codes(il) == [] and codes(wpl) == []
    # NC5 has no named labels: the name is an unknown instruction, which the import reports (E907)
    out, _, diags = import_text("w.csv", "000000,LD,X0\n000001,SKIP\n", NC5)
    assert out is None and [(d.code, d.span.line) for d in diags] == [("E907", 2)]
    assert "unknown instruction 'SKIP' for target nc5" in diags[0].message
