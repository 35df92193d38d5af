"""The conformance cases on the native engine: the cases of both suites that have no step
ladder in one program (conformance_kit.combined), built once, each case run with its own
stimulus and selector; the step-ladder cases run on their own in their suite's file."""

from __future__ import annotations

import pytest
from conformance_kit import combined
from test_conformance_isu_fx2n import CASES as ISU_FX2N
from test_conformance_ladder_drive import CASES as LADDER_DRIVE

import vskit
from mlctool.sim.engines import native
from mlctool.sim.run.run import Simulation
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from vskit import VS

pytestmark = pytest.mark.skipif(native.unavailable() is not None, reason=f"native engine: {native.unavailable()}")

PROGRAM, STIMULI = combined(ISU_FX2N + LADDER_DRIVE)


def test_the_combined_program_runs_on_the_native_engine():
    """The program is built (not left to the compiled engine): the cases below are native runs."""
    image = vskit.image_of(PROGRAM + "\nEND")
    assert image is not None
    sim = Simulation(image, VS, parse_stimulus_text("t.stim", "", VS)[0], [], 10_000, [], False, engine="native")
    assert sim.scan.engine == "native", getattr(sim.scan, "native_error", None)


@pytest.mark.parametrize("stim", [pytest.param(s, id=case) for case, s in STIMULI])
def test_case_on_the_native_engine(stim):
    vskit.run(PROGRAM, stim, engine="native")
