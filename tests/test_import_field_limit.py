"""A CSV field past the csv module's 131,072-character limit (issue 21 #10) is an import
error at its line (E907, exit 1), never a crash, in every CSV format."""

from __future__ import annotations

import pytest

from conftest import run_mlc

LONG = "Y" * 140_000
EXPORTS = {
    "gxdeveloper": ("Step,Instruction,I/O(Device)\n0,LD,X0\n1,OUT," + LONG + "\n2,END,\n", 3),
    "gxworks2": ("Step\tInstruction\tI/O(Device)\n0\tLD\tX0\n1\tOUT\t" + LONG + "\n2\tEND\t\n", 3),
    "wplsoft": ("000000,LD,X0\n000001,OUT," + LONG + "\n000002,END\n", 2),
    "quoted": ('Step,Instruction,I/O(Device)\n0,LD,X0\n1,OUT,"' + LONG + '"\n2,END,\n', 3),
}


@pytest.mark.parametrize("name", sorted(EXPORTS))
def test_field_over_the_csv_limit_is_an_error_at_its_line(name, tmp_path):
    text, line = EXPORTS[name]
    (tmp_path / "e.csv").write_text(text, "utf-8")
    r = run_mlc("import", "e.csv", "-o", "e.il", cwd=tmp_path)
    assert r.code == 1, r.err[-800:]
    assert f"e.csv:{line}:1: error[E907]" in r.err and "131,072" in r.err
    assert not (tmp_path / "e.il").exists()


def test_register_image_field_over_the_csv_limit(tmp_path):
    """The FBs register image CSV (objdump, --table) says the same for its own reader."""
    (tmp_path / "i.csv").write_text("register,value\nR0,1\nR1,2" + "x" * 140_000 + "\n", "utf-8")
    r = run_mlc("objdump", "i.csv", cwd=tmp_path)
    assert r.code == 2 and "CSV line 3" in r.err and "internal error" not in r.err, r.err[-800:]
