"""`mlc init [--target T] [DIR]` (mlctool/starter.py, docs/getting-started.md): a new project
that passes `mlc check`, `mlc fmt --check` and `mlc test` at once, for every target; its CI
workflow and pre-commit configuration run real mlc commands; nothing is ever overwritten."""

from __future__ import annotations

import json
import re

import pytest
import yaml

from mlctool.cli import all_commands
from mlctool.targetapi import available_targets


@pytest.mark.parametrize("target", available_targets())
def test_init_then_test_passes(mlc, tmp_path, target):
    r = mlc("init", "--target", target, "new", cwd=tmp_path)
    assert r.code == 0, r.err
    project = tmp_path / "new"
    written = sorted(p.relative_to(project).as_posix() for p in project.rglob("*") if p.is_file())
    assert {".github/workflows/plc.yml", ".pre-commit-config.yaml", "mlc.toml", "src/main.il",
            "tests/start.stim"} <= set(written)
    assert [line.removeprefix("wrote new/") for line in r.err.splitlines()[:-1]] == written
    assert f'target = "{target}"' in (project / "mlc.toml").read_text()
    assert mlc("check", cwd=project).code == 0
    assert mlc("fmt", "--check", cwd=project).code == 0
    r = mlc("test", "--coverage", "-q", cwd=project)
    assert r.code == 0, r.out + r.err
    assert "1 passed, 0 failed" in r.out
    uncovered = [s for s in json.loads((project / "coverage.json").read_text())["steps"] if not s["hits"]]
    assert uncovered == []  # the scenario runs every instruction (HSPSO and MPARA on FBs)


def test_fbs_project_names_its_positioning_table(mlc, tmp_path):
    assert mlc("init", "--target", "fbs", "-q", cwd=tmp_path).code == 0
    assert 'tables = ["R5000=tables/move.pos"]' in (tmp_path / "mlc.toml").read_text()
    assert "HSPSO" in (tmp_path / "src" / "main.il").read_text()
    (tmp_path / "mlc.toml").write_text((tmp_path / "mlc.toml").read_text().replace(
        'tables = ["R5000=tables/move.pos"]', "tables = []"))
    r = mlc("test", cwd=tmp_path)  # without the table the axis does not move: W330, and the expectation fails
    assert r.code == 1 and "W330" in r.err


def test_init_never_overwrites(mlc, tmp_path):
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "start.stim").write_text("run 1s\n")
    r = mlc("init", cwd=tmp_path)
    assert r.code == 2 and "E122" in r.err and "start.stim exists" in r.err
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["start.stim", "tests"]  # nothing written
    assert (tmp_path / "tests" / "start.stim").read_text() == "run 1s\n"


def test_init_refuses_an_unknown_target(mlc, tmp_path):
    r = mlc("init", "--target", "nc6", cwd=tmp_path)
    assert r.code == 2 and "E110" in r.err and "nc5" in r.err
    assert list(tmp_path.iterdir()) == []


def test_ci_workflow_and_hooks_run_real_commands(mlc, tmp_path):
    assert mlc("init", "-q", cwd=tmp_path).code == 0
    workflow = yaml.safe_load((tmp_path / ".github" / "workflows" / "plc.yml").read_text())
    runs = [s["run"] for s in workflow["jobs"]["plc"]["steps"] if "run" in s and s["run"].startswith("mlc ")]
    hooks = yaml.safe_load((tmp_path / ".pre-commit-config.yaml").read_text())["repos"][0]["hooks"]
    commands = runs + [h["entry"] for h in hooks]
    assert {c.split()[1] for c in commands} <= set(all_commands())
    for command in commands:  # each passes on the new project, as CI and the hooks run it
        r = mlc(*command.split()[1:], cwd=tmp_path)
        assert r.code == 0, (command, r.err)
    for h in hooks:
        re.compile(h["files"])
