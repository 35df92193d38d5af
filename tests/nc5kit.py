"""Helpers for the virtual NC tests (mlctool/targets/nc5/nc/): an IL program, a stimulus with a
`model nc5 ...` line and a part program -> RunResult, on simkit's engine (both engines: the
test_nc5_model modules are in conftest.SIM_MODULES)."""

from __future__ import annotations

import os
import tempfile

import simkit
from mlctool.sim.run.run import RunResult, Simulation, build_models, plan_scans
from mlctool.sim.state import parse_device_name
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targetapi.signals import device_signal

NC5 = simkit.NC5

# The MLC side every test needs: servo on, overrides at 100 %, jog at 50 % (LDI M0: always)
BASE = """
LDI M0
OUT M21012
MOV K100 D21002
MOV K100 D21004
MOV K50 D21006
MOV K100 D21026
"""


def run(il: str, stim: str, part: str | None = None, period_us: int = 10_000,
        watch: tuple[str, ...] = ()) -> RunResult:
    """Run BASE + il (END added) against stim (its model line may say program=part.nc, the
    `part` text); every expectation must hold."""
    r = outcome(il, stim, part, period_us, watch)
    assert r.fault is None, r.fault
    assert not r.failed, [(f.line, f.device, f.expected, f.actual) for f in r.failed]
    return r


def outcome(il: str, stim: str, part: str | None = None, period_us: int = 10_000,
            watch: tuple[str, ...] = (), trace: bool = False) -> RunResult:
    image = simkit.image_of(BASE + il + "\nEND\n")
    with tempfile.TemporaryDirectory() as tmp:
        if part is not None:
            with open(os.path.join(tmp, "part.nc"), "w", encoding="utf-8") as f:
                f.write(part)
        st, diags = parse_stimulus_text(os.path.join(tmp, "t.stim"), stim, NC5)
        assert not diags, [(d.span.line, d.code, d.message) for d in diags]
        models, mdiags = build_models(st, NC5)
    assert not mdiags, [(d.file, d.span.line, d.span.col, d.code, d.message) for d in mdiags]
    n = plan_scans(st, st.scan_us or period_us, None, None)
    views = [parse_device_name(w, NC5) for w in watch]
    return Simulation(image, NC5, st, models, st.scan_us or period_us, views, trace,
                      engine=simkit.ENGINE).run(n)


def nc_written(view) -> bool:
    """A device the NC (or the HMI) writes, which a stimulus must not play when the virtual NC
    runs: the rows of the signal table whose writer is the NC or the HMI (NC->MLC, HMI->MLC:
    M3cnnn, D3cnnn, M59xxx, D59xxx)."""
    found = device_signal(NC5, view.kind, view.number)
    return found is not None and found.signal.direction in ("NC->MLC", "HMI->MLC")


def model_diags(stim: str, part: str | None = None) -> list[tuple[str, int, int, str]]:
    """(file name, line, column, code) of what build_models says about the stimulus' models."""
    with tempfile.TemporaryDirectory() as tmp:
        if part is not None:
            with open(os.path.join(tmp, "part.nc"), "w", encoding="utf-8") as f:
                f.write(part)
        st, diags = parse_stimulus_text(os.path.join(tmp, "t.stim"), stim, NC5)
        assert not diags
        _, mdiags = build_models(st, NC5)
    return [(os.path.basename(d.file), d.span.line, d.span.col, d.code) for d in mdiags]
