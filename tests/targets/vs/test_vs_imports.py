"""`mlc import`: GX Works2 / GX Developer / WPLSoft exports and plain IL read to the same program
(same IL text, same assembled bytes) as tests/data/vs_imports/program.il (issue 8)."""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import run_mlc
from mlctool.imports import detect, import_file, import_text
from mlctool.targetapi import load_target

DATA = Path(__file__).resolve().parents[2] / "data" / "vs_imports"
VS = load_target("vs")
PLAIN = (DATA / "program.il").read_text("utf-8")
EXPORTS = {"gxworks2.csv": "gxworks2", "gxdeveloper.csv": "gxdeveloper", "wplsoft.csv": "wplsoft",
           "program.il": "il"}
# the dialect of origin each import writes first (issue 29: W217 reads it); plain IL has none
DIALECT = {"gxworks2": ".dialect fx\n", "gxdeveloper": ".dialect fx\n", "wplsoft": ".dialect dvp\n",
           "delta": ".dialect dvp\n", "il": ""}


def mlc(*args, cwd=None):
    return run_mlc(*args, cwd=cwd)


def test_the_export_files_have_their_formats_shapes():
    raw = (DATA / "gxworks2.csv").read_bytes()
    assert raw.startswith(b"\xff\xfe")  # UTF-16 LE with BOM
    text = raw.decode("utf-16")
    assert '"Step Number"\t"Line Statement"\t"Instruction"\t"I/O(Device)"' in text
    assert '""\t""\t""\t"K50"' in text and '"X000"' in text  # continuation row, zero padding
    assert '"0","","LD","X000"' in (DATA / "gxdeveloper.csv").read_text("ascii")
    assert "000014,DLD>=,D2,K100000" in (DATA / "wplsoft.csv").read_text("ascii")


@pytest.mark.parametrize("name", sorted(EXPORTS))
def test_each_export_reads_to_the_plain_program(name):
    text, fmt, diags = import_file(str(DATA / name), VS)
    assert (fmt, diags) == (EXPORTS[name], [])
    assert text == DIALECT[EXPORTS[name]] + PLAIN


def test_same_assembled_bytes(tmp_path):
    """Every import, built, is byte for byte the plain IL's object (its `.dialect` line aside,
    which the object keeps as it keeps every directive)."""
    built = {}
    for name in sorted(EXPORTS):
        folder = tmp_path / name.replace(".", "_")
        folder.mkdir()
        r = mlc("import", "--target", "vs", str(DATA / name), "-o", "prog.il", cwd=folder)
        assert r.code == 0, r.err
        il = (folder / "prog.il").read_text("utf-8")
        assert il.startswith(DIALECT[EXPORTS[name]])
        (folder / "prog.il").write_text(il.removeprefix(DIALECT[EXPORTS[name]]), "utf-8")
        r = mlc("build", "--target", "vs", "prog.il", "-o", "prog.mlx", cwd=folder)
        assert r.code == 0, r.err
        built[name] = (folder / "prog.mlx").read_bytes()
    assert len(set(built.values())) == 1


def test_the_32_bit_comparison_spellings():
    # in an export from a tool that writes DLD>=, the importer writes the target's LDD>=
    text, _, _ = import_text("w.csv", "000000,DLD>=,D0,K1\n000009,OUT,Y0\n000010,END\n", VS)
    assert text.splitlines()[:2] == [".dialect dvp", "LDD>= D0 K1"]
    # written by hand in IL, DLD>= is the wrong spelling, with a hint
    r = mlc("check", "--target", "vs", str(DATA / "bad_spelling.il"))
    assert r.code == 1 and "E201" in r.err and "LDD>=" in r.err


def test_detection():
    assert detect('"MAIN"\n"Step Number"\t"Line Statement"\t"Instruction"\t"I/O(Device)"\n') == "gxworks2"
    assert detect('"Step Number","Line Statement","Instruction","I/O(Device)"\n') == "gxdeveloper"
    assert detect("000000,LD,X0\n") == "wplsoft"
    assert detect("LD X0\nOUT Y0\n") == "il"


@pytest.mark.parametrize("text, fmt, code", [
    ('"MAIN"\n"LD","X0"\n', "gxdeveloper", "E907"),                          # no header row
    ('"Instruction","I/O(Device)"\n"","K50"\n', "gxdeveloper", "E907"),       # operand, no instruction
    ("Title\n000000,LD,X0\nLD X1\n", "wplsoft", "E907"),                      # row without a step
])
def test_unreadable_rows(text, fmt, code):
    out, _, diags = import_text("x.csv", text, VS, fmt)
    assert out is None and [d.code for d in diags] == [code]


