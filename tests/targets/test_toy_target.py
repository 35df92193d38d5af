"""A third-party target end to end: the toy controller of tests/targets/toy/ is installed
the way a package installs one (a *.dist-info with an `mlctool.targets` entry point on the
path; no code of mlctool names it) and mlc checks, builds and simulates a program with it,
its own instruction (TWICE) and its before-scan hook included (docs/architecture.md)."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

from conftest import MLC_COMMAND

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]

PROGRAM = """\
LD X0
MOV K21 D0
LD X1
TWICE D0 D1
LD X1
OUT Y0
END
"""

STIMULUS = """\
scan 10ms
0ms    expect D1=0 Y0=0
10ms   X0=1
20ms   X1=1
20ms   expect D0=21 D1=42 Y0=1
30ms   X0=0 X1=0 D0=5
30ms   expect D1=42 Y0=0
40ms   X1=1
40ms   expect D1=10 D99=5
run 50ms
"""


@pytest.fixture(scope="module")
def toy(tmp_path_factory):
    """(run, folder): run(*args) runs `python -m mlctool ARGS` with the toy installed."""
    site = tmp_path_factory.mktemp("site")
    dist = site / "toy_target-0.1.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: toy-target\nVersion: 0.1\n")
    (dist / "entry_points.txt").write_text("[mlctool.targets]\ntoy = toy_target:TARGET\n")
    path = [str(site), str(HERE / "toy"), str(ROOT), os.environ.get("PYTHONPATH", "")]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in path if p))
    work = tmp_path_factory.mktemp("work")
    (work / "prog.il").write_text(PROGRAM)
    (work / "prog.stim").write_text(STIMULUS)

    def run(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run([*MLC_COMMAND, *args], capture_output=True, text=True, env=env,
                              cwd=work, timeout=120)
    return run, work


def test_the_toy_is_listed(toy):
    run, _ = toy
    r = run("targets")
    assert r.returncode == 0, r.stderr
    assert any(line.split()[:1] == ["toy"] for line in r.stdout.splitlines()), r.stdout


def test_check_build_and_simulate(toy):
    run, work = toy
    r = run("check", "--target", "toy", "prog.il")
    assert r.returncode == 0, r.stdout + r.stderr
    r = run("build", "--target", "toy", "prog.il", "-o", "prog.mlx")
    assert r.returncode == 0 and (work / "prog.mlx").is_file(), r.stdout + r.stderr
    for engine in ("compiled", "interp"):
        r = run("sim", "prog.mlx", "--stimulus", "prog.stim", "--json", "--engine", engine)
        assert r.returncode == 0, r.stdout + r.stderr
        result = json.loads(r.stdout)["expectations"]
        assert result["failed"] == 0 and result["passed"] == 4, result


def test_the_toy_tables_are_checked(toy):
    """The toy's own tables decide what is an error: TWICE takes no bit device, X16 is
    past its inputs."""
    run, work = toy
    (work / "bad.il").write_text("LD X16\nTWICE M0 D1\nEND\n")
    r = run("check", "--target", "toy", "--format", "json", "bad.il")
    assert r.returncode == 1, r.stdout + r.stderr
    lines = sorted(d["line"] for d in json.loads(r.stdout)["diagnostics"] if d["severity"] == "error")
    assert lines == [1, 2], r.stdout


def test_a_failing_expectation_fails_the_run(toy):
    """The toy's routine really runs: a wrong expectation about TWICE fails."""
    run, work = toy
    (work / "wrong.stim").write_text(STIMULUS.replace("D1=42 Y0=1", "D1=43 Y0=1"))
    r = run("sim", "prog.mlx", "--stimulus", "wrong.stim", "--json")
    assert r.returncode == 1, r.stdout + r.stderr
    assert [f["device"] for f in json.loads(r.stdout)["expectations"]["failures"]] == ["D1"]


def test_the_code_cache_follows_the_targets_tables(tmp_path):
    """The on-disk cache keys on everything the generated code comes from, a third-party
    target's tables included (issue 30.15: with MOV changed to double its value, the cached
    code of the old MOV ran: D0=21, where MLC_CACHE=off gave 42)."""
    import shutil

    package = tmp_path / "toy"
    shutil.copytree(HERE / "toy", package, ignore=shutil.ignore_patterns("__pycache__"))
    site = tmp_path / "site" / "toy_target-0.1.dist-info"
    site.mkdir(parents=True)
    (site / "METADATA").write_text("Metadata-Version: 2.1\nName: toy-target\nVersion: 0.1\n")
    (site / "entry_points.txt").write_text("[mlctool.targets]\ntoy = toy_target:TARGET\n")
    path = [str(site.parent), str(package), str(ROOT), os.environ.get("PYTHONPATH", "")]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in path if p), MLC_CACHE="on",
               MLC_CACHE_DIR=str(tmp_path / "cache"))
    (tmp_path / "prog.il").write_text("LD X0\nMOV K21 D0\nEND\n")
    (tmp_path / "prog.stim").write_text("scan 10ms\n0ms X0=1\n10ms expect D0=21\n")
    (tmp_path / "doubled.stim").write_text("scan 10ms\n0ms X0=1\n10ms expect D0=42\n")

    def run(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run([*MLC_COMMAND, *args], capture_output=True, text=True, env=env, cwd=tmp_path,
                              timeout=120)

    assert run("build", "--target", "toy", "prog.il", "-o", "prog.mlx").returncode == 0
    r = run("sim", "prog.mlx", "--stimulus", "prog.stim")
    assert r.returncode == 0, r.stdout + r.stderr
    assert list((tmp_path / "cache").glob("sim-code-*")), "the compiled code was not cached"
    tables = package / "toy_target" / "tables" / "instructions.toml"
    text = tables.read_text()
    mov = text.index('names = ["MOV", ""]')
    tables.write_text(text[:mov] + text[mov:].replace('op = "mov"', 'op = "twice"', 1))
    r = run("sim", "prog.mlx", "--stimulus", "doubled.stim")
    assert r.returncode == 0, r.stdout + r.stderr
