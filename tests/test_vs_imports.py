"""`mlc import`: GX Works2 / GX Developer / WPLSoft exports and plain IL read to the same program
(same IL text, same assembled bytes) as tests/data/vs_imports/program.il (issue 8)."""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import run_mlc
from mlctool.imports import detect, import_file, import_text
from mlctool.targets import load_target

DATA = Path(__file__).resolve().parent / "data" / "vs_imports"
VS = load_target("vs")
PLAIN = (DATA / "program.il").read_text("utf-8")
EXPORTS = {"gxworks2.csv": "gxworks2", "gxdeveloper.csv": "gxdeveloper", "wplsoft.csv": "wplsoft",
           "program.il": "il"}


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
    assert text == PLAIN


def test_same_assembled_bytes(tmp_path):
    """Every import, built, is byte for byte the plain IL's object."""
    built = {}
    for name in sorted(EXPORTS):
        folder = tmp_path / name.replace(".", "_")
        folder.mkdir()
        r = mlc("import", "--target", "vs", str(DATA / name), "-o", "prog.il", cwd=folder)
        assert r.code == 0, r.err
        r = mlc("build", "--target", "vs", "prog.il", "-o", "prog.mlx", cwd=folder)
        assert r.code == 0, r.err
        built[name] = (folder / "prog.mlx").read_bytes()
    assert len(set(built.values())) == 1


def test_the_32_bit_comparison_spellings():
    # in an export from a tool that writes DLD>=, the importer writes the target's LDD>=
    text, _, _ = import_text("w.csv", "000000,DLD>=,D0,K1\n000009,OUT,Y0\n000010,END\n", VS)
    assert text.splitlines()[0] == "LDD>= D0 K1"
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
