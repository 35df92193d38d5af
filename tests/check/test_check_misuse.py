"""Inputs that are not what `mlc check` expects (mlctool/check/misuse.py, issue 14 §3)."""

from __future__ import annotations

import json
import shutil

import pytest

from conftest import ROOT, SAMPLES

IMPORTS = ROOT / "tests" / "data" / "vs_imports"


@pytest.mark.parametrize("name, says", [
    ("t.stim", "a stimulus file, not a program: `mlc sim PROGRAM --stimulus t.stim` runs"),
    ("p.mlx", "a linked program (built by `mlc build`), not a source: `mlc objdump p.mlx` lists it, "
              "`mlc sim p.mlx` runs it"),
    ("m.mlo", "an object module (built by `mlc build`), not a source: `mlc objdump m.mlo` lists it"),
])
def test_a_file_that_is_no_source_is_named(mlc, tmp_path, name, says):
    """Before: a .stim gave an E103 per line, an object E101 "contains a NUL byte"."""
    (tmp_path / "a.il").write_text("LD X0\nOUT Y0\nEND\n")
    assert mlc("build", "a.il", "-o", "p.mlx", cwd=tmp_path).code == 0
    assert mlc("build", "a.il", "-o", "m.mlo", cwd=tmp_path).code == 0
    shutil.copy(SAMPLES / "nc5" / "conveyor.stim", tmp_path / "t.stim")
    r = mlc("check", name, cwd=tmp_path)
    assert r.code == 2 and f"{name}:1:1: error[E111]: {says}" in r.err, r.err
    assert r.err.count("error[") == 1


@pytest.mark.parametrize("export, kind", [("gxworks2.csv", "GX Works2"), ("gxdeveloper.csv", "GX Developer")])
def test_a_vendor_export_is_named_with_the_import_command(mlc, tmp_path, export, kind):
    shutil.copy(IMPORTS / export, tmp_path / export)
    r = mlc("check", export, cwd=tmp_path)
    il = export.replace(".csv", ".il")
    assert r.code == 2 and f"error[E111]: a {kind} export, not a source: `mlc import {export} -o {il}`" in r.err
    assert mlc("build", export, "-o", "x.mlx", cwd=tmp_path).code == 2


def test_wplsoft_rows_are_still_checked_as_il(mlc, tmp_path):
    (tmp_path / "w.csv").write_text("000000,LD,X0\n000001,OUT,Y0\n000002,END\n")
    assert mlc("check", "w.csv", cwd=tmp_path).code == 0


def test_a_program_for_another_target_gets_a_note(mlc):
    """Issue 14 §3: 38 errors and no hint. A VS step-ladder program checked on nc5."""
    r = mlc("check", str(SAMPLES / "vs" / "traffic_light.il"))
    assert r.code == 1
    assert r.err.rstrip().endswith("note: this looks like a `--target vs` program: 38 errors on nc5, none on vs; "
                                   "choose the target with --target or `target` in mlc.toml")
    r = mlc("check", "--target", "vs", str(SAMPLES / "nc5" / "man_6_1_mode_switch.il"))
    assert r.code == 1 and "note: this looks like a `--target nc5` program: 22 errors on vs, none on nc5" in r.err
    # the JSON on stdout stays JSON; the note goes to stderr
    r = mlc("check", "--format", "json", str(SAMPLES / "vs" / "traffic_light.il"))
    assert r.out.startswith("{") and "--target vs" in r.err


def test_no_note_for_a_few_typos_or_errors_every_target_shares(mlc, tmp_path):
    p = tmp_path / "t.il"
    p.write_text("LD X0\nOTU Y0\nOTU Y1\nOTU Y2\nOTU Y3\nEND\n")  # 4 errors: below the threshold
    r = mlc("check", str(p))
    assert r.code == 1 and "looks like" not in r.err
    p.write_text("LD X0\n" + "QQQ Y0\n" * 8 + "END\n")  # unknown everywhere
    r = mlc("check", str(p))
    assert r.code == 1 and "looks like" not in r.err


@pytest.mark.parametrize("line, form", [("TMR T0 K10", "OUT T0 K10"), ("CNT C0 K3", "OUT C0 K10")])
def test_nc5_timer_and_counter_on_vs_name_the_vs_form(mlc, tmp_path, line, form):
    """TMR/CNT on VS: the VS form of the same instruction, not a near spelling (TTMR, INT)."""
    (tmp_path / "p.il").write_text(f"LD X0\n{line}\nEND\n")
    r = mlc("check", "--target", "vs", "p.il", cwd=tmp_path)
    assert r.code == 1 and "E201" in r.err
    assert f"target vs writes {line.split()[0]}'s instruction as `{form}`" in r.err
    assert "TTMR" not in r.err and "INT" not in r.err


def test_a_symbol_name_that_reads_as_an_operand_is_one_error(mlc, tmp_path):
    """`.define P1 X0`: E106 at the name, and its uses (LD P1, a P device in a contact) are
    not reported again."""
    (tmp_path / "p.il").write_text(".define P1 X0\nLD P1\nOUT Y0\nLD X1\nAND P1\nOUT Y1\nEND\n")
    r = mlc("check", "--format", "json", "p.il", cwd=tmp_path)
    found = [(d["code"], d["line"]) for d in json.loads(r.out)["diagnostics"]]
    assert r.code == 1 and found == [("E106", 1)]
