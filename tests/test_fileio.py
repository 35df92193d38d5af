"""Outputs (mlctool/fileio.py): every output option creates the folders on its way."""

from __future__ import annotations

import shutil

import pytest

from conftest import SAMPLES, run_mlc

PROJECT = SAMPLES / "project"
NC5 = SAMPLES / "nc5"


@pytest.fixture
def work(tmp_path):
    shutil.copy(NC5 / "conveyor.il", tmp_path / "c.il")
    shutil.copy(NC5 / "conveyor.stim", tmp_path / "c.stim")
    return tmp_path


@pytest.mark.parametrize("args, outputs", [
    (["build", "c.il", "-o", "build/x.mlx", "--listing", "lst/x.lst", "--map", "map/x.map"],
     ["build/x.mlx", "lst/x.lst", "map/x.map"]),
    (["build", "c.il", "-o", "mods/deep/c.mlo"], ["mods/deep/c.mlo"]),
    (["build", "-c", "c.il", "-o", "objs/"], ["objs/c.mlo"]),
    (["sim", "c.il", "--stimulus", "c.stim", "--vcd", "w/c.vcd", "--junit", "j/c.xml", "--report", "r/c.html"],
     ["w/c.vcd", "w/c.gtkw", "j/c.xml", "r/c.html"]),
    (["ladder", "c.il", "-o", "pics/c.svg"], ["pics/c.svg"]),
    (["import", "c.il", "--target", "nc5", "-o", "imported/c.il"], ["imported/c.il"]),
])
def test_missing_output_folders_are_created(work, args, outputs):
    r = run_mlc(*args, cwd=work)
    assert r.code == 0, r.err
    for out in outputs:
        assert (work / out).is_file(), out


def test_compile_folder_that_is_a_file_is_refused(work):
    (work / "objs").write_text("not a folder\n")
    r = run_mlc("build", "-c", "c.il", "-o", "objs", cwd=work)
    assert r.code == 2 and "E510" in r.err and "is a file" in r.err


def test_folder_that_cannot_be_created_is_e605(work):
    (work / "blocker").write_text("a file where a folder is needed\n")
    r = run_mlc("build", "c.il", "-o", "blocker/x.mlx", cwd=work)
    assert r.code != 0 and "E605" in r.err and "Traceback" not in r.err
