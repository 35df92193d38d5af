"""Shared test helpers."""

from __future__ import annotations

import io
import os
import sys
from contextlib import redirect_stderr, redirect_stdout
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "samples"


@dataclass
class CliResult:
    code: int
    out: str
    err: str


def run_mlc(*args: str, cwd: str | os.PathLike | None = None) -> CliResult:
    """Run the mlc CLI in-process (same code path as the console script, no subprocess cost)."""
    from mlctool.cli import main_group
    from mlctool.cli.common import run_guarded

    out, err = io.StringIO(), io.StringIO()
    old = os.getcwd()
    try:
        if cwd:
            os.chdir(cwd)
        with redirect_stdout(out), redirect_stderr(err):
            code = run_guarded(main_group, list(args))
    finally:
        os.chdir(old)
    return CliResult(code, out.getvalue(), err.getvalue())


@pytest.fixture
def mlc():
    return run_mlc


@pytest.fixture(autouse=True)
def _no_color(monkeypatch):
    monkeypatch.setenv("NO_COLOR", "1")
    monkeypatch.delenv("FORCE_COLOR", raising=False)


def pytest_report_header(config):
    return f"python {sys.version.split()[0]}"
