"""Helpers for the Vigor VS simulator tests: IL text + stimulus text -> RunResult, in memory."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from mlctool.asm import program_from_paths
from mlctool.check import check_texts
from mlctool.program import Image
from mlctool.sim.run.run import RunResult, Simulation, plan_scans
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.syntax.source import decode
from mlctool.targetapi import load_target

VS = load_target("vs")


def check_codes(il: str, model: str | None = "VS3", severities: tuple[str, ...] = ()) -> list[tuple[str, int]]:
    """(code, line) of the diagnostics `mlc check --target vs [--model]` gives `il` (only those
    of `severities` when given)."""
    src, _ = decode("t.il", (il.strip() + "\n").encode())
    return [(d.code, d.span.line) for d in check_texts([src], load_target("vs", model)).diagnostics
            if not severities or d.severity in severities]


def image_of(il: str) -> Image | None:
    """The linked program of `il` as written (None when the checker refuses it)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "t.il")
        Path(path).write_text(il.strip() + "\n", encoding="utf-8")
        image, _, _ = program_from_paths([path], VS)
    return image


def simulate(image: Image, stim: str, period_us: int = 10_000, scans: int | None = None,
             engine: str | None = None) -> RunResult:
    st, sd = parse_stimulus_text("t.stim", stim, VS)
    assert not sd, [(d.code, d.message) for d in sd]
    n = scans if scans is not None else plan_scans(st, period_us, None, None)
    return Simulation(image, VS, st, [], period_us, [], False, engine=engine).run(n)


def run(il: str, stim: str, alarms: bool = False, period_us: int = 10_000,
        scans: int | None = None, engine: str | None = None) -> RunResult:
    """Run il (END added) against stim on `engine` (the default one when None): no fault,
    every expectation holds, and (alarms=False) no operation error raised either."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "t.il")
        Path(path).write_text(il.strip() + "\nEND\n", encoding="utf-8")
        image, diags, _ = program_from_paths([path], VS)
    assert image is not None, [(d.code, d.message) for d in diags]
    r = simulate(image, stim, period_us, scans, engine)
    assert r.fault is None, r.fault
    assert not r.failed, [(f.line, f.device, f.expected, f.actual) for f in r.failed]
    if not alarms:
        assert not r.alarms, [(a.name, a.message) for a in r.alarms]
    return r
