"""One rule for every command (docs/project.md): with no FILE inside a project a command works
on the project; with a FILE that is a module of the project it loads the whole project and
focuses that module. Outputs named on the command line are relative to the current folder,
and every file written is named on stderr (`wrote FILE`, -q: silent). Runs in a scratch copy
of samples/project, whose main module CALLs P10/P11 of its library (alone: E304)."""

from __future__ import annotations

import io
import shutil
from pathlib import Path

import pytest

from tests.conftest import SAMPLES


@pytest.fixture
def project(tmp_path: Path) -> Path:
    dest = tmp_path / "project"
    shutil.copytree(SAMPLES / "project", dest, ignore=shutil.ignore_patterns("build", "out"))
    return dest


@pytest.mark.parametrize("module", [(), ("src/conveyor.il",)], ids=["project", "module"])
def test_ladder_draws_the_project_or_one_module_with_the_project_loaded(mlc, project, module):
    r = mlc("ladder", *module, cwd=project)
    assert r.code == 0, r.err
    assert "E304" not in r.err
    assert "src/conveyor.il" in r.out
    assert ("src/pickplace.il" in r.out) == (not module)  # the module alone is drawn


@pytest.mark.parametrize("module", [(), ("src/conveyor.il",)], ids=["project", "module"])
def test_sim_runs_the_project(mlc, project, module):
    r = mlc("sim", *module, "--stimulus", "tests/pick_cycle.stim", cwd=project)
    assert r.code == 0, r.err
    assert "expectations: 7 passed, 0 failed" in r.out


@pytest.mark.parametrize("module", [(), ("conveyor.il",)], ids=["project", "module"])
def test_debug_runs_the_project(mlc, project, module, monkeypatch):
    monkeypatch.setattr("sys.stdin", io.StringIO("run 3s\nprint D20\nquit\n"))
    r = mlc("debug", *module, "--stimulus", "../tests/pick_cycle.stim", cwd=project / "src")
    assert r.code == 0, r.err
    assert "E304" not in r.err and "D20 = 1" in r.out  # P10 of the library placed one part


@pytest.mark.parametrize("module", [(), ("src/pickplace.il",)], ids=["project", "module"])
def test_fmt_check_takes_the_project(mlc, project, module):
    assert mlc("fmt", "--check", *module, cwd=project).code == 0
    lib = project / "src" / "pickplace.il"
    lib.write_text(lib.read_text().replace("LD>     STEP K4", "LD>  STEP   K4"))
    r = mlc("fmt", "--check", *module, cwd=project / "src" if not module else project)
    assert r.code == 1 and "pickplace.il (formatted)" in r.out
    assert mlc("fmt", "--check", "src/conveyor.il", cwd=project).code == 0  # another module: untouched
    r = mlc("fmt", *module, cwd=project)
    assert r.code == 0 and r.err == "formatted src/pickplace.il\n"
    lib.write_text(lib.read_text().replace("LD>     STEP K4", "LD>  STEP   K4"))
    assert mlc("fmt", "-q", *module, cwd=project).err == ""


def test_check_of_a_module_shows_only_its_diagnostics(mlc, project):
    lib = project / "src" / "pickplace.il"
    lib.write_text(lib.read_text() + "LD X0\nOUT Y0\n")  # W406 in the library (after FEND/SRET)
    assert "W406" in mlc("check", "src/pickplace.il", cwd=project).err
    r = mlc("check", "src/conveyor.il", cwd=project)
    assert r.code == 0 and r.err == ""


def test_build_names_what_it_wrote_and_q_silences_it(mlc, project):
    r = mlc("build", cwd=project / "src")
    assert r.code == 0
    assert r.err.splitlines() == ["wrote ../build/program.mlx", "wrote ../build/program.map",
                                  "wrote ../build/program.lst"]
    r = mlc("build", "-q", "conveyor.il", cwd=project / "src")  # a module, no -o: the project's build
    assert r.code == 0 and r.err == ""
    r = mlc("objdump", cwd=project)  # no FILE: the project's program
    assert r.code == 0 and "unit src/pickplace.il" in r.out


def test_test_outputs_named_relative_go_under_the_current_folder(mlc, project):
    r = mlc("test", "--junit", "j.xml", "--coverage", "--coverage-dir", "cov", cwd=project / "src")
    assert r.code == 0, r.err
    assert (project / "src" / "j.xml").is_file() and not (project / "j.xml").exists()
    assert (project / "src" / "cov" / "coverage.xml").is_file()
    assert "wrote j.xml\n" in r.err and "wrote cov/coverage.json\n" in r.err


def test_test_of_one_scenario_or_a_module(mlc, project):
    r = mlc("test", "--json", "../tests/batch_full.stim", cwd=project / "src")
    assert r.code == 0 and '"tests/batch_full.stim"' in r.out and "pick_cycle" not in r.out
    r = mlc("test", "conveyor.il", cwd=project / "src")
    assert r.code == 0 and "4 passed, 0 failed" in r.out
    r = mlc("test", "../mlc.toml", cwd=project / "src")
    assert r.code == 0 and "4 passed, 0 failed" in r.out
    (project / "notes.il").write_text("END\n")
    r = mlc("test", "notes.il", cwd=project)
    assert r.code == 2 and "neither a module of the project" in r.err
    r = mlc("test", "tests/typo.stim", cwd=project)
    assert r.code == 2 and "E100" in r.err and "no such file or folder" in r.err


def test_a_file_outside_the_project_is_taken_as_given(mlc, project, tmp_path):
    shutil.copy(project / "src" / "conveyor.il", tmp_path / "alone.il")
    r = mlc("ladder", str(tmp_path / "alone.il"), cwd=project)
    assert r.code == 1 and "E304" in r.err


@pytest.mark.parametrize("args", [("sim", "--stimulus", "tests/pick_cycle.stim", "--report", "run.svg"),
                                  ("sim", "--stimulus", "tests/pick_cycle.stim", "--vcd", "run.html"),
                                  ("ladder", "-o", "ladder.txt")])
def test_an_output_named_as_another_format_is_refused(mlc, project, args):
    r = mlc(*args, cwd=project)
    assert r.code == 2 and "E120" in r.err
    assert sorted(p.name for p in project.iterdir()) == ["mlc.toml", "src", "tests"]


def test_an_output_of_unknown_extension_is_written_in_the_options_format(mlc, project):
    r = mlc("sim", "--stimulus", "tests/pick_cycle.stim", "--report", "run.page", cwd=project)
    assert r.code == 0 and r.err == "wrote run.page\n"
    assert (project / "run.page").read_text("utf-8").lstrip().lower().startswith("<!doctype html")


@pytest.mark.parametrize("command", ["sim", "ladder", "fmt", "debug", "objdump", "check"])
def test_no_file_outside_a_project_is_a_usage_error(mlc, tmp_path, command):
    r = mlc(command, cwd=tmp_path)
    assert r.code == 2 and "no FILE given and no mlc.toml here or above" in r.err
    assert "Traceback" not in r.err
