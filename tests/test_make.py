"""The Makefile's two promises (README): `make demo` installs only what running needs, `make
test` the test extras too, one .venv for both (`make -n`: the commands, none run)."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from tests.conftest import ROOT

pytestmark = pytest.mark.skipif(shutil.which("make") is None, reason="no make")


def planned(tmp_path, goal: str) -> list[str]:
    for name in ("Makefile", "pyproject.toml"):
        if not (tmp_path / name).exists():
            shutil.copy(ROOT / name, tmp_path / name)
    r = subprocess.run(["make", "-n", goal], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    return [line for line in r.stdout.splitlines() if "pip install" in line]


def test_demo_installs_only_the_runtime(tmp_path):
    installs = planned(tmp_path, "demo")
    assert installs[-1].endswith("pip install --quiet -e .")
    assert not any("[test]" in line for line in installs)


def test_test_installs_the_test_extra(tmp_path):
    assert planned(tmp_path, "test")[-1].endswith("pip install --quiet -e '.[test]'")


def test_demo_after_test_installs_nothing_more(tmp_path):
    planned(tmp_path, "test")  # (copies the Makefile and pyproject.toml: older than the stamps below)
    venv = tmp_path / ".venv"
    (venv / "bin").mkdir(parents=True)
    (venv / "bin" / "python").touch()
    (venv / ".installed-test").touch()
    (venv / ".installed-run").touch()  # as the test install's recipe leaves it
    assert planned(tmp_path, "demo") == []  # .ci/run: make test, then make demo


def test_bench_runs_every_bench_script_but_the_long_one(tmp_path):
    """`make bench` runs each script of bench/ (the files with a __main__) but lsp_memory.py
    (about 15 minutes; docs/bench.md), and its venv holds the extras they import."""
    lines = (ROOT / "Makefile").read_text(encoding="utf-8").split("\nbench:", 1)[1].split("\n\n", 1)[0]
    run = {line.split("bench/", 1)[1] for line in lines.splitlines() if "python bench/" in line}
    scripts = {p.name for p in (ROOT / "bench").glob("*.py") if "__main__" in p.read_text(encoding="utf-8")}
    assert run == scripts - {"lsp_memory.py"}
    assert planned(tmp_path, "bench")[-1].endswith("pip install --quiet -e '.[cluster,native,opcua,verify]'")
