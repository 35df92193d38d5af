"""An FBs project (docs/project.md `tables`, docs/fbs.md): mlc.toml names the positioning
tables with their SR; `mlc test`, `mlc sim` and `mlc check` load them; FUN140 started on an
empty table warns W330 (naming the table and the error code) instead of only setting R4060."""

from __future__ import annotations

import io
import json
import shutil
from pathlib import Path

import pytest

from tests.conftest import SAMPLES

TOML = """target = "fbs"
sources = ["src/home_and_run.il"]
tables = ["R5000=tables/home.pos", "R5100=tables/run.pos"]
tests = ["tests/*.stim"]
"""


@pytest.fixture
def project(tmp_path: Path) -> Path:
    fbs = SAMPLES / "fbs"
    for folder, names in (("src", ["home_and_run.il"]), ("tables", ["home.pos", "run.pos"]),
                          ("tests", ["home_and_run.stim"])):
        (tmp_path / folder).mkdir()
        for name in names:
            shutil.copy(fbs / name, tmp_path / folder / name)
    (tmp_path / "mlc.toml").write_text(TOML)
    return tmp_path


def test_mlc_test_loads_the_tables_and_covers_hspso(mlc, project):
    r = mlc("test", "--coverage", cwd=project)
    assert r.code == 0, r.out + r.err
    assert "W330" not in r.err
    steps = json.loads((project / "coverage.json").read_text())["steps"]
    hspso = [s["hits"] for s in steps if s["mnemonic"] in ("HSPSO", "FUN140")]
    assert len(hspso) == 2 and all(hspso), hspso  # homing and the positioning run both executed
    mpara = next(s["hits"] for s in steps if s["mnemonic"] == "MPARA")
    assert mpara == 850  # FUN141 runs in every scan of the 8.5 s scenario
    assert "HSPSO K0 R5000 R2100  (never executed)" not in r.out


def test_mlc_sim_without_file_runs_the_project_with_its_tables(mlc, project):
    r = mlc("sim", "--stimulus", "tests/home_and_run.stim", cwd=project / "tests")
    assert r.code == 2  # the stimulus is relative to the current folder: tests/tests/... is not there
    r = mlc("sim", "--stimulus", "home_and_run.stim", cwd=project / "tests")
    assert r.code == 0, r.err
    assert "expectations: 6 passed, 0 failed" in r.out


def test_mlc_debug_loads_the_projects_tables(mlc, project, monkeypatch):
    """`mlc debug` in the project runs HSPSO on its mlc.toml tables (it loaded none: W330, every
    expectation of the homing failed); without them the session says W330 once."""
    script = "continue\nprint R4088:d M1996\nquit\n"
    monkeypatch.setattr("sys.stdin", io.StringIO(script))
    r = mlc("debug", "--stimulus", "tests/home_and_run.stim", cwd=project)
    assert r.code == 0, r.err
    assert "W330" not in r.out + r.err and "expect failed" not in r.out
    assert "the stimulus ends here: scan 850" in r.out and "M1996 = 1" in r.out  # the run table ended
    (project / "mlc.toml").write_text(TOML.replace('tables = ["R5000=tables/home.pos", "R5100=tables/run.pos"]',
                                                   'tables = ["R5100=tables/run.pos"]'))
    monkeypatch.setattr("sys.stdin", io.StringIO(script))
    r = mlc("debug", "--stimulus", "tests/home_and_run.stim", "--table", "R5000=tables/home.pos", cwd=project)
    assert r.code == 0 and "W330" not in r.out and "M1996 = 1" in r.out, r.out + r.err  # --table too
    monkeypatch.setattr("sys.stdin", io.StringIO(script))
    r = mlc("debug", "--stimulus", "tests/home_and_run.stim", cwd=project)
    assert r.out.count("W330") == 1 and "HSPSO K0 R5000 R2100 started on an empty table at R5000" in r.out
    assert "expect failed" in r.out and "M1996 = 0" in r.out


def test_hspso_on_an_empty_table_warns_w330_with_the_table_and_code(mlc, project):
    (project / "mlc.toml").write_text(TOML.replace('tables = ["R5000=tables/home.pos", ', 'tables = ['))
    r = mlc("test", "--json", cwd=project)
    assert r.code == 1  # the homing never ran: its expectations fail
    assert "warning[W330]" in r.err
    assert "HSPSO K0 R5000 R2100 started on an empty table at R5000" in r.err
    assert "error 34 in R4060" in r.err
    assert r.err.count("warning[W330]") == 1  # once, though EN is held for many scans
    doc = json.loads(r.out)["scenarios"]["tests/home_and_run.stim"]
    assert [w["code"] for w in doc["warnings"]] == ["W330"]
    assert doc["devices"]["R4060"] == 34


def test_fun147_on_a_fun140_table_warns_w330(mlc, project):
    il = project / "src" / "home_and_run.il"
    il.write_text(il.read_text().replace("FUN140 K0 R5100 R2110", "MHSPO K0 R5100 R2110"))
    r = mlc("sim", "--stimulus", "tests/home_and_run.stim", "--json", cwd=project)
    warned = [w for w in json.loads(r.out)["warnings"] if w["code"] == "W330"]
    assert len(warned) == 1 and "R5100, which holds a FUN140 table" in warned[0]["message"]
    assert "error 34 in D4060" in warned[0]["message"]


def test_check_checks_the_projects_positioning_tables(mlc, project):
    assert mlc("check", cwd=project).code == 0
    pos = project / "tables" / "run.pos"
    pos.write_text(pos.read_text() + "\n FOO 12\n")
    r = mlc("check", cwd=project)
    assert r.code == 1 and "tables/run.pos" in r.err


@pytest.mark.parametrize("toml, message", [
    ('target = "nc5"\nsources = ["src/home_and_run.il"]\ntables = ["R5000=tables/home.pos"]\n',
     "target nc5 has no register tables"),
    (TOML.replace("R5000=tables/home.pos", "tables/home.pos"), "give the table's first register"),
])
def test_a_table_the_target_cannot_load_is_e121_at_its_line(mlc, project, toml, message):
    (project / "mlc.toml").write_text(toml)
    r = mlc("sim", "--stimulus", "tests/home_and_run.stim", cwd=project)
    assert r.code == 2 and "E121" in r.err and message in r.err
    assert "mlc.toml:3:1:" in r.err


def test_mlc_test_coverage_in_workers_keeps_the_projects_pulse_modes(mlc, project):
    """`mlc test --coverage -j 2`: each worker loaded the target again by its name, so the
    project's mlc.toml `pulse_modes` (and `model`) were lost there: P/R axes ran as U/D."""
    (project / "mlc.toml").write_text(TOML + 'pulse_modes = ["P/R"]\n')
    stim = project / "tests" / "home_and_run.stim"
    # P/R homing backwards: pulses on Y0, Y1 (the direction) Off; U/D would pulse Y1
    pr = stim.read_text().replace("expect M1992=0 Y0=0 Y1=1", "expect M1992=0 Y0=1 Y1=0")
    assert pr != stim.read_text()
    stim.write_text(pr)
    (project / "tests" / "again.stim").write_text(pr)
    one = mlc("test", "--coverage", "-j", "1", "--json", cwd=project)
    coverage = (project / "coverage.json").read_text()
    two = mlc("test", "--coverage", "-j", "2", "--json", cwd=project)
    assert one.code == 0 and two.code == 0, two.out + two.err
    assert json.loads(one.out)["scenarios"] == json.loads(two.out)["scenarios"]
    assert (project / "coverage.json").read_text() == coverage