def test_cli_errors_and_atomic_output(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_bytes(b'"Instruction","I/O(Device)"\n"","K50"\n')
    out = tmp_path / "out.il"
    out.write_text("keep\n")
    r = mlc("import", "--target", "vs", "--from", "gxdeveloper", str(bad), "-o", str(out))
    assert r.code == 1 and "E907" in r.err and "Traceback" not in r.err
    assert out.read_text() == "keep\n"  # nothing written on errors
    binary = tmp_path / "bin.csv"
    binary.write_bytes(b"\x00\x01\x02LD")
    r = mlc("import", "--target", "vs", str(binary))
    assert r.code == 2 and "E101" in r.err
    r = mlc("import", "--target", "vs", str(tmp_path / "missing.csv"))
    assert r.code == 2 and "E100" in r.err


# ------------------------------------------------------------------ issue 14 §3, issue 16 §4

def test_import_without_target_takes_the_exports_dialect(tmp_path):
    """Before: without --target the GX export was imported for nc5's name but in VS dialect,
    exit 0, and `mlc check` then failed it on nc5 with no hint."""
    for name in ("gxworks2.csv", "gxdeveloper.csv", "wplsoft.csv"):
        r = mlc("import", str(DATA / name), "-o", "prog.il", cwd=tmp_path)
        assert r.code == 0, r.err
        assert (tmp_path / "prog.il").read_text("utf-8") == DIALECT[EXPORTS[name]] + PLAIN
        assert "(target vs, the dialect of a" in r.err and "`mlc check --target vs prog.il`" in r.err
        assert mlc("check", "--target", "vs", "prog.il", cwd=tmp_path).code == 0
    # the command line still decides
    r = mlc("import", "--target", "nc5", str(DATA / "wplsoft.csv"), cwd=tmp_path)
    assert r.code == 0 and "DLD>= D2 K100000" in r.out and "dialect" not in r.err


def test_an_unrecognised_file_is_an_error_not_a_copy(tmp_path):
    notes = tmp_path / "notes.txt"
    notes.write_text("Shopping list\n\nmilk, eggs and bread for the week\n")
    out = tmp_path / "out.il"
    r = mlc("import", str(notes), "-o", str(out))
    assert r.code == 2 and "error[E909]: not recognised as a GX Works2, GX Developer, WPLSoft or Delta export" in r.err
    assert not out.exists()
    # plain IL is recognised and copied; --from il takes any text as it is
    r = mlc("import", str(DATA / "program.il"))
    assert r.code == 0 and r.out == PLAIN
    r = mlc("import", "--from", "il", str(notes))
    assert r.code == 0 and r.out.startswith("Shopping list")


def test_a_bare_name_is_a_label_only_when_jumped_to():
    """Issue 16 §4: `NOPLF` (an unknown mnemonic without operands) silently became a label."""
    text = "000000,LD,X0\n000001,NOPLF\n000002,CJ,HERE\n000005,HERE\n000006,LD,X1\n000007,DONE:\n000008,END\n"
    out, _, diags = import_text("w.csv", text, VS)
    assert out is None and [(d.code, d.span.line) for d in diags] == [("E907", 2)]
    assert diags[0].message == "row 2: unknown instruction 'NOPLF' for target vs; did you mean PLF?"
    out, _, diags = import_text("w.csv", text.replace("000001,NOPLF\n", ""), VS)
    assert diags == [] and out == ".dialect dvp\nLD X0\nCJ HERE\nHERE:\nLD X1\nDONE:\nEND\n"


def test_unknown_instructions_with_operands_are_import_errors():
    out, _, diags = import_text("w.csv", "000000,LD,X0\n000001,MOVV,K1,D0\n000004,MOVV,K2,D1\n000007,END\n", VS)
    assert out is None and len(diags) == 1
    assert diags[0].message == "row 2: unknown instruction 'MOVV' for target vs; did you mean MOV?"
    assert diags[0].notes == ("and 1 more row like it: 3",)


def test_identical_row_errors_are_reported_once():
    """Issue 16 §4: one unreadable file gave 220 identical E907 lines."""
    text = "".join(f"row {k}\n" for k in range(1, 221))
    out, _, diags = import_text("r.csv", text, VS, "wplsoft")
    assert out is None and len(diags) == 1
    assert diags[0].message == "row 2: expected a 6-digit step number, got 'row 2'"
    assert diags[0].notes == ("and 218 more rows like it: 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, ...",)


def _gx_text(rows: list[list[str]]) -> str:
    head = '"MAIN"\n"PLC Information:"\t"FXCPU FX3U/FX3UC"\n' \
        '"Step Number"\t"Line Statement"\t"Instruction"\t"I/O(Device)"\t"Blank"\t"PI Statement"\t"Note"\n'
    return head + "".join("\t".join(f'"{c}"' for c in (r + [""] * 7)[:7]) + "\n" for r in rows)


def test_buffer_memory_mc_relay_and_pointer_operands():
    text = _gx_text([["0", "", "LD", "M8000"], ["1", "", "MOV", "U1\\G3"], ["", "", "", "D0"],
                     ["6", "", "LD", "X000"], ["7", "", "MC", "N0"], ["", "", "", "M100"],
                     ["10", "", "LD", "X001"], ["11", "", "DHSCS", "K100"], ["", "", "", "C235"], ["", "", "", "I010"],
                     ["24", "", "MCR", "N0"], ["26", "", "END"]])
    out, _, diags = import_text("g.csv", text, VS)
    assert [d.code for d in diags] == ["N910"], [d.message for d in diags]
    lines = out.splitlines()
    assert "MOV U1G3 D0" in lines and "DHSCS K100 C235 IHC0" in lines
    assert lines[4].startswith("MC N0 ; the export's MC N0 M100")


def test_a_pointer_without_a_vs_counterpart_is_an_error_saying_how():
    text = _gx_text([["0", "", "FEND"], ["1", "", "I999"], ["2", "", "IRET"], ["3", "", "END"]])
    out, _, diags = import_text("g.csv", text, VS)
    assert out is None and diags[0].code == "E907" and "I999 has no counterpart" in diags[0].message
    assert "IX0P" in diags[0].notes[0]


def test_a_special_without_a_counterpart_is_kept_with_a_warning():
    text = _gx_text([["0", "", "LD", "M8005"], ["2", "", "OUT", "Y000"], ["3", "", "END"]])
    out, _, diags = import_text("g.csv", text, VS)
    assert "LD M8005" in out.splitlines() and [d.code for d in diags] == ["W107", "W910"]
    assert "M8005 is a FX special device with no counterpart" in diags[1].message


def test_an_export_step_count_unlike_the_target_is_w107_once_per_kind():
    # the export says RST C0 is 1 step (FX: 2) twice: one W107 naming the row, the other in a note
    text = _gx_text([["0", "", "LD", "X000"], ["1", "", "RST", "C0"], ["2", "", "LD", "X001"],
                     ["3", "", "RST", "C1"], ["4", "", "END"]])
    out, _, diags = import_text("g.csv", text, VS)
    assert out is not None and [d.code for d in diags] == ["W107"]
    assert "row 5: RST C0 is 1 steps in the export (step 1 to 2), 2 by target vs" in diags[0].message
    assert "row" in diags[0].notes[-1] and "7" in diags[0].notes[-1]


def test_headerless_and_delta_csv_and_delta_timers():
    rows = '"0","","LD","X000","","",""\n"1","","OUT","T0","","",""\n"","","","K10","","",""\n"4","","END","","","",""\n'
    assert detect(rows) == "gxdeveloper"
    out, _, diags = import_text("h.csv", rows, VS)
    assert out == ".dialect fx\nLD X0\nOUT T0 K10\nEND\n" and diags == []
    delta = "Step,Instruction,Operand1,Operand2,Operand3\n0,LD,M1000,,\n1,TMR,T0,K10,\n5,CNT,C0,K3,\n9,END,,,\n"
    assert detect(delta) == "delta"
    out, _, diags = import_text("d.csv", delta, VS)
    assert out == ".dialect dvp\nLD M9000\nOUT T0 K10\nOUT C0 K3\nEND\n" and [d.code for d in diags] == ["N910", "N911"]


@pytest.mark.parametrize("header", [
    ("步号", "行间声明", "指令", "I/O(软元件)", "空白栏", "PI声明", "注解"),
    ("步號", "行間聲明", "指令", "I/O(軟元件)", "空白欄", "PI聲明", "註解"),
    ("ステップ番号", "行間ステートメント", "命令", "I/O(デバイス)", "空欄", "PIステートメント", "ノート"),
])
def test_chinese_and_japanese_headers(header):
    text = '"MAIN"\n' + "\t".join(f'"{h}"' for h in header) + '\n"0"\t""\t"LD"\t"X000"\t""\t""\t"start"\n' \
        '"1"\t""\t"OUT"\t"Y000"\t""\t""\t""\n"2"\t""\t"END"\t""\t""\t""\t""\n'
    assert detect(text) == "gxworks2"
    out, _, diags = import_text("z.csv", text, VS)
    assert out == ".dialect fx\nLD X0 ; start\nOUT Y0\nEND\n" and diags == []
