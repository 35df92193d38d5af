"""Helpers for the simulator tests: IL text + stimulus text -> RunResult, in memory."""

from __future__ import annotations

import os
import tempfile

from mlctool.asm import program_from_paths
from mlctool.sim.engines.engine import scanner
from mlctool.sim.run.run import RunResult, Simulation, build_models, plan_scans
from mlctool.sim.scan import load_program
from mlctool.sim.state import Machine, parse_device_name
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targetapi import load_target

NC5 = load_target("nc5")

# The engine simulate() and Bench use: set per test module by the `sim_engine` fixture of
# conftest.py, which runs every test_sim_* module on each engine (None: the default).
ENGINE: str | None = None


def image_of(il: str, name: str = "t.il", target=NC5):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, name)
        with open(path, "w", encoding="utf-8") as f:
            f.write(il.strip() + "\n")
        image, diags, _ = program_from_paths([path], target)
    errors = [f"{d.span.line}: {d.code} {d.message}" for d in diags if d.severity == "error"]
    assert image is not None and not errors, errors
    return image


def simulate(il: str, stim: str = "", scans: int | None = None, period_us: int = 10_000,
             watch: tuple[str, ...] = (), trace: bool = False) -> RunResult:
    st, diags = parse_stimulus_text("t.stim", stim, NC5)
    assert not diags, [f"{d.span.line}:{d.span.col}: {d.code} {d.message}" for d in diags]
    models, mdiags = build_models(st, NC5)
    assert not mdiags, mdiags
    period = st.scan_us or period_us
    n = plan_scans(st, period, None, scans)
    views = [parse_device_name(w, NC5) for w in watch]
    return Simulation(image_of(il), NC5, st, models, period, views, trace, engine=ENGINE).run(n)


def passed(r: RunResult) -> bool:
    """All expectations held; on failure show why."""
    assert r.fault is None, r.fault
    assert not r.failed, [(f.line, f.device, f.expected, f.actual) for f in r.failed]
    return True


class Bench:
    """One program, a machine, scans on demand: for property tests and tight checks."""

    def __init__(self, il: str):
        self.prog = load_program(image_of(il), NC5)
        self.m = Machine(NC5, len(self.prog.steps))
        self.scan_no = 0
        self.scanners = {}  # engine -> Scanner on the one machine (benches live across modules)

    @property
    def engine(self) -> str:
        sc = self.scanners.get(ENGINE)
        if sc is None:
            sc = self.scanners[ENGINE] = scanner(self.prog, self.m, ENGINE)
        return sc.engine

    def set(self, name: str, value) -> None:
        parse_device_name(name, NC5).write(self.m, value)

    def get(self, name: str):
        return parse_device_name(name, NC5).read(self.m)

    def scan(self, n: int = 1, period_us: int = 10_000) -> None:
        for _ in range(n):
            self.m.now_us = self.scan_no * period_us
            sc = self.scanners.get(ENGINE)
            if sc is None:
                sc = self.scanners[ENGINE] = scanner(self.prog, self.m, ENGINE)
            sc()
            self.scan_no += 1
