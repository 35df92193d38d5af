"""Inputs that are not what `mlc check` expects (mlctool/check/misuse.py, issue 14 §3)."""

from __future__ import annotations

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
