"""`mlc export` (issue 29): the IL of every bundled corpus export, written back in the vendor's
form, re-imports to the same IL; the GX Works2 CSV has the documented layout, byte for byte the
corpus export GX Works2 writes (UTF-16LE with BOM, CRLF, tab-separated quoted cells, title and
header rows, continuation rows, X000 padding, the step column)."""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import run_mlc
from mlctool.exports import export_text
from mlctool.imports import import_file, import_text
from mlctool.syntax.source import decode
from mlctool.targetapi import load_target

CORPUS = Path(__file__).resolve().parent / "corpus"
VS = load_target("vs")
EXPORTS = sorted(p.name for p in CORPUS.glob("*.csv") if not p.name.startswith("COMMENT"))


def _text(data: bytes) -> str:
    src, _ = decode("x.csv", data)
    return src.text


@pytest.mark.parametrize("name", EXPORTS)
def test_import_export_import_is_identical(name):
    """Each written in the form of its family: GX exports as GX Works2 CSV, Delta ones as WPLSoft."""
    fmt = "wplsoft" if name in ("wplsoft.csv", "delta.csv") else "gxworks2"
    il, _, diags = import_file(str(CORPUS / name), VS)
    assert il is not None, [d.message for d in diags]
    data, errors = export_text("p.il", il, VS, fmt)
    assert data is not None and errors == [], [d.message for d in errors]
    again, found, diags = import_text("back.csv", _text(data), VS)
    assert found == fmt and not [d for d in diags if d.severity == "error"]
    assert again == il


def test_the_gx_works2_csv_is_the_vendors_layout():
    il, _, _ = import_file(str(CORPUS / "gxworks2_en.csv"), VS)
    data, _ = export_text("p.il", il, VS, "gxworks2")
    assert data.startswith(b"\xff\xfe") and b"\r\x00\n\x00" in data
    assert data == (CORPUS / "gxworks2_en.csv").read_bytes()


def test_plain_il_exports_with_the_target_step_column_and_the_family_spellings(tmp_path):
    (tmp_path / "p.il").write_text("LD M9000\nOUT T0 K10\nLD X10\nDRVR K100 K50 Y0 Y4\nFEND\nIX1P:\nIRET\nEND\n",
                                   "utf-8")
    r = run_mlc("export", "--target", "vs", "--to", "gxworks2", "p.il", "-o", "p.csv", cwd=tmp_path)
    assert r.code == 0, r.err
    rows = (tmp_path / "p.csv").read_bytes().decode("utf-16").splitlines()
    assert rows[:3] == ['"MAIN"', '"PLC Information:"\t"FXCPU FX3U/FX3UC"',
                        '"Step Number"\t"Line Statement"\t"Instruction"\t"I/O(Device)"\t"Blank"\t"PI Statement"\t"Note"']
    steps = [r.split("\t")[:4] for r in rows[3:] if not r.startswith('""')]
    assert steps == [['"0"', '""', '"LD"', '"M8000"'], ['"1"', '""', '"OUT"', '"T0"'], ['"4"', '""', '"LD"', '"X010"'],
                     ['"5"', '""', '"DRVI"', '"K100"'], ['"14"', '""', '"FEND"', '""'], ['"15"', '""', '"I101"', '""'],
                     ['"16"', '""', '"IRET"', '""'], ['"17"', '""', '"END"', '""']]
    r = run_mlc("export", "--target", "vs", "--to", "wplsoft", "p.il", cwd=tmp_path)
    assert r.code == 0 and "000000,LD,M1000\r\n000001,TMR,T0,K10\r\n" in r.out
    # a program with errors exports nothing
    (tmp_path / "bad.il").write_text("LD X0\nFROB Y0\nEND\n", "utf-8")
    r = run_mlc("export", "--target", "vs", "--to", "gxworks2", "bad.il", "-o", "bad.csv", cwd=tmp_path)
    assert r.code == 1 and "E201" in r.err and not (tmp_path / "bad.csv").exists()
