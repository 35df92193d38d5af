"""Shared test helpers."""

from __future__ import annotations

import atexit
import io
import os
import shutil
import sys
import tempfile
from contextlib import redirect_stderr, redirect_stdout
from dataclasses import dataclass
from pathlib import Path

import pytest
from hypothesis import settings

# CI runs the property tests on a fixed set of examples (derandomized), so a pass or fail
# is reproducible; locally each run explores new examples.
settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")

# the tests never read or fill the user's cache folder (mlctool/cache.py): a folder of their
# own for this run, inherited by the mlc subprocesses they start
os.environ["MLC_CACHE_DIR"] = tempfile.mkdtemp(prefix="mlc-test-cache-")
atexit.register(shutil.rmtree, os.environ["MLC_CACHE_DIR"], True)

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "samples"

# The CLI of the package under test, as a subprocess: never whatever `mlc` is on PATH.
MLC_COMMAND = [sys.executable, "-m", "mlctool"]


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


SIM_ENGINES = ("compiled", "interp")
SIM_MODULES = ("test_sim", "test_vs_sim", "test_vs_samples", "test_fbs_sim", "test_fbs_mpg",
               "test_fbs_pulse_window", "test_xc100_cosim", "test_nc5_model")


def pytest_generate_tests(metafunc):
    """Every simulator test module (SIM_MODULES: NC5, VS, FBs, co-simulation) runs on both
    engines (mlctool/sim/engines/compile.py and engine.py; a program it cannot compile, such as step ladder, runs on
    the interpreter either way)."""
    if "sim_engine" in metafunc.fixturenames and metafunc.module.__name__.startswith(SIM_MODULES):
        metafunc.parametrize("sim_engine", SIM_ENGINES, indirect=True, scope="module")


@pytest.fixture(autouse=True, scope="module")
def sim_engine(request):
    """The engine of this module's simulations: simkit.ENGINE and MLC_SIM_ENGINE (for mlc sim)."""
    engine = getattr(request, "param", None)
    if engine is None:
        yield None
        return
    import simkit
    from mlctool.sim.engines.engine import ENGINE_ENV

    old_env, old = os.environ.get(ENGINE_ENV), simkit.ENGINE
    os.environ[ENGINE_ENV] = simkit.ENGINE = engine
    try:
        yield engine
    finally:
        simkit.ENGINE = old
        if old_env is None:
            os.environ.pop(ENGINE_ENV, None)
        else:
            os.environ[ENGINE_ENV] = old_env


def pytest_report_header(config):
    return f"python {sys.version.split()[0]}"


def junit_schema():
    """Jenkins xUnit's junit-10.xsd (tests/data, unchanged) extended by the two optional
    testcase attributes `file` and `line` that mlctool writes (mlctool/sim/campaign/junit.py): GitLab,
    pytest's xunit1 files and Jenkins' JUnit plugin read them. Nothing else is relaxed."""
    from lxml import etree

    xs = "{http://www.w3.org/2001/XMLSchema}"
    doc = etree.parse(str(ROOT / "tests" / "data" / "junit-10.xsd"))
    [case] = [e for e in doc.iter(f"{xs}element") if e.get("name") == "testcase"]
    ctype = case.find(f"{xs}complexType")
    for name in ("file", "line"):
        etree.SubElement(ctype, f"{xs}attribute", name=name, type="xs:string")
    return etree.XMLSchema(doc)


def without_times(xml: bytes | str) -> bytes:
    """JUnit XML with its wall-clock `time` attributes blanked (the only bytes that vary)."""
    import re

    data = xml.encode() if isinstance(xml, str) else xml
    return re.sub(rb' time="[0-9.]+"', b' time=""', data)
