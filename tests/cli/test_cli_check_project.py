"""`mlc check` and `mlc test` find the project (mlc.toml) above the current folder; `mlc check`
takes folders. Each test runs from a subfolder of a scratch copy of samples/project."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from tests.conftest import SAMPLES


@pytest.fixture
def project(tmp_path: Path) -> Path:
    dest = tmp_path / "project"
    shutil.copytree(SAMPLES / "project", dest, ignore=shutil.ignore_patterns("build", "out"))
    (dest / "docs" / "notes").mkdir(parents=True)
    return dest


def _files(r) -> set[str]:
    return {d["file"] for d in json.loads(r.out)["diagnostics"]}


def test_check_without_files_checks_the_project_sources_together(mlc, project, tmp_path):
    # conveyor.il alone (outside the project) calls P10/P11 that only the library pickplace.il exports: E304
    shutil.copy(project / "src" / "conveyor.il", tmp_path / "conveyor.il")
    alone = mlc("check", "conveyor.il", cwd=tmp_path)
    assert alone.code == 1 and "E304" in alone.err
    # in the project, a module is checked with the others (docs/project.md, one rule)
    assert mlc("check", "src/conveyor.il", cwd=project).code == 0
    r = mlc("check", cwd=project / "docs" / "notes")
    assert r.code == 0, r.err
    assert "E304" not in r.err


def test_check_without_files_reports_project_files_relative_to_here(mlc, project):
    # the library exports a label it lacks (E304 there), so P11 is missing in conveyor.il (E304)
    lib = project / "src" / "pickplace.il"
    lib.write_text(lib.read_text().replace(".export P10 P11", ".export P10 P99"))
    r = mlc("check", "--format", "json", cwd=project / "docs")
    assert r.code == 1
    assert _files(r) == {"../src/conveyor.il", "../src/pickplace.il"}


def test_check_without_files_uses_the_project_settings(mlc, project):
    toml, main = project / "mlc.toml", project / "src" / "conveyor.il"
    main.write_text(main.read_text().replace("SET     PICKING", "SET     PICKING\nSET     M100", 1))
    # W405 (SET without RST) is a warning; the project makes it an error
    r = mlc("check", cwd=project / "src")
    assert r.code == 0 and "warning[W405]" in r.err
    toml.write_text(toml.read_text() + '\n[severity]\nW405 = "error"\n')
    r = mlc("check", cwd=project / "src")
    assert r.code == 1 and "error[W405]" in r.err
    # and its target: the NC5 program is not a VS program
    toml.write_text(toml.read_text().replace('target = "nc5"', 'target = "vs"'))
    r = mlc("check", cwd=project / "src")
    assert r.code == 1 and "error[E2" in r.err


def test_check_without_files_and_without_project_is_a_usage_error(mlc, tmp_path):
    r = mlc("check", cwd=tmp_path)
    assert r.code == 2
    assert "no FILE given and no mlc.toml here or above" in r.err
    assert "Traceback" not in r.err


def test_check_project_without_sources_is_a_usage_error(mlc, tmp_path):
    (tmp_path / "mlc.toml").write_text('target = "nc5"\n')
    r = mlc("check", cwd=tmp_path)
    assert r.code == 2 and "sources" in r.err


def test_check_searches_folders_for_il_files_in_sorted_order(mlc, tmp_path):
    src = tmp_path / "src"
    (src / "lib").mkdir(parents=True)
    (src / ".hidden").mkdir()
    for name in ("b.il", "a.il", "lib/c.il", ".hidden/x.il"):
        (src / name).write_text("LD X0\nOUT Y0\nOUT Y0\nEND\n")  # W401 double coil in each
    (src / "notes.txt").write_text("LD X0\n")
    r = mlc("check", "--format", "json", "src", cwd=tmp_path)
    files = [d["file"] for d in json.loads(r.out)["diagnostics"]]
    assert sorted(set(files)) == ["src/a.il", "src/b.il", "src/lib/c.il"]
    assert files == sorted(files)
    again = mlc("check", "--format", "json", "src", cwd=tmp_path)
    assert again.out == r.out


def test_check_folder_without_il_files_is_a_usage_error(mlc, tmp_path):
    (tmp_path / "empty").mkdir()
    r = mlc("check", "empty", cwd=tmp_path)
    assert r.code == 2 and "no *.il files" in r.err


def test_mlc_test_finds_the_project_above(mlc, project):
    r = mlc("test", cwd=project / "docs" / "notes")
    assert r.code == 0, r.out + r.err
    assert "4 passed, 0 failed" in r.out


def test_mlc_test_without_project_says_so(mlc, tmp_path):
    r = mlc("test", cwd=tmp_path)
    assert r.code == 2 and "no mlc.toml here or above" in r.err
